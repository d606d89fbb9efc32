//! The passive elongation of the paper's fusiform muscle (seed §2.2; see
//! [`crate::elongation`]): fixed grips, pulled at 5 mm/s to 20 % strain.
//!
//! Response: the engineering stress at 5, 10, 15 and 20 % strain [Pa].

use anyhow::{Context, Result, bail};

use crate::elongation::{Activation, ElongationTest, Unwatched, run_elongation};

use super::Response;
use super::method::{Method, StepSetting};
use crate::inertia::inertia_warning;

/// Strains at which the stress is compared [1].
pub const SAMPLE_STRAINS: [f64; 4] = [0.05, 0.10, 0.15, 0.20];
/// The `error_metric` column.
pub const ERROR_METRIC: &str = "max_relative_stress_error_at_strain_5_10_15_20pct";
/// The explicit elongation runs at the solver's default safety factor.
pub const ELONGATE_SAFETY: f64 = 0.9;

/// The passive elongation test of `method`.
pub fn elongation_test(method: &Method) -> Result<ElongationTest> {
    let time_step = match method.step {
        StepSetting::Implicit { increment } => increment,
        StepSetting::Explicit {
            mass_scaling,
            safety,
        } => {
            if safety != ELONGATE_SAFETY {
                bail!(
                    "the elongation test runs the explicit solver at safety factor \
                     {ELONGATE_SAFETY}, not {safety}"
                );
            }
            mass_scaling.context(
                "the elongation test needs mass scaling (its physical stable step, about \
                 2 µs, would take a million steps)",
            )?
        }
    };
    Ok(ElongationTest {
        solver: method.solver(),
        element: method.element,
        mesh_size: method.mesh_size,
        time_step: Some(time_step),
        ..ElongationTest::recommended(Activation::Passive)
    })
}

/// Run `method` on the passive elongation and return its stress at [`SAMPLE_STRAINS`].
pub fn run_elongate(method: &Method) -> Result<Response> {
    let run = run_elongation(&elongation_test(method)?, &mut Unwatched)?;
    let samples = SAMPLE_STRAINS
        .iter()
        .map(|&strain| {
            run.curve
                .stress_at_strain(strain)
                .with_context(|| format!("the run did not reach {} % strain", 100.0 * strain))
        })
        .collect::<Result<_>>()?;
    Ok(Response {
        samples,
        warning: run.kinetic_to_internal.and_then(inertia_warning),
    })
}
