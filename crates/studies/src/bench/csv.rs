//! `work_precision.csv`: one row per run of the matrix, with the header
//! [`WORK_PRECISION_HEADER`] exactly. A failed run has error `NaN`.

use super::Measurement;
use super::method::millimetres;

/// Header of `work_precision.csv`, exactly.
pub const WORK_PRECISION_HEADER: &str =
    "problem,solver,element,mesh_size_mm,step_setting,wall_s,error,error_metric";

/// One row: a run, its wall time [s] and its error [1] against the reference.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkPrecisionRow {
    pub problem: String,
    pub solver: String,
    pub element: String,
    pub mesh_size_mm: f64,
    pub step_setting: String,
    pub wall_s: f64,
    pub error: f64,
    pub error_metric: String,
}

impl WorkPrecisionRow {
    /// The row of `measurement`, whose error is `error`.
    pub fn new(measurement: &Measurement, error: f64) -> Self {
        let method = &measurement.method;
        WorkPrecisionRow {
            problem: measurement.problem.name().to_string(),
            solver: method.solver().name().to_string(),
            element: method.element.name().to_string(),
            mesh_size_mm: 1e3 * method.mesh_size,
            step_setting: method.step.label(),
            wall_s: measurement.wall.as_secs_f64(),
            error,
            error_metric: measurement.problem.error_metric().to_string(),
        }
    }
}

/// The CSV text of `rows`, header first.
pub fn to_csv(rows: &[WorkPrecisionRow]) -> String {
    let mut text = String::from(WORK_PRECISION_HEADER);
    text.push('\n');
    for row in rows {
        text += &format!(
            "{},{},{},{},{},{:.4},{:.6e},{}\n",
            row.problem,
            row.solver,
            row.element,
            millimetres(1e-3 * row.mesh_size_mm),
            row.step_setting,
            row.wall_s,
            row.error,
            row.error_metric
        );
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_have_as_many_fields_as_the_header() {
        let row = WorkPrecisionRow {
            problem: "cube".into(),
            solver: "explicit".into(),
            element: "hex8-fbar".into(),
            mesh_size_mm: 2.5,
            step_setting: "mass_scaling=1e-3s;safety=0.9".into(),
            wall_s: 0.25,
            error: f64::NAN,
            error_metric: "metric".into(),
        };
        let text = to_csv(&[row]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], WORK_PRECISION_HEADER);
        assert_eq!(lines[1].split(',').count(), 8);
        assert!(lines[1].contains(",NaN,"), "{}", lines[1]);
    }
}
