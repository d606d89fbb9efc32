//! The per-step equation of the series elastic element (SEE) and the contractile element
//! (CE) in series (seed Eq. 14), solved for the SEE stretch increment Δλ_s.
//!
//! # Derivation (our own; the printed coefficients, Eqs. 15–23, have slips)
//!
//! Let Δλ_s = λ_s(t+Δt) − λ_s(t), σ_s = σ_SEE(t), and T = Δt λ̇_m^min (< 0).
//!
//! - SEE (Eq. 7): σ_SEE(t+Δt) = (σ_s + β) e^{αΔλ_s} − β.
//! - Length relation (Eq. 19 read as in docs/design.md): (1 + k) λ̄_f = λ_m + k λ_s at t and
//!   t+Δt, so Δλ_m = w₁ − k Δλ_s with w₁ = (1 + k) λ̄_f(t+Δt) − λ_m(t) − k λ_s(t), and the
//!   CE rate (backward Euler) is λ̇_m = (w₁ − k Δλ_s)/Δt, i.e. r = λ̇_m/λ̇_m^min =
//!   (w₁ − k Δλ_s)/T.
//! - CE (Eq. 9, σ₀ kept): σ_CE = a f_v(r) with a = σ₀ f_λ(λ̄_f(t)) f_t(t+Δt).
//!
//! Setting σ_SEE = σ_CE and multiplying by the (positive) denominator of f_v:
//!
//! *Shortening* (λ̇_m ≤ 0, r ≥ 0), f_v = (1 − r)/(1 + k_c r):
//! [(σ_s+β) e^{αΔλ_s} − β](1 + k_c r) = a (1 − r), which is
//! f(Δλ_s) = (w₂ + w₃Δλ_s) e^{αΔλ_s} − w₄Δλ_s − w₅ = 0 with
//! - w₂ = (σ_s + β)(1 + k_c w₁/T)                      (Eq. 15)
//! - w₃ = −(σ_s + β) k k_c / T                          (Eq. 16)
//! - w₄ = k (a − β k_c)/T                               (Eq. 17, with σ₀ in a)
//! - w₅ = β + a − (a − β k_c) w₁/T                       (Eq. 18, with σ₀ in a; the print
//!   multiplies only β k_c by w₁, but the whole bracket carries it)
//!
//! *Lengthening* (λ̇_m > 0, r < 0), f_v = (1 − Q r)/(1 − K r) with K = k_c k_e and
//! Q = d K + d − 1 (the same as d − (d−1)(1+r)/(1−K r)):
//! [(σ_s+β) e^{αΔλ_s} − β](1 − K r) = a (1 − Q r), giving
//! - w₂ = (σ_s + β)(1 − K w₁/T)                         (Eq. 20 with w₁, not α₁)
//! - w₃ = (σ_s + β) k K / T                             (Eq. 21)
//! - w₄ = k (β K + a Q)/T                               (Eq. 22, with σ₀ in a)
//! - w₅ = β + a − (a Q + β K) w₁/T                       (Eq. 23: the printed bracket has
//!   the opposite sign; 1 − d(1 + K) = −Q)
//!
//! # How it is solved
//!
//! We solve the equivalent, better scaled h(Δλ_s) = σ_SEE(Δλ_s) − σ_CE(Δλ_s) = 0 (f is
//! h times a positive denominator, so the roots and signs agree; a test checks f = 0 at
//! the solution). h is continuous and strictly increasing (σ_SEE increases with Δλ_s,
//! f_v increases with λ̇_m, which decreases with Δλ_s), so the root is unique, and since
//! −a/k_c < σ_CE ≤ a sup f_v, it lies in a bracket known in closed form:
//! - upper: σ_SEE = a sup f_v;
//! - lower: the smaller of Δλ_s = w₁/k (λ̇_m = 0; a shortening root lies above it) and
//!   σ_SEE = 0 (a lengthening root has σ_SEE ≥ a ≥ 0).
//!
//! Newton's method runs inside the bracket, falling back to bisection whenever a step
//! would leave it, so the result is always finite and within the bracket.
//!
//! Special cases: a = 0 (no activation) gives σ_SEE = 0, λ_s = 1; Δt = 0 gives
//! Δλ_s = w₁/k (the CE cannot move in no time: the SEE takes the whole stretch).

use super::functions::ForceVelocity;

