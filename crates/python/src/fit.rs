//! `musclefem.fit`: `musclefem fit` from Python — its options as keyword arguments, the
//! measured curve from a CSV file or from arrays, the fitted parameters and the curves as
//! NumPy arrays.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use clap::Parser;
use numpy::IntoPyArray;
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

use musclefem_studies::fit::outputs::Outputs;
use musclefem_studies::fit::{FitArgs, FitStopped, FitWatch, Fitted, fit_curve};

use crate::background::{run_watched, thread_pool};
use crate::scene::Scene;
use crate::{MusclefemError, python_error};

/// `musclefem fit`'s options, parsed as the command parses them.
#[derive(Parser)]
#[command(name = "fit")]
struct FitCommand {
    #[command(flatten)]
    args: FitArgs,
}

/// The name a measured curve given as arrays has in messages.
const ARRAY_DATA: &str = "<data>";

/// The measured curve as `--data` and, for arrays, the CSV text they make.
fn data_source(
    data: &Bound<'_, PyAny>,
    columns: &mut (Option<String>, Option<String>),
) -> PyResult<(String, Option<String>)> {
    if let Ok(path) = data.extract::<PathBuf>() {
        return Ok((path.display().to_string(), None));
    }
    let numpy = data.py().import("numpy")?;
    let column = |values: &Bound<'_, PyAny>| -> PyResult<Vec<f64>> {
        numpy
            .call_method1("asarray", (values, "float64"))?
            .call_method0("ravel")?
            .call_method0("tolist")?
            .extract()
    };
    let (names, values): (Vec<String>, Vec<Vec<f64>>) = if let Ok(pair) = data.cast::<PyTuple>() {
        let [x, y] = <[Bound<'_, PyAny>; 2]>::try_from(pair.iter().collect::<Vec<_>>())
            .map_err(|_| MusclefemError::new_err("data=(x, y): give two arrays"))?;
        if columns.0.is_some() || columns.1.is_some() {
            return Err(MusclefemError::new_err(
                "data=(x, y) names its own columns: give strain_column and stress_column \
                 with a CSV file or a dict of columns",
            ));
        }
        *columns = (Some("x".into()), Some("y".into()));
        (vec!["x".into(), "y".into()], vec![column(&x)?, column(&y)?])
    } else if data.hasattr("keys")? {
        let keys = data.call_method0("keys")?;
        let mut names = Vec::new();
        let mut values = Vec::new();
        for key in keys.try_iter()? {
            let key = key?;
            let name: String = key.str()?.extract()?;
            if name.contains([',', '"', '\n']) {
                return Err(MusclefemError::new_err(format!(
                    "data: column name {name:?} cannot be a CSV header"
                )));
            }
            values.push(column(&data.get_item(&key)?)?);
            names.push(name);
        }
        (names, values)
    } else {
        return Err(MusclefemError::new_err(
            "data: a CSV file's path, a dict of columns (e.g. a pandas DataFrame) or (x, y)",
        ));
    };
    let rows = values.first().map_or(0, Vec::len);
    if let Some((name, _)) = names.iter().zip(&values).find(|(_, v)| v.len() != rows) {
        return Err(MusclefemError::new_err(format!(
            "data: column '{name}' has another length than '{}'",
            names[0]
        )));
    }
    let mut text = names.join(",") + "\n";
    for k in 0..rows {
        let row: Vec<String> = values.iter().map(|v| v[k].to_string()).collect();
        text.push_str(&row.join(","));
        text.push('\n');
    }
    Ok((ARRAY_DATA.to_string(), Some(text)))
}

/// Python's view of a fit: its output directory (if any) opened before the first run,
/// the residual on `sys.stderr` when asked.
struct Watch {
    out: Option<(PathBuf, bool)>,
    outputs: Option<Outputs>,
    progress: bool,
}

impl FitWatch for Watch {
    fn starting(&mut self, announcement: &str) -> anyhow::Result<()> {
        if let Some((dir, force)) = &self.out {
            self.outputs = Some(Outputs::new(dir, *force)?);
        }
        self.line(announcement);
        Ok(())
    }

    fn iteration(&mut self, iteration: usize, rms: f64, unit: &str) {
        self.line(&format!(
            "iteration {iteration}: RMS residual {rms:.4e} {unit}"
        ));
    }
}

impl Watch {
    fn line(&self, text: &str) {
        if self.progress {
            Python::attach(|py| -> PyResult<()> {
                let stderr = py.import("sys")?.getattr("stderr")?;
                stderr.call_method1("write", (format!("{text}\n"),))?;
                Ok(())
            })
            .ok();
        }
    }
}

