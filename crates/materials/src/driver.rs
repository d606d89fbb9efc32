//! Material-point driver: a homogeneous specimen in **uniaxial stress** along its fiber.
//!
//! The fiber direction is e₁; F = diag(λ, λ₂, λ₃). The fiber stretch λ(t) follows a
//! piecewise-linear history; at every step the two lateral stretches λ₂, λ₃ are found by
//! Newton's method (finite-difference Jacobian, so any material works, plugins too) such
//! that the lateral Cauchy stresses σ₂₂ and σ₃₃ vanish. The step's history variables are
//! those of the previous converged step, so a history-dependent material sees the same
//! sequence of (F_old, F_new) as in a finite-element run with that time step.
//!
//! Outputs per step: time, λ, engineering stress P₁₁ = λ₂λ₃ σ₁₁ (force per reference area
//! normal to the fiber) [Pa], Cauchy stress σ₁₁ [Pa] and J = λλ₂λ₃.

use std::fmt;

use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};

use crate::amplitude::Amplitude;
use crate::material::{PointBlock, PointResponse, VoigtStress};
use crate::{Material, MaterialError};

/// Header of the driver's CSV output.
pub const UNIAXIAL_CSV_HEADER: &str =
    "time_s,stretch,engineering_stress_pa,cauchy_stress_pa,jacobian";

/// Piecewise-linear fiber stretch history: knots (time [s], stretch [1]), strictly
/// increasing in time, stretches > 0.
#[derive(Debug, Clone, PartialEq)]
pub struct StretchHistory {
    stretch: Amplitude,
}

impl StretchHistory {
    /// Parse "T:L,T:L,..." (time in s : stretch). Errors quote the offending token.
    pub fn parse(text: &str) -> Result<Self, DriverError> {
        let bad = |token: &str, why: &str| DriverError::History(format!("'{token}': {why}"));
        if text.trim().is_empty() {
            return Err(DriverError::History(
                "empty stretch history; expected TIME:STRETCH,TIME:STRETCH,... e.g. 0:1,2:1.2"
                    .to_string(),
            ));
        }
        let mut knots: Vec<(f64, f64)> = Vec::new();
        for token in text.split(',') {
            let token = token.trim();
            let Some((t, l)) = token.split_once(':') else {
                return Err(bad(token, "expected TIME:STRETCH"));
            };
            let time: f64 = t
                .trim()
                .parse()
                .map_err(|_| bad(token, "time is not a number"))?;
            let stretch: f64 = l
                .trim()
                .parse()
                .map_err(|_| bad(token, "stretch is not a number"))?;
            if !time.is_finite() || !stretch.is_finite() {
                return Err(bad(token, "time and stretch must be finite"));
            }
            if stretch <= 0.0 {
                return Err(bad(token, "stretch must be > 0"));
            }
            if let Some(&(previous, _)) = knots.last()
                && time <= previous
            {
                return Err(bad(
                    token,
                    &format!("time must increase (previous knot at {previous} s)"),
                ));
            }
            knots.push((time, stretch));
        }
        if knots.len() < 2 {
            return Err(bad(text.trim(), "a history needs at least two knots"));
        }
        let stretch = Amplitude::new(knots).map_err(|e| DriverError::History(e.0))?;
        Ok(StretchHistory { stretch })
    }

    /// First and last knot times [s].
    pub fn time_span(&self) -> (f64, f64) {
        self.stretch.time_span()
    }

    /// Stretch at time `t` (linear between knots, constant outside).
    pub fn stretch_at(&self, t: f64) -> f64 {
        self.stretch.value_at(t)
    }
}

/// One row of the driver's output.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UniaxialRow {
    /// Time [s].
    pub time: f64,
    /// Fiber stretch λ [1].
    pub stretch: f64,
    /// Engineering (first Piola–Kirchhoff) stress P₁₁ [Pa].
    pub engineering_stress: f64,
    /// Cauchy stress σ₁₁ [Pa].
    pub cauchy_stress: f64,
    /// Volume ratio J [1].
    pub jacobian: f64,
}

/// Why a driver run failed.
#[derive(Debug, Clone, PartialEq)]
pub enum DriverError {
    /// The stretch history text is malformed.
    History(String),
    /// The time step is not a positive finite number.
    TimeStep(f64),
    /// The history would take more than [`MAX_DRIVER_STEPS`] steps.
    TooManySteps { steps: f64, dt: f64 },
    /// The material failed at a time.
    Material { time: f64, source: MaterialError },
    /// The lateral-stress equations did not converge.
    LateralStress {
        time: f64,
        residual: f64,
        iterations: usize,
    },
}

