//! `scaling.png`: wall time against unknowns on log–log axes, one line per code, solver
//! and Poisson's ratio, its fitted slope in the legend (lower right: the lines rise to the
//! right). Failed runs are not drawn.

use musclefem_io::plot::{Axes, Figure, LegendPosition, Panel, Series, SeriesStyle};

use super::case::ScalingRun;
use super::report::run_series;

/// The figure of `runs`.
pub fn scaling_figure(runs: &[ScalingRun]) -> Figure {
    let mut panel = Panel::new(
        "Implicit cube, 10 steps to stretch 1.5",
        "unknowns [1]",
        "wall time [s]",
    )
    .with_axes(Axes::LogLog)
    .with_legend(LegendPosition::LowerRight);
    for series in run_series(runs) {
        let label = match series.slope() {
            Some(slope) => format!("{} ({})", series.label(), slope.describe()),
            None => series.label(),
        };
        let mut points: Vec<(f64, f64)> = series
            .runs
            .iter()
            .filter(|r| r.failure.is_none())
            .map(|r| (r.unknowns as f64, r.wall_s))
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        panel =
            panel.with_series(Series::new(label, points).with_style(SeriesStyle::LineWithMarkers));
    }
    let mut figure = Figure::new("Scaling: wall time against unknowns").with_panel(panel);
    figure.panel_size = (1000, 700);
    figure
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_series_has_its_slope_in_the_legend() {
        let run = |solver: &str, n: usize, wall_s: f64| ScalingRun {
            code: "musclefem".into(),
            solver: solver.into(),
            divisions: n,
            poisson: 0.49,
            unknowns: n * n * n,
            wall_s,
            newton_iterations: 30,
            end_force_n: 1.0,
            peak_memory_bytes: None,
            failure: None,
        };
        let figure = scaling_figure(&[
            run("direct", 20, 8.0),
            run("direct", 40, 64.0),
            run("amg_cg", 20, 8.0),
        ]);
        let labels: Vec<&str> = figure.panels[0]
            .series
            .iter()
            .map(|s| s.label.as_str())
            .collect();
        // t ∝ n³ ∝ unknowns: slope 1.
        assert_eq!(
            labels,
            [
                "musclefem direct, ν = 0.49 (slope 1.00 over 20³–40³)",
                "musclefem amg_cg, ν = 0.49"
            ]
        );
        assert_eq!(
            figure.panels[0].series[0].points,
            [(8000.0, 8.0), (64000.0, 64.0)]
        );
    }
}
