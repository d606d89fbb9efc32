//! `musclefem.knee`: `musclefem knee` from Python — its options as keyword arguments, its
//! files under `out`, its peak-stress and tendon tables as NumPy arrays.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use clap::Parser;
use numpy::IntoPyArray;
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use musclefem_studies::knee::command::{KneeArgs, KneeOutcome, KneeView, run_knee};
use musclefem_studies::knee::simulation::patella::{TENDON_CSV_HEADER, tendon_values};

use crate::background::{run_watched, thread_pool};
use crate::{MusclefemError, python_error};

/// `musclefem knee`'s options, parsed as the command parses them.
#[derive(Parser)]
#[command(name = "knee")]
struct KneeCommand {
    #[command(flatten)]
    args: KneeArgs,
}

/// The knee squat 0° → 90° → 0° with the four quadriceps, passive and active side by side
/// (`musclefem knee`; about two hours on 2 cores with the defaults, the Visible Human
/// knee; about 14 minutes with `anatomy="procedural"`). The keyword
/// arguments are the command's options (`musclefem knee --help`), `None` meaning its
/// default: `passive`, `active`, `both` (flags), `solver`, `element`, `resolution`,
/// `tolerance` [%], `bench_table`, `anatomy` ("visible-human", "procedural" or a
/// directory), `interfaces`,
/// `peak_flexion` [°], `duration` [s], `time_step` [s], `frame_interval` [s], `out`
/// (default "out/knee"), `force`, `resume` (go on from the squats' last frames). Its
/// files are written under `out` as the command writes them. `progress`: the command's
/// bars on a terminal; `verbose`: its lines on `sys.stdout`. Returns a dict:
/// `peak_stress`, the columns of peak_stress.csv (`muscle`, `knee_angle_deg`, `phase`,
/// `activation`, `vm95_pa`), and `tendon`, {activation: the columns of its tendon.csv}.
/// Ctrl-C stops both squats at their next recorded instant (KeyboardInterrupt; the
/// frames written so far and a checkpoint at the last one stay: `resume=True` goes on).
#[pyfunction]
#[pyo3(signature = (
    *, passive = false, active = false, both = false, solver = None, element = None,
    resolution = None, tolerance = None, bench_table = None, anatomy = None,
    interfaces = None, peak_flexion = None, duration = None, time_step = None,
    frame_interval = None, out = None, force = false, resume = false, threads = None,
    progress = false, verbose = false
))]
#[allow(clippy::too_many_arguments)]
pub fn knee<'py>(
    py: Python<'py>,
    passive: bool,
    active: bool,
    both: bool,
    solver: Option<String>,
    element: Option<String>,
    resolution: Option<String>,
    tolerance: Option<f64>,
    bench_table: Option<PathBuf>,
    anatomy: Option<PathBuf>,
    interfaces: Option<String>,
    peak_flexion: Option<f64>,
    duration: Option<f64>,
    time_step: Option<f64>,
    frame_interval: Option<f64>,
    out: Option<PathBuf>,
    force: bool,
    resume: bool,
    threads: Option<usize>,
    progress: bool,
    verbose: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let mut argv: Vec<String> = vec!["knee".into()];
    for (flag, given) in [
        ("passive", passive),
        ("active", active),
        ("both", both),
        ("force", force),
        ("resume", resume),
    ] {
        if given {
            argv.push(format!("--{flag}"));
        }
    }
    let path = |p: PathBuf| p.display().to_string();
    for (flag, value) in [
        ("solver", solver),
        ("element", element),
        ("resolution", resolution),
        ("tolerance", tolerance.map(|v| v.to_string())),
        ("bench-table", bench_table.map(path)),
        ("anatomy", anatomy.map(path)),
        ("interfaces", interfaces),
        ("peak-flexion", peak_flexion.map(|v| v.to_string())),
        ("duration", duration.map(|v| v.to_string())),
        ("time-step", time_step.map(|v| v.to_string())),
        ("frame-interval", frame_interval.map(|v| v.to_string())),
        ("out", out.map(path)),
    ] {
        if let Some(value) = value {
            // `--flag=value`, so that a negative number is read as one.
            argv.push(format!("--{flag}={value}"));
        }
    }
    let args = KneeCommand::try_parse_from(&argv)
        .map_err(|e| {
            let text = e.to_string();
            let first = text.lines().next().unwrap_or_default();
            MusclefemError::new_err(first.trim_start_matches("error: ").to_string())
        })?
        .args;
    let pool = thread_pool(py, threads)?;
    let stop = AtomicBool::new(false);
    let say = move |text: &str| {
        if verbose {
            Python::attach(|py| -> PyResult<()> {
                py.import("sys")?
                    .getattr("stdout")?
                    .call_method1("write", (text,))?;
                Ok(())
            })
            .ok();
        }
    };
    let bars = progress && std::io::IsTerminal::is_terminal(&std::io::stderr());
    let (outcome, signal) = run_watched(py, pool.as_ref(), &stop, || {
        let view = KneeView {
            say: &say,
            bars,
            stop: &stop,
        };
        run_knee(&args, &view)
    })?;
    match (outcome, signal) {
        (Ok(outcome), _) => tables(py, &outcome),
        (Err(_), Some(signal)) if signal.is_instance_of::<PyKeyboardInterrupt>(py) => {
            Err(PyKeyboardInterrupt::new_err(
                "the squats were stopped; the frames written so far stay, and resume=True \
                 goes on from the last one",
            ))
        }
        (Err(_), Some(signal)) => Err(signal),
        (Err(error), None) => Err(python_error(error)),
    }
}

/// The peak-stress and tendon tables of `outcome`.
fn tables<'py>(py: Python<'py>, outcome: &KneeOutcome) -> PyResult<Bound<'py, PyDict>> {
    let rows = &outcome.rows;
    let peak = PyDict::new(py);
    let muscles: Vec<&str> = rows.iter().map(|r| r.muscle.abbreviation()).collect();
    peak.set_item("muscle", PyList::new(py, muscles)?)?;
    let angles: Vec<f64> = rows.iter().map(|r| r.angle_degrees).collect();
    peak.set_item("knee_angle_deg", angles.into_pyarray(py))?;
    let phases: Vec<&str> = rows.iter().map(|r| r.phase.name()).collect();
    peak.set_item("phase", PyList::new(py, phases)?)?;
    let activations: Vec<&str> = rows.iter().map(|r| r.activation.name()).collect();
    peak.set_item("activation", PyList::new(py, activations)?)?;
    let vm95: Vec<f64> = rows.iter().map(|r| r.vm95).collect();
    peak.set_item("vm95_pa", vm95.into_pyarray(py))?;
    let tendon = PyDict::new(py);
    for (activation, run) in outcome.activations.iter().zip(&outcome.runs) {
        let table = PyDict::new(py);
        let values: Vec<[f64; 10]> = run.tendon.iter().map(tendon_values).collect();
        for (k, name) in TENDON_CSV_HEADER.split(',').enumerate() {
            let column: Vec<f64> = values.iter().map(|row| row[k]).collect();
            table.set_item(name, column.into_pyarray(py))?;
        }
        tendon.set_item(activation.name(), table)?;
    }
    let dict = PyDict::new(py);
    dict.set_item("peak_stress", peak)?;
    dict.set_item("tendon", tendon)?;
    Ok(dict)
}
