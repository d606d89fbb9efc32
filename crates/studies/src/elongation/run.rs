//! Running an elongation test: the chosen solver on the setup, a curve point at every
//! recorded instant, and the caller's hook (frames, progress, Ctrl-C) at each.

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};

use musclefem_core::solver::{Analysis, Observer, Outcome, Problem, Record, Snapshot, run};
use musclefem_io::output::{FrameInstants, FrameSchedule};

use super::curve::{Curve, CurvePoint, CurveScale};
use super::setup::{Setup, explicit_settings, implicit_settings, setup};
use super::{ElongationTest, Solver};

/// What a caller sees of a running test: each curve point with the solver's snapshot, and
/// the progress (time [s]). Either may stop the run.
pub trait ElongationWatcher {
    fn point(&mut self, point: &CurvePoint, snapshot: &Snapshot) -> ControlFlow<()>;
    /// The solver's history row of a recorded instant (before its `point`).
    fn history_row(&mut self, _record: &Record) {}
    fn progress(&mut self, _time: f64) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// A watcher that watches nothing.
pub struct Unwatched;

impl ElongationWatcher for Unwatched {
    fn point(&mut self, _point: &CurvePoint, _snapshot: &Snapshot) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// The result of one test.
pub struct ElongationRun {
    pub curve: Curve,
    /// Elements and nodes of the specimen mesh.
    pub elements: usize,
    pub nodes: usize,
    /// Wall time of the solve (setup excluded).
    pub solve_time: Duration,
    /// Steps (explicit) or increments (implicit).
    pub steps: usize,
    /// Implicit only: Newton iterations over all increments.
    pub newton_iterations: Option<usize>,
    /// Explicit only: largest kinetic / internal energy over the pull, and the mass added
    /// by mass scaling over the physical mass.
    pub kinetic_to_internal: Option<f64>,
    pub added_mass_fraction: Option<f64>,
}

/// Run `test`, showing `watcher` every curve point.
pub fn run_elongation(
    test: &ElongationTest,
    watcher: &mut dyn ElongationWatcher,
) -> Result<ElongationRun> {
    run_on(test, &setup(test)?, watcher)
}

/// Run `test` on its already built `setup` (see [`setup`]).
pub fn run_on(
    test: &ElongationTest,
    setup: &Setup,
    watcher: &mut dyn ElongationWatcher,
) -> Result<ElongationRun> {
    let mut adapter = Adapter {
        frames: FrameInstants::new(FrameSchedule::new(
            test.checkpoint_interval(),
            test.mode.duration(),
            &[],
        )),
        scale: setup.curve_scale(test),
        curve: Curve::default(),
        watcher,
        kinetic_to_internal: 0.0,
        hold: test.mode.hold(),
    };
    let started = Instant::now();
    let mesh = &setup.specimen.mesh;
    let context = || {
        format!(
            "{} {} elongation of the {} ({} elements)",
            test.solver.name(),
            test.mode.name(),
            test.shape.name(),
            mesh.element_count()
        )
    };
    let analysis = match test.solver {
        Solver::Implicit => Analysis::Implicit(implicit_settings(test)),
        Solver::Explicit => Analysis::Explicit(explicit_settings(test)),
    };
    let problem = Problem {
        mesh,
        parts: &setup.parts,
        loads: &setup.loads,
        interactions: &mut [],
    };
    let outcome = run(problem, &analysis, &mut adapter).with_context(context)?;
    let (steps, newton_iterations, kinetic_to_internal, added_mass_fraction) = match &outcome {
        Outcome::Implicit(result) => {
            let iterations = result.history.iter().map(|r| r.iterations).sum();
            (result.history.len(), Some(iterations), None, None)
        }
        Outcome::Explicit(result) => (
            result.steps,
            None,
            Some(adapter.kinetic_to_internal),
            Some(result.added_mass_fraction),
        ),
    };
    let mut curve = std::mem::take(&mut adapter.curve);
    adapter.scale.start_at_rest(&mut curve.points);
    Ok(ElongationRun {
        solve_time: started.elapsed(),
        elements: mesh.element_count(),
        nodes: mesh.node_count(),
        curve,
        steps,
        newton_iterations,
        kinetic_to_internal,
        added_mass_fraction,
    })
}

/// Turns the solvers' history rows into curve points.
struct Adapter<'w> {
    /// Where `musclefem elongate` would write frames and take checkpoints (see
    /// [`ElongationTest::frame_interval`]).
    frames: FrameInstants,
    scale: CurveScale,
    curve: Curve,
    watcher: &'w mut dyn ElongationWatcher,
    kinetic_to_internal: f64,
    hold: f64,
}

impl Adapter<'_> {
    fn add(&mut self, time: f64, force: f64, snapshot: &Snapshot) -> ControlFlow<()> {
        let point = self.scale.point(time, force);
        self.curve.points.push(point);
        self.watcher.point(&point, snapshot)
    }
}

impl Observer for Adapter<'_> {
    /// The implicit solver's initial state: the curve's first point (no force yet).
    fn start(&mut self, snapshot: &Snapshot) -> ControlFlow<()> {
        self.frames.reached(snapshot.time);
        self.add(0.0, 0.0, snapshot)
    }

    /// Asked after a recorded row: a checkpoint (dropped) where `musclefem elongate`
    /// takes one, for the same numbers.
    fn wants_checkpoint(&mut self) -> bool {
        self.frames.take_due()
    }

    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        self.frames.reached(snapshot.time);
        self.watcher.history_row(record);
        match record {
            Record::Explicit(row) => {
                if row.time > self.hold && row.internal_energy > 0.0 {
                    self.kinetic_to_internal = self
                        .kinetic_to_internal
                        .max(row.kinetic_energy / row.internal_energy);
                }
                self.add(row.time, row.reactions[0], snapshot)
            }
            // Implicit increments are few: every one is a progress report.
            Record::Implicit(row) => {
                self.add(row.time, row.reactions[0], snapshot)?;
                self.watcher.progress(row.time)
            }
        }
    }

    fn progress(&mut self, time: f64, steps: usize) -> ControlFlow<()> {
        if steps.is_multiple_of(500) {
            self.watcher.progress(time)
        } else {
            ControlFlow::Continue(())
        }
    }
}
