//! [`RunWriter`]: a solver run written into its run directory as it goes — the history
//! from the first row on, the frames on a [`FrameSchedule`] (with the rigid bodies of
//! [`RunWriter::with_rigid_bodies`] at their pose, `rigid.pvd`), a checkpoint after every
//! frame — and every recorded instant and step shown to a [`RunProgress`] (a progress
//! bar, Ctrl-C). A run started again with [`RunStart::Resume`] continues from the
//! directory's checkpoint (see [`super::checkpoint`]). A study that observes the run
//! beside the writer (the knee) passes the solver's calls on to it as a
//! [`StudyRunWriter`] and stores its own state in every checkpoint.

use std::ops::ControlFlow;
use std::path::Path;

use musclefem_core::mesh::Mesh;
use musclefem_core::solver::{Checkpoint, Observer, Record, Snapshot, SolverError};

use super::checkpoint::{CHECKPOINT_FILE, RunCheckpoint};
use super::frame_schedule::{FrameInstants, FrameSchedule};
use super::history::HistoryWriter;
use super::rigid_frames::RigidBodyFrame;
use super::run_directory::{ExistingResults, RunDirectory};
use crate::OutputError;

/// The environment variable that makes a run abort (as if killed: no handler, no clean-up)
/// right after writing checkpoint number K (from 1), for the kill-and-resume tests: a
/// deterministic stand-in for a kill at a chosen frame.
pub const ABORT_AFTER_CHECKPOINT: &str = "MUSCLEFEM_ABORT_AFTER_CHECKPOINT";

/// Steps between two [`RunProgress::reached`] calls between recorded instants.
pub const PROGRESS_STEPS: usize = 200;

/// What a caller sees of a run while [`RunWriter`] writes it; either call may stop the run
/// (the solver then returns `SolverError::Interrupted`).
pub trait RunProgress {
    /// A history row was recorded (and written).
    fn recorded(&mut self, _record: &Record) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }

    /// Simulated time `time` [s] reached: at every recorded instant, and every
    /// [`PROGRESS_STEPS`] steps between.
    fn reached(&mut self, _time: f64) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// How [`RunWriter::open`] starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunStart {
    /// A new run; what to do with an earlier run's results in the directory.
    Fresh(ExistingResults),
    /// Continue the stopped run in the directory from its checkpoint.
    Resume,
}

/// How a run's outputs ended (see [`RunWriter::finish`]).
#[derive(Debug)]
pub struct WrittenRun {
    pub directory: RunDirectory,
    /// Writing an output failed (the run was stopped there).
    pub write_error: Option<OutputError>,
    /// Evaluating a frame's element fields failed (the run was stopped there).
    pub fields_error: Option<SolverError>,
    /// Why no checkpoint could be taken, if none could.
    pub no_checkpoints: Option<String>,
    /// `history.csv` as written: its header and every row (those before a checkpoint a
    /// resumed run started from included).
    pub history_header: String,
    pub history_rows: Vec<Vec<f64>>,
}

/// Writes a run's directory as the run goes (see the module documentation).
pub struct RunWriter<'a> {
    mesh: &'a Mesh,
    /// Written at their pose with every frame (none: no `rigid.pvd`).
    rigid_bodies: Vec<RigidBodyFrame<'a>>,
    directory: RunDirectory,
    history: HistoryWriter,
    write_frames: bool,
    /// The frames' instants: a checkpoint follows a framed row.
    frames: FrameInstants,
    /// Of the model, written into every checkpoint: a checkpoint resumes only its model.
    fingerprint: u64,
    no_checkpoints: Option<String>,
    /// [`ABORT_AFTER_CHECKPOINT`].
    abort_after_checkpoint: Option<usize>,
    /// The study's state in the checkpoint a resumed run started from (empty otherwise).
    resumed_study: Vec<u8>,
    write_error: Option<OutputError>,
    fields_error: Option<SolverError>,
    progress: &'a mut dyn RunProgress,
}

