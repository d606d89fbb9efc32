//! The scalar functions of the Hill-type muscle model (seed Eqs. 5–13), each a pure
//! function of its arguments so that it can be tested against the printed definitions.

/// Force–length relation f_λ (seed Eq. 10) of the ratio r = λ̄_f / λ_opt [1]:
///
/// | r            | f_λ              |
/// |--------------|------------------|
/// | r < 0.4      | 0                |
/// | 0.4 ≤ r < 0.6| 9 (r − 0.4)²     |
/// | 0.6 ≤ r < 1.4| 1 − 4 (1 − r)²   |
/// | 1.4 ≤ r < 1.6| 9 (r − 1.6)²     |
/// | r ≥ 1.6      | 0                |
///
/// Continuous (0.36 at r = 0.6 and 1.4), maximum 1 at r = 1.
#[inline]
pub fn force_length(r: f64) -> f64 {
    if r < 0.4 {
        0.0
    } else if r < 0.6 {
        9.0 * (r - 0.4) * (r - 0.4)
    } else if r < 1.4 {
        1.0 - 4.0 * (1.0 - r) * (1.0 - r)
    } else if r < 1.6 {
        9.0 * (r - 1.6) * (r - 1.6)
    } else {
        0.0
    }
}

/// Constants of the force–velocity relation (seed Eq. 11).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceVelocity {
    /// Curvature of the concentric branch k_c [1].
    pub k_c: f64,
    /// Curvature factor of the eccentric branch k_e [1].
    pub k_e: f64,
    /// Eccentric offset d [1] (≥ 1).
    pub d: f64,
    /// Minimum (most negative) CE stretch rate λ̇_m^min [1/s] (< 0).
    pub lambda_dot_min: f64,
}

impl ForceVelocity {
    /// f_v(λ̇_m) and its derivative df_v/dλ̇_m [s], with r = λ̇_m / λ̇_m^min:
    /// - shortening (λ̇_m ≤ 0, r ≥ 0): f_v = (1 − r)/(1 + k_c r);
    /// - lengthening (λ̇_m > 0, r < 0): f_v = d − (d − 1)(1 + r)/(1 − k_c k_e r).
    ///
    /// Both branches are 1 at λ̇_m = 0; f_v increases with λ̇_m on both (for d ≥ 1),
    /// tending to −1/k_c for fast shortening and d + (d − 1)/(k_c k_e) for fast
    /// lengthening. At λ̇_m = 0 the derivative of the shortening branch is returned.
    #[inline]
    pub fn value_and_slope(&self, lambda_dot_m: f64) -> (f64, f64) {
        let (value, slope, _) = self.value_slope_curvature(lambda_dot_m);
        (value, slope)
    }

    /// f_v, df_v/dλ̇_m [s] and d²f_v/dλ̇_m² [s²]. With D the branch's denominator:
    /// - shortening, D = 1 + k_c r: f_v' = −(1 + k_c)/D² · dr, f_v'' = 2 k_c (1 + k_c)/D³ · dr²;
    /// - lengthening, D = 1 − K r, K = k_c k_e: f_v' = −(d − 1)(1 + K)/D² · dr,
    ///   f_v'' = −2 K (d − 1)(1 + K)/D³ · dr²;
    ///
    /// where dr = dr/dλ̇_m = 1/λ̇_m^min.
    #[inline]
    pub fn value_slope_curvature(&self, lambda_dot_m: f64) -> (f64, f64, f64) {
        let dr = 1.0 / self.lambda_dot_min;
        let r = lambda_dot_m * dr;
        if lambda_dot_m <= 0.0 {
            let inverse = 1.0 / (1.0 + self.k_c * r);
            let value = (1.0 - r) * inverse;
            let slope = -(1.0 + self.k_c) * inverse * inverse;
            let curvature = -2.0 * self.k_c * slope * inverse;
            (value, slope * dr, curvature * dr * dr)
        } else {
            let kk = self.k_c * self.k_e;
            let inverse = 1.0 / (1.0 - kk * r);
            let value = self.d - (self.d - 1.0) * (1.0 + r) * inverse;
            let slope = -(self.d - 1.0) * (1.0 + kk) * inverse * inverse;
            let curvature = 2.0 * kk * slope * inverse;
            (value, slope * dr, curvature * dr * dr)
        }
    }

