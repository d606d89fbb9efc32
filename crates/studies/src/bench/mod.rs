//! Speed against accuracy (`musclefem bench`): run a matrix of methods (solver, element,
//! mesh size, step setting) on a problem, time each run, and measure its error against a
//! converged reference run of the same problem.
//!
//! - [`method`]: what one run is ([`Method`], [`StepSetting`]);
//! - [`matrix`]: which methods each problem runs, quick or full, and its reference;
//! - [`cube`], [`elongate`], [`knee`]: the problems, each returning a [`Response`] (the quantity
//!   compared, sampled at fixed instants);
//! - [`reference`]: the error of a response against the reference's;
//! - [`pareto`]: the runs no other run beats in both time and error;
//! - [`csv`], [`chart`]: `work_precision.csv` and `work_precision.png`;
//! - [`scene`]: a scene of the user's own, its step settings against a reference run;
//! - [`select`]: the cheapest measured setting within an error tolerance;
//! - [`scaling`]: not a work–precision matrix: the implicit cube timed at growing sizes
//!   (and through felupe), with the fitted growth of the time (`--problem scaling`).

pub mod chart;
pub mod csv;
pub mod cube;
pub mod elongate;
pub mod knee;
pub mod matrix;
pub mod method;
pub mod pareto;
pub mod reference;
pub mod scaling;
pub mod scene;
pub mod select;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::Result;

pub use matrix::{matrix, reference_method};
pub use method::{Method, StepSetting};

/// The work–precision table that `--tolerance` reads (written by `musclefem bench`).
#[derive(Debug, Clone, clap::Args)]
pub struct BenchTable {
    /// The work–precision table --tolerance reads (`musclefem bench`).
    #[arg(
        long = "bench-table",
        value_name = "FILE",
        default_value = "out/bench/work_precision.csv"
    )]
    pub path: PathBuf,
}

/// A benchmark problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Problem {
    /// A 1 cm neo-Hookean cube, clamped on one face, the opposite face pulled 5 mm in
    /// 1 s (non-homogeneous: the mesh matters).
    Cube,
    /// The paper's passive elongation of the 50 mm fusiform Hill muscle to 20 % strain.
    Elongate,
    /// The passive knee squat 0° → 90° → 0° in 2 s on the procedural anatomy (no quick
    /// matrix: its reference takes about 5 minutes).
    Knee,
}

impl Problem {
    pub fn name(self) -> &'static str {
        match self {
            Problem::Cube => "cube",
            Problem::Elongate => "elongate",
            Problem::Knee => "knee",
        }
    }

    /// How the error is measured (the `error_metric` column).
    pub fn error_metric(self) -> &'static str {
        match self {
            Problem::Cube => cube::ERROR_METRIC,
            Problem::Elongate => elongate::ERROR_METRIC,
            Problem::Knee => knee::ERROR_METRIC,
        }
    }

    /// Run `method` on this problem.
    pub fn run(self, method: &Method) -> Result<Response> {
        match self {
            Problem::Cube => cube::run_cube(method),
            Problem::Elongate => elongate::run_elongate(method),
            Problem::Knee => knee::run_knee(method),
        }
    }
}

/// What a run is judged by: one quantity sampled at the problem's fixed instants (e.g. the
/// reaction force at t = 0.25, 0.5, 0.75, 1 s) [its unit].
#[derive(Debug, Clone, PartialEq)]
pub struct Response {
    pub samples: Vec<f64>,
    /// Explicit runs: a warning if the run was not quasi-static (see
    /// [`crate::inertia::inertia_warning`]).
    pub warning: Option<String>,
}

/// One timed run of the matrix.
#[derive(Debug, Clone)]
pub struct Measurement {
    pub problem: Problem,
    pub method: Method,
    /// Wall time of the run, setup (meshing) included [s].
    pub wall: Duration,
    /// The response, or why the run failed (the solver's message).
    pub outcome: std::result::Result<Response, String>,
}

impl Measurement {
    /// Run `method` on `problem` and time it.
    pub fn take(problem: Problem, method: &Method) -> Self {
        let started = Instant::now();
        let outcome = problem.run(method).map_err(|e| format!("{e:#}"));
        Measurement {
            problem,
            method: method.clone(),
            wall: started.elapsed(),
            outcome,
        }
    }

    /// The relative error against `reference` (NaN if this run failed).
    pub fn error(&self, reference: &Response) -> f64 {
        match &self.outcome {
            Ok(response) => reference::relative_error(response, reference),
            Err(_) => f64::NAN,
        }
    }
}
