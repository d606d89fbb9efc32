//! A scene's model run into a run directory: the one loop behind `musclefem run`,
//! `musclefem elongate` and `musclefem knee` (which write their tests and squats as
//! scenes and run them here, the knee with its own observer beside the writer). Frames,
//! `result.pvd` (and the rigid bodies' `rigid.pvd`), `history.csv`, checkpoints, the
//! scene copy (with the files it names beside it) and `run.log` are written by
//! `musclefem_io::output::RunWriter`; a progress bar (or, without a terminal, a log line
//! every tenth of the run) follows the simulated time, and Ctrl-C stops the run after
//! its last complete frame.

use std::io::IsTerminal;
use std::ops::ControlFlow;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::Result;
use indicatif::ProgressBar;

use musclefem_core::solver::amg_cg::amg_cg_summary;
use musclefem_core::solver::{Checkpoint, Observer, Outcome, Record, Snapshot, SolverError};
use musclefem_io::OutputError;
use musclefem_io::output::run_directory::HISTORY_FILE;
use musclefem_io::output::{
    CHECKPOINT_FILE, FrameSchedule, HistoryWriter, RunDirectory, RunLog, RunProgress, RunStart,
    RunWriter, StudyRunWriter,
};
use musclefem_io::scene::Model;
use musclefem_io::write_atomically;

use crate::progress::{LINE_EVERY, progress_line, show_time, simulated_time_bar};

/// What a run into a directory needs besides the model.
pub struct DirectoryRun<'a> {
    /// The scene file the run log and messages name.
    pub scene: &'a Path,
    /// Its text (copied into the directory as `scene.toml`; part of the fingerprint a
    /// resumed run must match).
    pub scene_text: &'a str,
    /// Files the scene names, written beside its copy: (file name, text).
    pub beside: &'a [(&'a str, &'a str)],
    pub out: &'a Path,
    pub start: RunStart,
    /// Frame instants [s] besides those of the scene's `frame_interval` (the knee's
    /// table angles).
    pub frame_instants: &'a [f64],
    /// Lines at the top of `run.log` (each ending in a newline).
    pub log_header: String,
    /// Time spent reading and building the model (logged).
    pub setup_time: Duration,
    /// Whether a completed run keeps its last checkpoint, for the caller to remove (the
    /// knee keeps each squat's until the study is complete, so that `--resume` after a
    /// stop of the other squat finds both); otherwise it is removed.
    pub keep_checkpoint: bool,
    /// Set by Ctrl-C (or, for one of the knee's squats, by the other failing): the run
    /// stops after its last complete frame.
    pub interrupted: &'a AtomicBool,
    /// The bar to draw the run's progress on (one of several side by side); `None`: a
    /// bar of its own on a terminal, else a plain line every tenth of the run.
    pub bar: Option<ProgressBar>,
    /// An observer beside the writer (the knee's tables), its state in every checkpoint.
    pub companion: Option<&'a mut dyn RunCompanion>,
}

/// An observer that runs beside the run's writer: it sees every recorded instant after
/// the writer, and its state is stored with each checkpoint (and read back before a
/// resumed run goes on), so that a resumed run's companion has what it had.
pub trait RunCompanion: Observer {
    /// Its state at a checkpoint.
    fn save_state(&mut self) -> Vec<u8>;
    /// Go on from `state`, which [`Self::save_state`] wrote.
    fn restore_state(&mut self, state: &[u8]) -> Result<()>;
}

/// The writer and the companion as the solver's one observer: the writer decides when a
/// checkpoint is due and writes it with the companion's state.
struct Beside<'w, 'a> {
    writer: &'w mut RunWriter<'a>,
    companion: &'w mut dyn RunCompanion,
}