impl<'a> RunWriter<'a> {
    /// Open the run directory `root` for a run of `mesh` whose history is `history` (its
    /// path must be the directory's `history.csv`), framed on `frames` (when
    /// `write_frames`), and whose model has `fingerprint`. A resumed run gets back the
    /// solver's checkpoint to continue from, with the directory cut back to it.
    pub fn open(
        root: &Path,
        start: RunStart,
        mesh: &'a Mesh,
        history: HistoryWriter,
        (frames, write_frames): (FrameSchedule, bool),
        fingerprint: u64,
        progress: &'a mut dyn RunProgress,
    ) -> Result<(Self, Option<Checkpoint>), OutputError> {
        let (directory, history, frames, solver, resumed_study) = match start {
            RunStart::Fresh(existing) => (
                RunDirectory::create(root, existing)?,
                history,
                frames,
                None,
                Vec::new(),
            ),
            RunStart::Resume => {
                let checkpoint = read_checkpoint(root, fingerprint)?;
                if checkpoint.history_header != history.header() {
                    return Err(OutputError::Resume {
                        path: root.join(CHECKPOINT_FILE),
                        message: "its history has other columns than this run's".into(),
                    });
                }
                let directory = RunDirectory::resume(root, checkpoint.frames)?;
                // The frame schedule is a function of the recorded times: replay them.
                let mut frames = frames;
                for row in &checkpoint.history_rows {
                    frames.due(row[0]);
                }
                let history = history.with_rows(checkpoint.history_rows)?;
                (
                    directory,
                    history,
                    frames,
                    Some(checkpoint.solver),
                    checkpoint.study,
                )
            }
        };
        let writer = RunWriter {
            mesh,
            rigid_bodies: Vec::new(),
            directory,
            history,
            write_frames,
            frames: FrameInstants::new(frames),
            fingerprint,
            no_checkpoints: None,
            abort_after_checkpoint: std::env::var(ABORT_AFTER_CHECKPOINT)
                .ok()
                .and_then(|k| k.parse().ok()),
            resumed_study,
            write_error: None,
            fields_error: None,
            progress,
        };
        Ok((writer, solver))
    }

    /// The writer with `bodies` written at their pose at every frame, as a second series
    /// `rigid.pvd` (see [`super::rigid_frames`]).
    pub fn with_rigid_bodies(mut self, bodies: Vec<RigidBodyFrame<'a>>) -> Self {
        self.rigid_bodies = bodies;
        self
    }

    /// The run directory.
    pub fn directory(&self) -> &RunDirectory {
        &self.directory
    }

    /// The study's state stored in the checkpoint this run resumed from (empty for a
    /// fresh run, or one whose checkpoint held none).
    pub fn resumed_study(&self) -> &[u8] {
        &self.resumed_study
    }

    /// Write the history a last time and hand back the directory with how the writing
    /// went (a complete run's checkpoint is the caller's to remove, once it has said so).
    pub fn finish(self) -> Result<WrittenRun, OutputError> {
        let history_header = self.history.header().to_string();
        let history_rows = self.history.rows().to_vec();
        self.history.finish()?;
        Ok(WrittenRun {
            directory: self.directory,
            write_error: self.write_error,
            fields_error: self.fields_error,
            no_checkpoints: self.no_checkpoints,
            history_header,
            history_rows,
        })
    }

    /// The frame of `snapshot`, with its element fields, if one is due.
    fn frame(&mut self, snapshot: &Snapshot) -> ControlFlow<()> {
        let frame_due = self.frames.reached(snapshot.time);
        if self.write_frames && frame_due {
            let parts = match snapshot.element_fields() {
                Ok(parts) => parts,
                Err(e) => {
                    self.fields_error = Some(e);
                    return ControlFlow::Break(());
                }
            };
            let written = self
                .directory
                .write_state_frame(
                    self.mesh,
                    snapshot.time,
                    snapshot.displacement,
                    &parts,
                    &snapshot.nodal_fields(),
                )
                .and_then(|_| self.directory.write_rigid_frame(&self.rigid_bodies));
            if let Err(e) = written {
                self.write_error = Some(e);
                return ControlFlow::Break(());
            }
        }
        self.progress.reached(snapshot.time)
    }
}

