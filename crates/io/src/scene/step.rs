//! The `[step]` of a scene: its duration, output and frame intervals, and the analysis of
//! the solver that runs it (explicit or implicit, with the settings the file gives).

use toml::Spanned;

use musclefem_contact::RigidSurface;
use musclefem_core::mesh::Mesh;
use musclefem_core::solver::amg_cg::LinearSolver;
use musclefem_core::solver::bulk_viscosity::BulkViscosity;
use musclefem_core::solver::explicit::ExplicitSettings;
use musclefem_core::solver::implicit::{ImplicitSettings, Newmark};
use musclefem_core::solver::{Part, RigidMotion};

use super::Analysis;
use super::error::{Locator, SceneError, suggestion};
use super::format::{ExplicitEntry, ImplicitEntry, SceneFile};
use super::solver_choice::{AutoSolver, choose_solver};

/// What the step sets.
pub(super) struct StepSettings {
    pub analysis: Analysis,
    /// Why `solver = "auto"` chose the analysis's solver (`None`: the scene named it).
    pub solver_rationale: Option<String>,
    pub output_interval: f64,
    pub frame_interval: f64,
}

/// The step of `scene`, whose model has `mesh`, `parts` and `rigid_bodies` (and
/// interactions, when `has_interactions`).
pub(super) fn step_settings(
    scene: &SceneFile,
    mesh: &Mesh,
    parts: &[Part],
    has_interactions: bool,
    rigid_bodies: &[RigidSurface],
    locator: &Locator,
) -> Result<StepSettings, SceneError> {
    let at = |span: std::ops::Range<usize>, message: String| locator.error(span, message);
    let step = &scene.step;
    let duration = *step.duration.get_ref();
    if !(duration.is_finite() && duration > 0.0) {
        return Err(at(
            step.duration.span(),
            format!("duration {duration} s must be positive"),
        ));
    }
    let output_interval = match &step.output_interval {
        Some(v) if !(v.get_ref().is_finite() && *v.get_ref() > 0.0) => {
            return Err(at(
                v.span(),
                format!("output_interval {} s must be positive", v.get_ref()),
            ));
        }
        Some(v) => *v.get_ref(),
        None => duration / 100.0,
    };
    let frame_interval = match &scene.output.frame_interval {
        Some(v) if !(v.get_ref().is_finite() && *v.get_ref() > 0.0) => {
            return Err(at(
                v.span(),
                format!("frame_interval {} s must be positive", v.get_ref()),
            ));
        }
        Some(v) => *v.get_ref(),
        None => output_interval,
    };
    let solver_span = step
        .solver
        .as_ref()
        .map_or(step.duration.span(), |s| s.span());
    let (solver, solver_rationale) = match step.solver.as_ref().map(|s| s.get_ref().as_str()) {
        None | Some("auto") => {
            let (solver, why) = choose_solver(mesh, parts, duration, has_interactions);
            (solver, Some(why))
        }
        Some("explicit") => (AutoSolver::Explicit, None),
        Some("implicit") => (AutoSolver::Implicit { dynamic: false }, None),
        Some(other) => {
            return Err(at(
                solver_span,
                format!(
                    "unknown solver '{other}'{}; use auto, explicit or implicit",
                    suggestion(other, ["auto", "explicit", "implicit"])
                ),
            ));
        }
    };
    // Every setting the file gives is checked, whichever solver runs (`run --solver` may
    // switch it): `check` refuses what `run` would.
    let in_range = |value: &Option<Spanned<f64>>,
                    key: &str,
                    what: &str,
                    accepts: fn(f64) -> bool|
     -> Result<(), SceneError> {
        match value {
            Some(v) if !accepts(*v.get_ref()) => Err(at(
                v.span(),
                format!("{key} = {} must be {what}", v.get_ref()),
            )),
            _ => Ok(()),
        }
    };
    let explicit = &step.explicit;
    in_range(
        &explicit.safety_factor,
        "safety_factor",
        "in (0, 1] (a fraction of the stable time step)",
        |x| x > 0.0 && x <= 1.0,
    )?;
    in_range(
        &explicit.mass_scaling_time_step,
        "mass_scaling_time_step",
        "a positive time [s]",
        |x| x.is_finite() && x > 0.0,
    )?;
    in_range(
        &explicit.shear_viscosity,
        "shear_viscosity",
        "a viscosity ≥ 0 [Pa s]",
        |x| x.is_finite() && x >= 0.0,
    )?;
    in_range(
        &explicit.energy_tolerance,
        "energy_tolerance",
        "a positive fraction of the largest energy",
        |x| x.is_finite() && x > 0.0,
    )?;
    in_range(
        &step.implicit.residual_tolerance,
        "residual_tolerance",
        "in (0, 1) (relative to the first residual)",
        |x| x > 0.0 && x < 1.0,
    )?;
    implicit_checks(&step.implicit, locator)?;
    let mass_scaling_frame = mass_scaling_frame(&step.explicit, rigid_bodies, locator)?;
    let analysis = match solver {
        AutoSolver::Explicit => {
            let mut settings = ExplicitSettings::new(duration);
            settings.history_interval = output_interval;
            let e = &step.explicit;
            if let Some(v) = &e.safety_factor {
                settings.safety_factor = *v.get_ref();
            }
            settings.mass_scaling_time_step =
                e.mass_scaling_time_step.as_ref().map(|v| *v.get_ref());
            if let Some(v) = &e.energy_tolerance {
                settings.energy_tolerance = *v.get_ref();
            }
            settings.bulk_viscosity = e.bulk_viscosity.then(BulkViscosity::default);
            settings.shear_viscosity = e.shear_viscosity.as_ref().map(|v| *v.get_ref());
            settings.mass_scaling_frame = mass_scaling_frame;
            Analysis::Explicit(settings)
        }
        AutoSolver::Implicit { dynamic } => {
            let i = &step.implicit;
            let increments = i.increments.as_ref().map_or(10, |v| *v.get_ref());
            if increments == 0 {
                let span = i.increments.as_ref().map_or(solver_span, |v| v.span());
                return Err(at(span, "increments must be at least 1".to_string()));
            }
            let mut settings = ImplicitSettings::new(duration, increments);
            if i.step_cutting.unwrap_or(true) {
                settings = settings.with_cutting();
            }
            if let Some(v) = &i.residual_tolerance {
                settings.residual_tolerance = *v.get_ref();
            }
            if i.dynamic || dynamic {
                settings.dynamics = Some(match &i.numerical_dissipation {
                    Some(alpha) => dissipative_newmark(*alpha.get_ref()),
                    None => Newmark::default(),
                });
            }
            implicit_options(i, &mut settings, rigid_bodies, locator)?;
            Analysis::Implicit(settings)
        }
    };
    Ok(StepSettings {
        analysis,
        solver_rationale,
        output_interval,
        frame_interval,
    })
}

