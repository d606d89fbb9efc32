//! The explicit solver gives the same bits on 1 and 2 threads for every element
//! technology, on meshes large enough for many element chunks (64 elements each) and
//! several node ranges (2048 nodes each) of the parallel assembly and node loops.

use std::collections::BTreeMap;
use std::sync::Arc;

use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::{TetOrder, box_of_hexes, box_of_tets};
use musclefem_core::solver::bulk_viscosity::BulkViscosity;
use musclefem_core::solver::explicit::{ExplicitResult, ExplicitSettings, run_explicit};
use musclefem_core::solver::{Part, PrescribedDisplacement};
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

const SIDE: f64 = 0.01;

fn material(name: &str, params: &[(&str, f64)]) -> Arc<dyn Material> {
    let given: BTreeMap<String, f64> = params.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    MaterialLibrary::with_builtins()
        .create(name, &given)
        .unwrap()
}

/// x0 clamped along x, x1 pulled at 1 m/s: waves run through every element. With
/// `extras`, bulk viscosity and mass scaling (to a step well above the stable one) are on.
fn run(
    mesh: &Mesh,
    technology: Technology,
    material: Arc<dyn Material>,
    threads: usize,
    extras: bool,
) -> ExplicitResult {
    let prescribed = vec![
        PrescribedDisplacement {
            nodes: mesh.node_set("x0").unwrap().to_vec(),
            dof: 0,
            amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
        },
        PrescribedDisplacement {
            nodes: mesh.node_set("x1").unwrap().to_vec(),
            dof: 0,
            amplitude: Amplitude::ramp(1.0, 1.0).unwrap(),
        },
    ];
    let parts = vec![Part {
        block: 0,
        technology,
        material,
        density: 1060.0,
    }];
    let mut settings = ExplicitSettings::new(25.0 * 2e-7);
    settings.fixed_time_step = Some(2e-7);
    settings.history_interval = 5e-7;
    if extras {
        settings.bulk_viscosity = Some(BulkViscosity::default());
        settings.mass_scaling_time_step = Some(1e-5);
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| run_explicit(mesh, &parts, &prescribed.into(), &settings).unwrap())
}

fn same_on_one_and_two_threads(mesh: &Mesh, technology: Technology, material: Arc<dyn Material>) {
    same_bits(mesh, technology, material, false);
}

fn same_bits(mesh: &Mesh, technology: Technology, material: Arc<dyn Material>, extras: bool) {
    assert!(mesh.node_count() > 2 * 2048, "{} nodes", mesh.node_count());
    assert!(
        mesh.element_count() > 10 * 64,
        "{} elements",
        mesh.element_count()
    );
    let one = run(mesh, technology, material.clone(), 1, extras);
    let two = run(mesh, technology, material, 2, extras);
    if extras {
        assert!(one.added_mass_fraction > 0.0);
        assert!(one.history.last().unwrap().viscous_energy != 0.0);
    }
    assert_eq!(one.steps, 25);
    let moved = one.displacement.iter().filter(|u| u.x != 0.0).count();
    assert!(
        moved > mesh.node_count() / 4,
        "{moved} nodes moved: {technology:?}"
    );
    assert!(one.history.last().unwrap().internal_energy > 0.0);
    assert_eq!(one.displacement, two.displacement, "{technology:?}");
    assert_eq!(one.history, two.history, "{technology:?}");
}

#[test]
fn every_hex_technology_gives_the_same_bits_on_any_number_of_threads() {
    let mesh = box_of_hexes([SIDE; 3], [16, 16, 16]).unwrap();
    let neo_hookean = material("neo-hookean", &[]);
    same_on_one_and_two_threads(
        &mesh,
        Technology::hex8_one_point(11_370.0),
        neo_hookean.clone(),
    );
    same_on_one_and_two_threads(&mesh, Technology::Hex8Full, neo_hookean.clone());
    // With bulk viscosity the one-point hex8 takes the general kernel.
    same_bits(
        &mesh,
        Technology::hex8_one_point(11_370.0),
        neo_hookean,
        true,
    );
    same_on_one_and_two_threads(
        &mesh,
        Technology::Hex8FBar,
        material("hill", &[("n2", 1.0)]),
    );
}

#[test]
fn every_tet_technology_gives_the_same_bits_on_any_number_of_threads() {
    let neo_hookean = material("neo-hookean", &[]);
    let tet4 = box_of_tets([SIDE; 3], [16, 16, 16], TetOrder::Linear).unwrap();
    same_on_one_and_two_threads(&tet4, Technology::Tet4, neo_hookean.clone());
    same_on_one_and_two_threads(&tet4, Technology::Tet4NodalAverage, neo_hookean.clone());
    let tet10 = box_of_tets([SIDE; 3], [8, 8, 8], TetOrder::Quadratic).unwrap();
    same_on_one_and_two_threads(&tet10, Technology::Tet10, neo_hookean);
}
