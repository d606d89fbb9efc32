//! The material interface: a batched, VUMAT-like update of a block of material points.
//!
//! A call hands a material the time, the step, the deformation gradients at the start
//! and the end of the step, the reference fiber direction and the state variables at the
//! start of the step for `n` points, and receives the Cauchy stress and the state at the
//! end of the step (and, when asked, the consistent tangent).
//!
//! Conventions (the same in the C ABI, see `include/musclefem_material.h`):
//! - SI units: Pa, s, m.
//! - `time` is the time at the **end** of the step, t + Δt [s]; `dt` = Δt ≥ 0 [s].
//! - Deformation gradients are `Matrix3` (column-major in memory: entry (i, J) at i + 3J).
//! - Cauchy stress in Voigt order (σxx, σyy, σzz, σyz, σxz, σxy) [Pa].
//! - State variables: `state_count()` per point, point after point.
//! - **Tangent**: the first elasticity tensor 𝔸 = ∂P/∂F (P the first Piola–Kirchhoff
//!   stress, a two-point tensor: the total-Lagrangian, reference-configuration tangent)
//!   as a 9×9 matrix on column-major vec(F): 𝔸[(i+3J), (k+3L)] = ∂P_iJ/∂F_kL [Pa].
//!   It is *consistent*: it differentiates the stress actually returned after the
//!   step's local solve (state at the start of the step held fixed), so Newton on the
//!   discrete equations converges quadratically.

use nalgebra::{Matrix3, SMatrix, Vector3, Vector6};

use crate::MaterialError;

/// Cauchy stress in Voigt order (σxx, σyy, σzz, σyz, σxz, σxy) [Pa].
pub type VoigtStress = Vector6<f64>;

/// First elasticity tensor ∂P/∂F on column-major vec(F), 9×9 [Pa].
pub type Tangent = SMatrix<f64, 9, 9>;

/// Inputs of a block of `n` material points for one step.
#[derive(Debug, Clone, Copy)]
pub struct PointBlock<'a> {
    /// Time at the end of the step, t + Δt [s].
    pub time: f64,
    /// Step Δt ≥ 0 [s].
    pub dt: f64,
    /// Deformation gradient at the start of the step, one per point.
    pub deformation_gradient_old: &'a [Matrix3<f64>],
    /// Deformation gradient at the end of the step, one per point.
    pub deformation_gradient_new: &'a [Matrix3<f64>],
    /// Fiber direction in the reference configuration, one per point: any non-zero vector
    /// (the host does not normalise it; a material that needs a unit vector normalises).
    pub fiber_direction: &'a [Vector3<f64>],
    /// State variables at the start of the step, `state_count()` per point.
    pub state_old: &'a [f64],
}

impl PointBlock<'_> {
    /// Number of points in the block.
    pub fn len(&self) -> usize {
        self.deformation_gradient_new.len()
    }

    /// Whether the block holds no point.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Outputs of a block of material points.
#[derive(Debug)]
pub struct PointResponse<'a> {
    /// Cauchy stress at the end of the step, one per point [Pa].
    pub cauchy_stress: &'a mut [VoigtStress],
    /// State variables at the end of the step, `state_count()` per point.
    pub state_new: &'a mut [f64],
    /// Consistent tangent ∂P/∂F, one per point, when the caller asks for it.
    pub tangent: Option<&'a mut [Tangent]>,
}

/// Name, unit and initial value of one state variable.
#[derive(Debug, Clone, PartialEq)]
pub struct StateVariable {
    pub name: String,
    pub unit: String,
    pub initial: f64,
}

/// A constitutive model. Implementations compute; `<dyn Material>::update` checks.
pub trait Material: Send + Sync + std::fmt::Debug {
    /// Registry name of the material.
    fn name(&self) -> &str;

    /// The state variables each point carries (empty for a hyperelastic material).
    fn state_variables(&self) -> &[StateVariable];

    /// Whether `compute` fills the tangent; if not, `update` builds it by central
    /// finite differences of the stress.
    fn provides_tangent(&self) -> bool {
        true
    }

    /// Activation level at `time` [s] (dimensionless, 0 = passive, 1 = full) of a material
    /// that has one, for the outputs; `None` for a passive material.
    fn activation(&self, _time: f64) -> Option<f64> {
        None
    }

    /// This material as the built-in neo-Hookean solid, for the explicit solver's fused
    /// one-point kernel (`NeoHookean::accepted_block_stresses`); `None` for every other.
    fn as_neo_hookean(&self) -> Option<&crate::neo_hookean::NeoHookean> {
        None
    }

