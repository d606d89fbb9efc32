//! The settings of the implicit solver: increments, tolerances, step cutting, factor
//! reuse and (optional) Newmark dynamics.

use super::SolverError;
use super::amg_cg::{AmgCgSettings, LinearSolver};
use super::implicit::MAX_INCREMENTS;
use super::implicit_dynamics::Newmark;
use super::sparse::FactorReuse;

/// Automatic step cutting: halve a failed increment, grow it back after easy steps.
#[derive(Debug, Clone, PartialEq)]
pub struct StepCutting {
    /// Halvings allowed below the initial increment (smallest = initial / 2^max_cuts).
    pub max_cuts: u32,
    /// Factor by which the increment grows after `easy_steps` easy steps in a row (≥ 1),
    /// up to the initial increment.
    pub growth: f64,
    /// A step is easy if it converged in at most this many Newton iterations.
    pub easy_iterations: usize,
    /// Easy steps in a row before the increment grows.
    pub easy_steps: usize,
}

impl Default for StepCutting {
    /// 10 halvings, growth 1.5 after 2 steps of at most 5 iterations.
    fn default() -> Self {
        StepCutting {
            max_cuts: 10,
            growth: 1.5,
            easy_iterations: 5,
            easy_steps: 2,
        }
    }
}

/// Inexact Newton: how accurately the iterative linear solves (conjugate gradients with
/// an earlier Cholesky factor, AMG-CG) solve for a Newton correction. A correction need
/// not be more accurate than the step's nonlinearity lets the next residual be, nor
/// than the residual tolerance asks, so iteration k (k ≥ 1, residual r_k, force scale F)
/// stops its solve at the relative residual
///
/// η_k = min(`largest`, max(γ (‖r_k‖ / ‖r_{k−1}‖)², `safety` · tol_r · F / ‖r_k‖)),
///
/// the first term choice 2 of Eisenstat & Walker (1996, SIAM J Sci Comput 17:16) with
/// γ = `gamma` and exponent 2 (the rate of Newton's convergence), the second the accuracy
/// that reaches the tolerance in this iteration; r₀ is the predictor's right-hand side,
/// whose solve stops at `predictor`. A solver's own tolerance is the floor of η (direct
/// solves are exact). The converged states are those of exact solves to within the
/// residual tolerance; convergence stays quadratic in the limit.
///
/// η is capped at 1e-6 by default, far below the 0.1–0.9 usual for Eisenstat–Walker: in a
/// nearly incompressible solid (K/μ ≈ 10⁴) a small linear residual can hide a correction
/// error in the soft shear modes that changes the volume, and the bulk modulus amplifies
/// it. The block of `tests/implicit_mixed_pressure.rs` twisted 10° per increment took 27
/// Newton iterations with exact solves and with η ≤ 1e-6, 30 with η ≤ 1e-4, and 276
/// with 3 cuts with η ≤ 1e-2 and a predictor η of 1e-4.
#[derive(Debug, Clone, PartialEq)]
pub struct Forcing {
    /// η of the predictor's solve (default 1e-6).
    pub predictor: f64,
    /// γ of Eisenstat & Walker's choice 2 (default 0.9).
    pub gamma: f64,
    /// Factor on the η that just reaches the residual tolerance (default 0.1).
    pub safety: f64,
    /// Largest η (default 1e-6).
    pub largest: f64,
}

impl Default for Forcing {
    fn default() -> Self {
        Forcing {
            predictor: 1e-6,
            gamma: 0.9,
            safety: 0.1,
            largest: 1e-6,
        }
    }
}

impl Forcing {
    /// η_k of iteration k ≥ 1 from ‖r_k‖ (`residual`), ‖r_{k−1}‖ (`previous`), the force
    /// scale F (`force`) and tol_r (`tolerance`).
    pub fn eta(&self, residual: f64, previous: f64, force: f64, tolerance: f64) -> f64 {
        if !(residual > 0.0 && previous > 0.0) {
            return 0.0;
        }
        let nonlinear = self.gamma * (residual / previous).powi(2);
        let sufficient = self.safety * tolerance * force / residual;
        nonlinear.max(sufficient).min(self.largest)
    }
}

