//! The loading protocol of the paper's single-muscle tests (seed §2.2): one end fixed,
//! the other pulled along the axis at 5 mm/s for 2 s; in the active test both ends are
//! first held for 0.5 s while the muscle activates fully (n₂ = 1 from t₀ = 0).

use musclefem_materials::Amplitude;

/// Pulling speed of the moving end [m/s] (5 mm/s).
pub const PULL_SPEED: f64 = 0.005;
/// Duration of the pull [s].
pub const PULL_DURATION: f64 = 2.0;
/// Isometric hold before the pull in the active test [s].
pub const ACTIVE_HOLD: f64 = 0.5;

/// Passive (no activation) or active (fully activated during a hold, then pulled).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Mode {
    Passive,
    Active,
}

impl Mode {
    /// Lower-case name, as on the command line and in directory names.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Passive => "passive",
            Mode::Active => "active",
        }
    }

    /// Time before the pull starts [s].
    pub fn hold(self) -> f64 {
        match self {
            Mode::Passive => 0.0,
            Mode::Active => ACTIVE_HOLD,
        }
    }

    /// Duration of the whole test [s].
    pub fn duration(self) -> f64 {
        self.hold() + PULL_DURATION
    }

    /// Displacement of the pulled end along the axis against time [m]: zero during the
    /// hold, then 5 mm/s.
    pub fn pulled_end(self) -> Amplitude {
        let hold = self.hold();
        let knots = if hold > 0.0 {
            vec![
                (0.0, 0.0),
                (hold, 0.0),
                (hold + PULL_DURATION, PULL_SPEED * PULL_DURATION),
            ]
        } else {
            vec![(0.0, 0.0), (PULL_DURATION, PULL_SPEED * PULL_DURATION)]
        };
        Amplitude::new(knots).expect("the protocol's knots increase in time")
    }

    /// The Hill material's parameters for this mode on top of the given ones: full
    /// activation (n₂ = 1) from t₀ = 0 when active; no activation (n₂ = 0) when passive.
    pub fn activation_parameters(self) -> [(&'static str, f64); 2] {
        match self {
            Mode::Passive => [("n2", 0.0), ("t0", 0.0)],
            Mode::Active => [("n2", 1.0), ("t0", 0.0)],
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pulled_end_follows_the_protocol() {
        let passive = Mode::Passive.pulled_end();
        assert_eq!(passive.value_at(1.0), 0.005);
        assert_eq!(passive.value_at(2.0), 0.01);
        let active = Mode::Active.pulled_end();
        assert_eq!(active.value_at(0.5), 0.0);
        assert!((active.value_at(1.5) - 0.005).abs() < 1e-15);
        assert_eq!(Mode::Active.duration(), 2.5);
    }
}