    /// The same material driven by a recorded activation history instead of its own
    /// activation parameters (a typed input, see [`crate::ActivationHistory`]); `None`
    /// when the material has no activation to drive.
    fn with_activation_history(
        &self,
        _history: std::sync::Arc<crate::ActivationHistory>,
    ) -> Option<std::sync::Arc<dyn Material>> {
        None
    }

    /// Update a block whose shapes and inputs were already checked by `update`. Fills the
    /// tangent, when asked for, only if `provides_tangent()`; `update` completes it
    /// otherwise.
    fn compute(
        &self,
        block: &PointBlock,
        response: &mut PointResponse,
    ) -> Result<(), MaterialError>;
}

impl dyn Material + '_ {
    /// Number of state variables per point.
    pub fn state_count(&self) -> usize {
        self.state_variables().len()
    }

    /// Initial state for `points` points.
    pub fn initial_state(&self, points: usize) -> Vec<f64> {
        let one: Vec<f64> = self.state_variables().iter().map(|s| s.initial).collect();
        one.repeat(points)
    }

    /// Update a block of points: checks the block's shape and inputs (finite entries,
    /// det F > 0, non-zero fiber direction, finite dt ≥ 0), runs the material, and
    /// checks that what it returned is finite. Errors name the offending point.
    pub fn update(
        &self,
        block: &PointBlock,
        response: &mut PointResponse,
    ) -> Result<(), MaterialError> {
        check_block(self.state_count(), block, response)?;
        let wants_tangent = response.tangent.is_some();
        if self.provides_tangent() || !wants_tangent {
            self.compute(block, response)?;
        } else {
            let tangent = response.tangent.take();
            self.compute(block, response)?;
            if let Some(tangent) = tangent {
                finite_difference_tangent(self, block, tangent)?;
                response.tangent = Some(tangent);
            }
        }
        check_response(self.name(), response)
    }
}

/// Perturbation of each entry of F (dimensionless, absolute) used by
/// [`finite_difference_tangent`].
pub const TANGENT_PERTURBATION: f64 = 1e-6;

/// ∂P/∂F by central differences of P = J σ F⁻ᵀ, perturbing each entry of F_new by
/// h = 1e-6 (F is dimensionless), state at the start of the step held fixed.
/// Truncation error O(h²) ≈ 1e-12 relative; round-off ≈ 1e-10 relative. Used for
/// materials (plugins) that do not supply a tangent, and by the tests as a reference.
pub fn finite_difference_tangent(
    material: &dyn Material,
    block: &PointBlock,
    tangent: &mut [Tangent],
) -> Result<(), MaterialError> {
    let nstate = material.state_count();
    let n = block.len();
    first_mismatch(
        input_shapes(nstate, block)
            .into_iter()
            .chain([("tangent", n, tangent.len())]),
    )?;
    let mut state = vec![0.0; nstate];
    let mut stress = [VoigtStress::zeros()];
    let h = TANGENT_PERTURBATION;
    for p in 0..block.len() {
        let f0 = block.deformation_gradient_new[p];
        let mut first_piola_at = |f: Matrix3<f64>| -> Result<Matrix3<f64>, MaterialError> {
            let f_new = [f];
            let one = PointBlock {
                deformation_gradient_old: &block.deformation_gradient_old[p..p + 1],
                deformation_gradient_new: &f_new,
                fiber_direction: &block.fiber_direction[p..p + 1],
                state_old: &block.state_old[p * nstate..(p + 1) * nstate],
                ..*block
            };
            let mut out = PointResponse {
                cauchy_stress: &mut stress,
                state_new: &mut state,
                tangent: None,
            };
            material.compute(&one, &mut out)?;
            Ok(crate::tensor::first_piola_from_cauchy(&f, &stress[0]))
        };
        for column in 0..9 {
            let mut plus = f0;
            let mut minus = f0;
            plus[column] += h;
            minus[column] -= h;
            let dp = (first_piola_at(plus)? - first_piola_at(minus)?) / (2.0 * h);
            for row in 0..9 {
                tangent[p][(row, column)] = dp[row];
            }
        }
    }
    Ok(())
}