impl fmt::Display for DriverError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DriverError::History(m) => write!(f, "stretch history {m}"),
            DriverError::TimeStep(dt) => write!(f, "time step {dt} must be a positive number"),
            DriverError::TooManySteps { steps, dt } => write!(
                f,
                "time step {dt} s would take {steps:.0} steps, more than the limit of \
                 {MAX_DRIVER_STEPS}; use a larger time step"
            ),
            DriverError::Material { time, source } => write!(f, "at t = {time} s: {source}"),
            DriverError::LateralStress {
                time,
                residual,
                iterations,
            } => write!(
                f,
                "at t = {time} s: lateral stresses did not vanish after {iterations} Newton \
                 iterations (residual {residual:e} Pa)"
            ),
        }
    }
}

impl std::error::Error for DriverError {}

/// Most steps one driver run may take (2 million: a few seconds and ~100 MB of rows).
pub const MAX_DRIVER_STEPS: usize = 2_000_000;

/// Tolerances of the lateral-stress solve.
const LATERAL_ABSOLUTE_TOLERANCE_PA: f64 = 1e-6;
const LATERAL_RELATIVE_TOLERANCE: f64 = 1e-10;
const LATERAL_MAX_ITERATIONS: usize = 60;

/// Run `material` in uniaxial stress along the fiber through `history` with step `dt` [s]
/// (the last step is shortened to end on the last knot). Row 0 is the initial state.
pub fn run_uniaxial_stress(
    material: &dyn Material,
    history: &StretchHistory,
    dt: f64,
) -> Result<Vec<UniaxialRow>, DriverError> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(DriverError::TimeStep(dt));
    }
    let (t_start, t_end) = history.time_span();
    let step_count = (((t_end - t_start) / dt) - 1e-9).ceil().max(1.0);
    if step_count > MAX_DRIVER_STEPS as f64 {
        return Err(DriverError::TooManySteps {
            steps: step_count,
            dt,
        });
    }
    let steps = step_count as usize;
    let mut point = UniaxialPoint::new(material, history.stretch_at(t_start));
    let mut rows = Vec::with_capacity(steps + 1);
    rows.push(point.advance(t_start, 0.0, history.stretch_at(t_start))?);
    let mut time = t_start;
    for step in 1..=steps {
        let t_next = if step == steps {
            t_end
        } else {
            t_start + step as f64 * dt
        };
        rows.push(point.advance(t_next, t_next - time, history.stretch_at(t_next))?);
        time = t_next;
    }
    Ok(rows)
}

/// One homogeneous material point kept in uniaxial stress.
struct UniaxialPoint<'m> {
    material: &'m dyn Material,
    f_old: Matrix3<f64>,
    lateral: Vector2<f64>,
    state_old: Vec<f64>,
    state_new: Vec<f64>,
}

impl<'m> UniaxialPoint<'m> {
    fn new(material: &'m dyn Material, stretch: f64) -> Self {
        let lateral = Vector2::repeat(1.0 / stretch.sqrt());
        UniaxialPoint {
            material,
            f_old: Matrix3::from_diagonal(&Vector3::new(stretch, lateral[0], lateral[1])),
            lateral,
            state_old: material.initial_state(1),
            state_new: material.initial_state(1),
        }
    }

    /// Cauchy stress at F = diag(λ, λ₂, λ₃) after a step of `dt` ending at `time`;
    /// leaves the trial state in `state_new`.
    fn stress(
        &mut self,
        time: f64,
        dt: f64,
        stretch: f64,
        lateral: &Vector2<f64>,
    ) -> Result<VoigtStress, DriverError> {
        let f_new = [Matrix3::from_diagonal(&Vector3::new(
            stretch, lateral[0], lateral[1],
        ))];
        let block = PointBlock {
            time,
            dt,
            deformation_gradient_old: std::slice::from_ref(&self.f_old),
            deformation_gradient_new: &f_new,
            fiber_direction: &[Vector3::x()],
            state_old: &self.state_old,
        };
        let mut stress = [VoigtStress::zeros()];
        let mut response = PointResponse {
            cauchy_stress: &mut stress,
            state_new: &mut self.state_new,
            tangent: None,
        };
        self.material
            .update(&block, &mut response)
            .map_err(|source| DriverError::Material { time, source })?;
        Ok(stress[0])
    }

