//! The error of a run against the reference run of its problem.
//!
//! The reference is a run of the most trusted method (implicit F-bar hex8) on a finer mesh
//! and with a smaller step than any run of the matrix (see [`super::matrix`]). The error
//! is the largest deviation over the response's samples relative to the reference's
//! largest magnitude:
//!
//!   e = max_i |q_i − q_i^ref| / max_i |q_i^ref|   [1]

use super::Response;

/// e = max_i |q_i − q_i^ref| / max_i |q_i^ref| (NaN if the sample counts differ or the
/// reference is zero).
pub fn relative_error(response: &Response, reference: &Response) -> f64 {
    if response.samples.len() != reference.samples.len() {
        return f64::NAN;
    }
    let scale = reference
        .samples
        .iter()
        .fold(0.0_f64, |m, q| m.max(q.abs()));
    if scale == 0.0 {
        return f64::NAN;
    }
    let deviation = response
        .samples
        .iter()
        .zip(&reference.samples)
        .fold(0.0_f64, |m, (q, r)| m.max((q - r).abs()));
    deviation / scale
}

/// The value of the piecewise-linear history `points` (time-ordered (t, q)) at `time`;
/// `None` outside the recorded range.
pub fn sample_at(points: &[(f64, f64)], time: f64) -> Option<f64> {
    let tolerance = 1e-9 * time.abs().max(1.0);
    let after = points.iter().position(|p| p.0 >= time - tolerance)?;
    let upper = points[after];
    if after == 0 || upper.0 <= time {
        return Some(upper.1);
    }
    let lower = points[after - 1];
    let weight = (time - lower.0) / (upper.0 - lower.0);
    Some(lower.1 + weight * (upper.1 - lower.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_error_is_the_largest_deviation_over_the_largest_reference_value() {
        let response = |samples: Vec<f64>| Response {
            samples,
            warning: None,
        };
        let reference = response(vec![1.0, 2.0, 4.0]);
        let run = response(vec![1.2, 2.0, 3.9]);
        assert!((relative_error(&run, &reference) - 0.05).abs() < 1e-15);
        assert_eq!(relative_error(&reference, &reference), 0.0);
        let short = response(vec![1.0]);
        assert!(relative_error(&short, &reference).is_nan());
    }

    #[test]
    fn histories_are_sampled_linearly() {
        let points = [(0.0, 0.0), (0.4, 4.0), (1.0, 10.0)];
        assert_eq!(sample_at(&points, 0.2), Some(2.0));
        assert_eq!(sample_at(&points, 1.0), Some(10.0));
        assert!((sample_at(&points, 0.7).unwrap() - 7.0).abs() < 1e-12);
        assert_eq!(sample_at(&points, 1.5), None);
    }
}