/// Inputs of the local equation at one point for one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalEquation {
    /// SEE stiffness factor α [1].
    pub alpha: f64,
    /// SEE stress scale β [Pa].
    pub beta: f64,
    /// CE/SEE length ratio k [1].
    pub k: f64,
    /// Force–velocity constants.
    pub force_velocity: ForceVelocity,
    /// Step Δt [s].
    pub dt: f64,
    /// SEE stretch at the start of the step λ_s(t).
    pub lambda_s: f64,
    /// SEE stress at the start of the step σ_s(t) [Pa].
    pub series_stress: f64,
    /// w₁ = (1 + k) λ̄_f(t+Δt) − λ_m(t) − k λ_s(t) (Eq. 19).
    pub w1: f64,
    /// Isometric active stress a = σ₀ f_λ(λ̄_f(t)) f_t(t+Δt) [Pa] (≥ 0).
    pub active_stress: f64,
}

/// The solved step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalSolution {
    /// Δλ_s.
    pub delta_lambda_s: f64,
    /// σ_SEE(t+Δt) [Pa].
    pub series_stress: f64,
    /// Newton/bisection iterations used.
    pub iterations: u32,
}

/// h and its derivatives at one Δλ_s.
#[derive(Debug, Clone, Copy)]
struct Evaluation {
    grown: f64,
    h: f64,
    slope: f64,
    curvature: f64,
    /// Sum of the magnitudes of the SEE and CE parts of h'' (they can cancel in h'').
    curvature_bound: f64,
}

/// Which branch of f_v the coefficients belong to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// λ̇_m ≤ 0.
    Shortening,
    /// λ̇_m > 0.
    Lengthening,
}

const MAX_ITERATIONS: u32 = 200;

/// Relative accuracy of σ_SEE + β that the solve aims for.
pub const SEE_STRESS_RELATIVE_ACCURACY: f64 = 1e-12;

impl LocalEquation {
    /// CE stretch rate λ̇_m = (w₁ − k Δλ_s)/Δt [1/s].
    #[inline]
    pub fn ce_stretch_rate(&self, delta_lambda_s: f64) -> f64 {
        (self.w1 - self.k * delta_lambda_s) * (1.0 / self.dt)
    }

    /// σ_SEE(t+Δt) = (σ_s + β) e^{αΔλ_s} − β [Pa].
    #[inline]
    pub fn series_stress_after(&self, delta_lambda_s: f64) -> f64 {
        (self.series_stress + self.beta) * (self.alpha * delta_lambda_s).exp() - self.beta
    }

    /// h(Δλ_s) = σ_SEE − σ_CE and dh/dΔλ_s.
    #[cfg(test)]
    fn residual(&self, delta: f64) -> (f64, f64) {
        let r = self.evaluate(delta);
        (r.h, r.slope)
    }

    /// h, h', h'' and the grown SEE factor (σ_s + β) e^{αΔλ_s} at Δλ_s = `delta`:
    /// h = (σ_s + β) e^{αΔλ_s} − β − a f_v(λ̇_m), dλ̇_m/dΔλ_s = −k/Δt, so
    /// h' = α (σ_s + β) e^{αΔλ_s} + a f_v' k/Δt and h'' = α² (σ_s + β) e^{αΔλ_s} − a f_v'' (k/Δt)².
    #[inline]
    fn evaluate(&self, delta: f64) -> Evaluation {
        let grown = (self.series_stress + self.beta) * (self.alpha * delta).exp();
        let rate = self.ce_stretch_rate(delta);
        let (fv, dfv, d2fv) = self.force_velocity.value_slope_curvature(rate);
        let k_over_dt = self.k * (1.0 / self.dt);
        let a = self.active_stress;
        Evaluation {
            grown,
            h: grown - self.beta - a * fv,
            slope: self.alpha * grown + a * dfv * k_over_dt,
            curvature: self.alpha * self.alpha * grown - a * d2fv * k_over_dt * k_over_dt,
            curvature_bound: self.alpha * self.alpha * grown
                + (a * d2fv).abs() * k_over_dt * k_over_dt,
        }
    }

    /// Δλ_s at which σ_SEE(t+Δt) = `stress` (stress > −β).
    #[inline]
    fn delta_for_series_stress(&self, stress: f64) -> f64 {
        ((stress + self.beta) / (self.series_stress + self.beta)).ln() / self.alpha
    }

