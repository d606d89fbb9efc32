//! What one squat of the knee study writes as it goes (frames, history, vm95 samples)
//! and its progress bar.

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};

use musclefem_core::solver::Record;
use musclefem_core::solver::element_fields::PartFields;
use musclefem_core::solver::observer::Snapshot;
use musclefem_io::output::{FrameSchedule, HistoryColumns, HistoryWriter, RunDirectory};

use crate::elongation::Solver;
use crate::knee::simulation::{Activation, SquatStart, SquatWatcher, StressSample};

/// Frames, history and vm95 samples of one run, and the progress bar.
pub(super) struct Outputs<'a> {
    pub(super) directory: &'a mut RunDirectory,
    /// The muscles' mesh (given at the start of the run).
    pub(super) mesh: Option<musclefem_core::mesh::Mesh>,
    pub(super) history: Option<HistoryWriter>,
    pub(super) vm95: Vec<StressSample>,
    /// Frames every `--frame-interval`, at the table's angles (30°, 45°, 60°, 90° down
    /// and up) and at the end.
    pub(super) frames: FrameSchedule,
    pub(super) error: Option<anyhow::Error>,
    pub(super) bar: &'a ProgressBar,
    /// Set when the other run failed: this one stops too, and notes it in `stopped`.
    pub(super) stop: &'a AtomicBool,
    pub(super) stopped: bool,
}

impl Outputs<'_> {
    fn fail(&mut self, error: impl Into<anyhow::Error>) -> ControlFlow<()> {
        self.error = Some(error.into());
        ControlFlow::Break(())
    }
}

impl SquatWatcher for Outputs<'_> {
    fn start(&mut self, start: &SquatStart) -> Result<()> {
        let columns = HistoryColumns::new(Vec::new(), start.rigid_ties.clone())
            .with_interactions(start.interactions.clone());
        self.history = Some(match start.solver {
            Solver::Implicit => self.directory.implicit_history(&columns)?,
            Solver::Explicit => self.directory.explicit_history(&columns)?,
        });
        self.mesh = Some(start.mesh.clone());
        Ok(())
    }

    fn recorded(
        &mut self,
        sample: &StressSample,
        snapshot: &Snapshot,
        fields: &[PartFields],
    ) -> ControlFlow<()> {
        self.vm95.push(sample.clone());
        if !self.frames.due(sample.time) {
            return ControlFlow::Continue(());
        }
        let Some(mesh) = &self.mesh else {
            return ControlFlow::Continue(());
        };
        match self.directory.write_state_frame(
            mesh,
            snapshot.time,
            snapshot.displacement,
            fields,
            &[],
        ) {
            Ok(_) => ControlFlow::Continue(()),
            Err(e) => self.fail(e),
        }
    }

    fn progress(&mut self, time: f64) -> ControlFlow<()> {
        self.bar.set_position((1e3 * time) as u64);
        if self.stop.load(Ordering::Relaxed) {
            self.stopped = true;
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }

    fn history_row(&mut self, record: &Record) {
        if let Some(history) = &mut self.history
            && let Err(e) = history.push_record(record)
        {
            self.error = Some(e.into());
        }
    }
}

/// The bar of one squat of `duration` [s], in simulated milliseconds.
pub(super) fn progress_bar(duration: f64, activation: Activation) -> ProgressBar {
    let bar = ProgressBar::new((1e3 * duration) as u64);
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{:<7} {{bar:40}} {{pos}} / {{len}} ms of squat [{{elapsed_precise}}, ETA {{eta}}]",
            activation.name()
        ))
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}
