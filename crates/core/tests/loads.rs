//! Nodal forces and rigid ties in both solvers, each against an independent reference: the
//! material-point driver (uniaxial stress), Newton's second law for a free body, and the
//! rigid motion itself (a body carried by rigid ties at both ends must move rigidly).

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::sync::Arc;

use nalgebra::{Unit, Vector3};

use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit};
use musclefem_core::solver::implicit::{ImplicitSettings, run_quasi_static};
use musclefem_core::solver::{
    Loads, NodalForce, Part, PrescribedDisplacement, RigidMotion, RigidRotation, RigidTie,
};
use musclefem_materials::driver::{StretchHistory, run_uniaxial_stress};
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

const SIDE: f64 = 0.01;
const DENSITY: f64 = 1000.0;

/// Compressible neo-Hookean, μ = 10 kPa, K = 2/D = 100 kPa.
fn neo_hookean() -> Arc<dyn Material> {
    let params = BTreeMap::from([("mu".to_string(), 1e4), ("D".to_string(), 2e-5)]);
    MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap()
}

fn parts() -> Vec<Part> {
    vec![Part {
        block: 0,
        technology: Technology::Hex8Full,
        material: neo_hookean(),
        density: DENSITY,
    }]
}

fn held(mesh: &Mesh, set: &str, dof: usize) -> PrescribedDisplacement {
    PrescribedDisplacement {
        nodes: mesh.node_set(set).unwrap().to_vec(),
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    }
}

fn reference_positions(mesh: &Mesh) -> Vec<Vector3<f64>> {
    (0..mesh.nodes.len())
        .map(|i| mesh.nodes.position(i))
        .collect()
}

/// A uniform traction on the x1 face of a 2 × 2 × 2 cube as consistent nodal forces
/// (corner ¼ · ¼, edge ½ · ¼, centre 1 · ¼ of the face force), symmetry planes on x0, y0,
/// z0: the stretch reached is the one at which the material-point driver's uniaxial
/// engineering stress equals the traction.
#[test]
fn a_traction_by_nodal_forces_stretches_the_cube_as_the_material_point_driver_says() {
    let stretch = 1.4;
    let history = StretchHistory::parse(&format!("0:1,1:{stretch}")).unwrap();
    let driver = run_uniaxial_stress(neo_hookean().as_ref(), &history, 0.01).unwrap();
    let total_force = driver.last().unwrap().engineering_stress * SIDE * SIDE;

    let mesh = box_of_hexes([SIDE; 3], [2; 3]).unwrap();
    let face = mesh.node_set("x1").unwrap();
    let on_edge = |x: f64| x.abs() < 1e-12 || (x - SIDE).abs() < 1e-12;
    let mut by_share: BTreeMap<usize, Vec<u32>> = BTreeMap::new();
    for &n in face {
        let p = mesh.nodes.position(n as usize);
        let edges = usize::from(on_edge(p.y)) + usize::from(on_edge(p.z));
        by_share.entry(edges).or_default().push(n);
    }
    // Elements touching a node of the face: 4 (centre), 2 (edge), 1 (corner).
    let forces = by_share
        .into_iter()
        .map(|(edges, nodes)| {
            let elements = [4.0, 2.0, 1.0][edges];
            NodalForce {
                nodes,
                dof: 0,
                amplitude: Amplitude::ramp(1.0, total_force * elements / 16.0).unwrap(),
            }
        })
        .collect();
    let loads = Loads {
        displacements: vec![
            held(&mesh, "x0", 0),
            held(&mesh, "y0", 1),
            held(&mesh, "z0", 2),
        ],
        forces,
        rigid_ties: vec![],
    };
    let result = run_quasi_static(&mesh, &parts(), &loads, &ImplicitSettings::new(1.0, 8))
        .expect("the force-driven stretch converges");
    for &n in face {
        let u = result.displacement[n as usize].x;
        let error = (u / SIDE - (stretch - 1.0)).abs();
        assert!(
            error < 1e-6,
            "node {n}: stretch {} instead of {stretch}",
            1.0 + u / SIDE
        );
    }
    // The x0 face carries the whole traction.
    let reaction = result.history.last().unwrap().reactions[0];
    assert!(
        (reaction + total_force).abs() < 1e-9 * total_force,
        "reaction {reaction} N against the applied {total_force} N"
    );
}

