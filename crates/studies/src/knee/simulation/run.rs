//! One squat (passive or active) with either solver: its settings, the model and its
//! interactions, the solver's analysis, and the result gathered from the recorder (the
//! squat runs as its scene: [`super::scene_run`]).

use std::time::Duration;

use anyhow::Result;

use musclefem_core::solver::explicit::ExplicitSettings;
use musclefem_core::solver::implicit::{
    CutAttempt, EvaluationTimes, ImplicitSettings, LinearSolveStatistics, StepReport,
};
use musclefem_core::solver::{Analysis, Outcome, RigidMotion};
use musclefem_fibers::FiberField;
use musclefem_io::scene::dissipative_newmark;

use super::super::anatomy::Squat;
use super::interactions::{InteractionSummary, InterfaceLaw, KneeInteractions, knee_interactions};
use super::model::{Activation, KneeGeometry, KneeModel};
use super::patella::TendonRow;
use super::patella_clearance::PatellaApproach;
use super::peak_stress::{ElementRegions, PeakStressRow, StressSample, peak_stress_rows};
use super::plausibility::{PlausibilityRow, PlausibilitySample, plausibility_rows};
use super::recorder::Recorder;
use crate::elongation::{ElementChoice, Solver};
use crate::knee::Quadriceps;

/// How a squat is run.
#[derive(Clone, Debug, PartialEq)]
pub struct SquatSettings {
    pub squat: Squat,
    pub solver: Solver,
    /// The muscles' hexahedra: F-bar or one-point.
    pub element: ElementChoice,
    /// Implicit: the (largest) increment [s]; explicit: the mass-scaling target step [s].
    pub time_step: f64,
    /// Explicit: time between recorded instants [s] (implicit: every increment).
    pub record_interval: f64,
    /// Implicit: with the muscles' inertia (Newmark with [`KNEE_NEWMARK_DISSIPATION`], physical mass;
    /// the recommended setting) or quasi-static. Quasi-static Newton stalls at the active
    /// squat's onset of activation (increments cut to 0.15 ms at t = 0.43 s); with the
    /// inertia it passes in 0.5–3 ms increments, and the passive squat costs the same and
    /// gives the same vm95 within 0.9 %.
    pub inertia: bool,
    /// Implicit: Newton's relative residual and correction tolerances.
    pub residual_tolerance: f64,
    pub correction_tolerance: f64,
    /// How the bonded interfaces resist a slide.
    pub interfaces: InterfaceLaw,
}

/// Default squat duration [s]: 1 s down to 90°, 1 s back up.
pub const DEFAULT_SQUAT_DURATION: f64 = 2.0;

/// Default implicit increment [s]: resolves the activation's rise (1/S = 20 ms) and
/// keeps the knee's turn per increment below 2.2°.
pub const DEFAULT_IMPLICIT_INCREMENT: f64 = 0.02;

/// Halvings of the line search per Newton iteration on the knee (the solver's default is
/// 8). A correction that must be cut below 1/8 to reduce the residual is a sign the
/// increment is too long: cutting the increment is cheaper than crawling on. Measured on
/// the coarse default squat (2026-11-24; runs side by side, so the wall times are rough):
///
/// | halvings | passive: iterations, evaluations | active: iterations, evaluations, cuts |
/// |---|---|---|
/// | 8 | 765, 1397 | 2487, 4982, 15 |
/// | 4 | | 2557, 4853, 21 |
/// | 3 | 753, 1262 | 2319, 3752, 26 |
/// | 2 | | 2371, 3652, 47 |
///
/// The row of 8 is with the older round-off test of the line search, which took
/// diverging iterates for converged ones; with today's test and 8 halvings the active
/// squat stalls at 59° in extension. The rows of 2 and 4 are with a stricter draft of
/// today's test (the trial's floor no larger than the iteration's), which gave the row of
/// 3 to the count. Back to back, the default run took 138 s with 3 halvings against 158 s
/// before, and its vm95 moved by up to 1.9 % (mean 0.2 %), the size a different history
/// of cuts makes. All of this was with the displacement tangent. With the mixed element
/// pressure, before the mass shift (2026-11-24, active: increments, iterations, cuts), 4 gave
/// 168, 906, 18 on coarse (3: 240, 1241, 38) but 200, 1046, 28 on medium (3: 184, 951,
/// 26), and 8 stalled at 43° in extension on coarse: 3 stays.
pub const KNEE_LINE_SEARCH_CUTS: usize = 3;

