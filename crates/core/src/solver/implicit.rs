//! Implicit solver: equilibrium f_int(u) = f_ext on the free degrees of freedom at every
//! load step (quasi-static, the default), or M a + f_int(u) = f_ext with Newmark's method
//! and the lumped mass ([`ImplicitSettings::dynamics`], `implicit_dynamics.rs`), by
//! Newton's method with the consistent tangent (K, or K + M/(β Δt²)).
//!
//! - Time is the load parameter [s]: prescribed displacements follow their amplitudes, and
//!   materials update over each step with Δt = the step length (rate-dependent materials
//!   see the loading rate; no inertia).
//! - Each step starts with a predictor: the tangent at the converged state carries the
//!   prescribed increment Δū into the free unknowns, K_ff Δu_f = −(r_f + K_fp Δū); then
//!   Newton iterations K_ff δu = −r_f with a backtracking line search on ‖r_f‖ (step halved
//!   until ‖r(u + α δu)‖ ≤ (1 − 10⁻⁴ α) ‖r(u)‖). A quasi-static step may instead start
//!   from the last step's change extrapolated, when that guess's residual is small
//!   ([`ImplicitSettings::extrapolate`]); iterative solves stop at Newton's forcing term
//!   ([`ImplicitSettings::forcing`]); the stiffness of a state is built only when a solve
//!   needs it, so none at the converged one (`docs/implicit-speed.md`).
//! - Converged when ‖r_f‖ ≤ tol_r max(‖f_int‖, ‖f_ext‖) (all degrees of freedom, so the
//!   reactions set the scale) and the last correction max |α δu| ≤ tol_u max |u|, or when a correction
//!   is at round-off (max |δu| ≤ 1e-10 max |u|, see
//!   [`ImplicitSettings::round_off_correction`]), or when ‖r_f‖ is at its round-off floor
//!   10 ε max|x| max|K_ii| √n (F = Σ x_a ⊗ ∇N_a carries errors ε|x|/h): for a nearly
//!   incompressible material at small loads that floor lies above tol_r ‖f_int‖. The
//!   floor counts only up to twice the one at the step's start, so that a diverging
//!   iterate (whose stiffness, and so floor, explodes) is never taken for converged.
//! - Prescribed degrees of freedom are eliminated: the sparse matrix holds the free ones
//!   only (pattern built once from the connectivity, values refilled every iteration,
//!   serially in element order, so results do not depend on the thread count). Solved with
//!   faer's supernodal Cholesky in nested-dissection or AMD order, whichever fills less
//!   (symbolic analysis once per pattern), by conjugate gradients preconditioned with the
//!   last factor while that converges fast ([`FactorReuse`]; the corrections are still
//!   those of the current tangent, to 1e-12 or the forcing term), LBLᵀ if Cholesky fails, LU if that is not
//!   accurate or a material tangent is not symmetric (`sparse.rs`); serially unless
//!   [`ImplicitSettings::parallel_factorization_unknowns`] says otherwise.
//! - [`ImplicitResult`] reports counts and wall-clock times of the evaluations and solves.
//! - Steps: a fixed number, or with [`StepCutting`] a failed step (no convergence within
//!   the iteration limit, a line search that cannot reduce the residual, an inverted
//!   element, a failed solve) is retried from the last converged state with half the
//!   increment, down to a limit; after consecutive easy steps the increment grows back.
//!
//! Reactions: the internal force summed over the nodes of each prescribed displacement in
//! its direction, at the converged state. Material states are committed after convergence.
//!
//! Element technologies: those with a consistent element stiffness
//! ([`crate::element::BlockKernel::has_consistent_tangent`]): Hex8Full, Hex8FBar and
//! Tet10FBar (with the linearization through J̄ of `element/fbar.rs`, and by default the
//! mixed element pressure in their tangent, `mixed_pressure.rs`, which spares nearly
//! incompressible tissue most of its Newton iterations), Hex8OnePoint, Tet4 and Tet10. The
//! nodally averaged tet4 is refused ([`SolverError::NoConsistentTangent`]): its tangent
//! couples the 2-ring of elements around a node, a wider sparsity pattern not built yet.
//! Nodal forces enter the residual r = f_int − f_ext at the end of the step; nodes tied to
//! a rigid body are prescribed in every component. Interactions (contact, cohesion) add
//! their forces and stiffness blocks (`implicit_interactions.rs`), are searched once per
//! Newton iteration and committed with the materials.
//!
//! Memory besides the factor: every element keeps its dense stiffness between the parallel
//! update and the serial scatter (24² values, 4.6 kB, per hex8) and a scatter map (192
//! positions, 0.8 kB, per hex8).