    /// The printed form's coefficients (w₂, w₃, w₄, w₅) of f(Δλ_s) (Eq. 14) for `phase`.
    pub fn coefficients(&self, phase: Phase) -> [f64; 4] {
        let t = self.dt * self.force_velocity.lambda_dot_min;
        let (sb, a, b, k, w1) = (
            self.series_stress + self.beta,
            self.active_stress,
            self.beta,
            self.k,
            self.w1,
        );
        match phase {
            Phase::Shortening => {
                let kc = self.force_velocity.k_c;
                [
                    sb * (1.0 + kc * w1 / t),
                    -sb * k * kc / t,
                    k * (a - b * kc) / t,
                    b + a - (a - b * kc) * w1 / t,
                ]
            }
            Phase::Lengthening => {
                let fv = &self.force_velocity;
                let kk = fv.k_c * fv.k_e;
                let q = fv.d * kk + fv.d - 1.0;
                [
                    sb * (1.0 - kk * w1 / t),
                    sb * k * kk / t,
                    k * (b * kk + a * q) / t,
                    b + a - (a * q + b * kk) * w1 / t,
                ]
            }
        }
    }

    /// f(Δλ_s) = (w₂ + w₃Δλ_s) e^{αΔλ_s} − w₄Δλ_s − w₅ in the printed form (Eq. 14).
    pub fn printed_form(&self, delta: f64) -> f64 {
        let phase = if self.ce_stretch_rate(delta) <= 0.0 {
            Phase::Shortening
        } else {
            Phase::Lengthening
        };
        let [w2, w3, w4, w5] = self.coefficients(phase);
        (w2 + w3 * delta) * (self.alpha * delta).exp() - w4 * delta - w5
    }

