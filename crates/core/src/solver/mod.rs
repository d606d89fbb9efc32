//! Solvers that advance a body in time: the explicit central-difference solver
//! ([`explicit`]) with lumped mass, a stable step from the dilatational wave speed, optional
//! mass scaling and bulk viscosity ([`bulk_viscosity`]), reactions and an energy balance;
//! the implicit solver ([`implicit`]), quasi-static or Newmark dynamics, with Newton on the
//! consistent tangent, line search, sparse direct solves (faer) and step cutting.
//!
//! Both run through [`run`]: a [`Problem`] (mesh, parts, loads, interactions), an
//! [`Analysis`] (explicit or implicit settings) and one [`Observer`] of the recorded
//! [`Record`]s.
//!
//! Loads ([`Loads`]): prescribed displacement components, nodal forces and nodes tied to
//! rigid bodies with prescribed translation and rotation, with reactions (and rigid-tie
//! force and moment resultants).

pub mod added_mass_frame;
mod amg;
pub mod amg_cg;
mod assembly;
pub mod bulk_viscosity;
pub mod checkpoint;
mod chunk;
pub mod element_fields;
pub mod explicit;
mod explicit_parts;
mod explicit_settings;
pub mod free_motion;
mod hex8_one_point_chunk;
pub mod implicit;
mod implicit_checkpoint;
mod implicit_chunk;
mod implicit_dynamics;
mod implicit_interactions;
mod implicit_model;
mod implicit_newton;
mod implicit_report;
mod implicit_settings;
mod implicit_stiffness;
pub mod interaction;
mod krylov;
mod loads;
mod mixed_pressure;
mod nodal;
mod nodal_average;
pub mod observer;
mod ordering;
mod part;
mod rigid_motion;
mod run;
mod sparse;

pub use checkpoint::{Checkpoint, CheckpointReader, CheckpointWriter};
pub use interaction::{Interaction, InteractionReport, NodalField};
pub use loads::{Loads, NodalForce, PrescribedDisplacement, RigidReaction, RigidTie};
pub use observer::{NoObserver, Observer, Record, Snapshot};
pub use part::Part;
pub use rigid_motion::{PoseFollower, RigidMotion, RigidRotation, tie_followers};
pub use run::{Analysis, Outcome, Problem, resume, run};

use thiserror::Error;

use musclefem_materials::MaterialError;

/// Why a solve stopped.
#[derive(Debug, Error)]
pub enum SolverError {
    // The causes are in the messages and not `source`s, so that a report of the whole
    // chain (`{:#}`) says them once.
    #[error("part on block {block}: {cause}")]
    Element {
        block: usize,
        cause: crate::element::ElementError,
    },
    #[error("at t = {time:.6e} s, block '{block}', element {element}: {cause}")]
    Material {
        time: f64,
        block: String,
        element: usize,
        cause: MaterialError,
    },
    #[error("part on block {block}: {reason}")]
    InvalidPart { block: usize, reason: String },
    #[error("prescribed displacement: {0}")]
    InvalidBoundaryCondition(String),
    #[error("explicit settings: {0}")]
    InvalidSettings(String),
    #[error(
        "the requested time step {requested:.3e} s exceeds the stable step {stable:.3e} s \
         (block '{block}', element {element}): the central-difference scheme would blow up"
    )]
    UnstableTimeStep {
        requested: f64,
        stable: f64,
        block: String,
        element: usize,
    },
    #[error(
        "at t = {time:.6e} s the energy balance is off by {error:.3e} J ({relative:.1} % of \
         the largest energy, limit {limit:.1} %): the solution is not to be trusted"
    )]
    EnergyBalance {
        time: f64,
        error: f64,
        relative: f64,
        limit: f64,
    },
    #[error("at t = {time:.6e} s node {node} has a non-finite velocity: the solution diverged")]
    Diverged { time: f64, node: usize },
    #[error("implicit settings: {0}")]
    InvalidImplicitSettings(String),
    #[error(
        "the piece of block '{block}' ({nodes} nodes) can move as a rigid body: {motions}. \
         A quasi-static run has no inertia to hold it (its stiffness is singular); add \
         displacement conditions that hold these motions, or run with inertia \
         (implicit dynamic = true, or explicit)"
    )]
    FreeRigidMotion {
        block: String,
        nodes: usize,
        motions: String,
    },
    #[error(
        "part on block {block}: technology {technology:?} has no consistent tangent yet, so \
         the implicit solver cannot use it (use Hex8Full, Hex8FBar, Hex8OnePoint, Tet4, Tet10 or \
         Tet10FBar, or the explicit solver)"
    )]
    NoConsistentTangent {
        block: usize,
        technology: crate::element::Technology,
    },
    #[error(
        "at t = {time:.6e} s (increment {increment:.3e} s, the smallest allowed) Newton did \
         not converge after {iterations} iterations, relative residual {residual:.3e}: {reason}"
    )]
    NotConverged {
        time: f64,
        increment: f64,
        iterations: usize,
        residual: f64,
        reason: String,
    },
    #[error("stopped at t = {time:.6e} s on request; the outputs hold the run up to there")]
    Interrupted { time: f64 },
    #[error("checkpoint: {0}")]
    Checkpoint(String),
    #[error("at t = {time:.6e} s the linear solve failed: {reason}")]
    LinearSolve { time: f64, reason: String },
}