use nalgebra::Vector3;

use super::checkpoint::{Checkpoint, CheckpointReader};
use super::implicit_checkpoint::implicit_checkpoint;
use super::implicit_chunk::ImplicitChunk;
use super::implicit_model::Model;
use super::implicit_newton::{EXTRAPOLATION_ACCEPTANCE, Extrapolation, StepFailure, newton_step};
use super::interaction::Interaction;
use super::interaction::all_nodal_fields;
use super::observer::{NoObserver, Observer, Record, Snapshot};
use super::rigid_motion::{observe_followers, restore_follower_states};
use super::sparse::PRESCRIBED;
use super::{Loads, Part, SolverError};
use crate::mesh::Mesh;

pub use super::implicit_dynamics::{EnergyBalance, Newmark};
use super::implicit_dynamics::{Inertia, lumped_mass};
pub use super::implicit_model::EvaluationTimes;
pub use super::implicit_report::{CutAttempt, ImplicitHistoryRow, ImplicitResult, StepReport};
pub use super::implicit_settings::{Forcing, ImplicitSettings, StepCutting};
use super::implicit_settings::{check_newmark, check_settings};
pub use super::sparse::{FactorReuse, Factorization, LinearSolveStatistics};

/// The most increments a run may be set to take: beyond it the increment or the duration
/// is almost surely a mistake, and the run is refused before it starts.
pub const MAX_INCREMENTS: usize = 10_000_000;

/// Run the implicit solver (quasi-static, or dynamic with [`ImplicitSettings::dynamics`])
/// on `mesh` with `parts` under `loads`.
pub fn run_quasi_static(
    mesh: &Mesh,
    parts: &[Part],
    loads: &Loads,
    settings: &ImplicitSettings,
) -> Result<ImplicitResult, SolverError> {
    run_implicit_observed(mesh, parts, loads, settings, &mut NoObserver)
}

/// [`run_quasi_static`], showing `observer` every converged step.
pub fn run_implicit_observed(
    mesh: &Mesh,
    parts: &[Part],
    loads: &Loads,
    settings: &ImplicitSettings,
    observer: &mut dyn Observer,
) -> Result<ImplicitResult, SolverError> {
    run_implicit_with(mesh, parts, loads, &mut [], settings, observer)
}

/// [`run_implicit_observed`] with `interactions` (contact, cohesion) adding their forces
/// and stiffness.
pub fn run_implicit_with(
    mesh: &Mesh,
    parts: &[Part],
    loads: &Loads,
    interactions: &mut [Box<dyn Interaction>],
    settings: &ImplicitSettings,
    observer: &mut dyn Observer,
) -> Result<ImplicitResult, SolverError> {
    implicit_run(mesh, parts, loads, interactions, settings, observer, None)
}

