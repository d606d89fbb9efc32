//! What a caller sees of a run while it goes: every recorded history row as a [`Record`]
//! (explicit or implicit) with a [`Snapshot`] of that instant (displacements, and
//! per-element fields on request, for frames and live histories), and the progress of the
//! steps (for a progress bar). Either may stop the run cleanly (Ctrl-C): the solver then
//! returns [`super::SolverError::Interrupted`] after the last recorded row. One observer
//! serves both solvers.

use std::ops::ControlFlow;

use nalgebra::Vector3;

use super::SolverError;
use super::checkpoint::Checkpoint;
use super::element_fields::PartFields;
use super::explicit::HistoryRow;
use super::implicit::ImplicitHistoryRow;
use super::interaction::{InteractionReport, NodalField};
use super::loads::RigidReaction;

/// The state of a run at a recorded instant.
pub struct Snapshot<'a> {
    /// Time [s].
    pub time: f64,
    /// Displacement of every node [m].
    pub displacement: &'a [Vector3<f64>],
    fields: &'a dyn Fn() -> Result<Vec<PartFields>, SolverError>,
    nodal_fields: Option<&'a dyn Fn() -> Vec<NodalField>>,
}

impl<'a> Snapshot<'a> {
    /// A snapshot at `time` whose element fields `fields` evaluates when asked.
    pub fn new(
        time: f64,
        displacement: &'a [Vector3<f64>],
        fields: &'a dyn Fn() -> Result<Vec<PartFields>, SolverError>,
    ) -> Self {
        Self {
            time,
            displacement,
            fields,
            nodal_fields: None,
        }
    }

    /// The snapshot with per-node fields of the interactions, evaluated when asked.
    pub fn with_nodal_fields(mut self, nodal_fields: &'a dyn Fn() -> Vec<NodalField>) -> Self {
        self.nodal_fields = Some(nodal_fields);
        self
    }

    /// Per-node fields of the interactions (contact pressure, cohesive traction, …); empty
    /// without interactions.
    pub fn nodal_fields(&self) -> Vec<NodalField> {
        self.nodal_fields.map_or_else(Vec::new, |f| f())
    }

    /// Per-element fields of every part (stress, fiber direction, state, activation), in
    /// part order. Evaluated on each call, at about the cost of one step's material
    /// update: ask only for the instants that need them (frames).
    pub fn element_fields(&self) -> Result<Vec<PartFields>, SolverError> {
        (self.fields)()
    }
}

/// One recorded instant of a run: the row of the solver that recorded it.
#[derive(Debug, Clone, Copy)]
pub enum Record<'a> {
    /// A row of the explicit solver (energies of the central-difference balance).
    Explicit(&'a HistoryRow),
    /// A row of the implicit solver (Newton iterations, Newmark energies).
    Implicit(&'a ImplicitHistoryRow),
}

impl Record<'_> {
    /// Time [s].
    pub fn time(&self) -> f64 {
        match self {
            Record::Explicit(row) => row.time,
            Record::Implicit(row) => row.time,
        }
    }

    /// Reaction force of each prescribed displacement, in its direction [N].
    pub fn reactions(&self) -> &[f64] {
        match self {
            Record::Explicit(row) => &row.reactions,
            Record::Implicit(row) => &row.reactions,
        }
    }

    /// Resultant reaction force and moment of each rigid tie.
    pub fn rigid_reactions(&self) -> &[RigidReaction] {
        match self {
            Record::Explicit(row) => &row.rigid_reactions,
            Record::Implicit(row) => &row.rigid_reactions,
        }
    }

    /// Totals of each interaction, in the order given.
    pub fn interactions(&self) -> &[InteractionReport] {
        match self {
            Record::Explicit(row) => &row.interactions,
            Record::Implicit(row) => &row.interactions,
        }
    }

    /// Kinetic energy [J] (0 in a quasi-static implicit run).
    pub fn kinetic_energy(&self) -> f64 {
        match self {
            Record::Explicit(row) => row.kinetic_energy,
            Record::Implicit(row) => row.energy.kinetic,
        }
    }
}

/// Watches a run, explicit or implicit.
pub trait Observer {
    /// A history row was recorded, with the state of the run at its time.
    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()>;

    /// The initial state (t = 0, nothing displaced, every point in its initial state),
    /// shown by a solver that records no history row there (the implicit one; the
    /// explicit one's first row is at t = 0), so that a run's first frame is its start.
    fn start(&mut self, _snapshot: &Snapshot) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }

    /// Asked right after each recorded row: whether the run should hand this observer a
    /// [`Checkpoint`] of its state there (before the next step), to resume from. Never,
    /// by default.
    fn wants_checkpoint(&mut self) -> bool {
        false
    }

    /// The run's state right after the last recorded row (see [`super::resume`]), or why
    /// it could not be taken (an interaction that cannot write its state): the run goes
    /// on either way unless this returns `Break`.
    fn checkpoint(&mut self, _checkpoint: Result<Checkpoint, SolverError>) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }

    /// A step ended at `time` [s], the `steps`-th; called every step, keep it cheap.
    fn progress(&mut self, _time: f64, _steps: usize) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// An observer that watches nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoObserver;

impl Observer for NoObserver {
    fn record(&mut self, _record: &Record, _snapshot: &Snapshot) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}
