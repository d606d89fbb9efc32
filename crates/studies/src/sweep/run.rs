//! One run of a sweep: the base (an elongation test or a scene) with the run's parameter
//! values, its wall time, and its summary outputs (for the elongation tests the
//! engineering stress at [`SUMMARY_STRAINS`]). A failed run, including a panic inside the
//! solver, becomes an [`Outcome::Failed`] with its error instead of stopping the sweep.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Instant;

use crate::elongation::{ElongationTest, Unwatched, run_elongation};

/// Engineering strains [1] at which a run's stress is reported: 10 % and 20 %.
pub const SUMMARY_STRAINS: [f64; 2] = [0.1, 0.2];

/// What became of one run.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    Finished {
        /// Wall time of setup and solve [s].
        wall_time: f64,
        /// Solver steps or increments.
        steps: usize,
        /// The study's summary outputs, in its order (`None`: not reached).
        outputs: Vec<Option<f64>>,
    },
    Failed {
        wall_time: f64,
        /// The error chain on one line.
        error: String,
    },
}

impl Outcome {
    pub fn is_finished(&self) -> bool {
        matches!(self, Outcome::Finished { .. })
    }

    pub fn wall_time(&self) -> f64 {
        match self {
            Outcome::Finished { wall_time, .. } | Outcome::Failed { wall_time, .. } => *wall_time,
        }
    }
}

/// Run `base` with `names[i] = values[i]` added to its parameters: the engineering
/// stress at each of [`SUMMARY_STRAINS`] [Pa].
pub fn run_elongation_sample(
    base: &ElongationTest,
    names: &[String],
    values: &[f64],
) -> anyhow::Result<(usize, Vec<Option<f64>>)> {
    let mut test = base.clone();
    for (name, &value) in names.iter().zip(values) {
        test.parameters.insert(name.clone(), value);
    }
    let run = run_elongation(&test, &mut Unwatched)?;
    let stresses = SUMMARY_STRAINS
        .iter()
        .map(|&strain| run.curve.stress_at_strain(strain))
        .collect();
    Ok((run.steps, stresses))
}

/// Time `sample` (steps and outputs of one run) and turn its error or panic into an
/// [`Outcome::Failed`].
pub fn timed(sample: impl FnOnce() -> anyhow::Result<(usize, Vec<Option<f64>>)>) -> Outcome {
    let started = Instant::now();
    let result = catch_unwind(AssertUnwindSafe(sample));
    let wall_time = started.elapsed().as_secs_f64();
    match result {
        Ok(Ok((steps, outputs))) => Outcome::Finished {
            wall_time,
            steps,
            outputs,
        },
        Ok(Err(error)) => Outcome::Failed {
            wall_time,
            error: format!("{error:#}"),
        },
        Err(panic) => Outcome::Failed {
            wall_time,
            error: format!("panicked: {}", panic_message(panic.as_ref())),
        },
    }
}

fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    if let Some(text) = panic.downcast_ref::<&str>() {
        text.to_string()
    } else if let Some(text) = panic.downcast_ref::<String>() {
        text.clone()
    } else {
        "(no message)".to_string()
    }
}
