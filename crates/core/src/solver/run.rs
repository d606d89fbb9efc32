//! One entry point for both solvers: a [`Problem`] (what is simulated: mesh, parts,
//! loads, interactions), an [`Analysis`] (how: explicit or implicit, with its settings)
//! and [`run`], which shows every recorded instant to one [`Observer`] and returns an
//! [`Outcome`]. Commands and studies choose the solver by value, not by code path.

use nalgebra::Vector3;

use super::SolverError;
use super::checkpoint::Checkpoint;
use super::explicit::{ExplicitResult, ExplicitSettings, explicit_run};
use super::free_motion::refuse_free_motion;
use super::implicit::{ImplicitResult, ImplicitSettings, implicit_run};
use super::interaction::Interaction;
use super::loads::Loads;
use super::observer::Observer;
use super::part::Part;
use crate::mesh::Mesh;

/// What is simulated: the body (mesh and parts), its loads and the interactions (contact,
/// cohesion) that add forces and stiffness.
pub struct Problem<'a> {
    pub mesh: &'a Mesh,
    pub parts: &'a [Part],
    pub loads: &'a Loads,
    /// Searched, evaluated and committed by the solver; empty for none.
    pub interactions: &'a mut [Box<dyn Interaction>],
}

/// How it is solved.
#[derive(Debug, Clone)]
pub enum Analysis {
    /// Central differences with lumped mass ([`super::explicit`]).
    Explicit(ExplicitSettings),
    /// Newton on the consistent tangent, quasi-static or Newmark ([`super::implicit`]).
    Implicit(ImplicitSettings),
}

impl Analysis {
    /// `explicit` or `implicit`.
    pub fn solver_name(&self) -> &'static str {
        match self {
            Analysis::Explicit(_) => "explicit",
            Analysis::Implicit(_) => "implicit",
        }
    }

    /// The time the run ends at [s].
    pub fn end_time(&self) -> f64 {
        match self {
            Analysis::Explicit(settings) => settings.end_time,
            Analysis::Implicit(settings) => settings.end_time,
        }
    }
}

/// What a run returns: the result of the solver that ran. (One per run: the size of the
/// implicit variant's inline statistics costs nothing worth a box.)
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)]
pub enum Outcome {
    Explicit(ExplicitResult),
    Implicit(ImplicitResult),
}

impl Outcome {
    /// Nodal displacements at the end [m].
    pub fn displacement(&self) -> &[Vector3<f64>] {
        match self {
            Outcome::Explicit(result) => &result.displacement,
            Outcome::Implicit(result) => &result.displacement,
        }
    }

    /// Steps taken: explicit time steps, or converged implicit increments.
    pub fn steps(&self) -> usize {
        match self {
            Outcome::Explicit(result) => result.steps,
            Outcome::Implicit(result) => result.steps.len(),
        }
    }
}

/// Runs `problem` as `analysis` says, showing `observer` every recorded row and step.
pub fn run(
    problem: Problem,
    analysis: &Analysis,
    observer: &mut dyn Observer,
) -> Result<Outcome, SolverError> {
    run_from(problem, analysis, observer, None)
}

/// Goes on with `problem` from `checkpoint`, which a run of the same problem and analysis
/// handed its observer ([`Observer::wants_checkpoint`]): the rows recorded from there on
/// are those the uninterrupted run records, bit for bit (see [`super::checkpoint`]). The
/// outcome's history holds only those rows.
pub fn resume(
    problem: Problem,
    analysis: &Analysis,
    checkpoint: &Checkpoint,
    observer: &mut dyn Observer,
) -> Result<Outcome, SolverError> {
    if checkpoint.solver != analysis.solver_name() {
        return Err(SolverError::Checkpoint(format!(
            "the checkpoint was written by the {} solver, this run uses the {} one",
            checkpoint.solver,
            analysis.solver_name()
        )));
    }
    run_from(problem, analysis, observer, Some(checkpoint))
}

fn run_from(
    problem: Problem,
    analysis: &Analysis,
    observer: &mut dyn Observer,
    from: Option<&Checkpoint>,
) -> Result<Outcome, SolverError> {
    let Problem {
        mesh,
        parts,
        loads,
        interactions,
    } = problem;
    Ok(match analysis {
        Analysis::Explicit(settings) => Outcome::Explicit(explicit_run(
            mesh,
            parts,
            loads,
            interactions,
            settings,
            observer,
            from,
        )?),
        Analysis::Implicit(settings) => {
            refuse_free_motion(mesh, loads, analysis, interactions.len())?;
            Outcome::Implicit(implicit_run(
                mesh,
                parts,
                loads,
                interactions,
                settings,
                observer,
                from,
            )?)
        }
    })
}
