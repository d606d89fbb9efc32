//! Forces between surfaces that enter a solve beside the element forces: contact and
//! cohesion ([`Interaction`], implemented by `musclefem-contact`).
//!
//! An interaction sees only nodal positions. Each solver calls it in the same order:
//! 1. [`Interaction::search`] — the broadphase: once per explicit step, and once per
//!    implicit Newton iteration (the predictor included);
//! 2. [`Interaction::forces`] — the narrowphase and the traction law on the pairs of the
//!    last search (a line search's trial positions reuse them);
//! 3. [`Interaction::stiffness`] — implicit only, after a `forces` call with stiffness;
//! 4. [`Interaction::commit`] — when the step is accepted (explicit: every step; implicit:
//!    on convergence); damage and bonds evolve only there.
//!
//! Sign: the interaction force of a node enters the balance like the internal force,
//! M a + f_int + f_c = f_ext, so a node pushed along n by a contact traction t ≥ 0 over an
//! area A gets f_c = −t A n. The explicit solver reports the work Σ ½(f_c⁻ + f_c)·Δu
//! (stored penalty energy + dissipation − work done by moving rigid surfaces).

use nalgebra::{Matrix3, Vector3};

use super::SolverError;
use super::checkpoint::{CheckpointReader, CheckpointWriter};

/// A force law between surfaces, evaluated from nodal positions.
pub trait Interaction: Send {
    /// Name in messages and histories.
    fn name(&self) -> &str;

    /// Broadphase at nodal `positions` [m] and `time` [s]: finds the candidate pairs that
    /// the following [`forces`](Self::forces) calls evaluate.
    fn search(&mut self, time: f64, positions: &[Vector3<f64>]) -> Result<(), SolverError>;

    /// Adds the nodal forces f_c [N] at `positions` [m] and `time` [s] to `force` (sign as
    /// in the module docs). A trial: the committed state (bonds, damage) stays until
    /// [`commit`](Self::commit). With `with_stiffness`, also keeps ∂f_c/∂x for
    /// [`stiffness`](Self::stiffness).
    fn forces(
        &mut self,
        time: f64,
        positions: &[Vector3<f64>],
        with_stiffness: bool,
        force: &mut [Vector3<f64>],
    ) -> Result<(), SolverError>;

    /// The stiffness of the last [`forces`](Self::forces) call with `with_stiffness`: hands
    /// every 3×3 block K_ab = ∂f_a/∂x_b [N/m] to `add(a, b, K_ab)`; blocks of the same pair
    /// add up.
    fn stiffness(&self, add: &mut dyn FnMut(u32, u32, &Matrix3<f64>));

    /// Whether [`stiffness`](Self::stiffness) is symmetric (K_ab = K_baᵀ); if not, the
    /// implicit solver factorizes with LU.
    fn symmetric_stiffness(&self) -> bool {
        true
    }

    /// Accepts the state of the last [`forces`](Self::forces) call.
    fn commit(&mut self);

    /// Totals of the last [`forces`](Self::forces) call, for the history.
    fn report(&self) -> InteractionReport;

    /// Writes what a resumed run needs (see [`super::checkpoint`]): the committed
    /// history (bonds, damage) and whatever the last [`forces`](Self::forces) call left
    /// that the next [`report`](Self::report), [`nodal_fields`](Self::nodal_fields) or
    /// search reads. Caches that are cheap to rebuild (a broadphase tree) may be dropped
    /// here rather than written, so that the run goes on as the resumed one will. By
    /// default an interaction cannot be checkpointed.
    fn save_state(&mut self, _out: &mut CheckpointWriter) -> Result<(), SolverError> {
        Err(SolverError::Checkpoint(format!(
            "interaction '{}' cannot write its state yet",
            self.name()
        )))
    }

    /// Reads what [`save_state`](Self::save_state) wrote, into an interaction built for
    /// the same problem.
    fn restore_state(&mut self, _input: &mut CheckpointReader) -> Result<(), SolverError> {
        Err(SolverError::Checkpoint(format!(
            "interaction '{}' cannot read a state yet",
            self.name()
        )))
    }

    /// Per-node output fields of the last [`forces`](Self::forces) call (for example the
    /// contact pressure and the cohesive traction), each with one value (or three) per
    /// node of the mesh, zero where the interaction has no node.
    fn nodal_fields(&self, _node_count: usize) -> Vec<NodalField> {
        Vec::new()
    }
}

/// Totals of one interaction at one instant.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct InteractionReport {
    /// Name of the interaction.
    pub name: String,
    /// Resultant of the forces the interaction puts on the secondary surface's nodes,
    /// Σ −f_c over those nodes [N] (the main side takes the opposite force).
    pub force: Vector3<f64>,
    /// Pairs (contact points) carrying a nonzero traction.
    pub active_points: usize,
    /// Area of those points [m²].
    pub active_area: f64,
    /// Area still bonded by a cohesive law, damaged or not [m²] (0 for pure contact).
    pub bonded_area: f64,
    /// Elastic energy stored in the traction law [J].
    pub stored_energy: f64,
}

/// A per-node field of an interaction (see [`Interaction::nodal_fields`]).
#[derive(Debug, Clone, PartialEq)]
pub struct NodalField {
    /// Array name in the outputs, e.g. `contact_pressure`.
    pub name: String,
    /// 1 (scalar) or 3 (vector) values per node.
    pub components: usize,
    /// `components` values per node, node after node.
    pub values: Vec<f64>,
}

/// f_c of every interaction at `positions` and `time`, each searched first, into `force`
/// (overwritten).
pub(super) fn interaction_forces(
    interactions: &mut [Box<dyn Interaction>],
    time: f64,
    positions: &[Vector3<f64>],
    force: &mut [Vector3<f64>],
) -> Result<(), SolverError> {
    if interactions.is_empty() {
        return Ok(());
    }
    force.fill(Vector3::zeros());
    for interaction in interactions.iter_mut() {
        interaction.search(time, positions)?;
        interaction.forces(time, positions, false, force)?;
    }
    Ok(())
}

/// The per-node fields of every interaction, each named `INTERACTION_FIELD` (so two
/// interactions of one kind keep their fields apart).
pub(super) fn all_nodal_fields(
    interactions: &[Box<dyn Interaction>],
    node_count: usize,
) -> Vec<NodalField> {
    interactions
        .iter()
        .flat_map(|i| {
            i.nodal_fields(node_count).into_iter().map(|mut field| {
                field.name = format!("{}_{}", i.name(), field.name);
                field
            })
        })
        .collect()
}
