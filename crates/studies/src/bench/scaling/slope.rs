//! The growth exponent of the time with the problem size: the least-squares slope p of
//! log t = p log N + c over measured (N, t), N the unknowns and t the wall time. The
//! issue's criterion reads it from 20³ to 40³ ([`FIT_DIVISIONS`]).

use std::ops::RangeInclusive;

/// Cubes whose times the slope is fitted to when at least two of them were run (n, the
/// elements per edge); otherwise every size of the series is used.
pub const FIT_DIVISIONS: RangeInclusive<usize> = 20..=40;

/// The least-squares slope of log y against log x of `points` (x, y); `None` with fewer
/// than two usable points (finite and positive) or no spread in x.
pub fn log_log_slope(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if logs.len() < 2 {
        return None;
    }
    let count = logs.len() as f64;
    let mean_x = logs.iter().map(|p| p.0).sum::<f64>() / count;
    let mean_y = logs.iter().map(|p| p.1).sum::<f64>() / count;
    let covariance: f64 = logs.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    let variance: f64 = logs.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    (variance > 0.0).then(|| covariance / variance)
}

/// A series' fitted slope and the cubes it was fitted over.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FittedSlope {
    pub slope: f64,
    /// Smallest and largest n of the fit.
    pub from: usize,
    pub to: usize,
}

impl FittedSlope {
    /// E.g. "slope 1.46 over 20³–40³".
    pub fn describe(&self) -> String {
        format!("slope {:.2} over {}³–{}³", self.slope, self.from, self.to)
    }
}

/// The slope of time against unknowns of one series of (n, unknowns, time [s]): over the
/// cubes in [`FIT_DIVISIONS`] when there are two or more of them, else over all.
pub fn fitted_slope(runs: &[(usize, f64, f64)]) -> Option<FittedSlope> {
    let in_range: Vec<&(usize, f64, f64)> = runs
        .iter()
        .filter(|run| FIT_DIVISIONS.contains(&run.0) && run.2.is_finite())
        .collect();
    let chosen: Vec<&(usize, f64, f64)> = if in_range.len() >= 2 {
        in_range
    } else {
        runs.iter().filter(|run| run.2.is_finite()).collect()
    };
    let points: Vec<(f64, f64)> = chosen.iter().map(|run| (run.1, run.2)).collect();
    let slope = log_log_slope(&points)?;
    Some(FittedSlope {
        slope,
        from: chosen.iter().map(|run| run.0).min()?,
        to: chosen.iter().map(|run| run.0).max()?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_power_law_gives_its_exponent() {
        let points: Vec<(f64, f64)> = [3e3, 2.6e4, 8.6e4, 2e5]
            .iter()
            .map(|&n: &f64| (n, 4e-5 * n.powf(1.5)))
            .collect();
        let slope = log_log_slope(&points).unwrap();
        assert!((slope - 1.5).abs() < 1e-12, "{slope}");
    }

    #[test]
    fn too_few_points_have_no_slope() {
        assert_eq!(log_log_slope(&[(10.0, 1.0)]), None);
        assert_eq!(log_log_slope(&[(10.0, 1.0), (10.0, 2.0)]), None);
        assert_eq!(log_log_slope(&[(10.0, 1.0), (20.0, f64::NAN)]), None);
    }

    #[test]
    fn the_fit_takes_20_to_40_cubed_when_measured_and_all_sizes_otherwise() {
        // Time ∝ N below 20³, ∝ N² from 20³ on: the fit sees only the upper part.
        let runs = [
            (10, 1e3, 1.0),
            (20, 1e4, 10.0),
            (30, 2e4, 40.0),
            (40, 4e4, 160.0),
        ];
        let fit = fitted_slope(&runs).unwrap();
        assert!((fit.slope - 2.0).abs() < 1e-12, "{fit:?}");
        assert_eq!((fit.from, fit.to), (20, 40));
        assert_eq!(fit.describe(), "slope 2.00 over 20³–40³");

        let small = fitted_slope(&runs[..2]).unwrap();
        assert!((small.slope - 1.0).abs() < 1e-12, "{small:?}");
        assert_eq!((small.from, small.to), (10, 20));
    }
}