    /// Solve for Δλ_s (see the module documentation). Inlined into the material's point
    /// loop, where the reciprocals of per-block constants (1/Δt, 1/k, 1/α, 1/λ̇_m^min) are
    /// computed once, outside the loop. Never returns NaN for finite
    /// inputs with β > 0, α > 0, k > 0, a ≥ 0, σ_s > −β.
    #[inline]
    pub fn solve(&self) -> LocalSolution {
        let a = self.active_stress;
        if a <= 0.0 {
            return LocalSolution {
                delta_lambda_s: 1.0 - self.lambda_s,
                series_stress: 0.0,
                iterations: 0,
            };
        }
        if self.dt <= 0.0 {
            let delta = self.w1 / self.k;
            return LocalSolution {
                delta_lambda_s: delta,
                series_stress: self.series_stress_after(delta),
                iterations: 0,
            };
        }
        // What the evaluated signs of h tell about the root; the closed-form bracket (two
        // logarithms) is computed only when needed.
        let mut lower = f64::NEG_INFINITY;
        let mut upper = f64::INFINITY;
        let mut closed_bracket = false;
        // Initial guess: the CE rate that keeps σ_CE at the current SEE stress, exact in the
        // limit of small steps (where σ_SEE barely changes). When σ_SEE/a is near or beyond
        // the range of f_v, that rate is extreme, and for long steps the guess can be far
        // off (|Δλ_s| > 1 is never a root: the closed-form bracket spans less than that for
        // any stress the SEE can carry): then start inside the closed-form bracket.
        let fv = &self.force_velocity;
        let ratio = self.series_stress / a;
        let margin = 0.05;
        let steady_guess = if ratio > fv.infimum() + margin * (1.0 - fv.infimum())
            && ratio < fv.supremum() - margin * (fv.supremum() - 1.0)
        {
            (self.w1 - fv.rate_for_value(ratio) * self.dt) * (1.0 / self.k)
        } else {
            f64::NAN
        };
        let mut delta = if steady_guess.abs() <= 1.0 {
            steady_guess
        } else {
            closed_bracket = true;
            lower = self.closed_form_lower_bound();
            upper = self.closed_form_upper_bound();
            // max/min rather than clamp, which would panic on a NaN bound.
            0.0f64.max(lower).min(upper)
        };
        let tolerance = self.delta_tolerance();
        let mut previous_step = f64::INFINITY;
        let mut iterations = 0;
        loop {
            iterations += 1;
            let e = self.evaluate(delta);
            if e.h < 0.0 {
                lower = delta;
            } else {
                // Also where h is not finite: only the SEE term can overflow, at large Δλ_s.
                upper = delta;
            }
            // Where h or its derivatives overflow, no step estimate can be trusted: bisect.
            let finite = e.h.is_finite() && e.slope.is_finite() && e.curvature_bound.is_finite();
            // Halley's step (cubic convergence) from h, h', h'', or Newton's where the Halley
            // correction is not small. With c = h''/(2h') and Newton's step N = −h/h':
            // Halley's is N/(1 + cN). Predicted error after the step, with C ≥ |c| the bound
            // from the magnitudes of the SEE and CE parts of h'' (both parts of h' are
            // positive): Newton C N²; Halley (c² + |h'''/(6h')|) N³ ≤ 2 C² |N|³, since for the
            // exponential and for both rational branches of f_v |h'''/(6h')| ≤ C² (the CE part
            // has f_v''' / f_v' = 1.5 (f_v'' / f_v')² exactly); we use 4 C² |N|³.
            let half_inverse_slope = 0.5 / e.slope;
            let newton_step = -2.0 * e.h * half_inverse_slope;
            let c = e.curvature * half_inverse_slope;
            let c_bound = e.curvature_bound * half_inverse_slope;
            let (step, predicted_error) = if (c * newton_step).abs() < 0.5 {
                let step = newton_step / (1.0 + c * newton_step);
                (step, 4.0 * c_bound * c_bound * step.abs().powi(3))
            } else {
                (newton_step, c_bound * newton_step * newton_step)
            };
            let candidate = delta + step;
            // Safeguards (as in Numerical Recipes' rtsafe): a step must land inside the known
            // bracket and at least halve the previous one, else bisect the closed bracket.
            let inside = candidate >= lower && candidate <= upper;
            if finite && inside && step.abs() <= 0.5 * previous_step.abs() {
                // Stop when the predicted error is below the tolerance (and the step stays on
                // one branch of f_v, where those estimates hold), taking the step with the SEE
                // stress from a series of the exponential (|α step| ≤ 1e-6: truncation < 1e-25).
                // sign(λ̇_m) = sign(w₁ − k Δλ_s), Δt > 0.
                let same_branch =
                    (self.w1 - self.k * candidate <= 0.0) == (self.w1 - self.k * delta <= 0.0);
                let x = self.alpha * step;
                let converged =
                    (same_branch && predicted_error <= tolerance) || step.abs() <= tolerance;
                if converged && x.abs() <= 1e-6 {
                    let grown = e.grown * (1.0 + x * (1.0 + 0.5 * x * (1.0 + x / 3.0)));
                    return LocalSolution {
                        delta_lambda_s: candidate,
                        series_stress: grown - self.beta,
                        iterations,
                    };
                }
                delta = candidate;
                previous_step = step;
            } else {
                if !closed_bracket {
                    closed_bracket = true;
                    lower = lower.max(self.closed_form_lower_bound());
                    upper = upper.min(self.closed_form_upper_bound());
                }
                let midpoint = 0.5 * (lower + upper);
                previous_step = midpoint - delta;
                delta = midpoint;
            }
            if upper - lower <= tolerance || iterations >= MAX_ITERATIONS {
                break;
            }
        }
        LocalSolution {
            delta_lambda_s: delta,
            series_stress: self.series_stress_after(delta),
            iterations,
        }
    }

    /// Accuracy of the solved Δλ_s: 1e-12/α, so that the SEE stress, whose sensitivity is
    /// dσ_SEE/dΔλ_s = α (σ_SEE + β), is exact to 1e-12 relative to σ_SEE + β.
    pub fn delta_tolerance(&self) -> f64 {
        SEE_STRESS_RELATIVE_ACCURACY * (1.0 / self.alpha)
    }

    /// A Δλ_s below the root: the smaller of w₁/k (λ̇_m = 0; a shortening root lies above)
    /// and σ_SEE = 0 (a lengthening root has σ_SEE ≥ a ≥ 0).
    fn closed_form_lower_bound(&self) -> f64 {
        (self.w1 / self.k).min(self.delta_for_series_stress(0.0))
    }

    /// A Δλ_s above the root: σ_SEE = a sup f_v > σ_CE.
    fn closed_form_upper_bound(&self) -> f64 {
        self.delta_for_series_stress(self.active_stress * self.force_velocity.supremum())
    }