    /// Advance to `time` at fiber stretch `stretch`, solving for the lateral stretches.
    fn advance(&mut self, time: f64, dt: f64, stretch: f64) -> Result<UniaxialRow, DriverError> {
        // Start from the previous lateral stretches, scaled as if isochoric.
        let previous_stretch = self.f_old[(0, 0)];
        let mut lateral = self.lateral * (previous_stretch / stretch).sqrt();
        let mut iterations = 0;
        let stress = loop {
            let sigma = self.stress(time, dt, stretch, &lateral)?;
            let residual = Vector2::new(sigma[1], sigma[2]);
            let tolerance =
                LATERAL_ABSOLUTE_TOLERANCE_PA.max(LATERAL_RELATIVE_TOLERANCE * sigma[0].abs());
            if residual.amax() <= tolerance {
                break sigma;
            }
            if iterations == LATERAL_MAX_ITERATIONS {
                return Err(DriverError::LateralStress {
                    time,
                    residual: residual.amax(),
                    iterations,
                });
            }
            iterations += 1;
            // Forward-difference Jacobian of (σ22, σ33) with respect to (λ2, λ3).
            let mut jacobian = Matrix2::zeros();
            for c in 0..2 {
                let h = 1e-7 * lateral[c];
                let mut perturbed = lateral;
                perturbed[c] += h;
                let s = self.stress(time, dt, stretch, &perturbed)?;
                jacobian[(0, c)] = (s[1] - sigma[1]) / h;
                jacobian[(1, c)] = (s[2] - sigma[2]) / h;
            }
            let Some(step) = jacobian.lu().solve(&(-residual)) else {
                return Err(DriverError::LateralStress {
                    time,
                    residual: residual.amax(),
                    iterations,
                });
            };
            // Converged to round-off: the residual cannot get smaller in floating point.
            // Evaluate once more at `lateral`, so that `state_new` is its state and not that
            // of the last perturbed Jacobian column.
            if step.amax() <= 1e-14 * lateral.amax() {
                break self.stress(time, dt, stretch, &lateral)?;
            }
            // Keep the stretches positive: cut the step until they are.
            let mut scale = 1.0;
            while (0..2).any(|c| lateral[c] + scale * step[c] <= 0.0) {
                scale *= 0.5;
            }
            lateral += step * scale;
        };
        // `state_new` holds the state of the converged (last evaluated) stress.
        std::mem::swap(&mut self.state_old, &mut self.state_new);
        self.f_old = Matrix3::from_diagonal(&Vector3::new(stretch, lateral[0], lateral[1]));
        self.lateral = lateral;
        Ok(UniaxialRow {
            time,
            stretch,
            engineering_stress: lateral[0] * lateral[1] * stress[0],
            cauchy_stress: stress[0],
            jacobian: stretch * lateral[0] * lateral[1],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::neo_hookean::NeoHookean;

    #[test]
    fn history_parses_and_interpolates() {
        let h = StretchHistory::parse("0:1, 0.5:1,2.5:1.2").unwrap();
        assert_eq!(h.time_span(), (0.0, 2.5));
        assert_eq!(h.stretch_at(0.25), 1.0);
        assert!((h.stretch_at(1.5) - 1.1).abs() < 1e-15);
        assert_eq!(h.stretch_at(9.0), 1.2);
    }

    #[test]
    fn bad_histories_quote_the_token() {
        for (text, token) in [
            ("0:1,1:x", "'1:x'"),
            ("0:1,1", "'1'"),
            ("0:1,0:1.1", "'0:1.1'"),
            ("0:1,1:-1", "'1:-1'"),
            ("a:1,1:1", "'a:1'"),
        ] {
            let err = StretchHistory::parse(text).unwrap_err().to_string();
            assert!(err.contains(token), "{text}: {err}");
        }
        assert!(StretchHistory::parse("  ").is_err());
        let history = StretchHistory::parse("0:1,1000:1.1").unwrap();
        let material = NeoHookean {
            shear_modulus: 1e4,
            compressibility: 1e-9,
        };
        let err = run_uniaxial_stress(&material, &history, 1e-6).unwrap_err();
        assert!(matches!(err, DriverError::TooManySteps { .. }), "{err}");
        assert!(StretchHistory::parse("0:1").is_err());
    }

    /// Incompressible-limit neo-Hookean in uniaxial stress: P = μ (λ − λ⁻²).
    #[test]
    fn neo_hookean_uniaxial_stress_matches_closed_form() {
        let material = NeoHookean {
            shear_modulus: 10_000.0,
            compressibility: 1e-10,
        };
        let history = StretchHistory::parse("0:1,1:1.3").unwrap();
        let rows = run_uniaxial_stress(&material, &history, 0.1).unwrap();
        assert_eq!(rows.len(), 11);
        for row in &rows {
            let l = row.stretch;
            let expected = 10_000.0 * (l - 1.0 / (l * l));
            // Compressibility (μ D = 1e-6) moves the closed form by ~1e-6 relative.
            assert!(
                (row.engineering_stress - expected).abs() < 1e-5 * expected.abs().max(1.0),
                "{row:?} vs {expected}"
            );
            assert!((row.jacobian - 1.0).abs() < 1e-5);
        }
    }
}
