//! One increment of the implicit solver: the first guess (the tangent predictor, or the
//! last increment extrapolated), then Newton's iterations with a backtracking line search
//! (see the description of `implicit.rs` and `docs/implicit-speed.md`).

use nalgebra::Vector3;

use super::implicit_model::Model;
use super::implicit_report::StepReport;
use super::implicit_settings::ImplicitSettings;
use super::sparse::{Factorization, PRESCRIBED};
use super::{Loads, SolverError};

/// Why a step attempt failed.
pub(super) enum StepFailure {
    NotConverged {
        iterations: usize,
        residual: f64,
        reason: String,
        factorization: Factorization,
    },
    Error(SolverError),
}

/// One attempt at the step from `time` to `time + step`: predictor, then Newton with line
/// search. Leaves `displacement` at the converged state (or wherever it failed).
pub(super) fn newton_step(
    model: &mut Model,
    reference: &[Vector3<f64>],
    displacement: &mut [Vector3<f64>],
    loads: &Loads,
    settings: &ImplicitSettings,
    time: f64,
    step: f64,
    extrapolation: Option<Extrapolation>,
) -> Result<StepReport, StepFailure> {
    let end = time + step;
    let node_count = displacement.len();
    if let Some(frame) = &settings.predictor_frame {
        let carry = frame.isometry_at(end) * frame.isometry_at(time).inverse();
        for (u, x) in displacement.iter_mut().zip(reference) {
            *u = (carry * nalgebra::Point3::from(x + *u)).coords - x;
        }
    }
    // Prescribed increments Δū (the last condition on a component wins).
    let mut target = vec![f64::NAN; 3 * node_count];
    loads.prescribed_displacements(end, reference, &mut target);
    loads.external_forces(end, &mut model.external);
    let delta: Vec<f64> = target
        .iter()
        .enumerate()
        .map(|(d, t)| {
            if t.is_nan() {
                0.0
            } else {
                t - displacement[d / 3][d % 3]
            }
        })
        .collect();
    let mut positions: Vec<Vector3<f64>> = reference
        .iter()
        .zip(displacement.iter())
        .map(|(x, u)| x + u)
        .collect();
    let error = |e: SolverError| StepFailure::Error(e);

    model.start_step();
    // The extrapolated first guess: the free components continue the last increment's
    // change, the prescribed ones take their values at the end of this one (ū(t + Δt),
    // no lift then). Kept when its residual is below the tangent predictor's expected
    // right-hand side (`Extrapolation::accept_below`), else the tangent predictor.
    let mut extrapolated = false;
    if let Some(guess) = &extrapolation {
        let start = displacement.to_vec();
        let ratio = step / guess.length;
        for (d, &eq) in model.equation.iter().enumerate() {
            let u = &mut displacement[d / 3][d % 3];
            if eq != PRESCRIBED {
                *u += ratio * guess.change[d / 3][d % 3];
            } else if !target[d].is_nan() {
                *u = target[d];
            }
        }
        set_positions(&mut positions, reference, displacement);
        extrapolated = model
            .evaluate(&positions, end, step, true, None)
            .is_ok_and(|norms| norms.residual <= guess.accept_below);
        if !extrapolated {
            displacement.copy_from_slice(&start);
            set_positions(&mut positions, reference, displacement);
        }
    }
    // Predictor: the tangent one (from the last converged state, the prescribed
    // increments through the lift), or Newton's first iteration from the guess.
    if !extrapolated {
        model
            .evaluate(&positions, end, step, true, Some(&delta))
            .map_err(error)?;
    }
    model.ensure_stiffness();
    let start_norms = model.norms();
    let mut correction: Vec<f64> = model
        .residual
        .iter()
        .zip(&model.lift)
        .map(|(r, l)| -(r + l))
        .collect();
    let predictor_rhs = correction.iter().map(|c| c * c).sum::<f64>().sqrt();
    let forcing = settings.forcing.as_ref();
    let mut factorization = model
        .solve(
            &mut correction,
            end,
            settings,
            forcing.map_or(0.0, |f| f.predictor),
        )
        .map_err(error)?;
    // Work of the first correction |δuᵀ r| (energy criterion).
    let first_work = correction
        .iter()
        .zip(model.residual.iter().zip(&model.lift))
        .map(|(c, (r, l))| c * (r + l))
        .sum::<f64>()
        .abs();
    let mut work_ratio = f64::INFINITY;
    let mut largest_correction: f64 = 0.0;
    for (d, &eq) in model.equation.iter().enumerate() {
        let u = &mut displacement[d / 3][d % 3];
        if eq == PRESCRIBED {
            if !target[d].is_nan() {
                largest_correction = largest_correction.max((target[d] - *u).abs());
                *u = target[d];
            }
        } else {
            *u += correction[eq as usize];
            largest_correction = largest_correction.max(correction[eq as usize].abs());
        }
    }
    set_positions(&mut positions, reference, displacement);
    let mut iterations = 1;
    let mut residuals = Vec::new();
    let mut line_search_cuts = 0;
    let mut evaluated = false;
    let mut base = displacement.to_vec();
    // ‖r_{k−1}‖ for the forcing term (the predictor's right-hand side at k = 1).
    let mut previous_residual = predictor_rhs;
    loop {
        let norms = if evaluated {
            model.norms()
        } else {
            match model.evaluate(&positions, end, step, true, None) {
                Ok(norms) => norms,
                Err(e) => {
                    return Err(StepFailure::NotConverged {
                        factorization,
                        iterations,
                        residual: f64::INFINITY,
                        reason: e.to_string(),
                    });
                }
            }
        };
        let relative = norms.relative();
        residuals.push(relative);
        if !relative.is_finite() {
            return Err(StepFailure::NotConverged {
                factorization,
                iterations,
                residual: relative,
                reason: "the residual is not finite".to_string(),
            });
        }
        let largest_displacement = displacement.iter().map(|u| u.amax()).fold(0.0, f64::max);
        let converged = (relative <= settings.residual_tolerance
            && largest_correction <= settings.correction_tolerance * largest_displacement)
            || settings
                .energy_tolerance
                .is_some_and(|tol| work_ratio <= tol);
        // The stiffness of this state is built only past the convergence test (a
        // converged state needs none); the round-off floor is its scale.
        let at_round_off = !converged && {
            model.ensure_stiffness();
            model.norms().is_at_round_off(start_norms)
                || largest_correction <= settings.round_off_correction * largest_displacement
        };
        if converged || at_round_off {
            return Ok(StepReport {
                time: end,
                increment: step,
                iterations,
                residuals,
                line_search_cuts,
                factorization,
                extrapolated,
                predictor_residual: (!extrapolated).then_some(predictor_rhs),
            });
        }
        if iterations >= settings.max_iterations {
            return Err(StepFailure::NotConverged {
                factorization,
                iterations,
                residual: relative,
                reason: format!("iteration limit {} reached", settings.max_iterations),
            });
        }
        let mut direction: Vec<f64> = model.residual.iter().map(|r| -r).collect();
        let eta = forcing.map_or(0.0, |f| {
            f.eta(
                norms.residual,
                previous_residual,
                norms.force,
                settings.residual_tolerance,
            )
        });
        previous_residual = norms.residual;
        factorization = model
            .solve(&mut direction, end, settings, eta)
            .map_err(error)?;
        iterations += 1;
        let work: f64 = direction
            .iter()
            .zip(&model.residual)
            .map(|(d, r)| d * r)
            .sum();
        work_ratio = if first_work > 0.0 {
            work.abs() / first_work
        } else {
            0.0
        };
        base.copy_from_slice(displacement);
        // A correction at round-off is taken whole (the residual cannot decrease further).
        let full_correction = direction.iter().map(|x| x.abs()).fold(0.0, f64::max);
        let round_off = full_correction <= settings.round_off_correction * largest_displacement;
        // Line search: the full step first, with the stiffness for the next iteration.
        let mut alpha = 1.0;
        let mut accepted = false;
        for trial in 0..=settings.line_search_cuts {
            model.apply(displacement, &base, &direction, alpha);
            set_positions(&mut positions, reference, displacement);
            let with_stiffness = trial == 0;
            let trial_norms = model.evaluate(&positions, end, step, with_stiffness, None);
            if let Ok(trial_norms) = trial_norms
                && trial_norms.residual.is_finite()
                && (trial_norms.residual <= (1.0 - 1e-4 * alpha) * norms.residual
                    || trial_norms.relative() <= settings.residual_tolerance
                    || round_off
                    || {
                        // The floor is the scale of the trial's own stiffness (of the
                        // full step's for the halved ones, which build none).
                        model.ensure_stiffness();
                        model.norms().is_at_round_off(start_norms)
                    })
            {
                accepted = true;
                evaluated = with_stiffness;
                break;
            }
            alpha *= 0.5;
            line_search_cuts += 1;
        }
        if !accepted {
            return Err(StepFailure::NotConverged {
                factorization,
                iterations,
                residual: relative,
                reason: format!(
                    "the line search found no decrease of the residual in {} halvings",
                    settings.line_search_cuts
                ),
            });
        }
        largest_correction = alpha * full_correction;
    }
}