/// Settings of a quasi-static run.
#[derive(Debug, Clone, PartialEq)]
pub struct ImplicitSettings {
    /// End of the load history [s] (the run starts at t = 0).
    pub end_time: f64,
    /// Number of equal increments (the initial and largest increment with cutting).
    pub increments: usize,
    /// Automatic cutting, or `None` for fixed increments (a failed step is an error).
    pub cutting: Option<StepCutting>,
    /// Newton iterations allowed per step, predictor included (default 25).
    pub max_iterations: usize,
    /// Relative residual tolerance tol_r (default 1e-10).
    pub residual_tolerance: f64,
    /// Relative correction tolerance tol_u (default 1e-6).
    pub correction_tolerance: f64,
    /// A correction max |δu| ≤ this × max |u| ends the iterations whatever the residual
    /// (default 1e-10): the displacements are then exact to round-off, and the residual
    /// has hit its floor. For nearly incompressible materials that floor is ~ε K/μ of the
    /// stresses, above `residual_tolerance` at small loads (the muscle's matrix, K/μ ≈
    /// 35 000, stretched by 0.1 % stalled at 3e-8 before this criterion).
    pub round_off_correction: f64,
    /// Halvings the line search may try per iteration (default 8).
    pub line_search_cuts: usize,
    /// Unknowns from which the sparse factorizations run on rayon's threads; below,
    /// they run serially. Default `usize::MAX`: always serial, so that whole runs are the
    /// same, bit for bit, on any number of threads (element updates are parallel and
    /// deterministic either way). faer's parallel factorization is not reproducible across
    /// thread counts (a 20×20×20 hex8 cube, 26 019 unknowns, differed between 1 and 2
    /// threads), and on 2 busy cores it was not consistently faster (one step, 4 Newton
    /// iterations: 7.6–8.4 s serial, 6.7–11.9 s on 2 threads).
    pub parallel_factorization_unknowns: usize,
    /// Reuse of the last Cholesky factor as a preconditioner of conjugate gradients
    /// (default on, see [`FactorReuse`]); `None` factorizes every tangent.
    pub factor_reuse: Option<FactorReuse>,
    /// Start each increment's Newton iterations from the last converged displacements
    /// plus the last increment's change scaled to this increment's length (linear
    /// extrapolation in time, on the free degrees of freedom; default true). Quasi-static
    /// runs without interactions or a predictor frame only; after a checkpoint the next
    /// increment starts without it, as a resumed run does. The converged states are the
    /// same to the tolerances; on the uniaxial cube of issue #36 it saves one Newton
    /// iteration of every three (`docs/implicit-speed.md`).
    pub extrapolate: bool,
    /// Inexact Newton for the iterative linear solves (default on, see [`Forcing`]);
    /// `None` solves every system to the solver's own tolerance.
    pub forcing: Option<Forcing>,
    /// The solver of symmetric tangents (default [`LinearSolver::Direct`]) and the
    /// settings of AMG-preconditioned conjugate gradients (`amg_cg.rs`).
    pub linear_solver: LinearSolver,
    pub amg_cg: AmgCgSettings,
    /// Implicit dynamics with Newmark's method and the lumped mass (see
    /// `implicit_dynamics.rs`); `None` (default) is quasi-static. A dynamic run starts
    /// from rest in the undeformed, stress-free state, with a⁰ = M⁻¹ f_ext(0) on the free
    /// components.
    pub dynamics: Option<Newmark>,
    /// Energy criterion (default `None`): a step also converges when the work of the
    /// last correction |δuᵀ r| is at most this fraction of that of the step's first one.
    pub energy_tolerance: Option<f64>,
    /// Newton's tangent of F-bar hex8 and tet10 with the mixed element pressure of
    /// `mixed_pressure.rs` (default true): the converged states are the same, but for a
    /// nearly incompressible material Newton needs far fewer iterations (the coarse
    /// passive knee squat: 389 against 753, and no cut against 13).
    pub mixed_pressure_tangent: bool,
    /// With [`ImplicitSettings::dynamics`]: solve for Newton's correction with a larger mass
    /// term when the tangent is indefinite (default true): K + (s − 1) M/(β Δt²) for
    /// s = 4, 16, 64 (`sparse::MASS_SHIFTS`), the first Cholesky accepts, before LBLᵀ on
    /// K. The residual is unchanged, so the converged states are the same; the correction
    /// is taken with a shorter increment's tangent, so that a motion the increment is too
    /// long to follow does not dominate it (see the README's "Newton's convergence on the
    /// knee").
    pub mass_shift_for_indefinite_tangents: bool,
    /// Keep the nodal displacements of every converged step in
    /// [`ImplicitResult::displacement_history`] (default false).
    pub record_displacements: bool,
    /// A rigid motion that carries the whole model at the start of each increment, before
    /// the predictor (default `None`): every node moves from x to Q(t + Δt) Q(t)⁻¹ x, the
    /// frame's own motion over the increment. For a model that rides on a moving body (the
    /// knee's muscles on the femur, which moves in the closed-chain squat) this is a far
    /// better first guess than the positions at t: sliding contact on the moving body
    /// otherwise sees the body jump by the increment's motion, and the predictor answers
    /// through the soft tangential directions with large, distorting moves. Only Newton's
    /// starting point changes; the converged states are the same. (Boxed: a rigid motion
    /// is large, and the settings travel inside enums.)
    pub predictor_frame: Option<Box<super::RigidMotion>>,
}