/// (name, expected length, length) of a block's input arrays.
fn input_shapes(nstate: usize, block: &PointBlock) -> [(&'static str, usize, usize); 3] {
    let n = block.len();
    [
        (
            "deformation_gradient_old",
            n,
            block.deformation_gradient_old.len(),
        ),
        ("fiber_direction", n, block.fiber_direction.len()),
        ("state_old", n * nstate, block.state_old.len()),
    ]
}

/// The first array whose length is not the expected one, as an error.
fn first_mismatch(
    shapes: impl IntoIterator<Item = (&'static str, usize, usize)>,
) -> Result<(), MaterialError> {
    match shapes
        .into_iter()
        .find(|(_, expected, found)| expected != found)
    {
        Some((what, expected, found)) => Err(MaterialError::BlockShape {
            what,
            expected,
            found,
        }),
        None => Ok(()),
    }
}

/// Array lengths of a block and its response agree with its point count (`nstate` state
/// variables per point; a tangent, if asked for, per point).
pub(crate) fn check_shapes(
    nstate: usize,
    block: &PointBlock,
    response: &PointResponse,
) -> Result<(), MaterialError> {
    let n = block.len();
    first_mismatch(input_shapes(nstate, block).into_iter().chain([
        ("cauchy_stress", n, response.cauchy_stress.len()),
        ("state_new", n * nstate, response.state_new.len()),
        (
            "tangent",
            n,
            response.tangent.as_ref().map_or(n, |t| t.len()),
        ),
    ]))
}

fn check_block(
    nstate: usize,
    block: &PointBlock,
    response: &PointResponse,
) -> Result<(), MaterialError> {
    check_shapes(nstate, block, response)?;
    let n = block.len();
    if !block.dt.is_finite() || block.dt < 0.0 || !block.time.is_finite() {
        return Err(MaterialError::InvalidStep {
            time: block.time,
            dt: block.dt,
        });
    }
    for p in 0..n {
        let f_old = &block.deformation_gradient_old[p];
        let f_new = &block.deformation_gradient_new[p];
        let fiber = &block.fiber_direction[p];
        let state = &block.state_old[p * nstate..(p + 1) * nstate];
        // One sum catches any NaN or ±∞ cheaply; the slow path below names the culprit.
        let sum = f_old.sum() + f_new.sum() + fiber.sum() + state.iter().sum::<f64>();
        if !sum.is_finite() {
            check_finite_point(p, f_old, f_new, fiber, state)?;
        }
        for (label, f) in [("F_old", f_old), ("F_new", f_new)] {
            let det = f.determinant();
            if det <= 0.0 {
                return Err(invalid(
                    p,
                    format!("det {label} = {det:e} <= 0 (inverted or collapsed element)"),
                ));
            }
        }
        if fiber.norm_squared() < 1e-24 {
            return Err(invalid(
                p,
                format!("fiber direction {fiber:?} is not a direction"),
            ));
        }
    }
    Ok(())
}

fn check_finite_point(
    p: usize,
    f_old: &Matrix3<f64>,
    f_new: &Matrix3<f64>,
    fiber: &Vector3<f64>,
    state: &[f64],
) -> Result<(), MaterialError> {
    let finite = |values: &[f64]| values.iter().all(|x| x.is_finite());
    if !finite(f_old.as_slice()) {
        return Err(invalid(
            p,
            format!("F_old has a non-finite entry: {f_old:?}"),
        ));
    }
    if !finite(f_new.as_slice()) {
        return Err(invalid(
            p,
            format!("F_new has a non-finite entry: {f_new:?}"),
        ));
    }
    if !finite(fiber.as_slice()) {
        return Err(invalid(
            p,
            format!("fiber direction {fiber:?} is not finite"),
        ));
    }
    if !finite(state) {
        return Err(invalid(
            p,
            format!("state variables {state:?} are not finite"),
        ));
    }
    Ok(())
}

fn invalid(point: usize, reason: String) -> MaterialError {
    MaterialError::InvalidPoint { point, reason }
}

fn check_response(material: &str, response: &PointResponse) -> Result<(), MaterialError> {
    let non_finite = |point: usize, what: &'static str| MaterialError::NonFiniteResult {
        material: material.to_string(),
        point,
        what,
    };
    let stress_sum: f64 = response.cauchy_stress.iter().map(|s| s.sum()).sum();
    if !stress_sum.is_finite()
        && let Some(p) = response
            .cauchy_stress
            .iter()
            .position(|s| s.iter().any(|x| !x.is_finite()))
    {
        return Err(non_finite(p, "Cauchy stress"));
    }
    let n = response.cauchy_stress.len();
    if !response.state_new.iter().sum::<f64>().is_finite()
        && let Some(i) = response.state_new.iter().position(|x| !x.is_finite())
    {
        let nstate = response.state_new.len() / n.max(1);
        return Err(non_finite(i / nstate.max(1), "state variable"));
    }
    if let Some(tangent) = &response.tangent
        && let Some(p) = tangent
            .iter()
            .position(|t| t.iter().any(|x| !x.is_finite()))
    {
        return Err(non_finite(p, "tangent"));
    }
    Ok(())
}
