//! Hill-type hyperelastic active muscle (seed §2.1, Eqs. 1–23, Table 1).
//!
//! Strain energy W = W_I + W_f + W_V (Eq. 1), with the readings fixed in docs/design.md:
//!
//! - matrix: W_I = c [exp(b (Ī₁ − 3)) − 1] (the printed bracket of Eq. 2 is a slip); a
//!   parameter λ_M, 1 by default, makes the matrix slack along the fiber up to λ_M
//!   ([`functions::matrix_slack`]: E = Ī₁ − 3 + ΔE(λ̄_f) in place of Ī₁ − 3, and the
//!   nominal fiber stress W₁ x added to σ_PE + σ_SEE);
//! - fiber: W_f = ∫₁^λ̄_f (σ_PE + σ_SEE) dλ (Eq. 3), so σ_PE + σ_SEE = ∂W_f/∂λ̄_f is a
//!   *nominal* fiber stress, with λ̄_f = |F̄ a₀| the isochoric fiber stretch;
//! - volume: W_V = (J − 1)²/D (Eq. 4).
//!
//! Cauchy stress (decoupled):
//! σ = (1/J) dev[2 W₁ B̄] + (1/J) dev[λ̄_f (σ_PE + σ_SEE) ā ⊗ ā] + p I,
//! W₁ = ∂W_I/∂Ī₁ = b c exp(b (Ī₁ − 3)), ā = F̄ a₀ / λ̄_f the unit current fiber
//! direction, p = 2 (J − 1)/D.
//!
//! Fiber elements:
//! - PE (Eqs. 5–6): σ_PE = σ₀ A (λ̄_f − 1)² for λ̄_f > 1, at the end of the step (a
//!   parameter λ_PE, 1 by default, moves the slack stretch: σ₀ A (λ̄_f − λ_PE)² beyond it);
//! - SEE in series with the CE: σ_SEE = β [exp(α (λ_s − 1)) − 1] (Eq. 8);
//! - CE (Eq. 9): σ_CE = σ₀ f_λ(λ̄_f(t)/λ_opt) f_v(λ̇_m) f_t(t + Δt), f_λ at the start of the
//!   step, f_t at the end, f_v of the CE stretch rate;
//! - length relation (1 + k) λ̄_f = λ_m + k λ_s, at rest λ_m = λ_s = 1 (k enters only here);
//! - each step solves σ_SEE = σ_CE for Δλ_s ([`local_solve`]).
//!
//! State per point: λ_m, λ_s, σ_SEE (in that order), initially 1, 1, 0.
//!
//! Interpretations beyond docs/design.md, made here:
//! - the reference fiber direction is normalised before use;
//! - the state written at the end of the step satisfies the length relation exactly:
//!   λ_m(t+Δt) = (1 + k) λ̄_f(t+Δt) − k λ_s(t+Δt);
//! - the SEE is not switched off in compression (λ_s < 1 gives σ_SEE > −β), as the
//!   printed law allows; the CE force with negative f_v (shortening faster than
//!   |λ̇_m^min|) is kept too: the local equation's root stays unique either way;
//! - Δt = 0 puts the whole fiber stretch increment into the SEE (no time for the CE).

pub mod functions;
pub mod local_solve;
pub mod parameters;

use std::sync::{Arc, LazyLock};

use nalgebra::{Matrix3, Vector3};

use crate::material::{PointBlock, PointResponse, StateVariable};
use crate::parameters::ParameterSet;
use crate::registry::MaterialRegistration;
use crate::tensor::{
    IsochoricSplit, decoupled_tangent, deviatoric_voigt, inverse_cube_root, outer_voigt,
    symmetric_from_voigt, volumetric_kirchhoff_slope, volumetric_pressure,
};
use crate::{ActivationHistory, Material, MaterialError, VoigtStress};
use functions::{force_length, matrix_slack, parallel_element};
use local_solve::{LocalEquation, LocalSolution};
pub use parameters::{HILL_PARAMETERS, HillParameters};