impl ImplicitSettings {
    /// `increments` fixed increments to `end_time`, default tolerances, no cutting.
    pub fn new(end_time: f64, increments: usize) -> Self {
        ImplicitSettings {
            end_time,
            increments,
            cutting: None,
            max_iterations: 25,
            residual_tolerance: 1e-10,
            correction_tolerance: 1e-6,
            round_off_correction: 1e-10,
            line_search_cuts: 8,
            parallel_factorization_unknowns: usize::MAX,
            factor_reuse: Some(FactorReuse::default()),
            extrapolate: true,
            forcing: Some(Forcing::default()),
            linear_solver: LinearSolver::Direct,
            amg_cg: AmgCgSettings::default(),
            dynamics: None,
            energy_tolerance: None,
            mixed_pressure_tangent: true,
            mass_shift_for_indefinite_tangents: true,
            record_displacements: false,
            predictor_frame: None,
        }
    }

    /// The same with automatic cutting (default [`StepCutting`]).
    pub fn with_cutting(mut self) -> Self {
        self.cutting = Some(StepCutting::default());
        self
    }
}

pub(super) fn check_newmark(newmark: &Newmark) -> Result<(), SolverError> {
    if !(newmark.beta > 0.0 && newmark.beta <= 0.5 && newmark.gamma >= 0.0 && newmark.gamma <= 1.0)
    {
        return Err(SolverError::InvalidImplicitSettings(format!(
            "Newmark parameters beta = {}, gamma = {} must satisfy 0 < beta <= 1/2, 0 <= gamma <= 1",
            newmark.beta, newmark.gamma
        )));
    }
    Ok(())
}

pub(super) fn check_settings(settings: &ImplicitSettings) -> Result<(), SolverError> {
    let bad = |what: String| Err(SolverError::InvalidImplicitSettings(what));
    if !(settings.end_time.is_finite() && settings.end_time > 0.0) {
        return bad(format!("end time {} must be positive", settings.end_time));
    }
    if settings.increments == 0 {
        return bad("at least one increment is needed".to_string());
    }
    if settings.increments > MAX_INCREMENTS {
        return bad(format!(
            "{} increments are more than the {MAX_INCREMENTS} a run may take (each is a \
             history row): use a longer increment",
            settings.increments
        ));
    }
    if settings.max_iterations == 0 {
        return bad("at least one Newton iteration is needed".to_string());
    }
    for (name, value) in [
        ("residual tolerance", settings.residual_tolerance),
        ("correction tolerance", settings.correction_tolerance),
        ("round-off correction", settings.round_off_correction),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return bad(format!("{name} {value} must be positive"));
        }
    }
    if let Some(cutting) = &settings.cutting
        && !(cutting.growth.is_finite() && cutting.growth >= 1.0)
    {
        return bad(format!("growth factor {} must be >= 1", cutting.growth));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::Forcing;

    #[test]
    fn the_forcing_term_is_the_looser_of_the_nonlinear_and_the_sufficient_accuracy() {
        let forcing = Forcing {
            largest: 1e-2,
            ..Forcing::default()
        };
        // Early: ‖r_k‖/‖r_{k−1}‖ = 1e-2, so γ · 1e-4 = 9e-5 beats 0.1 · 1e-10 · 1 / 1e-3.
        let early = forcing.eta(1e-3, 1e-1, 1.0, 1e-10);
        assert!((early - 9e-5).abs() < 1e-18, "{early}");
        // Late: the tolerance is near, 0.1 · 1e-10 / 1e-8 = 1e-3 beats γ · 1e-4.
        let late = forcing.eta(1e-8, 1e-6, 1.0, 1e-10);
        assert!((late - 1e-3).abs() < 1e-15, "{late}");
        // Never looser than the largest, and exact solves for a zero residual.
        assert_eq!(forcing.eta(0.5, 0.6, 1.0, 1e-10), 1e-2);
        assert_eq!(forcing.eta(0.0, 1.0, 1.0, 1e-10), 0.0);
        // The defaults cap η at 1e-6 (nearly incompressible solids need it).
        assert_eq!(Forcing::default().eta(0.5, 0.6, 1.0, 1e-10), 1e-6);
    }
}
