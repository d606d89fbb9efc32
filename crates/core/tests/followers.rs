//! A pose follower that listens to the run (`PoseFollower::observe`): the solvers tell it
//! every recorded instant with its ties' reactions before the observer sees the instant,
//! and keep its state in their checkpoints, so that a resumed run follows the same poses
//! as an uninterrupted one.

use std::collections::BTreeMap;
use std::ops::ControlFlow;
use std::sync::{Arc, Mutex};

use nalgebra::{Isometry3, Vector3};

use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::explicit::ExplicitSettings;
use musclefem_core::solver::implicit::ImplicitSettings;
use musclefem_core::solver::{
    Analysis, Checkpoint, CheckpointReader, CheckpointWriter, Loads, Observer, Outcome, Part,
    PoseFollower, PrescribedDisplacement, Problem, Record, RigidMotion, RigidReaction, RigidTie,
    Snapshot, SolverError, resume, run,
};
use musclefem_materials::{Amplitude, MaterialLibrary};

/// A grip that moves 0.1 mm along x for every instant it has observed, and remembers
/// each instant's (time, reaction along x of tie 0).
#[derive(Debug, Default)]
struct StepwiseGrip {
    observed: Mutex<Vec<(f64, f64)>>,
}

impl PoseFollower for StepwiseGrip {
    fn isometry_at(&self, _time: f64) -> Isometry3<f64> {
        let steps = self.observed.lock().unwrap().len() as f64;
        Isometry3::translation(1e-4 * steps, 0.0, 0.0)
    }
    fn reference_point(&self) -> Vector3<f64> {
        Vector3::zeros()
    }
    fn observe(&self, time: f64, tie_reactions: &[RigidReaction]) {
        self.observed
            .lock()
            .unwrap()
            .push((time, tie_reactions[0].force.x));
    }
    fn save_state(&self, out: &mut CheckpointWriter) {
        let observed = self.observed.lock().unwrap();
        let flat: Vec<f64> = observed.iter().flat_map(|&(t, f)| [t, f]).collect();
        out.f64s(&flat);
    }
    fn restore_state(&self, input: &mut CheckpointReader) -> Result<(), SolverError> {
        let flat = input.f64s()?;
        *self.observed.lock().unwrap() = flat.chunks_exact(2).map(|p| (p[0], p[1])).collect();
        Ok(())
    }
}

/// A 10 mm cube of neo-Hookean rubber on symmetry planes, its face x1 tied to `grip`.
fn problem_parts(grip: Arc<StepwiseGrip>) -> (Mesh, Vec<Part>, Loads) {
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
    let held = |set: &str, dof: usize| PrescribedDisplacement {
        nodes: mesh.node_set(set).unwrap().to_vec(),
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    };
    let mut loads = Loads::from(vec![held("x0", 0), held("y0", 1), held("z0", 2)]);
    loads.rigid_ties.push(RigidTie {
        name: "grip".to_string(),
        nodes: mesh.node_set("x1").unwrap().to_vec(),
        motion: RigidMotion::followed(grip),
    });
    (mesh, parts, loads)
}

/// Checks that the grip has seen each instant before it; asks for a checkpoint at the
/// `checkpoint_at`-th instant and keeps it.
struct Watcher {
    grip: Arc<StepwiseGrip>,
    instants: usize,
    checkpoint_at: usize,
    checkpoint: Option<Checkpoint>,
    last_displacement: Vec<Vector3<f64>>,
}

impl Observer for Watcher {
    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        let observed = self.grip.observed.lock().unwrap();
        let &(time, force) = observed.last().expect("observed before the observer");
        assert_eq!(time, record.time());
        assert_eq!(force, record.rigid_reactions()[0].force.x);
        self.instants += 1;
        self.last_displacement = snapshot.displacement.to_vec();
        ControlFlow::Continue(())
    }
    fn wants_checkpoint(&mut self) -> bool {
        self.instants == self.checkpoint_at
    }
    fn checkpoint(&mut self, checkpoint: Result<Checkpoint, SolverError>) -> ControlFlow<()> {
        self.checkpoint = Some(checkpoint.unwrap());
        ControlFlow::Continue(())
    }
}

fn watcher(grip: &Arc<StepwiseGrip>, checkpoint_at: usize) -> Watcher {
    Watcher {
        grip: grip.clone(),
        instants: 0,
        checkpoint_at,
        checkpoint: None,
        last_displacement: Vec::new(),
    }
}

/// The uninterrupted run, and the run resumed from its `checkpoint_at`-th instant with a
/// fresh grip: the same observations and the same final displacements, bit for bit.
fn resumes_alike(analysis: &Analysis, checkpoint_at: usize) {
    let grip = Arc::new(StepwiseGrip::default());
    let (mesh, parts, loads) = problem_parts(grip.clone());
    let mut whole = watcher(&grip, checkpoint_at);
    let problem = Problem {
        mesh: &mesh,
        parts: &parts,
        loads: &loads,
        interactions: &mut [],
    };
    let outcome = run(problem, analysis, &mut whole).unwrap();
    let observed = grip.observed.lock().unwrap().clone();
    let rows = match &outcome {
        Outcome::Implicit(result) => result.history.len(),
        Outcome::Explicit(result) => result.history.len(),
    };
    // Every recorded row was observed once (the explicit run's closing row included).
    assert_eq!(observed.len(), rows);
    assert!(observed.len() > checkpoint_at + 2);
    // The grip moved, so the face carries a growing tension.
    assert!(observed.last().unwrap().1.abs() > 1e-3, "{observed:?}");

    let fresh = Arc::new(StepwiseGrip::default());
    let (mesh, parts, loads) = problem_parts(fresh.clone());
    let mut resumed = watcher(&fresh, usize::MAX);
    let problem = Problem {
        mesh: &mesh,
        parts: &parts,
        loads: &loads,
        interactions: &mut [],
    };
    resume(
        problem,
        analysis,
        whole.checkpoint.as_ref().unwrap(),
        &mut resumed,
    )
    .unwrap();
    assert_eq!(*fresh.observed.lock().unwrap(), observed);
    assert_eq!(resumed.last_displacement, whole.last_displacement);
}

#[test]
fn an_implicit_run_tells_its_followers_and_resumes_them() {
    resumes_alike(&Analysis::Implicit(ImplicitSettings::new(1.0, 8)), 3);
}

#[test]
fn an_explicit_run_tells_its_followers_and_resumes_them() {
    let mut settings = ExplicitSettings::new(2e-3);
    settings.history_interval = 2e-4;
    resumes_alike(&Analysis::Explicit(settings), 4);
}