/// A single free hex8 with the same force on each of its 8 nodes (equal lumped masses):
/// the central-difference scheme integrates a constant acceleration exactly, so
/// u(t) = ½ (F/m) t² to round-off and the external work equals the kinetic energy.
#[test]
fn a_free_body_under_nodal_forces_accelerates_as_newton_says() {
    let mesh = box_of_hexes([SIDE; 3], [1; 3]).unwrap();
    let force_per_node = 1e-3;
    let loads = Loads {
        forces: vec![NodalForce {
            nodes: (0..8).collect(),
            dof: 2,
            amplitude: Amplitude::new(vec![(0.0, force_per_node)]).unwrap(),
        }],
        ..Loads::default()
    };
    let end_time = 0.05;
    let result = run_explicit(&mesh, &parts(), &loads, &ExplicitSettings::new(end_time)).unwrap();
    let node_mass = DENSITY * SIDE.powi(3) / 8.0;
    let expected = 0.5 * force_per_node / node_mass * end_time * end_time;
    for (n, u) in result.displacement.iter().enumerate() {
        assert!(
            (u.z - expected).abs() < 1e-9 * expected && u.x.abs() + u.y.abs() < 1e-12 * expected,
            "node {n}: {u:?}, expected ({expected}) along z"
        );
    }
    let last = result.history.last().unwrap();
    assert!(
        (last.kinetic_energy - last.external_work).abs() < 1e-6 * last.external_work,
        "kinetic {} J against external work {} J",
        last.kinetic_energy,
        last.external_work
    );
    assert!(last.internal_energy.abs() < 1e-9 * last.external_work);
}

/// Both end faces tied to the same body, turned 60° about an oblique axis through the
/// cube's centre and translated: the whole cube must follow the rigid motion, stress free.
fn rigid_motion(end_time: f64) -> RigidTie {
    RigidTie {
        name: "carrier".into(),
        nodes: vec![],
        motion: RigidMotion {
            translation: [
                Some(Amplitude::ramp(end_time, 0.2 * SIDE).unwrap()),
                None,
                Some(Amplitude::ramp(end_time, -0.1 * SIDE).unwrap()),
            ],
            rotation: Some(RigidRotation {
                center: Vector3::repeat(SIDE / 2.0),
                axis: Unit::new_normalize(Vector3::new(1.0, 2.0, 2.0)),
                angle: Amplitude::ramp(end_time, PI / 3.0).unwrap(),
            }),
            follower: None,
        },
    }
}

fn tie_both_ends(mesh: &Mesh, end_time: f64) -> Loads {
    let mut ends = mesh.node_set("x0").unwrap().to_vec();
    ends.extend_from_slice(mesh.node_set("x1").unwrap());
    let mut tie = rigid_motion(end_time);
    tie.nodes = ends;
    Loads {
        rigid_ties: vec![tie],
        ..Loads::default()
    }
}

#[test]
fn implicit_a_body_carried_by_a_rigid_tie_moves_rigidly_and_stays_stress_free() {
    let mesh = box_of_hexes([SIDE; 3], [3; 3]).unwrap();
    let loads = tie_both_ends(&mesh, 1.0);
    let result = run_quasi_static(&mesh, &parts(), &loads, &ImplicitSettings::new(1.0, 6))
        .expect("a rigid motion converges");
    let tie = &loads.rigid_ties[0];
    for (n, (u, x)) in result
        .displacement
        .iter()
        .zip(reference_positions(&mesh))
        .enumerate()
    {
        let rigid = tie.motion.displacement_at(&x, 1.0);
        assert!(
            (u - rigid).norm() < 1e-9 * SIDE,
            "node {n}: {u:?} instead of {rigid:?}"
        );
    }
    let resultant = result.history.last().unwrap().rigid_reactions[0];
    // μ A = 1 N is the force scale of a strain of 1.
    assert!(resultant.force.norm() < 1e-7 && resultant.moment.norm() < 1e-7 * SIDE);
}

/// A bar tied at one end only, turned 60° and moved: starting each increment from the
/// body carried by the tie's own motion (`predictor_frame`) is the exact answer, so Newton
/// has nothing left to correct, while from the positions at t it needs iterations; both
/// end in the same rigid state.
#[test]
fn implicit_a_predictor_frame_carries_the_body_and_changes_only_the_start() {
    let mesh = box_of_hexes([2.0 * SIDE, SIDE, SIDE], [4, 2, 2]).unwrap();
    let mut tie = rigid_motion(1.0);
    tie.nodes = mesh.node_set("x0").unwrap().to_vec();
    let frame = tie.motion.clone();
    let loads = Loads {
        rigid_ties: vec![tie],
        ..Loads::default()
    };
    let plain = ImplicitSettings::new(1.0, 6);
    let mut carried = plain.clone();
    carried.predictor_frame = Some(Box::new(frame.clone()));
    let without = run_quasi_static(&mesh, &parts(), &loads, &plain).expect("converges");
    let with = run_quasi_static(&mesh, &parts(), &loads, &carried).expect("converges");
    for (n, ((a, b), x)) in without
        .displacement
        .iter()
        .zip(&with.displacement)
        .zip(reference_positions(&mesh))
        .enumerate()
    {
        let rigid = frame.displacement_at(&x, 1.0);
        assert!((a - rigid).norm() < 1e-9 * SIDE, "node {n}: {a:?}");
        assert!((b - rigid).norm() < 1e-9 * SIDE, "node {n}: {b:?}");
    }
    // Carried, every increment starts at its answer: one iteration confirms it (the
    // relative residual of a stress-free body is round-off over round-off).
    for step in &with.steps {
        assert!(step.iterations <= 1, "{step:?}");
    }
    let iterations = |r: &musclefem_core::solver::implicit::ImplicitResult| -> usize {
        r.steps.iter().map(|s| s.iterations).sum()
    };
    assert!(
        iterations(&with) < iterations(&without),
        "{} iterations carried against {}",
        iterations(&with),
        iterations(&without)
    );
}

