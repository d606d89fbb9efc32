//! Observers see every history row with the displacements of its instant, and can stop a
//! run cleanly.

use std::collections::BTreeMap;
use std::ops::ControlFlow;

use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit, run_explicit_observed};
use musclefem_core::solver::implicit::{ImplicitSettings, run_implicit_observed, run_quasi_static};
use musclefem_core::solver::observer::{Observer, Record, Snapshot};
use musclefem_core::solver::{Loads, Part, PrescribedDisplacement, SolverError};
use musclefem_materials::{Amplitude, MaterialLibrary};

fn setup() -> (Mesh, Vec<Part>, Loads) {
    let mesh = box_of_hexes([0.01; 3], [2; 3]).unwrap();
    let params = BTreeMap::from([("mu".to_string(), 1e4), ("D".to_string(), 2e-5)]);
    let material = MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap();
    let parts = vec![Part {
        block: 0,
        technology: Technology::Hex8Full,
        material,
        density: 1000.0,
    }];
    let held = |set: &str, dof: usize, amplitude: Amplitude| PrescribedDisplacement {
        nodes: mesh.node_set(set).unwrap().to_vec(),
        dof,
        amplitude,
    };
    let zero = || Amplitude::new(vec![(0.0, 0.0)]).unwrap();
    let loads = Loads::from(vec![
        held("x1", 0, Amplitude::ramp(1.0, 0.002).unwrap()),
        held("x0", 0, zero()),
        held("y0", 1, zero()),
        held("z0", 2, zero()),
    ]);
    (mesh, parts, loads)
}

/// Keeps (time, largest displacement) of each row; stops after `stop_after` rows.
struct Recorder {
    seen: Vec<(f64, f64)>,
    stop_after: usize,
}

impl Observer for Recorder {
    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        let largest = snapshot
            .displacement
            .iter()
            .map(|u| u.amax())
            .fold(0.0, f64::max);
        self.seen.push((record.time(), largest));
        if self.seen.len() >= self.stop_after {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

#[test]
fn the_explicit_observer_sees_every_row_and_can_stop_the_run() {
    let (mesh, parts, loads) = setup();
    let settings = ExplicitSettings::new(0.1);
    let whole = run_explicit(&mesh, &parts, &loads, &settings).unwrap();
    let mut all = Recorder {
        seen: Vec::new(),
        stop_after: usize::MAX,
    };
    run_explicit_observed(&mesh, &parts, &loads, &settings, &mut all).unwrap();
    let times: Vec<f64> = whole.history.iter().map(|r| r.time).collect();
    assert_eq!(all.seen.iter().map(|s| s.0).collect::<Vec<_>>(), times);
    let last = whole
        .displacement
        .iter()
        .map(|u| u.amax())
        .fold(0.0, f64::max);
    assert_eq!(all.seen.last().unwrap().1, last);

    let mut stopping = Recorder {
        seen: Vec::new(),
        stop_after: 3,
    };
    let error = run_explicit_observed(&mesh, &parts, &loads, &settings, &mut stopping).unwrap_err();
    match error {
        SolverError::Interrupted { time } => assert_eq!(time, times[2]),
        other => panic!("{other}"),
    }
    assert_eq!(stopping.seen.len(), 3);
}

#[test]
fn the_implicit_observer_sees_every_step_and_can_stop_the_run() {
    let (mesh, parts, loads) = setup();
    let settings = ImplicitSettings::new(1.0, 5);
    let whole = run_quasi_static(&mesh, &parts, &loads, &settings).unwrap();
    let mut all = Recorder {
        seen: Vec::new(),
        stop_after: usize::MAX,
    };
    run_implicit_observed(&mesh, &parts, &loads, &settings, &mut all).unwrap();
    let times: Vec<f64> = whole.history.iter().map(|r| r.time).collect();
    assert_eq!(all.seen.iter().map(|s| s.0).collect::<Vec<_>>(), times);
    let mut stopping = Recorder {
        seen: Vec::new(),
        stop_after: 2,
    };
    let error = run_implicit_observed(&mesh, &parts, &loads, &settings, &mut stopping).unwrap_err();
    assert!(
        matches!(error, SolverError::Interrupted { time } if time == times[1]),
        "{error}"
    );
}
