//! The linear traction–separation law with linear damage (seed §2.4), in the local frame
//! (n, s, t) of the main surface: δ = (δ_n, δ_s, δ_t) [m], t = (t_n, t_s, t_t) [Pa].
//!
//! - Undamaged: t_n = K_nn δ_n, t_s = K_ss δ_s, t_t = K_tt δ_t (K in N/m³).
//! - Effective separation λ = √(⟨δ_n⟩² + w (δ_s² + δ_t²)) [m], ⟨x⟩ = max(x, 0), w = 1 in
//!   [`TangentialMode::Elastic`], w = 0 in [`TangentialMode::FreeSlide`] and
//!   [`TangentialMode::SmoothSlide`] (only the normal opening counts). Compression never
//!   damages.
//! - Initiation: the paper's "maximum separation" D_nn = D_ss = D_tt = 30 mm is read as
//!   λ reaching δ_0. In a pure mode this is Abaqus' maximum-separation criterion
//!   max(⟨δ_n⟩, |δ_s|, |δ_t|) = δ_0 exactly; in mixed mode the Euclidean norm (the effective
//!   separation that Abaqus' damage evolution uses) initiates earlier, by up to √3, but is
//!   smooth, so that one quantity drives both initiation and evolution.
//! - Damage history κ = max over the past of λ (irreversible; the interface commits it,
//!   see [`super::CohesiveInterface`]); linear softening
//!   D(κ) = δ_f (κ − δ_0) / (κ (δ_f − δ_0)) for δ_0 < κ < δ_f, 0 below, 1 above, so that in
//!   pure opening t_n = K_nn δ_0 (δ_f − δ_n)/(δ_f − δ_0) on the softening branch and the
//!   dissipated energy is G_c = ½ K_nn δ_0 δ_f [J/m²].
//! - Damaged: t_n = (1 − D) K_nn δ_n if δ_n > 0, t_n = K_nn δ_n if δ_n ≤ 0 (compression is
//!   resisted by the undamaged normal stiffness even after failure: the contact-penalty
//!   role), t_s = (1 − D) K_ss δ_s, t_t = (1 − D) K_tt δ_t (Elastic), t_s = t_t = 0
//!   (FreeSlide, SmoothSlide).
//! - Consistent tangent C = ∂t/∂δ [N/m³]: on loading (λ ≥ κ_committed, δ_0 < λ < δ_f)
//!   C_ij = (1 − D) K_i δ_ij − K_i δ_i D'(λ) ∂λ/∂δ_j over the damaged components i, with
//!   D'(λ) = δ_f δ_0 / (λ² (δ_f − δ_0)) and ∂λ/∂δ_j = w_j ⟨δ_j⟩ / λ; otherwise the secant
//!   (1 − D) K_i δ_ij. At λ = κ_committed the loading tangent is taken (the tangent of
//!   continued loading). C is symmetric except in mixed-mode loading with K_nn ≠ K_ss or
//!   K_ss ≠ K_tt.

use nalgebra::{Matrix3, Vector3};

use super::error::CohesiveError;
use super::settings::{CohesiveSettings, TangentialMode};

/// The law at one separation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TractionResponse {
    /// (t_n, t_s, t_t) [Pa].
    pub traction: Vector3<f64>,
    /// ∂t/∂δ [N/m³].
    pub tangent: Matrix3<f64>,
    /// Trial damage history κ = max(κ_committed, λ) [m].
    pub history: f64,
    /// Damage D(κ) in [0, 1].
    pub damage: f64,
    /// Stored elastic energy per area ½ t·δ [J/m²].
    pub energy: f64,
}

/// The traction–separation law (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CohesiveLaw {
    /// (K_nn, K_ss, K_tt) [N/m³].
    stiffness: Vector3<f64>,
    /// δ_0 [m].
    initiation: f64,
    /// δ_f [m].
    failure: f64,
    tangential: TangentialMode,
}

impl CohesiveLaw {
    /// The law of `settings` (validated; `interface` names the interface in the error).
    pub fn new(settings: &CohesiveSettings, interface: &str) -> Result<Self, CohesiveError> {
        settings.validate(interface)?;
        Ok(CohesiveLaw {
            stiffness: Vector3::new(
                settings.normal_stiffness,
                settings.shear_stiffness,
                settings.tangential_stiffness,
            ),
            initiation: settings.initiation_separation,
            failure: settings.failure_separation,
            tangential: settings.tangential,
        })
    }

    /// The shear mode.
    pub fn tangential(&self) -> TangentialMode {
        self.tangential
    }

    /// Whether the tangent is symmetric at every separation: FreeSlide or SmoothSlide
    /// (normal traction only), or all three stiffnesses equal.
    pub fn has_symmetric_tangent(&self) -> bool {
        self.tangential != TangentialMode::Elastic
            || (self.stiffness.x == self.stiffness.y && self.stiffness.y == self.stiffness.z)
    }

    /// Weight w of the tangential separations in λ (1 Elastic, 0 FreeSlide and
    /// SmoothSlide).
    fn shear_weight(&self) -> f64 {
        match self.tangential {
            TangentialMode::Elastic => 1.0,
            TangentialMode::FreeSlide | TangentialMode::SmoothSlide => 0.0,
        }
    }