#[test]
fn explicit_a_body_carried_by_a_slow_rigid_tie_moves_rigidly() {
    let mesh = box_of_hexes([SIDE; 3], [2; 3]).unwrap();
    // 0.5 s is ~100 periods of the cube's lowest mode: quasi-static.
    let end_time = 0.5;
    let loads = tie_both_ends(&mesh, end_time);
    let result = run_explicit(&mesh, &parts(), &loads, &ExplicitSettings::new(end_time))
        .expect("a slow rigid motion runs");
    let tie = &loads.rigid_ties[0];
    let positions = reference_positions(&mesh);
    let largest = positions
        .iter()
        .map(|x| tie.motion.displacement_at(x, end_time).norm())
        .fold(0.0, f64::max);
    for (n, (u, x)) in result.displacement.iter().zip(&positions).enumerate() {
        let rigid = tie.motion.displacement_at(x, end_time);
        assert!(
            (u - rigid).norm() < 1e-3 * largest,
            "node {n}: {u:?} instead of {rigid:?}"
        );
    }
}

/// Torsion: x0 held by one tie, x1 turned 20° about the bar's axis by another. The two
/// ties' resultants balance (zero net force, opposite moments about the axis), and the bar
/// deforms as when the same end motions are prescribed component by component.
#[test]
fn two_ties_twisting_a_bar_balance_and_match_prescribed_components() {
    let mesh = box_of_hexes([2.0 * SIDE, SIDE, SIDE], [4, 2, 2]).unwrap();
    let angle = 20f64.to_radians();
    let base = RigidTie::fixed("base", mesh.node_set("x0").unwrap().to_vec());
    let twist = RigidTie {
        name: "twist".into(),
        nodes: mesh.node_set("x1").unwrap().to_vec(),
        motion: RigidMotion {
            translation: [None, None, None],
            rotation: Some(RigidRotation {
                center: Vector3::new(2.0 * SIDE, SIDE / 2.0, SIDE / 2.0),
                axis: Vector3::x_axis(),
                angle: Amplitude::ramp(1.0, angle).unwrap(),
            }),
            follower: None,
        },
    };
    let settings = ImplicitSettings::new(1.0, 4);
    let by_ties = Loads {
        rigid_ties: vec![base, twist.clone()],
        ..Loads::default()
    };
    let result = run_quasi_static(&mesh, &parts(), &by_ties, &settings).unwrap();
    let last = result.history.last().unwrap();
    let (held_end, turned_end) = (last.rigid_reactions[0], last.rigid_reactions[1]);
    let torque = turned_end.moment.x;
    assert!(torque > 0.0, "the twisted end resists: {torque} N m");
    assert!((held_end.force + turned_end.force).norm() < 1e-9 * torque / SIDE);
    // Moments about points on the axis: the held end's is taken about the origin, so
    // compare their x components, which do not depend on the point along x.
    assert!(
        (held_end.moment.x + torque).abs() < 1e-9 * torque,
        "{} against {torque}",
        held_end.moment.x
    );

    // The same twist as per-node, per-component prescribed displacements.
    let reference = reference_positions(&mesh);
    let mut displacements = Vec::new();
    for k in 0..3 {
        displacements.push(held(&mesh, "x0", k));
    }
    for &n in mesh.node_set("x1").unwrap() {
        let x = reference[n as usize];
        for k in 0..3 {
            let knots = (0..=40)
                .map(|i| {
                    let t = i as f64 / 40.0;
                    (t, twist.motion.displacement_at(&x, t)[k])
                })
                .collect();
            displacements.push(PrescribedDisplacement {
                nodes: vec![n],
                dof: k,
                amplitude: Amplitude::new(knots).unwrap(),
            });
        }
    }
    let by_components =
        run_quasi_static(&mesh, &parts(), &displacements.into(), &settings).unwrap();
    // The knots sample the rotation exactly at the step ends, so the interior must end
    // where the ties put it.
    for (n, (a, b)) in result
        .displacement
        .iter()
        .zip(&by_components.displacement)
        .enumerate()
    {
        assert!(
            (a - b).norm() < 1e-9 * SIDE,
            "node {n}: ties {a:?}, components {b:?}"
        );
    }
}
