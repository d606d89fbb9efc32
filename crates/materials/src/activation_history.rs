//! A recorded activation history a(t): what drives a muscle material when its activation
//! comes from measurements (EMG envelopes, an OpenSim controls or states file) instead of
//! the paper's step of Eqs. 12–13.
//!
//! Two ways in:
//! - **activation levels** a(tᵢ) ∈ [0, 1], linear between samples, held outside them
//!   ([`ActivationHistory::from_levels`]);
//! - **excitations** u(tᵢ) ∈ [0, 1] (neural drive), turned into activation by the
//!   first-order activation dynamics of Thelen (2003, J Biomech Eng 125:70–77, after
//!   Winters 1995), the one OpenSim's muscles use ([`ActivationHistory::from_excitation`]):
//!
//!   da/dt = (u − a) / τ(u, a),  τ = τ_act (0.5 + 1.5 a) when u > a,
//!   τ = τ_deact / (0.5 + 1.5 a) otherwise,
//!
//!   with τ_act = 10 ms and τ_deact = 40 ms by default ([`ActivationDynamics`]). It is
//!   integrated with the classical Runge–Kutta scheme on steps of at most τ / 100 (τ the
//!   smaller constant; never across an excitation sample), and the result is kept as
//!   levels at those steps, so a run reads it like a recorded activation: read between
//!   the steps linearly, it is within 1e-4 of the exact solution (the steps' own error is
//!   far smaller).

use std::fmt;

use crate::Amplitude;

/// Time constants of the first-order activation dynamics [s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ActivationDynamics {
    /// τ_act [s]: how fast activation rises towards a larger excitation.
    pub activation_time_constant: f64,
    /// τ_deact [s]: how fast it falls towards a smaller one.
    pub deactivation_time_constant: f64,
}

impl Default for ActivationDynamics {
    /// OpenSim's defaults (Thelen 2003): τ_act = 10 ms, τ_deact = 40 ms.
    fn default() -> Self {
        ActivationDynamics {
            activation_time_constant: 0.010,
            deactivation_time_constant: 0.040,
        }
    }
}

impl ActivationDynamics {
    /// da/dt [1/s] at activation `a` under excitation `u`.
    pub fn rate(&self, excitation: f64, activation: f64) -> f64 {
        let scale = 0.5 + 1.5 * activation;
        let tau = if excitation > activation {
            self.activation_time_constant * scale
        } else {
            self.deactivation_time_constant / scale
        };
        (excitation - activation) / tau
    }
}

/// Why samples do not make an activation history.
#[derive(Debug, Clone, PartialEq)]
pub struct ActivationHistoryError(pub String);

impl fmt::Display for ActivationHistoryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ActivationHistoryError {}

/// Activation a(t) ∈ [0, 1] of a muscle, piecewise linear in time.
#[derive(Debug, Clone, PartialEq)]
pub struct ActivationHistory {
    /// Where it came from, for messages and logs (e.g. "excitation column vaslat_r of
    /// walk.sto").
    pub source: String,
    levels: Amplitude,
}

impl ActivationHistory {
    /// Activation levels (time [s], a ∈ [0, 1]) as recorded: times strictly increasing,
    /// every level within [0, 1].
    pub fn from_levels(
        source: impl Into<String>,
        samples: Vec<(f64, f64)>,
    ) -> Result<Self, ActivationHistoryError> {
        let source = source.into();
        check_unit_interval(&source, "activation", &samples)?;
        let levels = Amplitude::new(samples)
            .map_err(|e| ActivationHistoryError(format!("{source}: {}", e.0)))?;
        Ok(ActivationHistory { source, levels })
    }

    /// The activation that excitations (time [s], u ∈ [0, 1]) produce through
    /// `dynamics`, starting at rest (a = u at the first sample: a record starts in a
    /// steady state).
    pub fn from_excitation(
        source: impl Into<String>,
        samples: Vec<(f64, f64)>,
        dynamics: ActivationDynamics,
    ) -> Result<Self, ActivationHistoryError> {
        let source = source.into();
        check_unit_interval(&source, "excitation", &samples)?;
        for (name, tau) in [
            ("activation", dynamics.activation_time_constant),
            ("deactivation", dynamics.deactivation_time_constant),
        ] {
            if !(tau.is_finite() && tau > 0.0) {
                return Err(ActivationHistoryError(format!(
                    "{source}: the {name} time constant must be positive and finite, not {tau} s"
                )));
            }
        }
        let excitation = Amplitude::new(samples.clone())
            .map_err(|e| ActivationHistoryError(format!("{source}: {}", e.0)))?;
        // The time scales are τ_act (0.5 + 1.5 a) ≥ τ_act / 2 and τ_deact / (0.5 + 1.5 a)
        // ≥ τ_deact / 2: at τ / 100 the linear interpolation between steps stays within
        // h² |a''| / 8 ≈ 1e-4.
        let largest_step = dynamics
            .activation_time_constant
            .min(dynamics.deactivation_time_constant)
            / 100.0;
        let mut activation = samples[0].1;
        let mut levels = vec![(samples[0].0, activation)];
        for window in samples.windows(2) {
            let (start, end) = (window[0].0, window[1].0);
            let steps = ((end - start) / largest_step).ceil().max(1.0) as usize;
            let h = (end - start) / steps as f64;
            for i in 0..steps {
                let t = start + h * i as f64;
                // The last step ends exactly on the next sample.
                let next = if i + 1 == steps {
                    end
                } else {
                    start + h * (i + 1) as f64
                };
                activation = runge_kutta_step(&dynamics, &excitation, t, next - t, activation);
                levels.push((next, activation.clamp(0.0, 1.0)));
            }
        }
        let levels = Amplitude::new(levels)
            .map_err(|e| ActivationHistoryError(format!("{source}: {}", e.0)))?;
        Ok(ActivationHistory { source, levels })
    }

