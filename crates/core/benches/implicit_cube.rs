//! Quasi-static implicit solves of a cube in uniaxial stretch: a compressible neo-Hookean
//! cube (μ = 10 kPa, K = 2/D = 100 kPa) of side 10 mm, symmetry on the x0, y0 and z0
//! faces, the x1 face pulled along x to λ = 1.5 in 10 equal load steps, the lateral faces
//! free. One measurement is a whole `run_quasi_static`: set-up (kernels, sparsity pattern,
//! scatter maps), symbolic factorization, and every Newton iteration of the 10 steps
//! (material updates, element stiffness, assembly, numeric factorization, solves, line
//! search). Run with `cargo bench -p musclefem-core --bench implicit_cube`.
//!
//! Meshes of 10³, 20³ and 30³ F-bar hex8 (3 509, 26 019 and 85 529 unknowns). Criterion's
//! smallest sample (10 runs) with a short measurement time, so the 30³ case stays
//! bearable; the thread count is rayon's default (all cores).

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};

use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::implicit::{ImplicitSettings, run_quasi_static};
use musclefem_core::solver::{Loads, Part, PrescribedDisplacement};
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

/// Side of the cube [m].
const SIDE: f64 = 0.01;
/// Final stretch of the pulled face.
const STRETCH: f64 = 1.5;
/// Equal load steps to the final stretch.
const STEPS: usize = 10;
/// Element technology of the cube.
const TECHNOLOGY: Technology = Technology::Hex8FBar;

fn compressible_neo_hookean() -> Arc<dyn Material> {
    let params = BTreeMap::from([("mu".to_string(), 1e4), ("D".to_string(), 2e-5)]);
    MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap()
}

/// Symmetry on x0, y0, z0; x1 pulled along x to `STRETCH` linearly over 1 s.
fn uniaxial(mesh: &Mesh) -> Vec<PrescribedDisplacement> {
    let fixed = |set: &str, dof: usize| PrescribedDisplacement {
        nodes: mesh.node_set(set).unwrap().to_vec(),
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    };
    vec![
        PrescribedDisplacement {
            nodes: mesh.node_set("x1").unwrap().to_vec(),
            dof: 0,
            amplitude: Amplitude::ramp(1.0, (STRETCH - 1.0) * SIDE).unwrap(),
        },
        fixed("x0", 0),
        fixed("y0", 1),
        fixed("z0", 2),
    ]
}

fn implicit_cube(c: &mut Criterion) {
    let mut group = c.benchmark_group("implicit_cube");
    group.sample_size(10);
    let material = compressible_neo_hookean();
    for divisions in [10, 20, 30] {
        let mesh = box_of_hexes([SIDE; 3], [divisions; 3]).unwrap();
        let parts = vec![Part {
            block: 0,
            technology: TECHNOLOGY,
            material: material.clone(),
            density: 1000.0,
        }];
        let loads: Loads = uniaxial(&mesh).into();
        let settings = ImplicitSettings::new(1.0, STEPS);
        group.measurement_time(Duration::from_secs(match divisions {
            10 => 5,
            20 => 20,
            _ => 60,
        }));
        // The last run's summary, printed when the case ran (criterion filters by name).
        let mut summary = None;
        group.bench_function(format!("{divisions}^3"), |b| {
            b.iter(|| {
                let result = run_quasi_static(&mesh, &parts, &loads, &settings).unwrap();
                let iterations: Vec<usize> = result.steps.iter().map(|s| s.iterations).collect();
                summary = Some(format!(
                    "{divisions}^3 {TECHNOLOGY:?}: {} unknowns, {} matrix entries, Newton \
                     iterations per step {iterations:?}, last factorization {:?}",
                    result.equations,
                    result.matrix_entries,
                    result.steps.last().map(|s| s.factorization)
                ));
                result
            })
        });
        if let Some(summary) = summary {
            println!("{summary}");
        }
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_secs(1));
    targets = implicit_cube
}
criterion_main!(benches);