/// Index of λ_m in a point's state.
pub const STATE_CE_STRETCH: usize = 0;
/// Index of λ_s in a point's state.
pub const STATE_SEE_STRETCH: usize = 1;
/// Index of σ_SEE in a point's state.
pub const STATE_SEE_STRESS: usize = 2;
/// State variables per point.
pub const STATE_COUNT: usize = 3;

static STATE_VARIABLES: LazyLock<[StateVariable; STATE_COUNT]> = LazyLock::new(|| {
    let var = |name: &str, unit: &str, initial: f64| StateVariable {
        name: name.to_string(),
        unit: unit.to_string(),
        initial,
    };
    [
        var("lambda_m", "1", 1.0),
        var("lambda_s", "1", 1.0),
        var("sigma_see", "Pa", 0.0),
    ]
});

/// The Hill-type active muscle material.
#[derive(Debug, Clone, PartialEq)]
pub struct HillMuscle {
    pub parameters: HillParameters,
    /// A recorded activation a(t) in place of f_t of Eqs. 12–13 (`None`: the paper's
    /// activation from n1, n2, t0, t1 and S).
    pub activation_history: Option<Arc<ActivationHistory>>,
}

/// Everything the stress and the tangent need at one point after the local solve.
struct PointSolution {
    split: IsochoricSplit,
    /// Unit reference fiber direction a₀.
    reference_fiber: Vector3<f64>,
    /// g = F̄ a₀ (|g| = λ̄_f).
    fiber: Vector3<f64>,
    fiber_stretch: f64,
    /// W₁ = ∂W_I/∂E [Pa] (∂W_I/∂Ī₁ without a matrix slack).
    w1_matrix: f64,
    /// x = ∂E/∂λ̄_f and x' = ∂²E/∂λ̄_f² of the matrix slack (0 without one).
    matrix_slack_slope: f64,
    matrix_slack_curvature: f64,
    /// σ_PE + σ_SEE + W₁ x [Pa].
    fiber_stress: f64,
    /// dσ_PE/dλ̄_f [Pa].
    d_pe_stress: f64,
    local_equation: LocalEquation,
    local: LocalSolution,
}

impl HillMuscle {
    /// The Hill muscle with typed `parameters` (checked: declared ranges, t1 ≥ t0), for
    /// studies that set activation or slack in code rather than by name.
    pub fn with_parameters(
        parameters: &HillParameters,
    ) -> Result<Arc<dyn Material>, MaterialError> {
        Ok(Arc::new(HillMuscle {
            parameters: parameters.checked()?,
            activation_history: None,
        }))
    }

    fn from_parameters(p: &ParameterSet) -> Result<Arc<dyn Material>, MaterialError> {
        Ok(Arc::new(HillMuscle {
            parameters: HillParameters::from_set(p)?,
            activation_history: None,
        }))
    }

