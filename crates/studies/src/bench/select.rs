//! The cheapest measured setting that meets an error tolerance: reads a
//! `work_precision.csv` written by `musclefem bench` and picks, for a problem, the row of
//! least wall time whose error is at most the tolerance.

use anyhow::{Context, Result, bail};

use crate::elongation::ElementChoice;

use super::csv::{WORK_PRECISION_HEADER, WorkPrecisionRow};
use super::method::{Method, StepSetting};

/// The rows of a `work_precision.csv` text.
pub fn read_table(text: &str) -> Result<Vec<WorkPrecisionRow>> {
    let mut lines = text.lines();
    if lines.next() != Some(WORK_PRECISION_HEADER) {
        bail!("not a work_precision.csv: the first line must be {WORK_PRECISION_HEADER}");
    }
    lines
        .enumerate()
        .map(|(i, line)| {
            let fields: Vec<&str> = line.split(',').collect();
            let [problem, solver, element, size, step, wall, error, metric] = fields[..] else {
                bail!("line {}: {} fields, expected 8", i + 2, fields.len());
            };
            let number = |text: &str| -> Result<f64> {
                text.parse()
                    .with_context(|| format!("line {}: '{text}' is not a number", i + 2))
            };
            Ok(WorkPrecisionRow {
                problem: problem.to_string(),
                solver: solver.to_string(),
                element: element.to_string(),
                mesh_size_mm: number(size)?,
                step_setting: step.to_string(),
                wall_s: number(wall)?,
                error: number(error)?,
                error_metric: metric.to_string(),
            })
        })
        .collect()
}

/// The fastest row of the problem named `problem` (a [`super::Problem`]'s name or a
/// scene's) with error ≤ `tolerance` [1] (failed runs never qualify).
pub fn cheapest_within<'a>(
    rows: &'a [WorkPrecisionRow],
    problem: &str,
    tolerance: f64,
) -> Option<&'a WorkPrecisionRow> {
    rows.iter()
        .filter(|r| r.problem == problem && r.error.is_finite() && r.error <= tolerance)
        .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s))
}

/// The method a row describes.
pub fn method_of(row: &WorkPrecisionRow) -> Result<Method> {
    use clap::ValueEnum;
    let element = ElementChoice::value_variants()
        .iter()
        .copied()
        .find(|&e| e.name() == row.element)
        .with_context(|| format!("unknown element '{}'", row.element))?;
    Ok(Method {
        element,
        mesh_size: 1e-3 * row.mesh_size_mm,
        step: step_of(row)?,
    })
}

/// The step setting a row describes (its `step_setting` column, see
/// [`StepSetting::label`]).
pub fn step_of(row: &WorkPrecisionRow) -> Result<StepSetting> {
    let seconds = |text: &str| -> Result<f64> {
        text.trim_end_matches('s')
            .parse()
            .with_context(|| format!("bad step setting '{}'", row.step_setting))
    };
    let mut settings = row.step_setting.split(';');
    let first = settings.next().unwrap_or_default();
    if let Some(increment) = first.strip_prefix("increment=") {
        return Ok(StepSetting::Implicit {
            increment: seconds(increment)?,
        });
    }
    let mass_scaling = match first.strip_prefix("mass_scaling=") {
        Some(target) => Some(seconds(target)?),
        None if first == "no_mass_scaling" => None,
        None => bail!("bad step setting '{}'", row.step_setting),
    };
    let safety = settings
        .next()
        .and_then(|s| s.strip_prefix("safety="))
        .with_context(|| format!("no safety factor in '{}'", row.step_setting))?;
    Ok(StepSetting::Explicit {
        mass_scaling,
        safety: safety
            .parse()
            .with_context(|| format!("bad step setting '{}'", row.step_setting))?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TABLE: &str = "problem,solver,element,mesh_size_mm,step_setting,wall_s,error,error_metric
elongate,implicit,hex8-fbar,4,increment=0.4s,3.9,1.1e-2,m
elongate,implicit,tet4,4,increment=0.2s,2.5,1.2e0,m
elongate,explicit,hex8-one-point,4,mass_scaling=1e-4s;safety=0.9,4.6,1.1e-1,m
elongate,explicit,hex8-one-point,4,mass_scaling=2e-4s;safety=0.9,1.0,NaN,m
cube,explicit,hex8-one-point,2.5,no_mass_scaling;safety=0.9,0.2,3e-3,m
";

    #[test]
    fn the_cheapest_row_within_the_tolerance_is_chosen_and_read_back() {
        let rows = read_table(TABLE).unwrap();
        assert_eq!(rows.len(), 5);
        let loose = cheapest_within(&rows, "elongate", 0.2).unwrap();
        assert_eq!(loose.step_setting, "increment=0.4s"); // 3.9 s beats 4.6 s
        let any = cheapest_within(&rows, "elongate", 2.0).unwrap();
        assert_eq!(any.element, "tet4");
        assert!(cheapest_within(&rows, "elongate", 0.01).is_none());
        let method = method_of(&rows[2]).unwrap();
        assert_eq!(method.element, ElementChoice::Hex8OnePoint);
        assert_eq!(
            method.step,
            StepSetting::Explicit {
                mass_scaling: Some(1e-4),
                safety: 0.9
            }
        );
        assert_eq!(method_of(&rows[0]).unwrap().step.label(), "increment=0.4s");
        assert!(read_table("a,b\n").is_err());
    }
}
