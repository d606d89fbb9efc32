//! Piecewise-linear functions of time: stretch histories of the material-point driver and
//! the amplitudes of prescribed motions in the finite-element solvers.

use std::fmt;

/// A piecewise-linear function of time through knots (time [s], value), strictly
/// increasing in time; constant before the first and after the last knot.
#[derive(Debug, Clone, PartialEq)]
pub struct Amplitude {
    knots: Vec<(f64, f64)>,
}

/// Why knots do not make an amplitude.
#[derive(Debug, Clone, PartialEq)]
pub struct AmplitudeError(pub String);

impl fmt::Display for AmplitudeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "amplitude: {}", self.0)
    }
}

impl std::error::Error for AmplitudeError {}

impl Amplitude {
    /// Knots must be finite, at least one, with strictly increasing times.
    pub fn new(knots: Vec<(f64, f64)>) -> Result<Self, AmplitudeError> {
        if knots.is_empty() {
            return Err(AmplitudeError("needs at least one knot".to_string()));
        }
        if let Some(k) = knots.iter().find(|(t, v)| !t.is_finite() || !v.is_finite()) {
            return Err(AmplitudeError(format!("knot {k:?} is not finite")));
        }
        if let Some(w) = knots.windows(2).find(|w| w[1].0 <= w[0].0) {
            return Err(AmplitudeError(format!(
                "times must increase: knot {:?} follows {:?}",
                w[1], w[0]
            )));
        }
        Ok(Amplitude { knots })
    }

    /// A linear ramp from 0 at t = 0 to `value` at `time`, then constant.
    pub fn ramp(time: f64, value: f64) -> Result<Self, AmplitudeError> {
        Amplitude::new(vec![(0.0, 0.0), (time, value)])
    }

    /// First and last knot times [s].
    pub fn time_span(&self) -> (f64, f64) {
        (self.knots[0].0, self.knots[self.knots.len() - 1].0)
    }

    /// The knots (time [s], value).
    pub fn knots(&self) -> &[(f64, f64)] {
        &self.knots
    }

    /// Value at time `t` (linear between knots, constant outside). The interval is found
    /// by bisection: recorded histories have thousands of knots.
    pub fn value_at(&self, t: f64) -> f64 {
        let k = &self.knots;
        if t <= k[0].0 {
            return k[0].1;
        }
        // The first knot at or after t; knots before it are earlier than t.
        let next = k.partition_point(|&(time, _)| time < t);
        if next == k.len() {
            return k[k.len() - 1].1;
        }
        let ((t0, v0), (t1, v1)) = (k[next - 1], k[next]);
        v0 + (v1 - v0) * (t - t0) / (t1 - t0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_and_holds() {
        let a = Amplitude::new(vec![(0.0, 1.0), (0.5, 1.0), (2.5, 1.2)]).unwrap();
        assert_eq!(a.value_at(-1.0), 1.0);
        assert!((a.value_at(1.5) - 1.1).abs() < 1e-15);
        assert_eq!(a.value_at(3.0), 1.2);
        assert_eq!(a.time_span(), (0.0, 2.5));
    }

    #[test]
    fn rejects_bad_knots() {
        assert!(Amplitude::new(vec![]).is_err());
        assert!(Amplitude::new(vec![(0.0, 1.0), (0.0, 2.0)]).is_err());
        assert!(Amplitude::new(vec![(0.0, f64::NAN)]).is_err());
    }
}