    /// Kinematics, local solve and fiber stress of one point.
    #[inline]
    fn solve_point(
        &self,
        activation: f64,
        dt: f64,
        f_old: &Matrix3<f64>,
        f_new: &Matrix3<f64>,
        fiber_direction: &Vector3<f64>,
        state: &[f64],
    ) -> PointSolution {
        let p = &self.parameters;
        // Fibers usually arrive as unit vectors: skip the square root and division then.
        let length_squared = fiber_direction.norm_squared();
        let a0 = if (length_squared - 1.0).abs() <= 4.0 * f64::EPSILON {
            *fiber_direction
        } else {
            fiber_direction / length_squared.sqrt()
        };
        let split = IsochoricSplit::new(f_new);
        let fiber = (f_new * a0) * split.j_minus_third;
        let fiber_stretch = fiber.norm();
        let fiber_stretch_old = (f_old * a0).norm() * inverse_cube_root(f_old.determinant());

        let active_stress = p.max_isometric_stress
            * force_length(fiber_stretch_old * (1.0 / p.optimal_stretch))
            * activation;
        let (lambda_m, lambda_s) = (state[STATE_CE_STRETCH], state[STATE_SEE_STRETCH]);
        let k = p.length_ratio;
        let local_equation = LocalEquation {
            alpha: p.see_exponent,
            beta: p.see_stress,
            k,
            force_velocity: p.force_velocity,
            dt,
            lambda_s,
            series_stress: state[STATE_SEE_STRESS],
            w1: (1.0 + k) * fiber_stretch - lambda_m - k * lambda_s,
            active_stress,
        };
        let local = local_equation.solve();

        let (pe_stress, d_pe_stress) = parallel_element(
            p.max_isometric_stress,
            p.parallel_factor,
            p.parallel_slack,
            fiber_stretch,
        );
        let (slack_energy, slack_slope, slack_curvature) =
            matrix_slack(p.matrix_slack, fiber_stretch);
        let w1_matrix = p.matrix_exponent
            * p.matrix_stress
            * (p.matrix_exponent * (split.i1_bar - 3.0 + slack_energy)).exp();
        PointSolution {
            split,
            reference_fiber: a0,
            fiber,
            fiber_stretch,
            w1_matrix,
            matrix_slack_slope: slack_slope,
            matrix_slack_curvature: slack_curvature,
            fiber_stress: pe_stress + local.series_stress + w1_matrix * slack_slope,
            d_pe_stress,
            local_equation,
            local,
        }
    }

    /// Kirchhoff stress τ = J σ = dev[2 W₁ B̄ + (σ_f/λ̄_f) g ⊗ g] + J p I (Voigt order).
    #[inline]
    fn kirchhoff_stress(&self, s: &PointSolution) -> VoigtStress {
        let jp = s.split.jacobian
            * volumetric_pressure(s.split.jacobian, self.parameters.compressibility);
        let m = s.split.b_bar * (2.0 * s.w1_matrix)
            + outer_voigt(&s.fiber) * (s.fiber_stress / s.fiber_stretch);
        let mut tau = deviatoric_voigt(&m);
        for i in 0..3 {
            tau[i] += jp;
        }
        tau
    }
}

impl Material for HillMuscle {
    fn name(&self) -> &str {
        "hill"
    }

    fn state_variables(&self) -> &[StateVariable] {
        STATE_VARIABLES.as_slice()
    }

    /// f_t(t) of Eq. 12, or the recorded history's a(t).
    fn activation(&self, time: f64) -> Option<f64> {
        Some(self.activation_level(time))
    }

    fn with_activation_history(
        &self,
        history: Arc<ActivationHistory>,
    ) -> Option<Arc<dyn Material>> {
        Some(Arc::new(HillMuscle {
            parameters: self.parameters,
            activation_history: Some(history),
        }))
    }

    fn compute(
        &self,
        block: &PointBlock,
        response: &mut PointResponse,
    ) -> Result<(), MaterialError> {
        let k = self.parameters.length_ratio;
        // f_t(t + Δt) is the same for every point of the block.
        let activation = self.activation_level(block.time);
        let mut tangents = response.tangent.as_deref_mut();
        for point in 0..block.len() {
            let state = &block.state_old[point * STATE_COUNT..(point + 1) * STATE_COUNT];
            self.check_state(point, state)?;
            let s = self.solve_point(
                activation,
                block.dt,
                &block.deformation_gradient_old[point],
                &block.deformation_gradient_new[point],
                &block.fiber_direction[point],
                state,
            );
            let tau = self.kirchhoff_stress(&s);
            response.cauchy_stress[point] = tau * (1.0 / s.split.jacobian);

            let lambda_s = state[STATE_SEE_STRETCH] + s.local.delta_lambda_s;
            let out = &mut response.state_new[point * STATE_COUNT..(point + 1) * STATE_COUNT];
            out[STATE_CE_STRETCH] = (1.0 + k) * s.fiber_stretch - k * lambda_s;
            out[STATE_SEE_STRETCH] = lambda_s;
            out[STATE_SEE_STRESS] = s.local.series_stress;

            if let Some(tangents) = tangents.as_deref_mut() {
                tangents[point] = self.tangent(&s, &symmetric_from_voigt(&tau));
            }
        }
        Ok(())
    }
}

