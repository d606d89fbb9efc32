//! Explicit element updates per second (one element's F, material update of its points,
//! and internal forces, per step), for the element technologies and materials of the
//! elements-and-solvers issue, on one and two threads. Run with
//! `cargo bench -p musclefem-core --bench explicit_element_updates`.
//!
//! Each measurement is a whole `run_explicit` of 50 fixed steps of 1e-7 s on a box of
//! 20 × 20 × 20 hexahedra (8 000 elements; 48 000 tets for the tet meshes), so it includes
//! the set-up (kernels, lumped mass) and the stable-step refreshes, about 2 steps' worth.
//! Criterion's throughput is in element updates (50 × elements).

use std::collections::BTreeMap;
use std::sync::Arc;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};

use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::{TetOrder, box_of_hexes, box_of_tets};
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit};
use musclefem_core::solver::{Part, PrescribedDisplacement};
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

const STEPS: usize = 50;
const STEP: f64 = 1e-7;
const DIVISIONS: usize = 20;
const SIDE: f64 = 0.02;

fn material(name: &str, params: &[(&str, f64)]) -> Arc<dyn Material> {
    let given: BTreeMap<String, f64> = params.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    MaterialLibrary::with_builtins()
        .create(name, &given)
        .unwrap()
}

/// x0 clamped along x, x1 pulled at 0.1 m/s: every element deforms.
fn loading(mesh: &Mesh) -> Vec<PrescribedDisplacement> {
    vec![
        PrescribedDisplacement {
            nodes: mesh.node_set("x0").unwrap().to_vec(),
            dof: 0,
            amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
        },
        PrescribedDisplacement {
            nodes: mesh.node_set("x1").unwrap().to_vec(),
            dof: 0,
            amplitude: Amplitude::ramp(1.0, 0.1).unwrap(),
        },
    ]
}

fn bench_case(
    c: &mut Criterion,
    name: &str,
    mesh: &Mesh,
    technology: Technology,
    material: Arc<dyn Material>,
) {
    let parts = vec![Part {
        block: 0,
        technology,
        material,
        density: 1060.0,
    }];
    let loads = loading(mesh).into();
    let mut settings = ExplicitSettings::new(STEPS as f64 * STEP);
    settings.fixed_time_step = Some(STEP);
    settings.history_interval = 1.0;
    let elements = mesh.element_count();
    let mut group = c.benchmark_group(format!("explicit_element_updates/{name}"));
    group.throughput(Throughput::Elements((STEPS * elements) as u64));
    group.sample_size(10);
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool");
        group.bench_function(format!("{threads}_thread"), |b| {
            b.iter(|| pool.install(|| run_explicit(mesh, &parts, &loads, &settings).unwrap()))
        });
    }
    group.finish();
}

fn explicit_element_updates(c: &mut Criterion) {
    let hexes = box_of_hexes([SIDE; 3], [DIVISIONS; 3]).unwrap();
    let neo_hookean = material("neo-hookean", &[]);
    let hill = material("hill", &[("n2", 1.0)]);
    bench_case(
        c,
        "hex8_one_point_neo_hookean",
        &hexes,
        Technology::hex8_one_point(11_370.0),
        neo_hookean.clone(),
    );
    bench_case(c, "hex8_fbar_hill", &hexes, Technology::Hex8FBar, hill);
    bench_case(
        c,
        "hex8_full_neo_hookean",
        &hexes,
        Technology::Hex8Full,
        neo_hookean.clone(),
    );
    let tets = box_of_tets([SIDE; 3], [DIVISIONS; 3], TetOrder::Linear).unwrap();
    bench_case(
        c,
        "tet4_neo_hookean",
        &tets,
        Technology::Tet4,
        neo_hookean.clone(),
    );
    let tet10 = box_of_tets([SIDE; 3], [DIVISIONS; 3], TetOrder::Quadratic).unwrap();
    bench_case(
        c,
        "tet10_neo_hookean",
        &tet10,
        Technology::Tet10,
        neo_hookean,
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .measurement_time(std::time::Duration::from_secs(5))
        .warm_up_time(std::time::Duration::from_secs(1));
    targets = explicit_element_updates
}
criterion_main!(benches);
