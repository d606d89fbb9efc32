//! `musclefem.Result`: what `Scene.run` returns — the history, the frames and the mesh
//! as NumPy arrays, and the run directory written again on request.

use std::path::PathBuf;

use pyo3::exceptions::{PyImportError, PyKeyError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyList};

use musclefem_core::mesh::Mesh;
use musclefem_io::output::{ExistingResults, HistoryWriter, RunDirectory, RunLog};

use crate::columns::column_dict;
use crate::frames::{CapturedFrame, frame_list, mesh_dict, write_frames};
use crate::python_error;
use crate::scene_run::RunOutput;

/// The result of `Scene.run`. `history` is a dict of arrays, one per column of
/// `history.csv` (`time_s` [s], `reaction_<part>.<set>.<c>_n` [N], energies [J], ...);
/// the result is also a read-only mapping of those columns (`result["time_s"]`), as
/// `run` returned before. `frames` is a list of dicts, one per frame `musclefem run`
/// writes (see `docs/python.md` for their arrays), `mesh` what they share.
#[pyclass(module = "musclefem", name = "Result", frozen, mapping)]
pub struct RunResult {
    history: Py<PyDict>,
    names: Vec<String>,
    header: String,
    rows: Vec<Vec<f64>>,
    frames: Vec<CapturedFrame>,
    frame_dicts: PyOnceLock<Py<PyList>>,
    mesh: Mesh,
    /// The scene's name and text, and its analysis as `run.log` gives it.
    scene: (String, String),
    analysis: String,
    steps: usize,
}

impl RunResult {
    /// The result of a run of the scene `scene` = (name, text) on `mesh` under `analysis`.
    pub(crate) fn new(
        py: Python<'_>,
        output: RunOutput,
        mesh: Mesh,
        scene: (String, String),
        analysis: String,
    ) -> PyResult<Self> {
        let names: Vec<String> = output.header.split(',').map(String::from).collect();
        let history = column_dict(py, &names, &output.rows)?.unbind();
        Ok(RunResult {
            history,
            names,
            header: output.header,
            rows: output.rows,
            frames: output.frames,
            frame_dicts: PyOnceLock::new(),
            mesh,
            scene,
            analysis,
            steps: output.steps,
        })
    }
}

#[pymethods]
impl RunResult {
    /// The history: a dict of arrays, one per column of history.csv, in its order.
    #[getter]
    fn history<'py>(&self, py: Python<'py>) -> Bound<'py, PyDict> {
        self.history.bind(py).clone()
    }

    /// The history as a pandas DataFrame (one column per history column). Needs pandas.
    fn history_frame<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let pandas = py.import("pandas").map_err(|e| {
            PyImportError::new_err(format!(
                "Result.history_frame() needs pandas ({e}); install it (pip install pandas) \
                 or use Result.history, a dict of NumPy arrays"
            ))
        })?;
        let columns = PyList::new(py, &self.names)?;
        let kwargs = PyDict::new(py);
        kwargs.set_item("columns", columns)?;
        pandas
            .getattr("DataFrame")?
            .call((self.history.bind(py),), Some(&kwargs))
    }

    /// The frames this call computed, one dict of arrays each (a new run's every frame;
    /// after `resume=True`, those from the checkpoint on).
    #[getter]
    fn frames<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = self.frame_dicts.get_or_try_init(py, || {
            frame_list(py, &self.frames, &self.mesh).map(Bound::unbind)
        })?;
        Ok(list.bind(py).clone())
    }

    /// The mesh the frames share: `points` (N, 3) [m], `block` and `element_in_block`
    /// (E,), `fiber_direction_reference` (E, 3) and `blocks` (names).
    #[getter]
    fn mesh<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        mesh_dict(py, &self.mesh)
    }

    /// Solver steps (explicit) or increments (implicit) of the run.
    #[getter]
    fn steps(&self) -> usize {
        self.steps
    }

    /// Write the run directory `musclefem run` writes into `directory`: the frames
    /// (`frames/frame_NNNNN.vtu`, `result.pvd`), `history.csv`, `scene.toml` and a
    /// `run.log` saying where they come from. The frames and history are those of the
    /// command line's, byte for byte. An earlier run there is replaced only with `force`.
    #[pyo3(signature = (directory, force = false))]
    fn write_vtu(&self, py: Python<'_>, directory: PathBuf, force: bool) -> PyResult<()> {
        let existing = if force {
            ExistingResults::Replace
        } else {
            ExistingResults::Refuse
        };
        py.detach(|| -> anyhow::Result<()> {
            let mut run = RunDirectory::create(&directory, existing)?;
            write_frames(&mut run, &self.frames, &self.mesh)?;
            HistoryWriter::new(&run.history_path(), &self.header)
                .with_rows(self.rows.clone())?
                .finish()?;
            run.write_scene(&self.scene.1)?;
            run.write_run_log(&RunLog::new(format!(
                "scene = {} (Python: musclefem.Scene)\nsolver = {}\nend = complete ({} \
                 steps); written by Result.write_vtu\n",
                self.scene.0, self.analysis, self.steps
            )))?;
            Ok(())
        })
        .map_err(python_error)
    }

    fn __getitem__<'py>(&self, py: Python<'py>, column: &str) -> PyResult<Bound<'py, PyAny>> {
        self.history
            .bind(py)
            .get_item(column)?
            .ok_or_else(|| PyKeyError::new_err(column.to_string()))
    }

    fn __len__(&self) -> usize {
        self.names.len()
    }

    fn __contains__(&self, column: &str) -> bool {
        self.names.iter().any(|n| n == column)
    }

    fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        PyList::new(py, &self.names)?
            .try_iter()
            .map(Bound::into_any)
    }

    /// The history's column names.
    fn keys(&self) -> Vec<String> {
        self.names.clone()
    }

    /// The history's columns (arrays), in order.
    fn values<'py>(&self, py: Python<'py>) -> Bound<'py, PyList> {
        self.history.bind(py).values()
    }

    /// (name, array) of every history column.
    fn items<'py>(&self, py: Python<'py>) -> Bound<'py, PyList> {
        self.history.bind(py).items()
    }

    /// The column `column`, or `default`.
    #[pyo3(signature = (column, default = None))]
    fn get<'py>(
        &self,
        py: Python<'py>,
        column: &str,
        default: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        Ok(self.history.bind(py).get_item(column)?.or(default))
    }

    fn __repr__(&self) -> String {
        format!(
            "Result({}: {} history rows of {} columns, {} frames, {} steps)",
            self.scene.0,
            self.rows.len(),
            self.names.len(),
            self.frames.len(),
            self.steps
        )
    }
}