    /// Effective separation λ = √(⟨δ_n⟩² + w (δ_s² + δ_t²)) [m].
    pub fn effective_separation(&self, separation: &Vector3<f64>) -> f64 {
        let opening = separation.x.max(0.0);
        let w = self.shear_weight();
        (opening * opening + w * (separation.y * separation.y + separation.z * separation.z)).sqrt()
    }

    /// Damage D(κ) of the damage history κ [m]: 0 up to δ_0, linear softening to 1 at δ_f.
    pub fn damage(&self, history: f64) -> f64 {
        if history <= self.initiation {
            0.0
        } else if history >= self.failure {
            1.0
        } else {
            self.failure * (history - self.initiation)
                / (history * (self.failure - self.initiation))
        }
    }

    /// The traction, tangent, damage and energy at the local `separation` (δ_n, δ_s, δ_t)
    /// [m] with the committed damage history `committed` [m].
    pub fn evaluate(&self, separation: &Vector3<f64>, committed: f64) -> TractionResponse {
        let lambda = self.effective_separation(separation);
        let history = committed.max(lambda);
        let damage = self.damage(history);
        let intact = 1.0 - damage;
        let opening = separation.x > 0.0;
        let elastic = self.tangential == TangentialMode::Elastic;
        // Components that the damage scales, and their weights in λ.
        let damaged = [opening, elastic, elastic];
        let mut traction = Vector3::zeros();
        let mut tangent = Matrix3::zeros();
        for i in 0..3 {
            let secant = if damaged[i] {
                intact * self.stiffness[i]
            } else if i == 0 {
                self.stiffness[0]
            } else {
                0.0
            };
            traction[i] = secant * separation[i];
            tangent[(i, i)] = secant;
        }
        let loading = lambda >= committed && lambda > self.initiation && lambda < self.failure;
        if loading {
            let slope = self.failure * self.initiation
                / (lambda * lambda * (self.failure - self.initiation));
            let w = self.shear_weight();
            let gradient = Vector3::new(
                separation.x.max(0.0) / lambda,
                w * separation.y / lambda,
                w * separation.z / lambda,
            );
            for i in (0..3).filter(|&i| damaged[i]) {
                let factor = self.stiffness[i] * separation[i] * slope;
                for j in 0..3 {
                    tangent[(i, j)] -= factor * gradient[j];
                }
            }
        }
        TractionResponse {
            traction,
            tangent,
            history,
            damage,
            energy: 0.5 * traction.dot(separation),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law(settings: CohesiveSettings) -> CohesiveLaw {
        CohesiveLaw::new(&settings, "test").unwrap()
    }

    fn unequal(tangential: TangentialMode) -> CohesiveLaw {
        law(CohesiveSettings {
            normal_stiffness: 5e7,
            shear_stiffness: 2e7,
            tangential_stiffness: 3.5e7,
            tangential,
            ..CohesiveSettings::default()
        })
    }

    #[test]
    fn pure_opening_follows_the_linear_law_and_softening_branch() {
        let s = CohesiveSettings::default();
        let l = law(s);
        let (k, d0, df) = (s.normal_stiffness, s.initiation_separation, 0.06);
        for i in 0..=80 {
            let delta = 0.08 * f64::from(i) / 80.0;
            let t = l.evaluate(&Vector3::new(delta, 0.0, 0.0), 0.0).traction;
            let expected = if delta <= d0 {
                k * delta
            } else if delta <= df {
                k * d0 * (df - delta) / (df - d0)
            } else {
                0.0
            };
            assert!(
                (t.x - expected).abs() <= 1e-9 * k * d0,
                "δ = {delta}: {} vs {expected}",
                t.x
            );
            assert_eq!((t.y, t.z), (0.0, 0.0));
        }
    }

    #[test]
    fn damage_is_irreversible_and_unloading_is_secant() {
        let l = law(CohesiveSettings::default());
        let loaded = l.evaluate(&Vector3::new(0.045, 0.0, 0.0), 0.0);
        // D(0.045) = 0.06 × 0.015 / (0.045 × 0.03) = 2/3.
        assert!((loaded.damage - 2.0 / 3.0).abs() < 1e-14);
        let unloaded = l.evaluate(&Vector3::new(0.01, 0.0, 0.0), loaded.history);
        assert_eq!(unloaded.history, 0.045);
        assert!((unloaded.traction.x - 5e7 / 3.0 * 0.01).abs() < 1e-6);
        assert!((unloaded.tangent[(0, 0)] - 5e7 / 3.0).abs() < 1e-6);
        // Compression after failure: the full normal stiffness, no shear (failed).
        let crushed = l.evaluate(&Vector3::new(-0.002, 0.003, 0.0), 0.07);
        assert_eq!(crushed.damage, 1.0);
        assert_eq!(crushed.traction, Vector3::new(-1e5, 0.0, 0.0));
        assert_eq!(crushed.energy, 0.5 * 5e7 * 0.002 * 0.002);
    }

    #[test]
    fn compression_does_not_damage() {
        let l = law(CohesiveSettings::default());
        let r = l.evaluate(&Vector3::new(-0.5, 0.0, 0.0), 0.0);
        assert_eq!(r.damage, 0.0);
        assert_eq!(r.history, 0.0);
        assert_eq!(r.traction.x, -5e7 * 0.5);
    }

    #[test]
    fn free_slide_has_no_shear_and_only_opening_damages() {
        for tangential in [TangentialMode::FreeSlide, TangentialMode::SmoothSlide] {
            let l = law(CohesiveSettings {
                tangential,
                ..CohesiveSettings::default()
            });
            let r = l.evaluate(&Vector3::new(0.01, 0.5, -0.3), 0.0);
            assert_eq!(r.traction, Vector3::new(5e7 * 0.01, 0.0, 0.0));
            assert_eq!(r.history, 0.01);
            assert_eq!(r.damage, 0.0);
            assert!(l.has_symmetric_tangent());
        }
        // Elastic mode with the same separation: shear tractions and damage from λ.
        let e = law(CohesiveSettings::default());
        let r = e.evaluate(&Vector3::new(0.01, 0.02, -0.01), 0.0);
        assert!((r.history - 0.0006f64.sqrt()).abs() < 1e-15);
        assert_eq!(r.traction, 5e7 * Vector3::new(0.01, 0.02, -0.01));
    }

    #[test]
    fn fracture_energy_is_dissipated_in_mode_one() {
        let s = CohesiveSettings::default();
        let l = law(s);
        // ∫ t dδ from 0 to δ_f by the trapezoidal rule on a fine grid.
        let n = 60_000;
        let h = s.failure_separation / f64::from(n);
        let mut work = 0.0;
        let mut history = 0.0;
        let mut previous = 0.0;
        for i in 1..=n {
            let r = l.evaluate(&Vector3::new(h * f64::from(i), 0.0, 0.0), history);
            history = r.history;
            work += 0.5 * h * (previous + r.traction.x);
            previous = r.traction.x;
        }
        assert!((work / s.fracture_energy() - 1.0).abs() < 1e-8, "{work}");
    }

    /// Central differences of the traction at fixed committed history.
    fn check_tangent(l: &CohesiveLaw, separation: Vector3<f64>, committed: f64) {
        let r = l.evaluate(&separation, committed);
        let h = 1e-7;
        let scale = r.tangent.abs().max().max(1e-3 * 5e7);
        for j in 0..3 {
            let mut plus = separation;
            let mut minus = separation;
            plus[j] += h;
            minus[j] -= h;
            let column = (l.evaluate(&plus, committed).traction
                - l.evaluate(&minus, committed).traction)
                / (2.0 * h);
            for i in 0..3 {
                let error = (column[i] - r.tangent[(i, j)]).abs();
                assert!(
                    error <= 1e-6 * scale,
                    "δ = {separation:?}, κ = {committed}: C[{i}{j}] = {} vs FD {} (error {error:e})",
                    r.tangent[(i, j)],
                    column[i]
                );
            }
        }
    }

    #[test]
    fn the_tangent_matches_finite_differences_on_every_branch() {
        for mode in [
            TangentialMode::Elastic,
            TangentialMode::FreeSlide,
            TangentialMode::SmoothSlide,
        ] {
            for l in [law(CohesiveSettings::default()), unequal(mode)] {
                let l = CohesiveLaw {
                    tangential: mode,
                    ..l
                };
                // Undamaged, opening and closing.
                check_tangent(&l, Vector3::new(0.01, 0.004, -0.007), 0.0);
                check_tangent(&l, Vector3::new(-0.01, 0.004, -0.007), 0.0);
                // Loading on the softening branch: pure opening and mixed mode.
                check_tangent(&l, Vector3::new(0.04, 0.0, 0.0), 0.0);
                check_tangent(&l, Vector3::new(0.035, 0.012, -0.018), 0.02);
                check_tangent(&l, Vector3::new(0.032, 0.02, 0.01), 0.0);
                // Unloading inside the damage surface (secant).
                check_tangent(&l, Vector3::new(0.02, 0.005, 0.001), 0.05);
                // Compression with damage: normal undamaged, shear damaged.
                check_tangent(&l, Vector3::new(-0.02, 0.035, 0.01), 0.0);
                check_tangent(&l, Vector3::new(-0.02, 0.01, 0.01), 0.045);
                // Failed.
                check_tangent(&l, Vector3::new(0.07, 0.01, 0.0), 0.0);
            }
        }
    }

    #[test]
    fn the_loading_tangent_is_symmetric_with_equal_stiffnesses_only() {
        let separation = Vector3::new(0.035, 0.012, -0.018);
        let equal = law(CohesiveSettings::default()).evaluate(&separation, 0.0);
        assert!((equal.tangent - equal.tangent.transpose()).abs().max() < 1e-6);
        let l = unequal(TangentialMode::Elastic);
        assert!(!l.has_symmetric_tangent());
        let r = l.evaluate(&separation, 0.0);
        assert!((r.tangent - r.tangent.transpose()).abs().max() > 1e6);
    }
}