/// The motion of the rigid body `[step.explicit] mass_scaling_frame` names, checked
/// whichever solver runs: it must name a rigid body, and mass scaling must be on.
fn mass_scaling_frame(
    explicit: &ExplicitEntry,
    rigid_bodies: &[RigidSurface],
    locator: &Locator,
) -> Result<Option<Box<RigidMotion>>, SceneError> {
    let Some(name) = &explicit.mass_scaling_frame else {
        return Ok(None);
    };
    if explicit.mass_scaling_time_step.is_none() {
        return Err(locator.error(
            name.span(),
            format!(
                "mass_scaling_frame = \"{}\" without mass_scaling_time_step: there is no \
                 added mass to carry",
                name.get_ref()
            ),
        ));
    }
    let body = (rigid_bodies.iter())
        .find(|b| &b.name == name.get_ref())
        .ok_or_else(|| {
            locator.error(
                name.span(),
                format!(
                    "mass_scaling_frame: no rigid body '{}'{}",
                    name.get_ref(),
                    suggestion(name.get_ref(), rigid_bodies.iter().map(|b| b.name.as_str()))
                ),
            )
        })?;
    Ok(Some(Box::new(body.motion.clone())))
}

/// Newmark's parameters with numerical dissipation α ≥ 0: γ = ½ + α, β = (1 + α)²/4
/// (unconditionally stable; α = 0 is the trapezoidal rule, which keeps every vibration).
pub fn dissipative_newmark(alpha: f64) -> Newmark {
    Newmark {
        gamma: 0.5 + alpha,
        beta: 0.25 * (1.0 + alpha).powi(2),
    }
}