    /// a(t) [1].
    #[inline]
    pub fn level(&self, time: f64) -> f64 {
        self.levels.value_at(time)
    }

    /// Smallest and largest activation over [start, end] [s] (the samples inside and
    /// the ends).
    pub fn range(&self, start: f64, end: f64) -> (f64, f64) {
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        let inside = self
            .levels
            .knots()
            .iter()
            .filter(|(t, _)| *t >= start && *t <= end)
            .map(|&(_, a)| a);
        for a in inside.chain([self.level(start), self.level(end)]) {
            low = low.min(a);
            high = high.max(a);
        }
        (low, high)
    }

    /// The samples (time [s], activation), linear in between.
    pub fn samples(&self) -> &[(f64, f64)] {
        self.levels.knots()
    }

    /// The first and last time the history was sampled at [s].
    pub fn time_span(&self) -> (f64, f64) {
        self.levels.time_span()
    }
}

/// One classical Runge–Kutta step of da/dt = rate(u(t), a) from `t` over `h`.
fn runge_kutta_step(
    dynamics: &ActivationDynamics,
    excitation: &Amplitude,
    t: f64,
    h: f64,
    a: f64,
) -> f64 {
    let rate = |time: f64, activation: f64| dynamics.rate(excitation.value_at(time), activation);
    let k1 = rate(t, a);
    let k2 = rate(t + 0.5 * h, a + 0.5 * h * k1);
    let k3 = rate(t + 0.5 * h, a + 0.5 * h * k2);
    let k4 = rate(t + h, a + h * k3);
    a + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
}

fn check_unit_interval(
    source: &str,
    what: &str,
    samples: &[(f64, f64)],
) -> Result<(), ActivationHistoryError> {
    if samples.is_empty() {
        return Err(ActivationHistoryError(format!("{source}: no samples")));
    }
    if let Some((t, v)) = samples
        .iter()
        .find(|(_, v)| !(v.is_finite() && (0.0..=1.0).contains(v)))
    {
        return Err(ActivationHistoryError(format!(
            "{source}: {what} {v} at t = {t} s is outside [0, 1] (a percentage or an \
             unnormalised EMG? scale it to 0..1 first)"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rising from rest under u = 1, da/dt = (1 − a) / (τ_a (0.5 + 1.5 a)) separates:
    /// t / τ_a = −2 ln(1 − a) − 1.5 a.
    #[test]
    fn excitation_step_up_follows_the_closed_form() {
        let dynamics = ActivationDynamics::default();
        let samples = vec![(0.0, 0.0), (1e-9, 1.0), (0.2, 1.0)];
        let history = ActivationHistory::from_excitation("step", samples, dynamics).unwrap();
        let tau = dynamics.activation_time_constant;
        for a in [0.1f64, 0.5, 0.9, 0.99] {
            let t = tau * (-2.0 * (1.0 - a).ln() - 1.5 * a);
            let computed = history.level(t);
            assert!(
                (computed - a).abs() < 1e-4,
                "a({t}) = {computed}, closed form {a}"
            );
        }
    }

    /// Falling under u = 0 from a = 1: da/dt = −a (0.5 + 1.5 a) / τ_d separates:
    /// ln(a / (0.5 + 1.5 a)) − ln(1/2) = −t / (2 τ_d).
    #[test]
    fn excitation_step_down_follows_the_closed_form() {
        let dynamics = ActivationDynamics {
            activation_time_constant: 0.015,
            deactivation_time_constant: 0.05,
        };
        let samples = vec![(0.0, 1.0), (0.1, 1.0), (0.1 + 1e-9, 0.0), (0.6, 0.0)];
        let history = ActivationHistory::from_excitation("step", samples, dynamics).unwrap();
        assert!((history.level(0.1) - 1.0).abs() < 1e-12);
        let tau = dynamics.deactivation_time_constant;
        for a in [0.8f64, 0.4, 0.1, 0.01] {
            let t = 0.1 + 1e-9 - 2.0 * tau * ((a / (0.5 + 1.5 * a)).ln() - 0.5f64.ln());
            let computed = history.level(t);
            assert!(
                (computed - a).abs() < 1e-4,
                "a({t}) = {computed}, closed form {a}"
            );
        }
    }

    #[test]
    fn levels_are_interpolated_and_checked() {
        let history =
            ActivationHistory::from_levels("emg", vec![(0.0, 0.0), (1.0, 0.5), (2.0, 0.3)])
                .unwrap();
        assert_eq!(history.level(-1.0), 0.0);
        assert!((history.level(0.5) - 0.25).abs() < 1e-15);
        assert_eq!(history.level(5.0), 0.3);
        assert_eq!(history.range(0.0, 2.0), (0.0, 0.5));
        assert_eq!(history.range(1.5, 3.0), (0.3, 0.4));
        let percent = ActivationHistory::from_levels("emg", vec![(0.0, 0.0), (1.0, 50.0)]);
        assert!(percent.unwrap_err().0.contains("outside [0, 1]"));
        let backwards = ActivationHistory::from_levels("emg", vec![(1.0, 0.0), (0.0, 0.5)]);
        assert!(backwards.unwrap_err().0.contains("times must increase"));
    }
}
