//! A knee run's own files and summary (see `knee/command.rs`): `vm95.csv`, `newton.csv`,
//! `run.log` and the lines printed after the run.

use std::path::Path;

use anyhow::Result;

use crate::elongation::Solver;
use crate::knee::Quadriceps;
use crate::knee::simulation::patella::tendon_summary;
use crate::knee::simulation::plausibility::plausibility_report;
use crate::knee::simulation::{Phase, SquatRun, SquatSettings, StressSample};
use musclefem_core::solver::implicit::{CutAttempt, Factorization, StepReport};
use musclefem_io::output::RunLog;

/// `vm95.csv`: each muscle's vm95 at every recorded instant, and the smallest element
/// Jacobian ratio (positive: no element inverted).
pub(super) fn write_vm95(
    path: &Path,
    muscles: &[Quadriceps],
    samples: &[StressSample],
) -> Result<()> {
    let mut header = "time_s,knee_angle_deg".to_string();
    for m in muscles {
        header.push_str(&format!(",{}_vm95_pa", m.abbreviation()));
    }
    header.push_str(",min_jacobian_ratio");
    let rows = samples.iter().map(|s| {
        let mut row = vec![s.time, s.flexion.to_degrees()];
        row.extend(&s.vm95);
        row.push(s.min_jacobian_ratio);
        row
    });
    let text = musclefem_io::csv::format_table(&header, rows);
    musclefem_io::atomic::write_atomically(path, text.as_bytes())?;
    Ok(())
}

/// The implicit run's Newton convergence, one row per converged increment: its relative
/// residuals ‖r‖/‖f‖ after the predictor and after each iteration, separated by spaces.
pub(super) fn write_newton_steps(path: &Path, steps: &[StepReport]) -> Result<()> {
    let mut text = String::from(
        "time_s,increment_s,iterations,line_search_cuts,factorization,relative_residuals\n",
    );
    for step in steps {
        let residuals: Vec<String> = step.residuals.iter().map(|r| format!("{r:.3e}")).collect();
        text.push_str(&format!(
            "{},{},{},{},{:?},{}\n",
            step.time,
            step.increment,
            step.iterations,
            step.line_search_cuts,
            step.factorization,
            residuals.join(" ")
        ));
    }
    musclefem_io::atomic::write_atomically(path, text.as_bytes())?;
    Ok(())
}

/// The implicit run's failed attempts, one row per attempt that was cut: the time it
/// aimed at, its increment, its Newton iterations, its last relative residual, the
/// factorization of its last solve (an indefinite tangent, `SymmetricIndefinite`, means
/// the muscle was near a loss of stability there) and why it failed.
pub(super) fn write_cut_attempts(path: &Path, attempts: &[CutAttempt]) -> Result<()> {
    let mut text =
        String::from("time_s,increment_s,iterations,relative_residual,factorization,reason\n");
    for attempt in attempts {
        let factorization = attempt
            .factorization
            .map_or("none".to_string(), |f| format!("{f:?}"));
        text.push_str(&format!(
            "{},{},{},{:.3e},{},\"{}\"\n",
            attempt.time,
            attempt.increment,
            attempt.iterations,
            attempt.residual,
            factorization,
            attempt.reason.replace('"', "\"\"")
        ));
    }
    musclefem_io::atomic::write_atomically(path, text.as_bytes())?;
    Ok(())
}

