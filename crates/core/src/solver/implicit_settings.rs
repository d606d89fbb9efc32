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
