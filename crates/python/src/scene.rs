//! `musclefem.Scene`: a scene file (docs/scene-format.md) checked, described and run.

use std::ops::ControlFlow;
use std::path::PathBuf;

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use musclefem_core::solver::{Observer, Record, Snapshot, SolverError};
use musclefem_io::output::run_directory::HISTORY_FILE;
use musclefem_io::output::{
    ExistingResults, FrameSchedule, HistoryColumns, HistoryWriter, RunLog, RunProgress, RunStart,
    RunWriter,
};
use musclefem_io::scene::{Model, PluginPolicy, Trust, load_scene_trusting};
use musclefem_materials::MaterialLibrary;

use crate::columns::column_dict;
use crate::python_error;

/// A scene file, read and checked at once (a bad file raises `MusclefemError` naming its
/// line and key). Material plugins load only with `allow_plugins`; files outside the
/// scene's folder are refused unless `allow_outside_paths` (as `musclefem run`).
#[pyclass(module = "musclefem", frozen)]
pub struct Scene {
    path: PathBuf,
    trust: Trust,
}

impl Scene {
    fn load(&self) -> anyhow::Result<Model> {
        Ok(load_scene_trusting(
            &self.path,
            &mut MaterialLibrary::with_builtins(),
            self.trust,
        )?)
    }
}

#[pymethods]
impl Scene {
    #[new]
    #[pyo3(signature = (path, allow_plugins = false, allow_outside_paths = false))]
    fn new(path: PathBuf, allow_plugins: bool, allow_outside_paths: bool) -> PyResult<Self> {
        let scene = Scene {
            path,
            trust: Trust {
                plugins: if allow_plugins {
                    PluginPolicy::Load
                } else {
                    PluginPolicy::Refuse
                },
                outside_paths: allow_outside_paths,
            },
        };
        scene.load().map_err(python_error)?;
        Ok(scene)
    }

    /// What `musclefem check` prints: parts, nodes and loads, interactions, analysis.
    fn describe(&self) -> PyResult<String> {
        Ok(self.load().map_err(python_error)?.describe())
    }

    /// Run the scene. Without `out`, in memory; with `out`, the run directory of
    /// `musclefem run` (frames, result.pvd, history.csv, checkpoints) is written there
    /// too (`force` replaces an earlier run, `resume` continues a stopped one). Returns
    /// the history: a dict of arrays, one per column of history.csv (time_s, reactions
    /// [N], energies [J], ...). The GIL is released while it runs; Ctrl-C stops it after
    /// the last complete frame (KeyboardInterrupt).
    #[pyo3(signature = (out = None, force = false, resume = false))]
    fn run<'py>(
        &self,
        py: Python<'py>,
        out: Option<PathBuf>,
        force: bool,
        resume: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let model = self.load().map_err(python_error)?;
        let scene_text = std::fs::read_to_string(&self.path).map_err(|e| {
            python_error(anyhow::anyhow!("cannot read {}: {e}", self.path.display()))
        })?;
        let columns = model.history_columns();
        let outcome = py.detach(|| match &out {
            None => run_in_memory(&model, &columns),
            Some(root) => run_into(&model, &scene_text, root, force, resume),
        });
        let (header, rows) = match outcome {
            Ok(table) => table,
            Err(RunFailure::Interrupted(time)) => {
                return Err(PyKeyboardInterrupt::new_err(format!(
                    "the run stopped at t = {time:e} s"
                )));
            }
            Err(RunFailure::Error(error)) => return Err(python_error(error)),
        };
        let names: Vec<String> = header.split(',').map(String::from).collect();
        column_dict(py, &names, &rows)
    }

    fn __repr__(&self) -> String {
        format!("Scene({:?})", self.path.display().to_string())
    }
}

/// Why a run returned no table.
enum RunFailure {
    /// Ctrl-C at this time [s].
    Interrupted(f64),
    Error(anyhow::Error),
}

impl From<anyhow::Error> for RunFailure {
    fn from(error: anyhow::Error) -> Self {
        RunFailure::Error(error)
    }
}

/// Why the solver stopped, as a [`RunFailure`].
fn solver_failure(error: SolverError) -> RunFailure {
    match error {
        SolverError::Interrupted { time } => RunFailure::Interrupted(time),
        error => RunFailure::Error(error.into()),
    }
}

/// Stops the run when Python has a signal pending (Ctrl-C).
struct Signals;