/// Newton's relative residual tolerance on the knee (the solver's default is 1e-10). The
/// sliding interfaces and the contacts between muscles take their normals from the
/// deformed neighbour, and their tangents leave out how those normals turn with the
/// neighbour's nodes (a relative error of the order of the gap over the element size,
/// 0.1–0.3 for the 1–4 mm gaps of the coarse mesh): Newton's method converges linearly
/// there, and at 1e-10 the coarse passive squat took 7–8 iterations an increment and
/// increments of 2.6 ms (2026-11-25). 1e-6 of the force scale (about 1 mN at the passive
/// squat's 90°) is still far below what the stresses can show (Abaqus's default is
/// 5e-3).
pub const KNEE_RESIDUAL_TOLERANCE: f64 = 1e-6;

/// Newton's relative correction tolerance on the knee (the solver's default is 1e-6):
/// max |δu| ≤ 1e-5 max |u|, where max |u| is the thigh's motion in the closed chain
/// (about 0.25 m at 90°).
pub const KNEE_CORRECTION_TOLERANCE: f64 = 1e-5;

/// The numerical dissipation α of the knee's Newmark integration (γ = ½ + α,
/// β = (1 + α)²/4: unconditionally stable, damps the highest frequencies, first-order
/// accurate in time). The trapezoidal rule (α = 0) keeps every vibration it excites: on
/// the coarse closed-chain squat (2026-11-25) the passive run crept from t = 1.45 s on in
/// 0.2 ms increments and was stopped at 1.503 s (44.5° in extension), while with α = 0.1
/// it finished in 281 increments (30 cuts, 583 s), its vm95 at t ≈ 1.05 s (89°) within
/// 2 % of the undamped run's.
pub const KNEE_NEWMARK_DISSIPATION: f64 = 0.1;

/// Default mass-scaling target step of the explicit solver [s].
pub const DEFAULT_MASS_SCALING_STEP: f64 = 2e-5;

/// Shear viscosity η of the explicit squat [Pa s] (`[step.explicit] shear_viscosity`).
///
/// Mass scaling to 2e-5 s multiplies the Visible Human knee's mass by about 100, which
/// slows the muscles' shear modes tenfold: a 5 mm element's shear mode (μ ≈ 50 kPa) rings
/// with a period of about 20 ms. Undamped, 5–10 % of the vasti's elements changed their
/// fiber stretch by more than 0.05 between frames 20 ms apart (2026-11-27), and at the
/// activation the Hill series element of a ringing element was squeezed through zero
/// length (a fiber shortening at 77 /s, faster than the contractile element's 17 /s).
/// η = 1000 Pa s gives such modes a damping ratio ηω/(2μ) of 1–3 while the squat's own
/// rates (fiber strain rates below 0.5 /s) meet a viscous stress below 1 kPa. It is
/// numerical damping, a thousand times the viscosity measured in muscle, that stands in
/// for the stiffness the mass scaling took away from those modes' time scale.
pub const KNEE_SHEAR_VISCOSITY: f64 = 1000.0;

/// Why a solver is the one to use on the knee, from the runs measured on the coarse knee
/// (README, "The knee") and on the Visible Human's (`visible_human`,
/// docs/knee-model.md).
pub fn solver_rationale(solver: Solver, visible_human: bool) -> &'static str {
    match (solver, visible_human) {
        (Solver::Explicit, true) => {
            "the default on the Visible Human knee (the paper's method): central \
             differences, mass scaling to a 2e-5 s step; the coarse squat's two runs side \
             by side took 8.3 and 8.5 ks on 2 cores (2026-11-27), one alone about an hour: \
             expect about two hours for both (--anatomy procedural: minutes)"
        }
        (Solver::Implicit, true) => {
            "chosen: on the Visible Human knee (78 k unknowns, coarse) one Newton \
             iteration took about a minute on 2 cores (2026-11-27: the first 10 ms \
             increment, 11 iterations, in 10 minutes), so the 90° squat takes many hours"
        }
        (Solver::Implicit, false) => {
            "the default off the Visible Human knee: on the coarse procedural knee \
             (2026-11-26) passive and active \
             ran side by side to the end in 14 minutes on a 2-core machine (511 and 312 \
             increments), the active vm95 at 90° within 10 % of the explicit solver's"
        }
        (Solver::Explicit, false) => {
            "the paper's method: central differences, mass scaling to a 2e-5 s step \
             (145 069 steps; 1653 s for the active coarse knee beside another run; the \
             medium mesh has 6 times the elements, so expect hours there: add \
             --resolution coarse for a first look)"
        }
    }
}

