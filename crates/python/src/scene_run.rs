//! A scene's run from Python: in memory, or into the run directory of `musclefem run`,
//! keeping the history and (unless asked not to) the frames as they go.

use std::ops::ControlFlow;
use std::path::Path;

use musclefem_core::mesh::Mesh;
use musclefem_core::solver::{Checkpoint, Observer, Record, Snapshot, SolverError};
use musclefem_io::output::run_directory::HISTORY_FILE;
use musclefem_io::output::run_writer::PROGRESS_STEPS;
use musclefem_io::output::{
    FrameInstants, FrameSchedule, HistoryColumns, HistoryWriter, RunLog, RunStart, RunWriter,
};
use musclefem_io::scene::Model;

use crate::frames::CapturedFrame;
use crate::progress::Progress;

/// What a run hands back.
pub(crate) struct RunOutput {
    /// The history's columns, as in `history.csv`.
    pub header: String,
    pub rows: Vec<Vec<f64>>,
    /// The frames computed in this call (a resumed run's earlier frames are only in its
    /// directory).
    pub frames: Vec<CapturedFrame>,
    /// Solver steps or increments.
    pub steps: usize,
}

/// Why a run returned no output.
pub(crate) enum RunFailure {
    /// Stopped on request (Ctrl-C) at this time [s].
    Interrupted(f64),
    Error(anyhow::Error),
}

impl From<anyhow::Error> for RunFailure {
    fn from(error: anyhow::Error) -> Self {
        RunFailure::Error(error)
    }
}

impl From<musclefem_io::OutputError> for RunFailure {
    fn from(error: musclefem_io::OutputError) -> Self {
        RunFailure::Error(error.into())
    }
}

/// Why the solver stopped, as a [`RunFailure`].
fn solver_failure(error: SolverError) -> RunFailure {
    match error {
        SolverError::Interrupted { time } => RunFailure::Interrupted(time),
        error => RunFailure::Error(error.into()),
    }
}

/// The run kept in memory. It asks for a checkpoint wherever `musclefem run` writes a
/// frame, and drops it: a checkpoint makes the implicit solver factorize afresh (see
/// docs/checkpoint-restart.md), so the numbers are those of `musclefem run` to the last
/// digit.
struct InMemory<'a> {
    model: &'a Model,
    columns: &'a HistoryColumns,
    rows: Vec<Vec<f64>>,
    frames: Vec<CapturedFrame>,
    keep_frames: bool,
    error: Option<anyhow::Error>,
    frames_at: FrameInstants,
    progress: Progress<'a>,
}

impl InMemory<'_> {
    /// The instant of `snapshot`: its frame kept if one is due, the progress shown.
    fn instant(&mut self, snapshot: &Snapshot) -> ControlFlow<()> {
        let frame_due = self.frames_at.reached(snapshot.time);
        if frame_due && self.keep_frames && self.model.write_frames {
            match CapturedFrame::capture(&self.model.mesh, snapshot) {
                Ok(frame) => self.frames.push(frame),
                Err(e) => {
                    self.error =
                        Some(anyhow::Error::from(e).context("evaluating a frame's element fields"));
                    return ControlFlow::Break(());
                }
            }
        }
        self.progress.at(snapshot.time)
    }
}

impl Observer for InMemory<'_> {
    fn start(&mut self, snapshot: &Snapshot) -> ControlFlow<()> {
        self.instant(snapshot)
    }

    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        match self
            .columns
            .record_row(record, snapshot, Path::new(HISTORY_FILE))
        {
            Ok(row) => self.rows.push(row),
            Err(e) => {
                self.error = Some(e.into());
                return ControlFlow::Break(());
            }
        }
        self.instant(snapshot)
    }

    fn wants_checkpoint(&mut self) -> bool {
        self.frames_at.take_due()
    }

    fn progress(&mut self, time: f64, steps: usize) -> ControlFlow<()> {
        if steps.is_multiple_of(PROGRESS_STEPS) {
            self.progress.at(time)
        } else {
            ControlFlow::Continue(())
        }
    }
}

/// Run `model` in memory, showing `progress`.
pub(crate) fn run_in_memory(
    model: &Model,
    progress: Progress<'_>,
    keep_frames: bool,
) -> Result<RunOutput, RunFailure> {
    let columns = model.history_columns();
    let mut observer = InMemory {
        model,
        columns: &columns,
        rows: Vec::new(),
        frames: Vec::new(),
        keep_frames,
        error: None,
        frames_at: FrameInstants::new(FrameSchedule::new(
            model.frame_interval,
            model.analysis.end_time(),
            &[],
        )),
        progress,
    };
    let outcome = model.run(&mut observer);
    if let Some(error) = observer.error {
        return Err(error.into());
    }
    let outcome = outcome.map_err(solver_failure)?;
    Ok(RunOutput {
        header: columns.header(&model.analysis),
        rows: observer.rows,
        frames: observer.frames,
        steps: outcome.steps(),
    })
}

