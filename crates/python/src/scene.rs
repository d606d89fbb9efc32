//! `musclefem.Scene`: a scene (docs/scene-format.md) from a file or a dict, checked,
//! described and run.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyType};

use musclefem_io::output::{ExistingResults, RunStart};
use musclefem_io::scene::{Model, PluginPolicy, Trust};
use musclefem_studies::scene_check::{check_report, refuse_free_body};

use crate::background::{run_watched, thread_pool};
use crate::progress::Progress;
use crate::python_error;
use crate::run_result::RunResult;
use crate::scene_run::{RunFailure, run_in_memory, run_into};
use crate::scene_source::SceneSource;
use crate::toml_text::toml_from_dict;

/// A scene, read and checked at once (a bad file raises `MusclefemError` naming its
/// line and key). Material plugins load only with `allow_plugins`; files outside the
/// scene's folder are refused unless `allow_outside_paths` (as `musclefem run`).
#[pyclass(module = "musclefem", frozen)]
pub struct Scene {
    source: SceneSource,
    trust: Trust,
}

impl Scene {
    fn checked(
        source: SceneSource,
        allow_plugins: bool,
        allow_outside_paths: bool,
    ) -> PyResult<Self> {
        let scene = Scene {
            source,
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

    fn load(&self) -> anyhow::Result<Model> {
        self.source.load(self.trust)
    }

    /// The scene's file and permissions, for the studies that read a scene file
    /// themselves (`fit(scene=...)`); an error for a scene from a dict.
    pub(crate) fn file_and_trust(&self) -> PyResult<(PathBuf, Trust)> {
        match self.source.dict {
            None => Ok((self.source.path.clone(), self.trust)),
            Some(_) => Err(crate::MusclefemError::new_err(
                "a scene from a dict has no file to fit: write scene.toml to a file and pass \
                 its path",
            )),
        }
    }
}

#[pymethods]
impl Scene {
    /// The scene file at `path` (as `Scene.from_toml`).
    #[new]
    #[pyo3(signature = (path, allow_plugins = false, allow_outside_paths = false))]
    fn new(path: PathBuf, allow_plugins: bool, allow_outside_paths: bool) -> PyResult<Self> {
        let source = SceneSource::file(&path).map_err(python_error)?;
        Scene::checked(source, allow_plugins, allow_outside_paths)
    }

    /// The scene file (TOML) at `path`.
    #[classmethod]
    #[pyo3(signature = (path, allow_plugins = false, allow_outside_paths = false))]
    fn from_toml(
        _cls: &Bound<'_, PyType>,
        path: PathBuf,
        allow_plugins: bool,
        allow_outside_paths: bool,
    ) -> PyResult<Self> {
        Scene::new(path, allow_plugins, allow_outside_paths)
    }

    /// The scene `scene`, a dict with the tables and keys of a scene file (nested dicts
    /// for tables, lists of dicts for arrays of tables such as `parts`). Files it names
    /// (meshes, fibers, surfaces) are relative to `base_dir` (default: the current
    /// directory). An error names the dict's key, e.g. `Scene.from_dict: materials[0].model:
    /// unknown material model ...`. `Scene.toml` is the text it was written as.
    #[classmethod]
    #[pyo3(signature = (scene, base_dir = None, allow_plugins = false, allow_outside_paths = false))]
    fn from_dict(
        _cls: &Bound<'_, PyType>,
        scene: &Bound<'_, PyDict>,
        base_dir: Option<PathBuf>,
        allow_plugins: bool,
        allow_outside_paths: bool,
    ) -> PyResult<Self> {
        let toml = toml_from_dict(scene)?;
        let base_dir = match base_dir {
            Some(dir) => dir,
            None => std::env::current_dir().map_err(|e| {
                python_error(anyhow::anyhow!("cannot read the current directory: {e}"))
            })?,
        };
        Scene::checked(
            SceneSource::dict(toml, &base_dir),
            allow_plugins,
            allow_outside_paths,
        )
    }

    /// The scene's TOML text (a dict's as written for the reader).
    #[getter]
    fn toml(&self) -> &str {
        &self.source.text
    }

    /// What the scene holds, as `musclefem check` describes it: parts, nodes and loads,
    /// interactions, analysis.
    fn describe(&self) -> PyResult<String> {
        Ok(self.load().map_err(python_error)?.describe())
    }

    /// What `musclefem check` prints: "NAME: ok", the materials whose plugin it did not
    /// load (it runs no foreign code), and the description; raises `MusclefemError` where
    /// `check` fails (e.g. a body no condition holds in a quasi-static step).
    fn check(&self) -> PyResult<String> {
        let trust = Trust {
            plugins: PluginPolicy::SkipForCheck,
            ..self.trust
        };
        let model = self.source.load(trust).map_err(python_error)?;
        check_report(&model, std::path::Path::new(&self.source.name())).map_err(python_error)
    }

    /// Run the scene; returns a `Result` (its history, frames and mesh as NumPy arrays).
    /// Without `out`, in memory; with `out`, the run directory of `musclefem run`
    /// (frames, result.pvd, history.csv, checkpoints) is written there too (`force`
    /// replaces an earlier run, `resume` continues a stopped one). `threads`: worker
    /// threads for this run (default one per core). `progress`: show the progress over
    /// simulated time (a tqdm bar if tqdm is installed, else the command line's bar on a
    /// terminal, else its lines on `sys.stderr`). `keep_frames=False` keeps no frames in
    /// memory (a large model's frames can take gigabytes). The GIL is released while it
    /// runs; Ctrl-C stops it after the last complete frame (KeyboardInterrupt).
    #[pyo3(signature = (
        out = None,
        force = false,
        resume = false,
        threads = None,
        progress = false,
        keep_frames = true
    ))]
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        py: Python<'_>,
        out: Option<PathBuf>,
        force: bool,
        resume: bool,
        threads: Option<usize>,
        progress: bool,
        keep_frames: bool,
    ) -> PyResult<RunResult> {
        let model = self.load().map_err(python_error)?;
        let name = self.source.name();
        refuse_free_body(&model, std::path::Path::new(&name)).map_err(python_error)?;
        let pool = thread_pool(py, threads)?;
        let stop = AtomicBool::new(false);
        let shown = Progress::new(py, progress, model.analysis.end_time(), &stop)?;
        let start = match (resume, force) {
            (true, _) => RunStart::Resume,
            (false, true) => RunStart::Fresh(ExistingResults::Replace),
            (false, false) => RunStart::Fresh(ExistingResults::Refuse),
        };
        let text = self.source.text.as_str();
        let (outcome, signal) = run_watched(py, pool.as_ref(), &stop, || match &out {
            None => run_in_memory(&model, shown, keep_frames),
            Some(root) => run_into(&model, (&name, text), root, start, shown, keep_frames),
        })?;
        match outcome {
            Ok(output) => {
                let analysis = format!("{:?}", model.analysis);
                let scene = (name, self.source.text.clone());
                RunResult::new(py, output, model.mesh, scene, analysis)
            }
            Err(RunFailure::Interrupted(time)) => Err(match signal {
                Some(error) if !error.is_instance_of::<PyKeyboardInterrupt>(py) => error,
                _ => PyKeyboardInterrupt::new_err(format!("the run stopped at t = {time:e} s")),
            }),
            Err(RunFailure::Error(error)) => Err(python_error(error)),
        }
    }

    fn __repr__(&self) -> String {
        match &self.source.dict {
            None => format!("Scene({:?})", self.source.path.display().to_string()),
            Some(_) => "Scene.from_dict(...)".to_string(),
        }
    }
}