/// The implicit keys checked whichever solver runs (`run --solver` may switch it).
fn implicit_checks(implicit: &ImplicitEntry, locator: &Locator) -> Result<(), SceneError> {
    if let Some(v) = &implicit.correction_tolerance
        && !(*v.get_ref() > 0.0 && *v.get_ref() < 1.0)
    {
        return Err(locator.error(
            v.span(),
            format!(
                "correction_tolerance = {} must be in (0, 1) (relative to the largest \
                 displacement)",
                v.get_ref()
            ),
        ));
    }
    if let Some(alpha) = &implicit.numerical_dissipation {
        let value = *alpha.get_ref();
        if !(value.is_finite() && (0.0..=0.5).contains(&value)) {
            return Err(locator.error(
                alpha.span(),
                format!("numerical_dissipation = {value} must be in [0, 0.5]"),
            ));
        }
        if !implicit.dynamic {
            return Err(locator.error(
                alpha.span(),
                "numerical_dissipation applies to Newmark dynamics: add `dynamic = true`",
            ));
        }
    }
    if let Some(v) = &implicit.max_iterations
        && *v.get_ref() == 0
    {
        return Err(locator.error(v.span(), "max_iterations must be at least 1"));
    }
    Ok(())
}

/// The implicit keys beyond increments, dynamics and the residual tolerance.
fn implicit_options(
    implicit: &ImplicitEntry,
    settings: &mut ImplicitSettings,
    rigid_bodies: &[RigidSurface],
    locator: &Locator,
) -> Result<(), SceneError> {
    if let Some(v) = &implicit.correction_tolerance {
        settings.correction_tolerance = *v.get_ref();
    }
    if let Some(v) = &implicit.line_search_cuts {
        settings.line_search_cuts = *v.get_ref();
    }
    if let Some(v) = &implicit.max_iterations {
        settings.max_iterations = *v.get_ref();
    }
    if implicit.factor_reuse == Some(false) {
        settings.factor_reuse = None;
    }
    if implicit.inexact_newton == Some(false) {
        settings.forcing = None;
    }
    if implicit.extrapolate == Some(false) {
        settings.extrapolate = false;
    }
    if let Some(name) = &implicit.linear_solver {
        const SOLVERS: [(&str, LinearSolver); 3] = [
            ("direct", LinearSolver::Direct),
            ("amg_cg", LinearSolver::AmgCg),
            ("auto", LinearSolver::Auto),
        ];
        settings.linear_solver = SOLVERS
            .iter()
            .find(|(n, _)| n == name.get_ref())
            .map(|(_, solver)| *solver)
            .ok_or_else(|| {
                locator.error(
                    name.span(),
                    format!(
                        "linear_solver: '{}' is none of \"direct\", \"amg_cg\", \"auto\"{}",
                        name.get_ref(),
                        suggestion(name.get_ref(), SOLVERS.iter().map(|(n, _)| *n))
                    ),
                )
            })?;
    }
    if let Some(name) = &implicit.predictor_frame {
        let body = rigid_bodies
            .iter()
            .find(|b| &b.name == name.get_ref())
            .ok_or_else(|| {
                locator.error(
                    name.span(),
                    format!(
                        "predictor_frame: no rigid body '{}'{}",
                        name.get_ref(),
                        suggestion(name.get_ref(), rigid_bodies.iter().map(|b| b.name.as_str()))
                    ),
                )
            })?;
        settings.predictor_frame = Some(Box::new(body.motion.clone()));
    }
    Ok(())
}