/// [`RunWriter`] with a copy of every frame it writes kept in memory.
struct Keeping<'a> {
    writer: RunWriter<'a>,
    mesh: &'a Mesh,
    frames: Vec<CapturedFrame>,
    keep_frames: bool,
    error: Option<SolverError>,
}

impl Keeping<'_> {
    /// After the writer saw `snapshot`: keep its frame if the writer wrote one.
    fn keep(&mut self, written_before: usize, snapshot: &Snapshot) -> ControlFlow<()> {
        if self.keep_frames && self.writer.directory().frames().len() > written_before {
            match CapturedFrame::capture(self.mesh, snapshot) {
                Ok(frame) => self.frames.push(frame),
                Err(e) => {
                    self.error = Some(e);
                    return ControlFlow::Break(());
                }
            }
        }
        ControlFlow::Continue(())
    }
}

impl Observer for Keeping<'_> {
    fn start(&mut self, snapshot: &Snapshot) -> ControlFlow<()> {
        let before = self.writer.directory().frames().len();
        let flow = self.writer.start(snapshot);
        self.keep(before, snapshot)?;
        flow
    }

    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        let before = self.writer.directory().frames().len();
        let flow = self.writer.record(record, snapshot);
        self.keep(before, snapshot)?;
        flow
    }

    fn wants_checkpoint(&mut self) -> bool {
        self.writer.wants_checkpoint()
    }

    fn checkpoint(&mut self, checkpoint: Result<Checkpoint, SolverError>) -> ControlFlow<()> {
        self.writer.checkpoint(checkpoint)
    }

    fn progress(&mut self, time: f64, steps: usize) -> ControlFlow<()> {
        self.writer.progress(time, steps)
    }
}

/// The run written into the run directory `root` as `musclefem run` writes it (scene
/// `name`, text `scene_text`), showing `progress`.
pub(crate) fn run_into(
    model: &Model,
    (name, scene_text): (&str, &str),
    root: &Path,
    start: RunStart,
    mut progress: Progress<'_>,
    keep_frames: bool,
) -> Result<RunOutput, RunFailure> {
    let history = HistoryWriter::for_analysis(
        &root.join(HISTORY_FILE),
        &model.history_columns(),
        &model.analysis,
    )?;
    let frames = FrameSchedule::new(model.frame_interval, model.analysis.end_time(), &[]);
    let (writer, resumed) = RunWriter::open(
        root,
        start,
        &model.mesh,
        history,
        (frames, model.write_frames),
        model.fingerprint(scene_text, &model.analysis),
        &mut progress,
    )?;
    let writer = writer.with_rigid_bodies(model.rigid_body_frames());
    writer.directory().write_scene(scene_text)?;
    // A log from the start, rewritten with how the run ended (as `musclefem run`'s).
    let settings = |end: &str| {
        RunLog::new(format!(
            "scene = {name} (Python: musclefem.Scene)\nsolver = {:?}\n{}end = {end}\n",
            model.analysis,
            resumed.as_ref().map_or(String::new(), |c| format!(
                "resumed = from the checkpoint at t = {:e} s\n",
                c.time
            ))
        ))
    };
    writer.directory().write_run_log(&settings("running"))?;
    let mut keeping = Keeping {
        writer,
        mesh: &model.mesh,
        frames: Vec::new(),
        keep_frames,
        error: None,
    };
    let outcome = match &resumed {
        Some(checkpoint) => model.resume_with(&model.analysis, checkpoint, &mut keeping),
        None => model.run(&mut keeping),
    };
    let Keeping {
        writer,
        frames,
        error: keep_error,
        ..
    } = keeping;
    let written = writer.finish()?;
    let end = match (&outcome, &written.write_error, &written.fields_error) {
        (_, Some(error), _) => format!("failed writing the outputs: {error}"),
        (_, _, Some(error)) => format!("failed evaluating a frame's element fields: {error}"),
        (Ok(outcome), None, None) => format!("complete ({} steps)", outcome.steps()),
        (Err(SolverError::Interrupted { time }), ..) => {
            format!("interrupted at t = {time:e} s (KeyboardInterrupt)")
        }
        (Err(error), ..) => format!("failed: {error}"),
    };
    written
        .directory
        .write_run_log(&settings(&end.replace('\n', "; ")))?;
    if let Some(error) = written.write_error {
        return Err(error.into());
    }
    if let Some(error) = written.fields_error.or(keep_error) {
        return Err(anyhow::Error::from(error)
            .context("evaluating a frame's element fields")
            .into());
    }
    let outcome = outcome.map_err(solver_failure)?;
    written.directory.remove_checkpoint()?;
    Ok(RunOutput {
        header: written.history_header,
        rows: written.history_rows,
        frames,
        steps: outcome.steps(),
    })
}