impl HillMuscle {
    /// f_t(t) [1]: the recorded history's a(t) when there is one, else Eq. 12.
    #[inline]
    fn activation_level(&self, time: f64) -> f64 {
        match &self.activation_history {
            Some(history) => history.level(time),
            None => self.parameters.activation.level(time),
        }
    }

    /// The local solve needs λ_s > 0 and σ_SEE > −β (the SEE stress's lower limit).
    #[inline]
    fn check_state(&self, point: usize, state: &[f64]) -> Result<(), MaterialError> {
        let beta = self.parameters.see_stress;
        if state[STATE_SEE_STRETCH] > 0.0 && state[STATE_SEE_STRESS] > -beta {
            return Ok(());
        }
        Err(MaterialError::InvalidPoint {
            point,
            reason: format!(
                "Hill state (lambda_m, lambda_s, sigma_see) = {state:?} needs lambda_s > 0 and \
                 sigma_see > -beta = {}",
                -beta
            ),
        })
    }

    /// Consistent ∂P/∂F through [`decoupled_tangent`], with
    /// dM = 2 W₁₁ dE B̄ + 2 W₁ dB̄ + d(σ_f/λ̄) g⊗g + (σ_f/λ̄)(dg⊗g + g⊗dg),
    /// dB̄ = dF̄ F̄ᵀ + F̄ dF̄ᵀ, dE = tr dB̄ + x dλ̄, dg = dF̄ a₀, dλ̄ = g·dg/λ̄,
    /// d(σ_f/λ̄) = (σ_f' λ̄ − σ_f)/λ̄² dλ̄ + (W₁₁ x/λ̄) tr dB̄, W₁₁ = b W₁, and
    /// σ_f' = σ_PE' + σ_SEE' (through the local solve) + W₁₁ x² + W₁ x'.
    fn tangent(&self, s: &PointSolution, tau: &Matrix3<f64>) -> crate::Tangent {
        let p = &self.parameters;
        let d_jp_dj = volumetric_kirchhoff_slope(s.split.jacobian, p.compressibility);
        let a0 = s.reference_fiber;
        let w11 = p.matrix_exponent * s.w1_matrix;
        let stretch = s.fiber_stretch;
        let ratio = s.fiber_stress / stretch;
        let x = s.matrix_slack_slope;
        let d_fiber_stress = s.d_pe_stress
            + s.local_equation.series_stress_sensitivity(&s.local)
            + w11 * x * x
            + s.w1_matrix * s.matrix_slack_curvature;
        let d_ratio_d_stretch = (d_fiber_stress * stretch - s.fiber_stress) / (stretch * stretch);
        let d_ratio_d_i1 = w11 * x / stretch;
        let f_bar = s.split.f_bar();
        let b_bar = symmetric_from_voigt(&s.split.b_bar);
        decoupled_tangent(&s.split, tau, d_jp_dj, |d_f_bar| {
            let half = d_f_bar * f_bar.transpose();
            let d_b_bar = half + half.transpose();
            let d_fiber = d_f_bar * a0;
            let d_stretch = s.fiber.dot(&d_fiber) / stretch;
            let d_g_g = d_fiber * s.fiber.transpose();
            let d_i1 = d_b_bar.trace();
            b_bar * (2.0 * w11 * (d_i1 + x * d_stretch))
                + d_b_bar * (2.0 * s.w1_matrix)
                + s.fiber
                    * s.fiber.transpose()
                    * (d_ratio_d_stretch * d_stretch + d_ratio_d_i1 * d_i1)
                + (d_g_g + d_g_g.transpose()) * ratio
        })
    }
}

inventory::submit! {
    MaterialRegistration {
        name: "hill",
        description: "Hill-type hyperelastic active skeletal muscle (matrix + PE + SEE + CE, seed Eqs. 1-23, Table 1)",
        parameters: &HILL_PARAMETERS,
        build: HillMuscle::from_parameters,
    }
}

#[cfg(test)]
mod tests;