impl Signals {
    fn check(&self) -> ControlFlow<()> {
        if Python::attach(|py| py.check_signals()).is_err() {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

impl RunProgress for Signals {
    fn reached(&mut self, _time: f64) -> ControlFlow<()> {
        self.check()
    }
}

/// The history rows of a run kept in memory. It asks for a checkpoint wherever
/// `musclefem run` writes a frame, and drops it: a checkpoint makes the implicit solver
/// factorize afresh (see docs/checkpoint-restart.md), so the numbers are those of
/// `musclefem run` to the last digit.
struct InMemory<'a> {
    columns: &'a HistoryColumns,
    rows: Vec<Vec<f64>>,
    error: Option<anyhow::Error>,
    steps: usize,
    frames: FrameSchedule,
    frame_due: bool,
}

impl Observer for InMemory<'_> {
    fn start(&mut self, snapshot: &Snapshot) -> ControlFlow<()> {
        self.frames.due(snapshot.time);
        ControlFlow::Continue(())
    }

    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        match self
            .columns
            .record_row(record, std::path::Path::new("history"))
        {
            Ok(row) => self.rows.push(row),
            Err(e) => {
                self.error = Some(e.into());
                return ControlFlow::Break(());
            }
        }
        self.frame_due = self.frames.due(snapshot.time);
        Signals.check()
    }

    fn wants_checkpoint(&mut self) -> bool {
        std::mem::take(&mut self.frame_due)
    }

    fn progress(&mut self, _time: f64, _steps: usize) -> ControlFlow<()> {
        self.steps += 1;
        if self
            .steps
            .is_multiple_of(musclefem_io::output::run_writer::PROGRESS_STEPS)
        {
            Signals.check()
        } else {
            ControlFlow::Continue(())
        }
    }
}

fn run_in_memory(
    model: &Model,
    columns: &HistoryColumns,
) -> Result<(String, Vec<Vec<f64>>), RunFailure> {
    let mut observer = InMemory {
        columns,
        rows: Vec::new(),
        error: None,
        steps: 0,
        frames: FrameSchedule::new(model.frame_interval, model.analysis.end_time(), &[]),
        frame_due: false,
    };
    let outcome = model.run(&mut observer);
    if let Some(error) = observer.error {
        return Err(error.into());
    }
    outcome.map_err(solver_failure)?;
    Ok((columns.header(&model.analysis), observer.rows))
}

/// The run written into the run directory `root`, as `musclefem run` writes it.
fn run_into(
    model: &Model,
    scene_text: &str,
    root: &std::path::Path,
    force: bool,
    resume: bool,
) -> Result<(String, Vec<Vec<f64>>), RunFailure> {
    let start = match (resume, force) {
        (true, _) => RunStart::Resume,
        (false, true) => RunStart::Fresh(ExistingResults::Replace),
        (false, false) => RunStart::Fresh(ExistingResults::Refuse),
    };
    let history = HistoryWriter::for_analysis(
        &root.join(HISTORY_FILE),
        &model.history_columns(),
        &model.analysis,
    )
    .map_err(anyhow::Error::from)?;
    let frames = FrameSchedule::new(model.frame_interval, model.analysis.end_time(), &[]);
    let mut signals = Signals;
    let (mut writer, resumed) = RunWriter::open(
        root,
        start,
        &model.mesh,
        history,
        (frames, model.write_frames),
        model.fingerprint(scene_text, &model.analysis),
        &mut signals,
    )
    .map_err(anyhow::Error::from)?;
    writer
        .directory()
        .write_scene(scene_text)
        .map_err(anyhow::Error::from)?;
    // A log from the start, rewritten with how the run ended (as `musclefem run`'s).
    let settings = |end: &str| {
        RunLog::new(format!(
            "scene = (Python) musclefem.Scene\nsolver = {:?}\n{}end = {end}\n",
            model.analysis,
            resumed.as_ref().map_or(String::new(), |c| format!(
                "resumed = from the checkpoint at t = {:e} s\n",
                c.time
            ))
        ))
    };
    writer
        .directory()
        .write_run_log(&settings("running"))
        .map_err(anyhow::Error::from)?;
    let outcome = match &resumed {
        Some(checkpoint) => model.resume_with(&model.analysis, checkpoint, &mut writer),
        None => model.run(&mut writer),
    };
    let written = writer.finish().map_err(anyhow::Error::from)?;
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
        .write_run_log(&settings(&end.replace('\n', "; ")))
        .map_err(anyhow::Error::from)?;
    if let Some(error) = written.write_error {
        return Err(anyhow::Error::from(error).into());
    }
    if let Some(error) = written.fields_error {
        return Err(anyhow::Error::from(error).into());
    }
    outcome.map_err(solver_failure)?;
    written
        .directory
        .remove_checkpoint()
        .map_err(anyhow::Error::from)?;
    Ok((written.history_header, written.history_rows))
}
