//! A node that belongs to no element (no mass, no stiffness), such as the patella's end of
//! tendon strands, is allowed in both solvers when every component of it is prescribed:
//! it follows its motion and leaves the rest of the model as it would be without it. One
//! held in only some components is refused, naming it.

use std::collections::BTreeMap;
use std::sync::Arc;

use nalgebra::Vector3;

use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit};
use musclefem_core::solver::implicit::{ImplicitSettings, run_quasi_static};
use musclefem_core::solver::{Loads, Part, PrescribedDisplacement, RigidMotion, RigidTie};
use musclefem_materials::{Amplitude, MaterialLibrary};

const SIDE: f64 = 0.01;

fn parts() -> Vec<Part> {
    let params = BTreeMap::from([("mu".to_string(), 1e4), ("D".to_string(), 2e-5)]);
    let material = MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap();
    vec![Part {
        block: 0,
        technology: Technology::Hex8Full,
        material: Arc::clone(&material),
        density: 1000.0,
    }]
}

/// A cube of 2 × 2 × 2 hexes, with or without an extra node beside it (the last node).
fn cube(with_extra_node: bool) -> Mesh {
    let mut mesh = box_of_hexes([SIDE; 3], [2; 3]).unwrap();
    if with_extra_node {
        mesh.nodes
            .push(Vector3::new(0.5 * SIDE, 0.5 * SIDE, 3.0 * SIDE));
    }
    mesh
}

/// x0 held, x1 pulled 1 mm along x over `end_time`; the extra node (if any) carried by a
/// rigid tie moving it along x and z.
fn loads(mesh: &Mesh, end_time: f64, extra_node: Option<u32>) -> Loads {
    let component = |set: &str, dof: usize, amplitude: Amplitude| PrescribedDisplacement {
        nodes: mesh.node_set(set).unwrap().to_vec(),
        dof,
        amplitude,
    };
    let hold = || Amplitude::new(vec![(0.0, 0.0)]).unwrap();
    let mut displacements: Vec<PrescribedDisplacement> =
        (0..3).map(|dof| component("x0", dof, hold())).collect();
    displacements.push(component("x1", 0, Amplitude::ramp(end_time, 1e-3).unwrap()));
    let rigid_ties = extra_node
        .map(|node| RigidTie {
            name: "carrier".to_string(),
            nodes: vec![node],
            motion: carrier(end_time),
        })
        .into_iter()
        .collect();
    Loads {
        displacements,
        rigid_ties,
        ..Loads::default()
    }
}

fn carrier(end_time: f64) -> RigidMotion {
    RigidMotion {
        translation: [
            Some(Amplitude::ramp(end_time, 2e-3).unwrap()),
            None,
            Some(Amplitude::ramp(end_time, -1e-3).unwrap()),
        ],
        ..RigidMotion::default()
    }
}

/// The extra node's displacement is its motion's, its tie feels nothing, and the cube's
/// nodes move as without it, to `round_off` of the largest displacement.
fn check(without: &[Vector3<f64>], with: &[Vector3<f64>], tie_force: Vector3<f64>, round_off: f64) {
    let extra = without.len();
    assert_eq!(with.len(), extra + 1);
    let largest = without.iter().map(|u| u.norm()).fold(0.0, f64::max);
    for (n, (a, b)) in without.iter().zip(with).enumerate() {
        assert!(
            (a - b).norm() <= round_off * largest,
            "node {n}: {a:?} against {b:?}"
        );
    }
    let expected = Vector3::new(2e-3, 0.0, -1e-3);
    assert!((with[extra] - expected).norm() < 1e-15, "{:?}", with[extra]);
    assert_eq!(tie_force, Vector3::zeros());
}

#[test]
fn implicit_a_node_in_no_element_held_in_every_component_follows_its_motion() {
    let end_time = 1.0;
    let settings = ImplicitSettings::new(end_time, 4);
    let plain = cube(false);
    let without = run_quasi_static(&plain, &parts(), &loads(&plain, end_time, None), &settings)
        .expect("the cube converges");
    let mesh = cube(true);
    let extra = Some(plain.node_count() as u32);
    let with = run_quasi_static(&mesh, &parts(), &loads(&mesh, end_time, extra), &settings)
        .expect("the cube with a carried node converges");
    let tie = with.history.last().unwrap().rigid_reactions[0];
    check(
        &without.displacement,
        &with.displacement,
        tie.force,
        end_time,
    );
}

#[test]
fn explicit_a_node_in_no_element_held_in_every_component_follows_its_motion() {
    let end_time = 0.02;
    let settings = ExplicitSettings::new(end_time);
    let plain = cube(false);
    let without = run_explicit(&plain, &parts(), &loads(&plain, end_time, None), &settings)
        .expect("the cube runs");
    let mesh = cube(true);
    let extra = Some(plain.node_count() as u32);
    let with = run_explicit(&mesh, &parts(), &loads(&mesh, end_time, extra), &settings)
        .expect("the cube with a carried node runs");
    assert_eq!(with.steps, without.steps);
    let tie = with.history.last().unwrap().rigid_reactions[0];
    check(
        &without.displacement,
        &with.displacement,
        tie.force,
        end_time,
    );
}

#[test]
fn a_node_in_no_element_held_in_only_some_components_is_refused_by_both_solvers() {
    let mesh = cube(true);
    let extra = mesh.node_count() as u32 - 1;
    let mut loads = loads(&mesh, 1.0, None);
    loads.displacements.push(PrescribedDisplacement {
        nodes: vec![extra],
        dof: 0,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    });
    let explicit = run_explicit(&mesh, &parts(), &loads, &ExplicitSettings::new(0.01))
        .unwrap_err()
        .to_string();
    assert!(
        explicit.contains(&format!(
            "node {extra} belongs to no element of any part and is not held in every component"
        )),
        "{explicit}"
    );
    let implicit = run_quasi_static(&mesh, &parts(), &loads, &ImplicitSettings::new(1.0, 1))
        .unwrap_err()
        .to_string();
    assert!(
        implicit.contains(&format!(
            "node {extra} belongs to no element of any part and is not held"
        )),
        "{implicit}"
    );
}