    /// f_v(λ̇_m) alone.
    #[inline]
    pub fn value(&self, lambda_dot_m: f64) -> f64 {
        self.value_and_slope(lambda_dot_m).0
    }

    /// The CE stretch rate at which f_v = `value`, the inverse of f_v, for
    /// inf f_v < value < sup f_v (values outside are clamped just inside):
    /// - value ≤ 1 (shortening): r = (1 − y)/(1 + k_c y);
    /// - value > 1 (lengthening): r = (y − 1)/(y K − Q), K = k_c k_e, Q = d K + d − 1;
    ///
    /// and λ̇_m = r λ̇_m^min [1/s].
    #[inline]
    pub fn rate_for_value(&self, value: f64) -> f64 {
        let margin = 1e-9;
        let y = value.clamp(self.infimum() + margin, self.supremum() - margin);
        let r = if y <= 1.0 {
            (1.0 - y) / (1.0 + self.k_c * y)
        } else {
            let kk = self.k_c * self.k_e;
            let q = self.d * kk + self.d - 1.0;
            (y - 1.0) / (y * kk - q)
        };
        r * self.lambda_dot_min
    }

    /// sup f_v = d + (d − 1)/(k_c k_e), the limit of fast lengthening.
    #[inline]
    pub fn supremum(&self) -> f64 {
        self.d + (self.d - 1.0) / (self.k_c * self.k_e)
    }

    /// inf f_v = −1/k_c, the limit of fast shortening.
    #[inline]
    pub fn infimum(&self) -> f64 {
        -1.0 / self.k_c
    }
}

/// Activation constants (seed Eqs. 12–13).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Activation {
    /// Level before activation and after deactivation n₁ [1].
    pub n1: f64,
    /// Level reached during activation n₂ [1].
    pub n2: f64,
    /// Activation time t₀ [s].
    pub t0: f64,
    /// Deactivation time t₁ [s] (may be +∞: never).
    pub t1: f64,
    /// Rate S [1/s].
    pub rate: f64,
}

impl Activation {
    /// h_t(t_j, t_k) = 1 − exp(−S (t_j − t_k)) (seed Eq. 13).
    #[inline]
    fn rise(&self, tj: f64, tk: f64) -> f64 {
        1.0 - (-self.rate * (tj - tk)).exp()
    }

    /// f_t(t) (seed Eq. 12):
    /// n₁ for t ≤ t₀; n₁ + (n₂ − n₁) h_t(t, t₀) for t₀ < t ≤ t₁;
    /// n₁ + (n₂ − n₁) h_t(t₁, t₀) − (n₂ − n₁) h_t(t₁, t₀) h_t(t, t₁) for t > t₁.
    #[inline]
    pub fn level(&self, t: f64) -> f64 {
        let span = self.n2 - self.n1;
        if t <= self.t0 {
            self.n1
        } else if t <= self.t1 {
            self.n1 + span * self.rise(t, self.t0)
        } else {
            let reached = span * self.rise(self.t1, self.t0);
            self.n1 + reached - reached * self.rise(t, self.t1)
        }
    }
}

/// Parallel element stress σ_PE = σ₀ A (λ̄_f − λ_PE)² for λ̄_f > λ_PE, else 0 (seed
/// Eqs. 5–6 with the slack stretch λ_PE = `slack`, 1 in the paper), and its derivative
/// dσ_PE/dλ̄_f [Pa].
#[inline]
pub fn parallel_element(sigma0: f64, a: f64, slack: f64, fiber_stretch: f64) -> (f64, f64) {
    if fiber_stretch > slack {
        let e = fiber_stretch - slack;
        (sigma0 * a * e * e, 2.0 * sigma0 * a * e)
    } else {
        (0.0, 0.0)
    }
}

