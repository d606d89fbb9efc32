//! Cohesive runs give the same results, bit for bit, on 1 and 3 rayon threads: bonds are
//! formed and evaluated in parallel, each on its own, and scattered in bond order. The
//! interface has 169 bonds, evaluated in blocks of 64, so 3 threads do split the work.

mod cohesive_common;

use cohesive_common::{BoxSpec, held, neo_hookean, ramped, two_boxes};
use musclefem_contact::{CohesiveInterface, CohesiveSettings, DeformableSurface, TangentialMode};
use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit_with};
use musclefem_core::solver::implicit::{ImplicitSettings, run_implicit_with};
use musclefem_core::solver::observer::NoObserver;
use musclefem_core::solver::{Interaction, InteractionReport, Loads, Part};
use nalgebra::Vector3;

fn mesh() -> Mesh {
    let spec = |z: f64| BoxSpec {
        size: [0.01, 0.01, 0.005],
        divisions: [12, 12, 1],
        origin: [0.0, 0.0, z],
    };
    two_boxes(&spec(0.0), &spec(0.005))
}

fn interface(mesh: &Mesh, tangential: TangentialMode) -> Vec<Box<dyn Interaction>> {
    let settings = CohesiveSettings {
        initiation_separation: 0.001,
        failure_separation: 0.002,
        tangential,
        ..CohesiveSettings::default()
    };
    let secondary = DeformableSurface::from_mesh_surface(mesh, "upper_z0").unwrap();
    let main = DeformableSurface::from_mesh_surface(mesh, "lower_z1").unwrap();
    let interface = CohesiveInterface::new("glue", &secondary, main, mesh, &settings).unwrap();
    assert_eq!(interface.bond_count(), 169);
    vec![Box::new(interface)]
}

fn parts() -> Vec<Part> {
    (0..2)
        .map(|block| Part {
            block,
            technology: Technology::Hex8Full,
            material: neo_hookean(2.6e8, 0.3),
            density: 1000.0,
        })
        .collect()
}

/// The top pulled up by 1.5 mm (into softening: δ_0 = 1 mm, δ_f = 2 mm) and sideways by
/// `slide` [m]; the lower block's bottom held, symmetry on y0.
fn loads(mesh: &Mesh, slide: f64) -> Loads {
    let top = mesh.node_set("upper_z1").unwrap().to_vec();
    Loads::from(vec![
        ramped(top.clone(), 2, 0.0015),
        ramped(top, 0, slide),
        held(mesh, "lower_z0", 0),
        held(mesh, "lower_z0", 1),
        held(mesh, "lower_z0", 2),
        held(mesh, "upper_y0", 1),
    ])
}

type Outcome = (Vec<Vector3<f64>>, Vec<Vec<InteractionReport>>);

fn implicit(tangential: TangentialMode) -> Outcome {
    let mesh = mesh();
    let result = run_implicit_with(
        &mesh,
        &parts(),
        &loads(&mesh, 0.001),
        &mut interface(&mesh, tangential),
        &ImplicitSettings::new(1.0, 9).with_cutting(),
        &mut NoObserver,
    )
    .unwrap();
    let reports = result.history.into_iter().map(|r| r.interactions).collect();
    (result.displacement, reports)
}

fn explicit(tangential: TangentialMode) -> Outcome {
    let mesh = mesh();
    let result = run_explicit_with(
        &mesh,
        &parts(),
        &loads(&mesh, 0.001),
        &mut interface(&mesh, tangential),
        &ExplicitSettings::new(2e-3),
        &mut NoObserver,
    )
    .unwrap();
    let reports = result.history.into_iter().map(|r| r.interactions).collect();
    (result.displacement, reports)
}

fn on_threads(threads: usize, run: impl Fn() -> Outcome + Send + Sync) -> Outcome {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(run)
}

fn assert_bitwise(one: &Outcome, three: &Outcome) {
    let bits = |u: &[Vector3<f64>]| -> Vec<u64> {
        u.iter()
            .flat_map(|v| v.iter().map(|x| x.to_bits()))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&one.0), bits(&three.0));
    assert_eq!(one.1, three.1);
}

#[test]
fn implicit_runs_are_bitwise_the_same_on_one_and_three_threads() {
    for mode in [
        TangentialMode::Elastic,
        TangentialMode::FreeSlide,
        TangentialMode::SmoothSlide,
    ] {
        let one = on_threads(1, || implicit(mode));
        let three = on_threads(3, || implicit(mode));
        // Past the peak σ_max A = 5 N: the runs went into the softening branch.
        let force = one.1.last().unwrap()[0].force.z.abs();
        assert!(force > 0.0 && force < 0.6 * 5.0, "{force}");
        assert_bitwise(&one, &three);
    }
}

#[test]
fn explicit_runs_are_bitwise_the_same_on_one_and_three_threads() {
    for mode in [TangentialMode::FreeSlide, TangentialMode::SmoothSlide] {
        let one = on_threads(1, || explicit(mode));
        let three = on_threads(3, || explicit(mode));
        assert!(one.1.last().unwrap()[0].active_points > 0);
        assert_bitwise(&one, &three);
    }
}