impl Observer for RunWriter<'_> {
    /// The implicit solver's initial state: the first frame.
    fn start(&mut self, snapshot: &Snapshot) -> ControlFlow<()> {
        self.frame(snapshot)
    }

    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        if let Err(e) = self.history.push_record(record, snapshot) {
            self.write_error = Some(e);
            return ControlFlow::Break(());
        }
        if self.progress.recorded(record).is_break() {
            return ControlFlow::Break(());
        }
        self.frame(snapshot)
    }

    fn wants_checkpoint(&mut self) -> bool {
        self.no_checkpoints.is_none() && self.frames.take_due()
    }

    /// Written after every frame: the state and the outputs up to it.
    fn checkpoint(&mut self, checkpoint: Result<Checkpoint, SolverError>) -> ControlFlow<()> {
        self.checkpoint_with_study(checkpoint, Vec::new())
    }

    /// Every [`PROGRESS_STEPS`] steps (a step of a small explicit model takes
    /// microseconds).
    fn progress(&mut self, time: f64, steps: usize) -> ControlFlow<()> {
        if steps.is_multiple_of(PROGRESS_STEPS) {
            self.progress.reached(time)
        } else {
            ControlFlow::Continue(())
        }
    }
}

/// A run's writer as a study that observes the run beside it sees it: every call of the
/// solver is passed on to it, and a checkpoint carries the study's own state (read back
/// with [`RunWriter::resumed_study`]), so that a resumed study goes on with what it had.
pub trait StudyRunWriter: Observer {
    /// Write the checkpoint of the solver's `checkpoint` with the study's state `study`.
    fn checkpoint_with_study(
        &mut self,
        checkpoint: Result<Checkpoint, SolverError>,
        study: Vec<u8>,
    ) -> ControlFlow<()>;
}

impl StudyRunWriter for RunWriter<'_> {
    fn checkpoint_with_study(
        &mut self,
        checkpoint: Result<Checkpoint, SolverError>,
        study: Vec<u8>,
    ) -> ControlFlow<()> {
        let solver = match checkpoint {
            Ok(solver) => solver,
            Err(why) => {
                eprintln!("warning: the run cannot be checkpointed: {why}");
                self.no_checkpoints = Some(why.to_string());
                return ControlFlow::Continue(());
            }
        };
        let file = RunCheckpoint {
            fingerprint: self.fingerprint,
            history_header: self.history.header().to_string(),
            history_rows: self.history.rows().to_vec(),
            frames: self.directory.frames().to_vec(),
            solver,
            study,
        };
        if let Err(e) = file.write(&self.directory.checkpoint_path()) {
            self.write_error = Some(e);
            return ControlFlow::Break(());
        }
        if let Some(k) = &mut self.abort_after_checkpoint {
            *k = k.saturating_sub(1);
            if *k == 0 {
                std::process::abort();
            }
        }
        ControlFlow::Continue(())
    }
}

/// The checkpoint in the run directory `root`, if it belongs to the model of
/// `fingerprint`.
fn read_checkpoint(root: &Path, fingerprint: u64) -> Result<RunCheckpoint, OutputError> {
    let path = root.join(CHECKPOINT_FILE);
    if !path.exists() {
        return Err(OutputError::Resume {
            path,
            message: "no checkpoint to resume from (the run there completed, or stopped \
                      before its first frame); start again without --resume, with --force"
                .into(),
        });
    }
    let checkpoint = RunCheckpoint::read(&path)?;
    if checkpoint.fingerprint != fingerprint {
        return Err(OutputError::Resume {
            path,
            message: "the checkpoint was written by a run of another scene, mesh or solver \
                      setting; resume with the same ones, or start again with --force"
                .into(),
        });
    }
    Ok(checkpoint)
}