/// The matrix's slack along the fiber (a project extension; λ_M = 1 is the paper's matrix).
///
/// Ī₁ − 3 splits into a part that an isochoric stretch along the fiber does not change
/// and the uniaxial part e(λ̄_f) = λ̄_f² + 2/λ̄_f − 3 (Ī₁ − Ī₄ ≥ 2/λ̄_f for det C̄ = 1, so
/// the first part is ≥ 0). With a slack λ_M the matrix energy takes
/// W_I = c [exp(b E) − 1], E = Ī₁ − 3 − e(λ̄_f) + e(λ*),
/// λ* = λ̄_f below 1, 1 between 1 and λ_M (the crimped matrix is slack along the fiber),
/// λ̄_f − (λ_M − 1) beyond: the paper's matrix, shifted to start at λ_M. e and e' vanish
/// at 1, so E and its slope are continuous.
///
/// Returns (ΔE, x, x') with ΔE = e(λ*) − e(λ̄_f), x = dΔE/dλ̄_f and x' = d²ΔE/dλ̄_f²:
/// the matrix adds the nominal fiber stress W₁ x to σ_PE + σ_SEE, W₁ = b c exp(b E).
/// All three are exactly 0 for λ_M = 1 or λ̄_f ≤ 1.
#[inline]
pub fn matrix_slack(slack: f64, fiber_stretch: f64) -> (f64, f64, f64) {
    let e = |l: f64| l * l + 2.0 / l - 3.0;
    let de = |l: f64| 2.0 * l - 2.0 / (l * l);
    let dde = |l: f64| 2.0 + 4.0 / (l * l * l);
    let l = fiber_stretch;
    if slack <= 1.0 || l <= 1.0 {
        (0.0, 0.0, 0.0)
    } else if l <= slack {
        (-e(l), -de(l), -dde(l))
    } else {
        let shifted = l - (slack - 1.0);
        (
            e(shifted) - e(l),
            de(shifted) - de(l),
            dde(shifted) - dde(l),
        )
    }
}

