//! `solver = "auto"` (the default): the solver a scene needs, from how slow its step is
//! against the time a pressure wave takes to cross the model.
//!
//! t_wave = L / c, with L the diagonal of the mesh's bounding box [m] and
//! c = √((K + 4μ/3) / ρ) the fastest small-strain dilatational wave speed of the parts
//! [m/s]. A step of duration T with T / t_wave ≥ [`SLOW_MOTION_RATIO`] is slow motion:
//! inertia hardly matters, the explicit solver would need at least T / t_wave steps (its
//! stable step is below the time a wave takes to cross one element), and Newton's
//! increments are far fewer, so the implicit solver runs it. With interactions (contact,
//! cohesion) it keeps the inertia (Newmark's trapezoidal rule), which let the active
//! knee squat through the activation's onset where quasi-static Newton stalled. A faster
//! step (impact, waves) runs explicitly.
//!
//! Measured basis (README, `docs/stability.md`): the elongation test (T / t_wave ≈ 2e4)
//! is cheapest within 2 % implicitly (F-bar hex8 at 4 mm: 1.1 % in 2.2 s), while the
//! explicit runs with mass scaling were 11–19 % off in 3–5.5 s; the knee squat
//! (≈ 3e3, contact and cohesion) took 524 s implicitly with inertia against 1290 s
//! explicitly, both within 1.9 % of each other; the bench's clamped cube pulled in 1 s
//! (615) has the implicit one-point hex8 on its Pareto front (0.58 % in 0.017 s).

use musclefem_core::mesh::Mesh;
use musclefem_core::solver::Part;

use super::locking::small_strain_bulk_modulus;
use super::locking::small_strain_shear_modulus;

/// T / t_wave from which a step counts as slow motion and runs implicitly.
pub const SLOW_MOTION_RATIO: f64 = 100.0;

/// What `auto` chose.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AutoSolver {
    Explicit,
    /// Implicit, with the inertia (Newmark) when `dynamic`.
    Implicit {
        dynamic: bool,
    },
}

/// The choice for a step of `duration` [s] on `mesh` and `parts`, with or without
/// interactions, and why (one sentence for the log).
pub fn choose_solver(
    mesh: &Mesh,
    parts: &[Part],
    duration: f64,
    has_interactions: bool,
) -> (AutoSolver, String) {
    let Some(wave_speed) = fastest_wave_speed(parts) else {
        return (
            AutoSolver::Explicit,
            "solver auto: explicit, because no part's material has a small-strain \
             stiffness to judge the motion's speed by"
                .to_string(),
        );
    };
    let crossing = bounding_box_diagonal(mesh) / wave_speed;
    let ratio = duration / crossing;
    let measure = format!(
        "the step lasts {duration} s, {ratio:.0} times the {crossing:.2e} s a pressure wave \
         ({wave_speed:.1} m/s) takes to cross the model"
    );
    if ratio >= SLOW_MOTION_RATIO {
        let solver = AutoSolver::Implicit {
            dynamic: has_interactions,
        };
        let inertia = if has_interactions {
            ", with inertia (Newmark) because of the interactions"
        } else {
            ", quasi-static"
        };
        (
            solver,
            format!(
                "solver auto: implicit{inertia}: {measure}, at least {SLOW_MOTION_RATIO} \
                 (slow motion)"
            ),
        )
    } else {
        (
            AutoSolver::Explicit,
            format!("solver auto: explicit: {measure}, below {SLOW_MOTION_RATIO} (fast motion)"),
        )
    }
}

/// √((K + 4μ/3) / ρ) of the stiffest part [m/s]; `None` when no part has one.
pub fn fastest_wave_speed(parts: &[Part]) -> Option<f64> {
    parts
        .iter()
        .filter_map(|part| {
            let material = part.material.as_ref();
            let mu = small_strain_shear_modulus(material)?;
            let bulk = small_strain_bulk_modulus(material)?;
            Some(((bulk + 4.0 * mu / 3.0) / part.density).sqrt())
        })
        .filter(|c| c.is_finite() && *c > 0.0)
        .reduce(f64::max)
}

/// The diagonal of the nodes' bounding box [m].
fn bounding_box_diagonal(mesh: &Mesh) -> f64 {
    let n = mesh.node_count();
    if n == 0 {
        return 0.0;
    }
    let first = mesh.nodes.position(0);
    let (low, high) = (1..n).fold((first, first), |(low, high), i| {
        let x = mesh.nodes.position(i);
        (low.inf(&x), high.sup(&x))
    });
    (high - low).norm()
}
