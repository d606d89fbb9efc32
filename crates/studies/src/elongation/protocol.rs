//! The loading protocol of the paper's single-muscle tests (seed §2.2): one end fixed,
//! the other pulled along the axis at 5 mm/s to an elongation of 10 mm (20 % strain); in
//! the active test both ends are first held for 0.5 s while the muscle activates fully
//! (n₂ = 1 from t₀ = 0).
//!
//! The pull reaches its speed over the first [`SPEED_RAMP`] = 0.1 s at constant
//! acceleration (ten linear pieces), not at once: a velocity jump is a shock that rings
//! through a mass-scaled explicit model (it put ±5 kPa oscillations on the passive curve
//! at 10⁻² of the mass scaling used, against 14 kPa at 10 % strain). The pull then lasts
//! 2.05 s instead of 2 s to reach the same 10 mm; both solvers follow the same history.

use musclefem_materials::Amplitude;

/// Pulling speed of the moving end [m/s] (5 mm/s).
pub const PULL_SPEED: f64 = 0.005;
/// Elongation at the end of the pull [m] (10 mm: 20 % of the 50 mm specimen).
pub const PULL_ELONGATION: f64 = 0.010;
/// Time over which the pull accelerates to its speed [s].
pub const SPEED_RAMP: f64 = 0.1;
/// Linear pieces of the speed ramp's parabola.
const RAMP_PIECES: usize = 10;
/// Duration of the pull [s]: the ramp costs half its length, 2 s + 0.05 s.
pub const PULL_DURATION: f64 = PULL_ELONGATION / PULL_SPEED + 0.5 * SPEED_RAMP;
/// Isometric hold before the pull in the active test [s].
pub const ACTIVE_HOLD: f64 = 0.5;

/// The elongation tests' activation: passive, or active (fully activated during a
/// 0.5 s hold at the rest length, then pulled).
pub use crate::activation::Activation;

/// The elongation protocol of each activation.
impl Activation {
    /// Time before the pull starts [s].
    pub fn hold(self) -> f64 {
        match self {
            Activation::Passive => 0.0,
            Activation::Active => ACTIVE_HOLD,
        }
    }

    /// Duration of the whole test [s].
    pub fn duration(self) -> f64 {
        self.hold() + PULL_DURATION
    }

    /// Displacement of the pulled end along the axis against time [m]: zero during the
    /// hold, u = v τ²/(2 t_r) over the speed ramp (τ the time since the pull began,
    /// sampled at ten knots), then u = v (τ − t_r/2), to 10 mm.
    pub fn pulled_end(self) -> Amplitude {
        Amplitude::new(self.pulled_end_knots()).expect("the protocol's knots increase in time")
    }

    /// The (time [s], displacement [m]) knots of [`Activation::pulled_end`].
    pub fn pulled_end_knots(self) -> Vec<(f64, f64)> {
        let hold = self.hold();
        let mut knots = vec![(0.0, 0.0)];
        if hold > 0.0 {
            knots.push((hold, 0.0));
        }
        for piece in 1..=RAMP_PIECES {
            let tau = SPEED_RAMP * piece as f64 / RAMP_PIECES as f64;
            knots.push((hold + tau, PULL_SPEED * tau * tau / (2.0 * SPEED_RAMP)));
        }
        knots.push((hold + PULL_DURATION, PULL_ELONGATION));
        knots
    }

    /// The Hill material's parameters for this mode on top of the given ones: full
    /// activation (n₂ = 1) from t₀ = 0 when active; no activation (n₂ = 0) when passive.
    pub fn activation_parameters(self) -> [(&'static str, f64); 2] {
        match self {
            Activation::Passive => [("n2", 0.0), ("t0", 0.0)],
            Activation::Active => [("n2", 1.0), ("t0", 0.0)],
        }
    }
}

/// How the ends are held.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Grips {
    /// The end faces are clamped: every component held (the pulled end moves along the
    /// axis only).
    Fixed,
    /// Only the axial displacement of the end faces is prescribed: lateral contraction is
    /// free (rigid-body motion is removed at two nodes of the fixed end).
    Sliding,
}

impl Grips {
    /// `fixed` or `sliding` (as on the command line).
    pub fn name(self) -> &'static str {
        match self {
            Grips::Fixed => "fixed",
            Grips::Sliding => "sliding",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pulled_end_follows_the_protocol() {
        let passive = Activation::Passive.pulled_end();
        // After the ramp: 5 mm/s, 0.25 mm behind an instant start.
        assert!((passive.value_at(1.0) - 0.00475).abs() < 1e-15);
        assert!((passive.value_at(1.5) - passive.value_at(0.5) - 0.005).abs() < 1e-15);
        assert!((passive.value_at(Activation::Passive.duration()) - 0.01).abs() < 1e-15);
        // On the ramp: the parabola at its knots.
        assert!((passive.value_at(0.05) - 0.005 * 0.05 * 0.05 / 0.2).abs() < 1e-15);
        let active = Activation::Active.pulled_end();
        assert_eq!(active.value_at(0.5), 0.0);
        assert!((active.value_at(1.5) - 0.00475).abs() < 1e-15);
        assert!((Activation::Active.duration() - 2.55).abs() < 1e-15);
    }
}