/// Series elastic element stress σ_SEE = β (exp(α (λ_s − 1)) − 1) (seed Eq. 8) [Pa].
#[inline]
pub fn series_elastic(alpha: f64, beta: f64, lambda_s: f64) -> f64 {
    beta * ((alpha * (lambda_s - 1.0)).exp() - 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TABLE_1: ForceVelocity = ForceVelocity {
        k_c: 4.0,
        k_e: 5.0,
        d: 1.45,
        lambda_dot_min: -17.0,
    };

    /// Values straight from the printed piecewise definition of Eq. 10.
    #[test]
    fn force_length_matches_the_printed_pieces() {
        assert_eq!(force_length(0.3), 0.0);
        assert!((force_length(0.5) - 9.0 * 0.01).abs() < 1e-15);
        assert!((force_length(0.8) - (1.0 - 4.0 * 0.04)).abs() < 1e-15);
        assert_eq!(force_length(1.0), 1.0);
        assert!((force_length(1.5) - 9.0 * 0.01).abs() < 1e-15);
        assert_eq!(force_length(1.7), 0.0);
    }

    #[test]
    fn force_length_is_continuous_at_its_breakpoints() {
        for r in [0.4, 0.6, 1.4, 1.6] {
            let jump = (force_length(r + 1e-12) - force_length(r - 1e-12)).abs();
            assert!(jump < 1e-10, "jump {jump} at r = {r}");
        }
        assert!((force_length(0.6) - 0.36).abs() < 1e-14);
        assert!((force_length(1.4) - 0.36).abs() < 1e-14);
    }

    #[test]
    fn force_velocity_matches_the_printed_branches() {
        // Shortening at λ̇_m = −8.5 /s: r = 0.5, f_v = 0.5 / 3.
        assert!((TABLE_1.value(-8.5) - 0.5 / 3.0).abs() < 1e-15);
        // Maximum shortening velocity: f_v = 0.
        assert!(TABLE_1.value(-17.0).abs() < 1e-15);
        // Lengthening at λ̇_m = 1.7 /s: r = −0.1, f_v = 1.45 − 0.45 · 0.9 / 3.
        assert!((TABLE_1.value(1.7) - (1.45 - 0.45 * 0.9 / 3.0)).abs() < 1e-15);
        // Isometric.
        assert_eq!(TABLE_1.value(0.0), 1.0);
    }

    #[test]
    fn force_velocity_is_continuous_and_increasing() {
        let jump = (TABLE_1.value(1e-12) - TABLE_1.value(-1e-12)).abs();
        assert!(jump < 1e-10);
        let mut previous = f64::NEG_INFINITY;
        for i in -400..=400 {
            let rate = i as f64 * 0.1;
            let (value, slope) = TABLE_1.value_and_slope(rate);
            assert!(value > previous, "f_v not increasing at {rate}");
            assert!(slope >= 0.0);
            assert!(value > TABLE_1.infimum() && value < TABLE_1.supremum());
            previous = value;
            // Slope and curvature against central differences away from the kink at 0.
            if rate.abs() > 1e-3 {
                let h = 1e-6;
                let fd = (TABLE_1.value(rate + h) - TABLE_1.value(rate - h)) / (2.0 * h);
                assert!((fd - slope).abs() < 1e-6 * slope.abs().max(1e-3), "{rate}");
                let (_, curvature) = (0, TABLE_1.value_slope_curvature(rate).2);
                let h = 1e-4;
                let fd2 = (TABLE_1.value_and_slope(rate + h).1
                    - TABLE_1.value_and_slope(rate - h).1)
                    / (2.0 * h);
                assert!(
                    (fd2 - curvature).abs() < 1e-5 * curvature.abs().max(1e-4),
                    "{rate}"
                );
            }
        }
    }

    #[test]
    fn rate_for_value_inverts_force_velocity() {
        for i in -300..=300 {
            let rate = i as f64 * 0.1;
            let back = TABLE_1.rate_for_value(TABLE_1.value(rate));
            assert!(
                (back - rate).abs() < 1e-9 * (1.0 + rate.abs()),
                "{rate} -> {back}"
            );
        }
    }

    #[test]
    fn activation_matches_eq_12_and_is_continuous() {
        let act = Activation {
            n1: 0.1,
            n2: 0.9,
            t0: 0.2,
            t1: 1.0,
            rate: 50.0,
        };
        assert_eq!(act.level(0.0), 0.1);
        assert_eq!(act.level(0.2), 0.1);
        let expected = 0.1 + 0.8 * (1.0 - (-50.0f64 * 0.3).exp());
        assert!((act.level(0.5) - expected).abs() < 1e-15);
        let reached = 0.8 * (1.0 - (-50.0f64 * 0.8).exp());
        let after = 0.1 + reached - reached * (1.0 - (-50.0f64 * 0.1).exp());
        assert!((act.level(1.1) - after).abs() < 1e-15);
        for t in [0.2, 1.0] {
            assert!((act.level(t + 1e-12) - act.level(t - 1e-12)).abs() < 1e-9);
        }
        // Long after deactivation it returns to n1.
        assert!((act.level(10.0) - 0.1).abs() < 1e-12);
    }

    #[test]
    fn element_stresses_vanish_at_rest() {
        assert_eq!(parallel_element(7e5, 4.0, 1.0, 1.0), (0.0, 0.0));
        assert_eq!(parallel_element(7e5, 4.0, 1.0, 0.9), (0.0, 0.0));
        // A slack element starts later: at λ_PE = 1.1 the stress at 1.2 is the paper's
        // at 1.1.
        assert_eq!(parallel_element(7e5, 4.0, 1.1, 1.05), (0.0, 0.0));
        let shifted = parallel_element(7e5, 4.0, 1.1, 1.2);
        let paper = parallel_element(7e5, 4.0, 1.0, 1.1);
        assert!((shifted.0 - paper.0).abs() < 1e-12 * paper.0);
        assert!((shifted.1 - paper.1).abs() < 1e-12 * paper.1);
        let (s, ds) = parallel_element(7e5, 4.0, 1.0, 1.1);
        assert!((s - 7e5 * 4.0 * 0.01).abs() < 1e-6 && (ds - 7e5 * 8.0 * 0.1).abs() < 1e-6);
        assert_eq!(series_elastic(10.0, 1e3, 1.0), 0.0);
    }
}