impl SquatSettings {
    /// The recommended settings of `solver` for the default squat.
    pub fn recommended(solver: Solver) -> Self {
        SquatSettings {
            squat: Squat::to_ninety_degrees(DEFAULT_SQUAT_DURATION),
            solver,
            element: ElementChoice::Hex8Fbar,
            time_step: match solver {
                Solver::Implicit => DEFAULT_IMPLICIT_INCREMENT,
                Solver::Explicit => DEFAULT_MASS_SCALING_STEP,
            },
            record_interval: DEFAULT_IMPLICIT_INCREMENT,
            inertia: true,
            residual_tolerance: KNEE_RESIDUAL_TOLERANCE,
            correction_tolerance: KNEE_CORRECTION_TOLERANCE,
            interfaces: InterfaceLaw::Sliding,
        }
    }
}

/// The result of one squat.
pub struct SquatRun {
    pub activation: Activation,
    pub samples: Vec<StressSample>,
    pub rows: Vec<PeakStressRow>,
    pub interactions: Vec<InteractionSummary>,
    pub elements: usize,
    pub nodes: usize,
    pub solve_time: Duration,
    /// Increments (implicit) or steps (explicit).
    pub steps: usize,
    /// Implicit: Newton iterations in all and increments cut.
    pub newton_iterations: Option<usize>,
    pub cuts: Option<usize>,
    /// Implicit: where the time went, evaluations (elements, assembly) and linear solves.
    pub implicit_times: Option<(EvaluationTimes, LinearSolveStatistics)>,
    /// Implicit: every converged increment with its Newton residuals, and every attempt
    /// that failed and was cut.
    pub newton_steps: Vec<StepReport>,
    pub cut_attempts: Vec<CutAttempt>,
    /// Explicit: mass added by mass scaling over the physical mass, largest
    /// |W_int + W_visc + W_c + K − W_ext| over the largest energy.
    pub added_mass_fraction: Option<f64>,
    pub energy_error: Option<f64>,
    /// The patellar tendon at every report of the quadriceps' pull.
    pub tendon: Vec<TendonRow>,
    /// The closest any muscle node (the insertions' excepted) came to the patella, which
    /// has no contact surface (`None`: none came within range).
    pub patella_approach: Option<PatellaApproach>,
    /// The plausibility measures at every recorded instant and at the table's angles.
    pub plausibility: Vec<PlausibilitySample>,
    pub plausibility_rows: Vec<PlausibilityRow>,
    /// The time [s] of the checkpoint the run went on from (`None`: from the start). The
    /// samples, tendon rows and plausibility cover the whole squat; `steps`, the Newton
    /// counts and reports and the timings only the part after it.
    pub resumed_from: Option<f64>,
}

/// The model and the interactions of the squat of `activation` on `geometry` with
/// `fibers`: what the squat's scene and its recorder are built from.
pub(super) fn squat_model(
    geometry: &KneeGeometry,
    fibers: &FiberField,
    activation: Activation,
    settings: &SquatSettings,
) -> Result<(KneeModel, KneeInteractions)> {
    let model = KneeModel::new(
        geometry,
        fibers,
        activation,
        &settings.squat,
        settings.element,
    )?;
    let built = knee_interactions(
        geometry,
        &model.mesh,
        model.material.as_ref(),
        settings.interfaces,
    )?;
    Ok((model, built))
}

/// The regions (origin, insertion, interface, belly) of every muscle's elements of
/// `mesh`, from the fibers' flow potential and the interfaces' nodes of `built`.
pub(super) fn element_regions(
    geometry: &KneeGeometry,
    mesh: &musclefem_core::mesh::Mesh,
    fibers: &FiberField,
    built: &KneeInteractions,
) -> Vec<ElementRegions> {
    (0..geometry.muscles.len())
        .map(|b| {
            let block = &mesh.blocks[b];
            let offset = fibers.block_offsets[b];
            ElementRegions::new(
                fibers.potential[offset..offset + block.len()].to_vec(),
                &block.connectivity,
                block.shape.nodes_per_element(),
                &built.interface_nodes,
            )
        })
        .collect()
}