pub(super) fn run_log(run: &SquatRun, settings: &SquatSettings, muscles: &[Quadriceps]) -> RunLog {
    let mut text = format!(
        "activation = {}\nsolver = {}\nduration_s = {}\npeak_flexion_deg = {}\ntime_step_s = {}\nelements = {}\nnodes = {}\nsteps = {}\n",
        run.activation.name(),
        settings.solver.name(),
        settings.squat.duration,
        settings.squat.peak_flexion.to_degrees(),
        settings.time_step,
        run.elements,
        run.nodes,
        run.steps,
    );
    if settings.solver == Solver::Explicit && run.steps > 0 {
        // The step taken: below the mass-scaling target above where the shear viscosity
        // damps the highest mode (docs/knee-solver.md).
        text.push_str(&format!(
            "mean_time_step_s = {:.4e}\n",
            settings.squat.duration / run.steps as f64
        ));
    }
    if let (Some(iterations), Some(cuts)) = (run.newton_iterations, run.cuts) {
        let indefinite = run
            .cut_attempts
            .iter()
            .filter(|a| a.factorization == Some(Factorization::SymmetricIndefinite))
            .count();
        text.push_str(&format!(
            "newton_iterations = {iterations}\ncuts = {cuts}\n\
             cuts_after_an_indefinite_tangent = {indefinite}\n"
        ));
    }
    if let Some((evaluations, solves)) = &run.implicit_times {
        text.push_str(&format!(
            "evaluations = {}\nelement_s = {:.1}\nassembly_s = {:.1}\nlinear_solves = {}\n\
             krylov_solves = {}\nkrylov_iterations = {}\nkrylov_failures = {}\nnumeric_factorizations = {}\n\
             indefinite_factorizations = {}\nmass_shifted_factorizations = {}\n\
             cholesky_factor_entries = {}\nfill_reducing_order = {}\n\
             factorization_s = {:.1}\nsubstitution_s = {:.1}\n",
            evaluations.evaluations,
            evaluations.element_seconds,
            evaluations.assembly_seconds,
            solves.solves,
            solves.krylov_solves,
            solves.krylov_iterations,
            solves.krylov_failures,
            solves.numeric_factorizations,
            solves.indefinite_factorizations,
            solves.mass_shifted_factorizations,
            solves.factor_entries,
            solves.ordering.map_or("none", |o| o.name()),
            solves.numeric_seconds,
            solves.substitution_seconds,
        ));
    }
    if let Some(approach) = run.patella_approach {
        text.push_str(&format!(
            "patella_closest_approach_mm = {:.2}\n",
            1e3 * approach.distance
        ));
    }
    text.push_str(&plausibility_report(&run.plausibility_rows, muscles));
    for s in &run.interactions {
        text.push_str(&format!(
            "interaction {} = {}, {} nodes, {:.2} cm²\n",
            s.name,
            s.kind,
            s.nodes,
            1e4 * s.area
        ));
    }
    if let Some(time) = run.resumed_from {
        text.push_str(&format!(
            "resumed = from the checkpoint at t = {time:e} s (steps, Newton counts, \
             newton.csv, cuts.csv and the timings are of the part after it)\n"
        ));
    }
    text.push_str("end = complete\n");
    RunLog::new(text)
}

/// The summary of one run, as one block of text (the runs finish on their own threads).
pub(super) fn run_summary(run: &SquatRun, muscles: &[Quadriceps]) -> String {
    let solver = match (run.newton_iterations, run.cuts) {
        (Some(iterations), Some(cuts)) => {
            format!(
                "{} increments, {iterations} Newton iterations, {cuts} cuts",
                run.steps
            )
        }
        _ => format!(
            "{} steps, mass scaling added {:.2e} of the mass, energy balance within {:.2} %",
            run.steps,
            run.added_mass_fraction.unwrap_or(0.0),
            100.0 * run.energy_error.unwrap_or(0.0)
        ),
    };
    let resumed = run.resumed_from.map_or(String::new(), |time| {
        format!(" (resumed from its checkpoint at t = {time:.3} s)")
    });
    let mut text = format!(
        "{} squat: {} elements, {solver}, in {:.1?}{resumed}\n",
        run.activation.name(),
        run.elements,
        run.solve_time
    );
    let bonds: Vec<String> = run
        .interactions
        .iter()
        .filter(|s| s.kind == "cohesive")
        .map(|s| format!("{} ({} bonds)", s.name, s.nodes))
        .collect();
    text.push_str(&format!("  cohesive: {}\n", bonds.join(", ")));
    text.push_str(&format!("  {}", tendon_summary(&run.tendon)));
    if let Some(approach) = run.patella_approach {
        let millimetres = 1e3 * approach.distance.abs();
        text.push_str(&format!(
            "  patella (no contact surface): {} {} at t = {:.2} s\n",
            approach.muscle.abbreviation(),
            if approach.distance < 0.0 {
                format!("went {millimetres:.1} mm into it")
            } else {
                format!("came within {millimetres:.1} mm of it")
            },
            approach.time
        ));
    }
    if let Some((evaluations, solves)) = &run.implicit_times {
        text.push_str(&format!(
            "  time: elements {:.0} s, assembly {:.0} s, {} factorizations {:.0} s, \
             {} solves {:.0} s\n",
            evaluations.element_seconds,
            evaluations.assembly_seconds,
            solves.numeric_factorizations,
            solves.numeric_seconds,
            solves.solves,
            solves.substitution_seconds,
        ));
    }
    text.push_str(&plausibility_report(&run.plausibility_rows, muscles));
    for row in run
        .rows
        .iter()
        .filter(|r| r.angle_degrees == 90.0 && r.phase == Phase::Flexion)
    {
        text.push_str(&format!(
            "  {} at 90°: vm95 {:.1} kPa, elements above it at: {}\n",
            row.muscle.abbreviation(),
            1e-3 * row.vm95,
            row.location.describe()
        ));
    }
    text
}