impl Observer for Beside<'_, '_> {
    fn start(&mut self, snapshot: &Snapshot) -> ControlFlow<()> {
        self.writer.start(snapshot)?;
        self.companion.start(snapshot)
    }

    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        self.writer.record(record, snapshot)?;
        self.companion.record(record, snapshot)
    }

    fn wants_checkpoint(&mut self) -> bool {
        self.writer.wants_checkpoint()
    }

    fn checkpoint(&mut self, checkpoint: Result<Checkpoint, SolverError>) -> ControlFlow<()> {
        let state = self.companion.save_state();
        self.writer.checkpoint_with_study(checkpoint, state)
    }

    fn progress(&mut self, time: f64, steps: usize) -> ControlFlow<()> {
        self.writer.progress(time, steps)?;
        self.companion.progress(time, steps)
    }
}

/// How a run into a directory went.
pub struct DirectoryReport {
    /// The solver's outcome: `Err(SolverError::Interrupted)` after Ctrl-C.
    pub outcome: Result<Outcome, SolverError>,
    pub directory: RunDirectory,
    /// Time of the checkpoint the run went on from.
    pub resumed_from: Option<f64>,
    pub solve_time: Duration,
    /// The last history row's time and reactions, for a summary line.
    pub last_row: String,
}

impl DirectoryReport {
    /// Steps (explicit) or increments (implicit) of a completed run, else 0.
    pub fn steps(&self) -> usize {
        self.outcome.as_ref().map_or(0, Outcome::steps)
    }
}

/// Run `model` into `job.out`. Writing errors (frames, history, log) are errors; how the
/// solver ended is in the report. A completed run's checkpoint is removed (unless
/// `job.keep_checkpoint`).
pub fn run_into_directory(model: &Model, job: DirectoryRun<'_>) -> Result<DirectoryReport> {
    let duration = model.analysis.end_time();
    let mut progress = Progress {
        model,
        log_lines: job.bar.is_none() && !std::io::stderr().is_terminal(),
        bar: job.bar.unwrap_or_else(|| progress_bar(duration)),
        next_log: 0.0,
        started: Instant::now(),
        interrupted: job.interrupted,
        last_row: String::new(),
    };
    let history = HistoryWriter::for_analysis(
        &job.out.join(HISTORY_FILE),
        &model.history_columns(),
        &model.analysis,
    )?;
    let frames = FrameSchedule::new(model.frame_interval, duration, job.frame_instants);
    let fingerprint = model.fingerprint(job.scene_text, &model.analysis);
    let (writer, resumed) = RunWriter::open(
        job.out,
        job.start,
        &model.mesh,
        history,
        (frames, model.write_frames),
        fingerprint,
        &mut progress,
    )
    .map_err(|e| match e {
        OutputError::Resume { .. } => anyhow::Error::from(e),
        e => anyhow::anyhow!("{e} (use --force to replace a previous run)"),
    })?;
    let mut writer = writer.with_rigid_bodies(model.rigid_body_frames());
    for (name, text) in job.beside {
        write_atomically(&job.out.join(name), text.as_bytes())?;
    }
    writer.directory().write_scene(job.scene_text)?;
    let mut companion = job.companion;
    if let (Some(_), Some(companion)) = (&resumed, companion.as_deref_mut()) {
        companion.restore_state(writer.resumed_study())?;
    }
    let resumed_from = resumed.as_ref().map(|c| c.time);
    let resumed_line = resumed_from.map_or(String::new(), |time| {
        format!("resumed = from the checkpoint at t = {time:e} s\n")
    });
    let head = format!(
        "{}scene = {}\nsolver = {:?}\n{resumed_line}",
        job.log_header,
        job.scene.display(),
        model.analysis
    );
    // A log from the start: a run killed before its end leaves one that says so.
    writer.directory().write_run_log(&RunLog::new(format!(
        "{head}end = running (a run that ended rewrites this line; this one was stopped \
         without being able to)\n"
    )))?;
    let solve_started = Instant::now();
    let outcome = {
        let mut beside;
        let observer: &mut dyn Observer = match companion {
            Some(companion) => {
                beside = Beside {
                    writer: &mut writer,
                    companion,
                };
                &mut beside
            }
            None => &mut writer,
        };
        match &resumed {
            Some(checkpoint) => model.resume_with(&model.analysis, checkpoint, observer),
            None => model.run(observer),
        }
    };
    let solve_time = solve_started.elapsed();
    let written = writer.finish()?;
    progress.bar.finish_and_clear();
    let directory = written.directory;
    let steps = outcome.as_ref().map_or(0, Outcome::steps);
    // How the run ended, for whoever reads the directory later.
    let end = match (&outcome, &written.write_error, &written.fields_error) {
        (_, Some(error), _) => format!("failed writing the outputs: {error}"),
        (_, _, Some(error)) => format!("failed evaluating a frame's element fields: {error}"),
        (Ok(_), None, None) => format!("complete ({steps} steps)"),
        (Err(SolverError::Interrupted { time }), ..) => {
            format!("interrupted at t = {time:e} s (Ctrl-C)")
        }
        (Err(error), ..) => format!("failed: {error}"),
    };
    let checkpoints = match &written.no_checkpoints {
        Some(why) => format!("checkpoints = none: {}\n", why.replace('\n', "; ")),
        None => format!("checkpoints = at every frame, in {CHECKPOINT_FILE} until the end\n"),
    };
    let linear = match &outcome {
        Ok(Outcome::Implicit(result)) => amg_cg_summary(&result.linear_solves)
            .map_or(String::new(), |line| format!("linear_solver = {line}\n")),
        _ => String::new(),
    };
    let log = RunLog::new(format!(
        "{head}{checkpoints}{linear}end = {}\n",
        end.replace('\n', "; ")
    ))
    .timing("setup", job.setup_time)
    .timing("solve", solve_time);
    directory.write_run_log(&log)?;
    if let Some(error) = written.write_error {
        return Err(
            anyhow::Error::from(error).context("writing the outputs failed; the run was stopped")
        );
    }
    if let Some(error) = written.fields_error {
        anyhow::bail!(
            "{}: evaluating the element fields of a frame failed: {error}\n(the frames and \
             history up to there are in {})",
            job.scene.display(),
            job.out.display()
        );
    }
    if outcome.is_ok() && !job.keep_checkpoint {
        directory.remove_checkpoint()?;
    }
    Ok(DirectoryReport {
        outcome,
        directory,
        resumed_from,
        solve_time,
        last_row: progress.last_row,
    })
}