/// The squat's result from what `recorder` gathered and the solver's `outcome`, after
/// `solve_time` (from the checkpoint at `resumed_from` [s], if it went on from one).
pub(super) fn squat_result(
    recorder: &mut Recorder,
    outcome: Outcome,
    (activation, settings, muscles): (Activation, &SquatSettings, &[Quadriceps]),
    interactions: Vec<InteractionSummary>,
    solve_time: Duration,
    resumed_from: Option<f64>,
) -> Result<SquatRun> {
    let (mut newton_steps, mut cut_attempts) = (Vec::new(), Vec::new());
    let (steps, newton_iterations, cuts, implicit_times, added_mass_fraction) = match outcome {
        Outcome::Implicit(result) => {
            let iterations = result.steps.iter().map(|s| s.iterations).sum();
            newton_steps = result.steps;
            cut_attempts = result.cut_attempts;
            (
                result.history.len(),
                Some(iterations),
                Some(result.cuts),
                Some((result.evaluation_times, result.linear_solves)),
                None,
            )
        }
        Outcome::Explicit(result) => (
            result.steps,
            None,
            None,
            None,
            Some(result.added_mass_fraction),
        ),
    };
    let rows = peak_stress_rows(&recorder.samples, muscles, &settings.squat, activation)?;
    let plausibility_table = plausibility_rows(&recorder.plausibility, &settings.squat)?;
    let energy_error = added_mass_fraction
        .map(|_| recorder.energy_error / recorder.largest_energy.max(f64::MIN_POSITIVE));
    Ok(SquatRun {
        activation,
        samples: std::mem::take(&mut recorder.samples),
        rows,
        interactions,
        elements: recorder.mesh.element_count(),
        nodes: recorder.mesh.node_count(),
        solve_time,
        steps,
        newton_iterations,
        cuts,
        implicit_times,
        newton_steps,
        cut_attempts,
        added_mass_fraction,
        energy_error,
        tendon: std::mem::take(&mut recorder.tendon),
        patella_approach: recorder.patella_clearance.closest,
        plausibility: std::mem::take(&mut recorder.plausibility),
        plausibility_rows: plausibility_table,
        resumed_from,
    })
}

/// The analysis of a squat with `settings`, the femur moving as `femur` (the implicit
/// solver's predictor frame, the explicit solver's carrier of the added mass).
pub fn squat_analysis(settings: &SquatSettings, femur: &RigidMotion) -> Analysis {
    let duration = settings.squat.duration;
    match settings.solver {
        Solver::Implicit => {
            let increments = (duration / settings.time_step).round().max(1.0) as usize;
            let mut solver_settings = ImplicitSettings::new(duration, increments).with_cutting();
            solver_settings.residual_tolerance = settings.residual_tolerance;
            solver_settings.correction_tolerance = settings.correction_tolerance;
            // Every Newton iteration factorizes: on the coarse knee a Cholesky factorization
            // (≈ 45 ms then, in the nested-dissection order) costs about 15 conjugate-gradient
            // iterations preconditioned with the last factor, and the tangents change too much
            // between iterations for fewer. Measured on an idle 2-core machine, default run:
            // 282 s without reuse, 322 s with the default reuse (2026-11-23, before the AMD
            // order and LBLᵀ, which made factorizations 3× cheaper and reuse less worth it).
            solver_settings.factor_reuse = None;
            solver_settings.line_search_cuts = KNEE_LINE_SEARCH_CUTS;
            if settings.inertia {
                solver_settings.dynamics = Some(dissipative_newmark(KNEE_NEWMARK_DISSIPATION));
            }
            // The muscles ride on the femur, which moves in the closed chain: each
            // increment starts from them carried with it.
            solver_settings.predictor_frame = Some(Box::new(femur.clone()));
            Analysis::Implicit(solver_settings)
        }
        Solver::Explicit => {
            let mut solver_settings = ExplicitSettings::new(duration);
            solver_settings.mass_scaling_time_step = Some(settings.time_step);
            solver_settings.shear_viscosity = Some(KNEE_SHEAR_VISCOSITY);
            solver_settings.history_interval = settings.record_interval;
            // The added mass rides on the femur without its inertia: with the knee's
            // hundredfold mass, the vasti's inertia at the turn of the squat would
            // otherwise be as large as their passive pull (docs/knee-model.md).
            solver_settings.mass_scaling_frame = Some(Box::new(femur.clone()));
            Analysis::Explicit(solver_settings)
        }
    }
}
