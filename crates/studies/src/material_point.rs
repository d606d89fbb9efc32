//! A material point driven in uniaxial stress (`musclefem point`, `demo`): the material
//! built from its parameters, the stretch history parsed, the driver run, and the answer
//! refused when halving the step changes it (a step that does not resolve the history).

use std::collections::BTreeMap;

use anyhow::{Context, Result, bail};

use musclefem_io::csv::format_number;
use musclefem_materials::driver::{DriverError, StretchHistory, UniaxialRow, run_uniaxial_stress};
use musclefem_materials::{Material, MaterialLibrary};

/// "name=value, ..." of the given parameters, or "defaults".
fn params_text(params: &BTreeMap<String, f64>) -> String {
    if params.is_empty() {
        return "default parameters".to_string();
    }
    params
        .iter()
        .map(|(k, v)| format!("{k}={}", format_number(*v)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// One material-point run, checked and computed in memory.
pub struct PointRun {
    /// Legend label, e.g. "hill (n2=1)".
    pub label: String,
    pub rows: Vec<UniaxialRow>,
}

/// Build `material` from `params` and drive it through `stretch` (the `--stretch`
/// syntax TIME:STRETCH,...) with step `dt` [s], refusing an answer the step does not
/// resolve.
pub fn run_point(
    library: &MaterialLibrary,
    material: &str,
    params: &BTreeMap<String, f64>,
    stretch: &str,
    dt: f64,
) -> Result<PointRun> {
    let history = StretchHistory::parse(stretch).context("--stretch")?;
    if !(dt.is_finite() && dt > 0.0) {
        bail!(
            "--dt {}: the time step must be a positive number of seconds",
            format_number(dt)
        );
    }
    let model = library.create(material, params)?;
    let rows = run_uniaxial_stress(model.as_ref(), &history, dt).with_context(|| {
        format!(
            "material-point run of '{material}' ({}) with --stretch {stretch} --dt {dt}",
            params_text(params)
        )
    })?;
    check_step_resolves(model.as_ref(), &history, dt, &rows)?;
    Ok(PointRun {
        label: format!("{material} ({})", params_text(params)),
        rows,
    })
}

/// Largest change of the engineering stress when the step is halved, as a fraction of the
/// largest stress of the run, above which `point` refuses its answer.
const STEP_RESOLUTION_TOLERANCE: f64 = 0.01;

/// The answer must not depend on the step: the run is repeated with `dt / 2`, and if the
/// engineering stress at a common time differs by more than [`STEP_RESOLUTION_TOLERANCE`]
/// of the largest stress, the step does not resolve the history (one step of 1 ms from
/// λ = 1 to 0.5 wrote −592 MPa for the active Hill muscle and J = 0.56; with half the step
/// its series element fails). Skipped where the halved step would exceed the driver's step
/// limit.
fn check_step_resolves(
    material: &dyn Material,
    history: &StretchHistory,
    dt: f64,
    rows: &[UniaxialRow],
) -> Result<()> {
    let finer = match run_uniaxial_stress(material, history, 0.5 * dt) {
        Ok(rows) => rows,
        Err(DriverError::TooManySteps { .. }) => return Ok(()),
        Err(error) => bail!(
            "--dt {dt}: the step does not resolve the stretch history: with half the step the \
             run fails ({error}); use a smaller --dt (e.g. {}), or a gentler history",
            format_number(0.1 * dt)
        ),
    };
    let largest = finer
        .iter()
        .map(|r| r.engineering_stress.abs())
        .fold(1.0, f64::max);
    let last = rows.len() - 1;
    let worst = rows
        .iter()
        .enumerate()
        .map(|(k, row)| {
            let fine = if k == last {
                &finer[finer.len() - 1]
            } else {
                &finer[2 * k]
            };
            (
                row,
                fine,
                (row.engineering_stress - fine.engineering_stress).abs(),
            )
        })
        .max_by(|a, b| a.2.total_cmp(&b.2));
    if let Some((row, fine, difference)) = worst
        && difference > STEP_RESOLUTION_TOLERANCE * largest
    {
        bail!(
            "--dt {dt}: the step does not resolve the stretch history: at t = {} s (stretch \
             {:.4}) the engineering stress is {:.4} kPa, and {:.4} kPa with half the step \
             ({:.1} % of the largest stress); use a smaller --dt, e.g. {}",
            format_number(row.time),
            row.stretch,
            1e-3 * row.engineering_stress,
            1e-3 * fine.engineering_stress,
            100.0 * difference / largest,
            format_number(0.1 * dt)
        );
    }
    Ok(())
}