/// A bar over simulated time on a terminal; hidden otherwise (plain log lines are printed
/// instead, see [`Progress`]).
fn progress_bar(duration: f64) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    simulated_time_bar(duration)
}

/// Drives the bar (or plain log lines), keeps the last row's reactions for the summary,
/// honours Ctrl-C.
struct Progress<'a> {
    model: &'a Model,
    bar: ProgressBar,
    /// Without a terminal: a plain log line on stderr every tenth of the duration and at
    /// the end.
    log_lines: bool,
    next_log: f64,
    started: Instant,
    interrupted: &'a AtomicBool,
    last_row: String,
}

impl RunProgress for Progress<'_> {
    fn recorded(&mut self, record: &Record) -> ControlFlow<()> {
        let newton = match record {
            Record::Explicit(_) => String::new(),
            Record::Implicit(row) => format!(" ({} Newton iterations)", row.iterations),
        };
        let reactions: Vec<String> = (self.model.displacement_names.iter())
            .zip(record.reactions())
            .map(|(name, r)| format!("{name} {r:.6e} N"))
            .collect();
        self.last_row = format!(
            "t = {:.6e} s{newton}: {}",
            record.time(),
            reactions.join(", ")
        );
        show_time(&self.bar, record.time(), self.model.analysis.end_time());
        ControlFlow::Continue(())
    }

    fn reached(&mut self, time: f64) -> ControlFlow<()> {
        let duration = self.model.analysis.end_time();
        show_time(&self.bar, time, duration);
        let at_end = time >= duration * (1.0 - 1e-12);
        if self.log_lines && (time >= self.next_log || at_end) {
            eprintln!("{}", progress_line(time, duration, self.started.elapsed()));
            self.next_log = time + LINE_EVERY * duration;
        }
        if self.interrupted.load(Ordering::SeqCst) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}