/// Fit material parameters to a measured curve through the elongation test (`test`,
/// with `shape`, `grips`, `solver`, `element`, `mesh_size` [mm], `time_step` [s]) or a
/// scene (`scene`: a path or a `Scene` from a file; its history column `y` against `x`),
/// as `musclefem fit` does; see `musclefem fit --help` for every option. `data`: a CSV
/// file's path (columns `strain_column`, `stress_column`, scaled by `strain_scale` and
/// `stress_scale` to SI units), a dict of columns (also a pandas DataFrame), or a pair
/// of arrays (x, y). `params`: the names fitted (a list, or "c,A"); `start` and `bound`:
/// dicts {name: value} and {name: (lower, upper)}. With `out`, `fit.csv`,
/// `fit_curve.csv`, `fit.txt` and `fit.png` are written there (`force` replaces a
/// previous fit). Returns a dict: `parameters` {name: fitted value}; `table`, the
/// columns of fit.csv (`parameter`, `start`, `fitted`, `standard_error`, `ci95_low`,
/// `ci95_high` (NaN where there is none), `at_bound`); `curve`, the columns of
/// fit_curve.csv (measured and fitted values at the measured abscissae, SI units);
/// `fitted_curve` and `start_curve`, the model's whole curves as {`x`, `y`} arrays;
/// `rms_residual`, `r_squared`, `iterations`, `runs`, `stop`, `left_out` and
/// `summary` (fit.txt). Ctrl-C stops it between two runs (KeyboardInterrupt).
#[pyfunction]
#[pyo3(signature = (
    data, params, *, test = None, scene = None, x = None, y = None, start = None,
    bound = None, strain_column = None, stress_column = None, strain_scale = None,
    stress_scale = None, solver = None, element = None, mesh_size = None, shape = None,
    grips = None, time_step = None, allow_plugins = false, allow_outside_paths = false,
    out = None, force = false, threads = None, progress = false
))]
#[allow(clippy::too_many_arguments)]
pub fn fit<'py>(
    py: Python<'py>,
    data: &Bound<'py, PyAny>,
    params: &Bound<'py, PyAny>,
    test: Option<String>,
    scene: Option<&Bound<'py, PyAny>>,
    x: Option<String>,
    y: Option<String>,
    start: Option<&Bound<'py, PyDict>>,
    bound: Option<&Bound<'py, PyDict>>,
    strain_column: Option<String>,
    stress_column: Option<String>,
    strain_scale: Option<f64>,
    stress_scale: Option<f64>,
    solver: Option<String>,
    element: Option<String>,
    mesh_size: Option<f64>,
    shape: Option<String>,
    grips: Option<String>,
    time_step: Option<f64>,
    allow_plugins: bool,
    allow_outside_paths: bool,
    out: Option<PathBuf>,
    force: bool,
    threads: Option<usize>,
    progress: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let mut columns = (strain_column, stress_column);
    let (data_name, data_text) = data_source(data, &mut columns)?;
    let params: Vec<String> = match params.extract::<String>() {
        Ok(text) => vec![text],
        Err(_) => params.extract()?,
    };
    let mut argv: Vec<String> = vec!["fit".into(), "--data".into(), data_name];
    let mut option = |flag: &str, value: Option<String>| {
        if let Some(value) = value {
            argv.push(format!("--{flag}"));
            argv.push(value);
        }
    };
    option("params", Some(params.join(",")));
    option("test", test);
    let (allow_plugins, allow_outside_paths, scene) = match scene {
        None => (allow_plugins, allow_outside_paths, None),
        Some(scene) => match scene.cast::<Scene>() {
            Ok(scene) => {
                let (path, trust) = scene.get().file_and_trust()?;
                let plugins = trust.plugins == musclefem_io::scene::PluginPolicy::Load;
                (plugins, trust.outside_paths, Some(path))
            }
            Err(_) => (
                allow_plugins,
                allow_outside_paths,
                Some(scene.extract::<PathBuf>()?),
            ),
        },
    };
    option("scene", scene.map(|p| p.display().to_string()));
    option("x", x);
    option("y", y);
    option("strain-column", columns.0);
    option("stress-column", columns.1);
    option("strain-scale", strain_scale.map(|v| v.to_string()));
    option("stress-scale", stress_scale.map(|v| v.to_string()));
    option("solver", solver);
    option("element", element);
    option("mesh-size", mesh_size.map(|v| v.to_string()));
    option("shape", shape);
    option("grips", grips);
    option("time-step", time_step.map(|v| v.to_string()));
    for (name, value) in start
        .map(|d| d.iter().collect::<Vec<_>>())
        .unwrap_or_default()
    {
        let value: f64 = value.extract()?;
        option("start", Some(format!("{}={value}", name.str()?)));
    }
    for (name, value) in bound
        .map(|d| d.iter().collect::<Vec<_>>())
        .unwrap_or_default()
    {
        let (lower, upper): (f64, f64) = value.extract()?;
        option("bound", Some(format!("{}={lower}:{upper}", name.str()?)));
    }
    if allow_plugins {
        argv.push("--allow-plugins".into());
    }
    if allow_outside_paths {
        argv.push("--allow-outside-paths".into());
    }
    let args = FitCommand::try_parse_from(&argv)
        .map_err(|e| {
            let text = e.to_string();
            let first = text.lines().next().unwrap_or_default();
            MusclefemError::new_err(first.trim_start_matches("error: ").to_string())
        })?
        .args;
    let mut watch = Watch {
        out: out.map(|dir| (dir, force)),
        outputs: None,
        progress,
    };
    let pool = thread_pool(py, threads)?;
    let stop = AtomicBool::new(false);
    let (outcome, signal) = run_watched(py, pool.as_ref(), &stop, || {
        let fitted = fit_curve(&args, data_text.as_deref(), &mut watch, &stop)?;
        if let Some(outputs) = &watch.outputs {
            outputs.write(&fitted)?;
        }
        Ok::<_, anyhow::Error>(fitted)
    })?;
    match outcome {
        Ok(fitted) => fitted_dict(py, &fitted),
        Err(error) if error.downcast_ref::<FitStopped>().is_some() => Err(match signal {
            Some(error) if !error.is_instance_of::<PyKeyboardInterrupt>(py) => error,
            _ => PyKeyboardInterrupt::new_err("the fit was stopped"),
        }),
        Err(error) => Err(python_error(error)),
    }
}

