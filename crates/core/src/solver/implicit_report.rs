//! What the implicit solver reports: every converged step, every attempt that failed and
//! was cut, and the run's totals ([`ImplicitResult`]).

use nalgebra::Vector3;

use super::RigidReaction;
use super::implicit_dynamics::EnergyBalance;
use super::implicit_model::EvaluationTimes;
use super::interaction::InteractionReport;
use super::sparse::{Factorization, LinearSolveStatistics};

/// One converged step.
#[derive(Debug, Clone, PartialEq)]
pub struct ImplicitHistoryRow {
    /// Time at the end of the step [s].
    pub time: f64,
    /// Increment of the step [s].
    pub increment: f64,
    /// Newton iterations (predictor included).
    pub iterations: usize,
    /// Reaction force of each prescribed displacement, in its direction, summed over its
    /// nodes [N].
    pub reactions: Vec<f64>,
    /// Resultant reaction force and moment of each rigid tie.
    pub rigid_reactions: Vec<RigidReaction>,
    /// Kinetic energy and works at the end of the step (dynamics; zero when quasi-static).
    pub energy: EnergyBalance,
    /// Totals of each interaction at the end of the step, in the order given.
    pub interactions: Vec<InteractionReport>,
}

/// How one converged step went.
#[derive(Debug, Clone, PartialEq)]
pub struct StepReport {
    pub time: f64,
    pub increment: f64,
    pub iterations: usize,
    /// ‖r_f‖ / ‖f_int‖ after the predictor and after each iteration.
    pub residuals: Vec<f64>,
    /// Line-search halvings taken over the step.
    pub line_search_cuts: usize,
    /// The factorization of the last solve.
    pub factorization: Factorization,
    /// Whether Newton started from the extrapolated first guess
    /// ([`super::implicit::ImplicitSettings::extrapolate`]) rather than the tangent
    /// predictor.
    pub extrapolated: bool,
    /// ‖r_f + K_fp Δū‖ [N], the right-hand side of the tangent predictor (`None` when
    /// the step started from the extrapolated guess).
    pub predictor_residual: Option<f64>,
}

/// A step attempt that failed and was retried with half the increment.
#[derive(Debug, Clone, PartialEq)]
pub struct CutAttempt {
    /// Time the attempt aimed at, and its increment [s].
    pub time: f64,
    pub increment: f64,
    /// Newton iterations it took (predictor included) and its last ‖r_f‖ / ‖f_int‖; 0 and
    /// NaN when it ended in an error (a failed linear solve or evaluation of the predictor)
    /// rather than in Newton not converging.
    pub iterations: usize,
    pub residual: f64,
    /// The factorization of its last solve (`None` after an error).
    pub factorization: Option<Factorization>,
    /// Why it failed, in words.
    pub reason: String,
}

/// What a quasi-static run returns.
#[derive(Debug, Clone)]
pub struct ImplicitResult {
    pub history: Vec<ImplicitHistoryRow>,
    pub steps: Vec<StepReport>,
    /// Failed attempts that were cut.
    pub cuts: usize,
    /// Each of them, in order.
    pub cut_attempts: Vec<CutAttempt>,
    /// Nodal displacements at the end [m].
    pub displacement: Vec<Vector3<f64>>,
    /// Unknowns (free degrees of freedom) and stored matrix entries.
    pub equations: usize,
    pub matrix_entries: usize,
    /// Counts and times of the evaluations (element updates, assembly).
    pub evaluation_times: EvaluationTimes,
    /// Counts and times of the linear solves.
    pub linear_solves: LinearSolveStatistics,
    /// Nodal displacements after every converged step [m] (with
    /// [`ImplicitSettings::record_displacements`](crate::solver::implicit::ImplicitSettings::record_displacements)).
    pub displacement_history: Vec<Vec<Vector3<f64>>>,
}
