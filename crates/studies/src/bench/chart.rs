//! `work_precision.png`: per problem, error against wall time on log–log axes, one line
//! per method family (solver + element, its runs in order of time), the Pareto front
//! marked with squares. Failed runs and the reference are not drawn; a family whose every
//! run failed is named so in the legend.

use std::collections::BTreeMap;

use musclefem_io::plot::{Axes, Figure, LegendPosition, Panel, Series, SeriesStyle};

use super::csv::WorkPrecisionRow;
use super::pareto::pareto_front;

/// The figure of `rows`: one panel per problem, in order of first appearance.
pub fn work_precision_figure(rows: &[WorkPrecisionRow]) -> Figure {
    let mut problems: Vec<&str> = Vec::new();
    for row in rows {
        if !problems.contains(&row.problem.as_str()) {
            problems.push(&row.problem);
        }
    }
    let mut figure = Figure::new("Work–precision: error against wall time");
    for problem in problems {
        let runs: Vec<&WorkPrecisionRow> = rows.iter().filter(|r| r.problem == problem).collect();
        figure = figure.with_panel(problem_panel(problem, &runs));
    }
    figure.columns = Some(2.min(figure.panels.len().max(1)));
    figure.panel_size = (900, 680);
    figure
}

fn problem_panel(problem: &str, runs: &[&WorkPrecisionRow]) -> Panel {
    let mut families: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    for run in runs {
        families
            .entry(format!("{} {}", run.solver, run.element))
            .or_default()
            .push((run.wall_s, run.error));
    }
    let mut panel = Panel::new(
        problem,
        "wall time [s]",
        "relative error against the reference [1]",
    )
    .with_axes(Axes::LogLog)
    .with_legend(LegendPosition::UpperRight);
    for (family, mut points) in families {
        points.retain(|p| p.1.is_finite() && p.1 > 0.0);
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        let label = if points.is_empty() {
            format!("{family} (every run failed)")
        } else {
            family
        };
        panel =
            panel.with_series(Series::new(label, points).with_style(SeriesStyle::LineWithMarkers));
    }
    let points: Vec<(f64, f64)> = runs
        .iter()
        .map(|r| (r.wall_s, r.error))
        .map(|(t, e)| if e > 0.0 { (t, e) } else { (t, f64::NAN) })
        .collect();
    let front = pareto_front(&points);
    panel.with_series(
        Series::new("Pareto front", front.into_iter().map(|i| points[i]))
            .with_style(SeriesStyle::Markers),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_family_whose_every_run_failed_says_so_in_the_legend() {
        let row = |element: &str, wall_s: f64, error: f64| WorkPrecisionRow {
            problem: "knee".to_string(),
            solver: "implicit".to_string(),
            element: element.to_string(),
            mesh_size_mm: 12.753,
            step_setting: "increment=0.02s".to_string(),
            wall_s,
            error,
            error_metric: "m".to_string(),
        };
        let figure = work_precision_figure(&[
            row("hex8-fbar", 51.4, 0.117),
            row("hex8-one-point", 37.1, f64::NAN),
        ]);
        let labels: Vec<&str> = figure.panels[0]
            .series
            .iter()
            .map(|s| s.label.as_str())
            .collect();
        assert_eq!(
            labels,
            [
                "implicit hex8-fbar",
                "implicit hex8-one-point (every run failed)",
                "Pareto front"
            ]
        );
        assert_eq!(figure.panels[0].series[1].points, []);
    }
}
