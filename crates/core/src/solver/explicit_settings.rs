//! The settings of an explicit run ([`ExplicitSettings`]) and the checks made before it
//! starts: valid values, a step budget, and enough steps for a mass-scaled run.

use super::SolverError;
use super::bulk_viscosity::BulkViscosity;

/// Settings of an explicit run.
#[derive(Debug, Clone, PartialEq)]
pub struct ExplicitSettings {
    /// End of the step [s] (the run starts at t = 0).
    pub end_time: f64,
    /// Fraction of the stable step taken (0 < safety ≤ 1), default 0.9.
    pub safety_factor: f64,
    /// A fixed step instead of the stable one [s]; refused if above the stable step
    /// (unless `refuse_unstable_step` is off).
    pub fixed_time_step: Option<f64>,
    /// Refuse a fixed step above the estimated stable step (default true). Off, the step
    /// is taken anyway, so that the real limit can be measured: beyond it the energy
    /// balance or the divergence check stops the run (docs/stability.md).
    pub refuse_unstable_step: bool,
    /// A history row is recorded every this many seconds, and at the end.
    pub history_interval: f64,
    /// Largest allowed |W_int + W_visc + K − W_ext| relative to the largest energy,
    /// default 0.01.
    pub energy_tolerance: f64,
    /// Target stable step of mass scaling [s]; `None` (default) = no mass scaling.
    pub mass_scaling_time_step: Option<f64>,
    /// Linear and quadratic bulk viscosity; `None` (default) = none.
    pub bulk_viscosity: Option<BulkViscosity>,
    /// Shear (deviatoric) viscosity η [Pa s] of every element: σ_v = 2η dev D̄ from the
    /// element's mean rate of deformation ([`super::bulk_viscosity`]); `None` (default) =
    /// none. For quasi-static runs whose mass scaling slows a soft tissue's shear modes
    /// down to the loading's time scale, where they ring undamped.
    pub shear_viscosity: Option<f64>,
    /// A rigid motion that carries the mass added by mass scaling (default `None`): the
    /// added mass gets the frame's acceleration as a body force, so that it has inertia
    /// only for motion relative to the frame ([`super::added_mass_frame`]). For a
    /// mass-scaled model that rides on a moving body (the knee's muscles on the femur).
    /// (Boxed: a rigid motion is large, and the settings travel inside enums.)
    pub mass_scaling_frame: Option<Box<super::RigidMotion>>,
}

impl ExplicitSettings {
    /// Whether any artificial viscosity (bulk or shear) is on.
    pub fn has_viscosity(&self) -> bool {
        self.bulk_viscosity.is_some() || self.shear_viscosity.is_some()
    }
}

impl ExplicitSettings {
    /// Defaults for a run to `end_time`: safety 0.9, 100 history rows, 1 % energy balance.
    pub fn new(end_time: f64) -> Self {
        ExplicitSettings {
            end_time,
            safety_factor: 0.9,
            fixed_time_step: None,
            refuse_unstable_step: true,
            history_interval: end_time / 100.0,
            energy_tolerance: 0.01,
            mass_scaling_time_step: None,
            bulk_viscosity: None,
            shear_viscosity: None,
            mass_scaling_frame: None,
        }
    }
}

/// The most steps a run may take (estimated from the first stable step): beyond it the
/// duration or the mesh is almost surely a mistake (10⁹ steps of even a small model take
/// days), and the run is refused before it starts.
pub const MAX_EXPLICIT_STEPS: f64 = 1e9;

/// The fewest steps a mass-scaled run may take: a target step above a tenth of the run
/// makes the added mass, not the material, carry the response.
pub const MIN_MASS_SCALED_STEPS: f64 = 10.0;

pub(super) fn check_settings(settings: &ExplicitSettings) -> Result<(), SolverError> {
    let bad = |what: String| Err(SolverError::InvalidSettings(what));
    if !(settings.end_time.is_finite() && settings.end_time > 0.0) {
        return bad(format!("end time {} must be positive", settings.end_time));
    }
    if !(settings.safety_factor > 0.0 && settings.safety_factor <= 1.0) {
        return bad(format!(
            "safety factor {} must be in (0, 1]",
            settings.safety_factor
        ));
    }
    if !(settings.history_interval.is_finite() && settings.history_interval > 0.0) {
        return bad(format!(
            "history interval {} must be positive",
            settings.history_interval
        ));
    }
    if let Some(eta) = settings.shear_viscosity
        && !(eta.is_finite() && eta >= 0.0)
    {
        return bad(format!(
            "shear viscosity {eta} Pa s must be finite and not negative"
        ));
    }
    for (name, step) in [
        ("mass-scaling target step", settings.mass_scaling_time_step),
        ("fixed time step", settings.fixed_time_step),
    ] {
        if let Some(step) = step
            && !(step.is_finite() && step > 0.0)
        {
            return bad(format!("{name} {step} s must be positive and finite"));
        }
    }
    // The step that governs the run: a fixed step overrides the mass-scaling target
    // (which then only adds mass).
    let governing = match (settings.fixed_time_step, settings.mass_scaling_time_step) {
        (Some(fixed), _) => Some(("fixed time step", fixed)),
        (None, Some(target)) => Some(("mass-scaling target step", target)),
        (None, None) => None,
    };
    if let Some((name, step)) = governing
        && step > settings.end_time / MIN_MASS_SCALED_STEPS
    {
        return bad(format!(
            "{name} {step} s is more than a tenth of the run's {} s: the run would take \
             fewer than {MIN_MASS_SCALED_STEPS} steps and inertia would swamp the response",
            settings.end_time
        ));
    }
    Ok(())
}

/// Refuses a run whose first stable step `step` [s] would need more than
/// [`MAX_EXPLICIT_STEPS`] steps to reach `end_time`.
pub(super) fn check_step_budget(end_time: f64, step: f64) -> Result<(), SolverError> {
    let steps = end_time / step;
    if steps.is_nan() || steps > MAX_EXPLICIT_STEPS {
        return Err(SolverError::InvalidSettings(format!(
            "the run of {end_time} s would take about {steps:.3e} steps of {step:.3e} s, \
             more than the {MAX_EXPLICIT_STEPS:e} allowed: shorten it, coarsen the mesh or \
             use mass scaling"
        )));
    }
    Ok(())
}
