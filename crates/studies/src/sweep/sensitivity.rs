//! Normalised sensitivities of a summary output to the varied parameters, from all the
//! finished runs of a sweep, and their bar chart.
//!
//! The sensitivity S_j of output y to parameter p_j is the dimensionless slope of the
//! linear least-squares fit
//!
//!   y/ȳ − 1 = a + Σ_j S_j (p_j/p̄_j − 1)
//!
//! over the runs (bars: means over the runs): a 1 % change of p_j changes y by S_j %. On
//! a full-factorial grid it is the main effect of p_j averaged over the other parameters;
//! on a Latin hypercube it is the standardised regression coefficient. Parameters that
//! take one value only have no sensitivity.

use nalgebra::{DMatrix, DVector};

use musclefem_io::plot::{BarChart, BarPanel, BarSeries, LegendPosition};

/// The sensitivity of the output to every parameter with more than one value (`None`
/// for the others), or `None` altogether if the runs cannot determine them (fewer runs
/// than unknowns, or a zero mean output).
///
/// `runs` holds, for each finished run, its parameter values and its output.
pub fn normalised_sensitivities(runs: &[(Vec<f64>, f64)]) -> Option<Vec<Option<f64>>> {
    let count = runs.len();
    let parameters = runs.first()?.0.len();
    let mean_output = runs.iter().map(|r| r.1).sum::<f64>() / count as f64;
    let means: Vec<f64> = (0..parameters)
        .map(|j| runs.iter().map(|r| r.0[j]).sum::<f64>() / count as f64)
        .collect();
    let varied: Vec<usize> = (0..parameters)
        .filter(|&j| runs.iter().any(|r| r.0[j] != runs[0].0[j]) && means[j] != 0.0)
        .collect();
    if mean_output == 0.0 || !mean_output.is_finite() || count < varied.len() + 1 {
        return None;
    }
    let design = DMatrix::from_fn(count, varied.len() + 1, |i, k| {
        if k == 0 {
            1.0
        } else {
            let j = varied[k - 1];
            runs[i].0[j] / means[j] - 1.0
        }
    });
    let response = DVector::from_fn(count, |i, _| runs[i].1 / mean_output - 1.0);
    let coefficients = design.svd(true, true).solve(&response, 1e-12).ok()?;
    let mut sensitivities = vec![None; parameters];
    for (k, &j) in varied.iter().enumerate() {
        sensitivities[j] = Some(coefficients[k + 1]);
    }
    Some(sensitivities)
}

/// Bar chart of |S| per parameter, one series per output.
pub fn sensitivity_chart(
    title: &str,
    parameters: &[String],
    outputs: &[(&str, Vec<Option<f64>>)],
) -> BarChart {
    let mut panel = BarPanel::new(
        title,
        "|normalised sensitivity| (% output / % parameter)",
        parameters.iter().cloned(),
    )
    .with_x_label("parameter")
    .with_legend(LegendPosition::UpperRight);
    for (label, values) in outputs {
        panel = panel.with_series(BarSeries::new(
            *label,
            values.iter().map(|s| s.map_or(f64::NAN, f64::abs)),
        ));
    }
    BarChart::new("musclefem sweep: normalised sensitivity").with_panel(panel)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::grid::full_factorial;
    use crate::sweep::vary::Axis;
    use approx::assert_relative_eq;

    #[test]
    fn a_linear_response_on_a_grid_gives_its_elasticities() {
        // y = 3 + 2 a − 0.5 b: S_a = 2 ā / ȳ, S_b = −0.5 b̄ / ȳ; c is held fixed.
        let axes = [
            Axis {
                name: "a".into(),
                values: vec![1.0, 2.0, 3.0],
            },
            Axis {
                name: "b".into(),
                values: vec![10.0, 30.0],
            },
            Axis {
                name: "c".into(),
                values: vec![4.0],
            },
        ];
        let runs: Vec<(Vec<f64>, f64)> = full_factorial(&axes)
            .into_iter()
            .map(|p| {
                let y = 3.0 + 2.0 * p[0] - 0.5 * p[1];
                (p, y)
            })
            .collect();
        let mean_y = 3.0 + 2.0 * 2.0 - 0.5 * 20.0;
        let s = normalised_sensitivities(&runs).unwrap();
        assert_relative_eq!(s[0].unwrap(), 2.0 * 2.0 / mean_y, max_relative = 1e-12);
        assert_relative_eq!(s[1].unwrap(), -0.5 * 20.0 / mean_y, max_relative = 1e-12);
        assert_eq!(s[2], None);
    }

    #[test]
    fn too_few_runs_determine_nothing() {
        let runs = vec![(vec![1.0, 1.0], 2.0), (vec![2.0, 3.0], 5.0)];
        assert_eq!(normalised_sensitivities(&runs), None);
    }
}
