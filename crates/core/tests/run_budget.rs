//! Runs that would never end, or end in one meaningless step, are refused before they
//! start, with the number that is wrong in the message.

use std::collections::BTreeMap;

use musclefem_core::element::Technology;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit};
use musclefem_core::solver::implicit::{ImplicitSettings, MAX_INCREMENTS, run_quasi_static};
use musclefem_core::solver::{Loads, Part, PrescribedDisplacement, SolverError};
use musclefem_materials::{Amplitude, MaterialLibrary};

fn cube() -> (musclefem_core::mesh::Mesh, Vec<Part>, Loads) {
    let mesh = box_of_hexes([0.01; 3], [1; 3]).unwrap();
    let parameters = BTreeMap::from([("mu".to_string(), 1e4), ("D".to_string(), 2e-5)]);
    let material = MaterialLibrary::with_builtins()
        .create("neo-hookean", &parameters)
        .unwrap();
    let parts = vec![Part {
        block: 0,
        technology: Technology::Hex8FBar,
        material,
        density: 1000.0,
    }];
    let pulled = PrescribedDisplacement {
        nodes: mesh.node_set("x1").unwrap().to_vec(),
        dof: 0,
        amplitude: Amplitude::ramp(1.0, 1e-3).unwrap(),
    };
    let held = PrescribedDisplacement {
        nodes: mesh.node_set("x0").unwrap().to_vec(),
        dof: 0,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    };
    (mesh, parts, Loads::from(vec![pulled, held]))
}

fn message(error: SolverError) -> String {
    error.to_string()
}

#[test]
fn an_implicit_run_of_more_increments_than_the_budget_is_refused() {
    let (mesh, parts, loads) = cube();
    let settings = ImplicitSettings::new(1.0, 1_000_000_000_000);
    let error = message(run_quasi_static(&mesh, &parts, &loads, &settings).unwrap_err());
    assert!(
        error.contains("1000000000000 increments") && error.contains(&MAX_INCREMENTS.to_string()),
        "{error}"
    );
}

#[test]
fn an_explicit_run_of_more_steps_than_the_budget_is_refused() {
    let (mesh, parts, loads) = cube();
    let error =
        message(run_explicit(&mesh, &parts, &loads, &ExplicitSettings::new(1e9)).unwrap_err());
    assert!(
        error.contains("would take about") && error.contains("steps"),
        "{error}"
    );
}

/// A mass-scaling target of 1e9 s ran one step and reported a reaction of 1.7e21 N; zero,
/// negative and non-finite targets are refused too.
#[test]
fn a_mass_scaling_target_that_leaves_fewer_than_ten_steps_is_refused() {
    let (mesh, parts, loads) = cube();
    for target in [1e9, 0.2, 0.0, -1.0, f64::NAN] {
        let mut settings = ExplicitSettings::new(1.0);
        settings.mass_scaling_time_step = Some(target);
        let error = message(run_explicit(&mesh, &parts, &loads, &settings).unwrap_err());
        assert!(
            error.contains("mass-scaling target step"),
            "{target}: {error}"
        );
    }
    let mut settings = ExplicitSettings::new(1.0);
    settings.mass_scaling_time_step = Some(0.1);
    settings.history_interval = 0.1;
    assert!(run_explicit(&mesh, &parts, &loads, &settings).is_ok());
}