/// [`run_implicit_with`], started from `from` (a checkpoint of the same problem) when
/// given: the result's history and step reports then hold the increments after the
/// checkpoint only. A factorization kept for reuse ([`ImplicitSettings::factor_reuse`])
/// is not part of a checkpoint: the increment after one factorizes afresh, in the run
/// that took it as in the resumed one, so both compute the same numbers.
pub(super) fn implicit_run(
    mesh: &Mesh,
    parts: &[Part],
    loads: &Loads,
    interactions: &mut [Box<dyn Interaction>],
    settings: &ImplicitSettings,
    observer: &mut dyn Observer,
    from: Option<&Checkpoint>,
) -> Result<ImplicitResult, SolverError> {
    check_settings(settings)?;
    let mut model = Model::new(
        mesh,
        parts,
        loads,
        interactions,
        settings.parallel_factorization_unknowns,
        settings.mixed_pressure_tangent,
    )?;
    let node_count = mesh.nodes.len();
    let reference: Vec<Vector3<f64>> = (0..node_count).map(|i| mesh.nodes.position(i)).collect();
    let mut displacement = vec![Vector3::zeros(); node_count];
    let mut converged = displacement.clone();
    let mut history = Vec::new();
    let mut steps = Vec::new();
    let mut cut_attempts = Vec::new();
    let end = settings.end_time;
    let initial = end / settings.increments as f64;
    let smallest = settings
        .cutting
        .as_ref()
        .map_or(initial, |c| initial / 2f64.powi(c.max_cuts as i32));
    let mut increment = initial;
    let mut easy = 0;
    let mut time = 0.0;
    let mut displacement_history = Vec::new();
    let mut energy = EnergyBalance::default();
    // The last accepted increment's displacement change and length, for the next
    // increment's first guess (`ImplicitSettings::extrapolate`).
    let extrapolate = settings.extrapolate
        && settings.dynamics.is_none()
        && settings.predictor_frame.is_none()
        && model.interactions.is_empty();
    let mut last_increment: Option<(Vec<Vector3<f64>>, f64)> = None;
    // The last tangent predictor's right-hand side per unit time [N/s] (see
    // `Extrapolation::accept_below`).
    let mut predictor_rate = f64::NAN;
    // Internal and external (loads and supports) nodal forces at the last converged state.
    let mut internal_before = vec![Vector3::zeros(); node_count];
    let mut external_before = vec![Vector3::zeros(); node_count];
    // The loads at t = 0 on the free components (the supports carry the rest).
    loads.external_forces(0.0, &mut external_before);
    for (d, &eq) in model.equation.iter().enumerate() {
        if eq == PRESCRIBED {
            external_before[d / 3][d % 3] = 0.0;
        }
    }
    if let Some(newmark) = &settings.dynamics {
        check_newmark(newmark)?;
        let mut inertia = Inertia::new(lumped_mass(mesh, parts)?);
        for (d, &eq) in model.equation.iter().enumerate() {
            if eq != PRESCRIBED {
                inertia.acceleration[d / 3][d % 3] =
                    external_before[d / 3][d % 3] / inertia.mass[d / 3];
            }
        }
        model.inertia = Some(inertia);
        model.mass_shift = settings.mass_shift_for_indefinite_tangents;
    }
    if let Some(checkpoint) = from {
        let mut input = CheckpointReader::new(&checkpoint.state);
        time = input.f64()?;
        increment = input.f64()?;
        easy = input.index()?;
        energy.kinetic = input.f64()?;
        energy.internal_work = input.f64()?;
        energy.external_work = input.f64()?;
        input.matrices_into("displacements", &mut displacement)?;
        converged.copy_from_slice(&displacement);
        input.matrices_into("internal forces", &mut internal_before)?;
        input.matrices_into("external forces", &mut external_before)?;
        if let Some(inertia) = model.inertia.as_mut() {
            input.matrices_into("velocities", &mut inertia.velocity)?;
            input.matrices_into("accelerations", &mut inertia.acceleration)?;
        }
        for run in &mut model.runs {
            for chunk in &mut run.chunks {
                chunk.restore_state(&mut input)?;
            }
        }
        for interaction in model.interactions.iter_mut() {
            interaction.restore_state(&mut input)?;
        }
        // The pattern as it had grown, so that the factorizations order alike.
        let pairs = input.u32s()?;
        restore_follower_states(&loads.rigid_ties, &mut input)?;
        input.finish()?;
        if !pairs.is_empty() {
            model.coupled_pairs = pairs.chunks_exact(2).map(|p| (p[0], p[1])).collect();
            model.build_system().map_err(SolverError::Checkpoint)?;
        }
    } else {
        let fields = || model.fields(0.0);
        let nodal = || all_nodal_fields(model.interactions, node_count);
        let snapshot = Snapshot::new(0.0, &displacement, &fields).with_nodal_fields(&nodal);
        if observer.start(&snapshot).is_break() {
            return Err(SolverError::Interrupted { time: 0.0 });
        }
    }
    while time < end {
        let mut step = increment.min(end - time);
        if end - (time + step) < 1e-9 * step {
            step = end - time;
        }
        if let (Some(newmark), Some(inertia)) = (&settings.dynamics, model.inertia.as_mut()) {
            inertia.start_step(newmark, &converged, step);
        }
        let attempt = newton_step(
            &mut model,
            &reference,
            &mut displacement,
            loads,
            settings,
            time,
            step,
            last_increment
                .as_ref()
                .filter(|_| predictor_rate.is_finite())
                .map(|(change, length)| Extrapolation {
                    change,
                    length: *length,
                    accept_below: EXTRAPOLATION_ACCEPTANCE * predictor_rate * step,
                }),
        );
        match attempt {
            Ok(report) => {
                for run in &mut model.runs {
                    run.chunks.iter_mut().for_each(ImplicitChunk::commit);
                }
                // A stiffness is built from the last update's inputs, which the commit
                // has just made the start of the next step: none may be due past it.
                model.stiffness_due = false;
                model.interactions.iter_mut().for_each(|i| i.commit());
                time = if end - (time + step) < 1e-9 * step {
                    end
                } else {
                    time + step
                };
                if let (Some(newmark), Some(inertia)) = (&settings.dynamics, model.inertia.as_mut())
                {
                    inertia.commit(newmark, &displacement, step);
                }
                // Work of the internal and of the external forces (loads and supports),
                // trapezoidal over the increment; quasi-static runs too (W_int = W_ext
                // there to the Newton tolerance, the strain energy put in).
                let supports = model.support_forces();
                for n in 0..node_count {
                    let du = displacement[n] - converged[n];
                    let internal = model.force[n];
                    let external = model.external[n] + supports[n];
                    energy.internal_work += 0.5 * (internal_before[n] + internal).dot(&du);
                    energy.external_work += 0.5 * (external_before[n] + external).dot(&du);
                    internal_before[n] = internal;
                    external_before[n] = external;
                }
                energy.kinetic = model.inertia.as_ref().map_or(0.0, Inertia::kinetic_energy);
                if let Some(residual) = report.predictor_residual {
                    predictor_rate = residual / step;
                }
                if extrapolate {
                    let change = last_increment
                        .get_or_insert_with(|| (vec![Vector3::zeros(); node_count], step));
                    for ((c, u), before) in change.0.iter_mut().zip(&displacement).zip(&converged) {
                        *c = u - before;
                    }
                    change.1 = step;
                }
                converged.copy_from_slice(&displacement);
                if settings.record_displacements {
                    displacement_history.push(displacement.clone());
                }
                let positions: Vec<Vector3<f64>> = reference
                    .iter()
                    .zip(&displacement)
                    .map(|(x, u)| x + u)
                    .collect();
                let (reactions, rigid_reactions) = model.reactions(loads, time, &positions);
                history.push(ImplicitHistoryRow {
                    time,
                    increment: step,
                    iterations: report.iterations,
                    reactions,
                    rigid_reactions,
                    energy,
                    interactions: model.interactions.iter().map(|i| i.report()).collect(),
                });
                if let Some(row) = history.last() {
                    observe_followers(&loads.rigid_ties, time, &row.rigid_reactions);
                }
                let fields = || model.fields(time);
                let nodal = || all_nodal_fields(model.interactions, node_count);
                let snapshot =
                    Snapshot::new(time, &displacement, &fields).with_nodal_fields(&nodal);
                if let Some(row) = history.last()
                    && (observer
                        .record(&Record::Implicit(row), &snapshot)
                        .is_break()
                        || observer.progress(time, history.len()).is_break())
                    && time < end
                {
                    return Err(SolverError::Interrupted { time });
                }
                let checkpoint_wanted = time < end && observer.wants_checkpoint();
                if let Some(cutting) = &settings.cutting {
                    if report.iterations <= cutting.easy_iterations {
                        easy += 1;
                        if easy >= cutting.easy_steps {
                            increment = (increment * cutting.growth).min(initial);
                            easy = 0;
                        }
                    } else {
                        easy = 0;
                    }
                }
                steps.push(report);
                if checkpoint_wanted {
                    model.system.forget_factorization();
                    // A resumed run starts without the last increment: so does this one.
                    last_increment = None;
                    predictor_rate = f64::NAN;
                    let checkpoint = implicit_checkpoint(
                        &mut model,
                        time,
                        increment,
                        easy,
                        &energy,
                        [&displacement, &internal_before, &external_before],
                        &loads.rigid_ties,
                    );
                    if observer.checkpoint(checkpoint).is_break() {
                        return Err(SolverError::Interrupted { time });
                    }
                }
            }
            Err(failure) => {
                displacement.copy_from_slice(&converged);
                let half = step / 2.0;
                if settings.cutting.is_some() && half >= smallest * (1.0 - 1e-12) {
                    increment = half;
                    easy = 0;
                    cut_attempts.push(match failure {
                        StepFailure::Error(error) => CutAttempt {
                            time: time + step,
                            increment: step,
                            iterations: 0,
                            residual: f64::NAN,
                            factorization: None,
                            reason: error.to_string(),
                        },
                        StepFailure::NotConverged {
                            iterations,
                            residual,
                            reason,
                            factorization,
                        } => CutAttempt {
                            time: time + step,
                            increment: step,
                            iterations,
                            residual,
                            factorization: Some(factorization),
                            reason,
                        },
                    });
                    continue;
                }
                return Err(match failure {
                    StepFailure::Error(error) => error,
                    StepFailure::NotConverged {
                        iterations,
                        residual,
                        reason,
                        ..
                    } => SolverError::NotConverged {
                        time: time + step,
                        increment: step,
                        iterations,
                        residual,
                        reason,
                    },
                });
            }
        }
    }
    Ok(ImplicitResult {
        history,
        steps,
        cuts: cut_attempts.len(),
        cut_attempts,
        displacement,
        equations: model.system.size(),
        matrix_entries: model.system.entries(),
        evaluation_times: model.times.clone(),
        linear_solves: model.system.statistics().clone(),
        displacement_history,
    })
}