/// The extrapolated first guess of an increment (see [`ImplicitSettings::extrapolate`]).
pub(super) struct Extrapolation<'a> {
    /// The last accepted increment's displacement change [m] and length [s].
    pub change: &'a [Vector3<f64>],
    pub length: f64,
    /// The guess is kept when its residual ‖r_f‖ is at most this [N]:
    /// [`EXTRAPOLATION_ACCEPTANCE`] times the last tangent predictor's right-hand side
    /// scaled to this increment's length.
    pub accept_below: f64,
}

/// Fraction of the tangent predictor's right-hand side below which the extrapolated
/// guess's residual must lie for Newton to start from it. The uniaxial cube of issue #36
/// keeps it in every increment after the first (its residual there is ~1e-4 of the
/// predictor's); a nearly incompressible block twisted by 10° per increment
/// (`tests/implicit_mixed_pressure.rs`) refuses it (a rotation continued along its
/// tangent changes the volume, which the bulk modulus amplifies): taken there, Newton
/// needed 81 iterations and 2 cuts instead of 27.
pub(super) const EXTRAPOLATION_ACCEPTANCE: f64 = 0.1;

fn set_positions(
    positions: &mut [Vector3<f64>],
    reference: &[Vector3<f64>],
    displacement: &[Vector3<f64>],
) {
    for ((x, x0), u) in positions.iter_mut().zip(reference).zip(displacement) {
        *x = x0 + u;
    }
}