/// What `fit` returns (see its documentation).
fn fitted_dict<'py>(py: Python<'py>, fitted: &Fitted) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    let parameters = PyDict::new(py);
    for (name, value) in fitted.names.iter().zip(&fitted.values) {
        parameters.set_item(name, value)?;
    }
    dict.set_item("parameters", parameters)?;
    let errors: Vec<f64> = fitted
        .standard_errors
        .iter()
        .map(|e| e.unwrap_or(f64::NAN))
        .collect();
    let z = musclefem_studies::fit::Z_95;
    let table = PyDict::new(py);
    table.set_item("parameter", PyList::new(py, &fitted.names)?)?;
    table.set_item("start", fitted.start.clone().into_pyarray(py))?;
    table.set_item("fitted", fitted.values.clone().into_pyarray(py))?;
    let low: Vec<f64> = fitted
        .values
        .iter()
        .zip(&errors)
        .map(|(x, e)| x - z * e)
        .collect();
    let high: Vec<f64> = fitted
        .values
        .iter()
        .zip(&errors)
        .map(|(x, e)| x + z * e)
        .collect();
    table.set_item("standard_error", errors.into_pyarray(py))?;
    table.set_item("ci95_low", low.into_pyarray(py))?;
    table.set_item("ci95_high", high.into_pyarray(py))?;
    table.set_item("at_bound", fitted.at_bound.clone().into_pyarray(py))?;
    dict.set_item("table", table)?;
    let header: Vec<&str> = fitted
        .curve_table
        .lines()
        .next()
        .unwrap_or_default()
        .split(',')
        .collect();
    let curve = PyDict::new(py);
    let measured = &fitted.measured;
    for (name, values) in
        header
            .iter()
            .zip([&measured.strain, &measured.stress, &fitted.fitted_at_data])
    {
        curve.set_item(*name, values.clone().into_pyarray(py))?;
    }
    dict.set_item("curve", curve)?;
    for (name, points) in [
        ("fitted_curve", &fitted.fitted_curve),
        ("start_curve", &fitted.start_curve),
    ] {
        let xy = PyDict::new(py);
        xy.set_item(
            "x",
            points
                .iter()
                .map(|p| p.0)
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?;
        xy.set_item(
            "y",
            points
                .iter()
                .map(|p| p.1)
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?;
        dict.set_item(name, xy)?;
    }
    dict.set_item("rms_residual", fitted.rms)?;
    dict.set_item("r_squared", fitted.r_squared)?;
    dict.set_item("iterations", fitted.iterations)?;
    dict.set_item("runs", fitted.evaluations)?;
    dict.set_item("stop", format!("{:?}", fitted.stop))?;
    dict.set_item("left_out", measured.left_out)?;
    dict.set_item("summary", &fitted.summary)?;
    Ok(dict)
}