    /// dσ_SEE(t+Δt)/dλ̄_f(t+Δt) through the solve [Pa], for the consistent tangent.
    ///
    /// Implicit function theorem on h(Δλ_s; λ̄_f) = 0 with ∂w₁/∂λ̄_f = 1 + k:
    /// ∂h/∂λ̄_f = −a f_v'(λ̇_m)(1 + k)/Δt, so dΔλ_s/dλ̄_f = a f_v' (1 + k)/Δt / (∂h/∂Δλ_s),
    /// and dσ_SEE/dλ̄_f = α (σ_SEE + β) dΔλ_s/dλ̄_f. For Δt = 0, dΔλ_s/dλ̄_f = (1 + k)/k;
    /// without activation, 0.
    pub fn series_stress_sensitivity(&self, solution: &LocalSolution) -> f64 {
        let a = self.active_stress;
        let grown = solution.series_stress + self.beta;
        if a <= 0.0 {
            0.0
        } else if self.dt <= 0.0 {
            self.alpha * grown * (1.0 + self.k) / self.k
        } else {
            let rate = self.ce_stretch_rate(solution.delta_lambda_s);
            let (_, dfv) = self.force_velocity.value_and_slope(rate);
            let a_dfv_over_dt = a * dfv / self.dt;
            let dh = self.alpha * grown + a_dfv_over_dt * self.k;
            self.alpha * grown * a_dfv_over_dt * (1.0 + self.k) / dh
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table_1(dt: f64, lambda_s: f64, w1: f64, active_stress: f64) -> LocalEquation {
        let (alpha, beta) = (10.0, 1e3);
        LocalEquation {
            alpha,
            beta,
            k: 0.3,
            force_velocity: ForceVelocity {
                k_c: 4.0,
                k_e: 5.0,
                d: 1.45,
                lambda_dot_min: -17.0,
            },
            dt,
            lambda_s,
            series_stress: super::super::functions::series_elastic(alpha, beta, lambda_s),
            w1,
            active_stress,
        }
    }

    /// Shortening, lengthening and isometric steps across a range of states: the solved
    /// increment makes σ_SEE equal σ_CE and zeroes the printed-form f of Eq. 14, up to the
    /// solve's accuracy in Δλ_s (backward error: |h| ≤ |dh/dΔλ_s| × tolerance, which
    /// dominates where σ_CE is steep: fast shortening with tiny steps, where dh/dΔλ_s
    /// reaches 1e10 Pa).
    #[test]
    fn solution_balances_see_and_ce_stress() {
        for &dt in &[1e-6, 1e-4, 1e-3, 1e-2] {
            for &lambda_s in &[0.95, 1.0, 1.3, 1.65] {
                for &w1 in &[-0.01, -1e-4, 0.0, 1e-4, 0.01] {
                    for &a in &[1.0, 3.5e5, 7e5] {
                        let eq = table_1(dt, lambda_s, w1, a);
                        let s = eq.solve();
                        assert!(s.delta_lambda_s.is_finite());
                        let fv = eq
                            .force_velocity
                            .value(eq.ce_stretch_rate(s.delta_lambda_s));
                        let ce = a * fv;
                        let see = s.series_stress;
                        let scale = see.abs().max(ce.abs()).max(eq.beta);
                        let (_, slope) = eq.residual(s.delta_lambda_s);
                        let allowed = 1e-10 * scale
                            + slope * eq.delta_tolerance()
                            + 8.0 * f64::EPSILON * (1.0 + lambda_s) * slope;
                        assert!(
                            (see - ce).abs() <= allowed,
                            "dt {dt} λs {lambda_s} w1 {w1} a {a}: SEE {see} CE {ce}"
                        );
                        // f = h × (the branch's positive f_v denominator), evaluated with
                        // cancelling terms: its tolerance is the one of h times that
                        // denominator plus the round-off of its largest term.
                        let delta = s.delta_lambda_s;
                        let r = eq.ce_stretch_rate(delta) / eq.force_velocity.lambda_dot_min;
                        let (phase, denominator) = if eq.ce_stretch_rate(delta) <= 0.0 {
                            (Phase::Shortening, 1.0 + eq.force_velocity.k_c * r)
                        } else {
                            let kk = eq.force_velocity.k_c * eq.force_velocity.k_e;
                            (Phase::Lengthening, 1.0 - kk * r)
                        };
                        let [w2, w3, w4, w5] = eq.coefficients(phase);
                        let largest_term = ((w2 + w3 * delta) * (eq.alpha * delta).exp())
                            .abs()
                            .max((w4 * delta).abs())
                            .max(w5.abs());
                        let f = eq.printed_form(delta);
                        assert!(
                            f.abs() <= allowed * denominator + 16.0 * f64::EPSILON * largest_term,
                            "printed form f = {f} at dt {dt} λs {lambda_s} w1 {w1} a {a}"
                        );
                        assert!(s.iterations < MAX_ITERATIONS);
                    }
                }
            }
        }
    }

    /// 20 000 pseudo-random states over wide ranges (Δt from 1e-7 to 10 s, λ_s from 0.8
    /// to 1.8, fiber stretch increments up to ±5 %, activation up to σ₀): every solve
    /// balances the stresses within its accuracy, lands inside the closed-form bracket,
    /// and takes few iterations.
    #[test]
    fn random_states_are_solved() {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut total_iterations = 0;
        let mut most = 0;
        for _ in 0..20_000 {
            let dt = 10f64.powf(-7.0 + 8.0 * uniform());
            let lambda_s = 0.8 + uniform();
            let w1 = 1.3 * 0.05 * (2.0 * uniform() - 1.0) * uniform().powi(3);
            let a = 7e5 * uniform();
            let eq = table_1(dt, lambda_s, w1, a);
            let s = eq.solve();
            let fv = eq
                .force_velocity
                .value(eq.ce_stretch_rate(s.delta_lambda_s));
            let (_, slope) = eq.residual(s.delta_lambda_s);
            let scale = s.series_stress.abs().max(a * fv.abs()).max(eq.beta);
            let allowed = 1e-10 * scale + 2.0 * slope * eq.delta_tolerance();
            assert!(
                (s.series_stress - a * fv).abs() <= allowed,
                "dt {dt} λs {lambda_s} w1 {w1} a {a}: SEE {} CE {}",
                s.series_stress,
                a * fv
            );
            if a > 0.0 {
                let (lower, upper) = (eq.closed_form_lower_bound(), eq.closed_form_upper_bound());
                assert!(
                    s.delta_lambda_s >= lower - 1e-12 && s.delta_lambda_s <= upper + 1e-12,
                    "dt {dt}: Δλ_s {} outside [{lower}, {upper}]",
                    s.delta_lambda_s
                );
            }
            total_iterations += s.iterations;
            most = most.max(s.iterations);
        }
        let mean = total_iterations as f64 / 20_000.0;
        println!("mean iterations {mean}, most {most}");
        assert!(
            mean < 10.0 && most < MAX_ITERATIONS,
            "mean {mean}, most {most}"
        );
    }

    #[test]
    fn passive_step_returns_the_see_to_rest() {
        let s = table_1(1e-3, 1.4, 0.02, 0.0).solve();
        assert_eq!(s.series_stress, 0.0);
        assert!((1.4 + s.delta_lambda_s - 1.0).abs() < 1e-15);
    }

    #[test]
    fn zero_step_puts_the_whole_stretch_into_the_see() {
        let eq = table_1(0.0, 1.2, 0.003, 5e5);
        let s = eq.solve();
        assert!((s.delta_lambda_s - 0.01).abs() < 1e-15);
    }

    /// dσ_SEE/dλ̄_f from the implicit function theorem against a central difference of
    /// the solve with respect to w₁ (dw₁/dλ̄_f = 1 + k).
    #[test]
    fn stress_derivative_matches_finite_difference() {
        for &(w1, lambda_s) in &[(0.004, 1.5), (-0.004, 1.6), (0.0005, 1.1)] {
            let eq = table_1(1e-3, lambda_s, w1, 6e5);
            let analytic = eq.series_stress_sensitivity(&eq.solve());
            let h = 1e-7;
            let plus = LocalEquation {
                w1: w1 + h * 1.3,
                ..eq
            }
            .solve()
            .series_stress;
            let minus = LocalEquation {
                w1: w1 - h * 1.3,
                ..eq
            }
            .solve()
            .series_stress;
            let fd = (plus - minus) / (2.0 * h);
            assert!(
                (fd - analytic).abs() < 1e-5 * analytic.abs(),
                "w1 {w1}: analytic {analytic} fd {fd}"
            );
        }
    }
}
