//! The implicit solver's checkpoint after a converged increment (read back in
//! `implicit.rs`; see `checkpoint.rs` for what a checkpoint is).

use nalgebra::Vector3;

use super::checkpoint::{Checkpoint, CheckpointWriter};
use super::implicit_dynamics::EnergyBalance;
use super::implicit_model::Model;
use super::rigid_motion::save_follower_states;
use super::{RigidTie, SolverError};

/// The state after a converged increment ending at `time`, with the step control
/// (`increment`, `easy`), the energy books and the nodal `displacement`, internal and
/// external forces (in that order), then the states of the followers of `ties`, as
/// [`implicit_run`] reads it back.
pub(super) fn implicit_checkpoint(
    model: &mut Model,
    time: f64,
    increment: f64,
    easy: usize,
    energy: &EnergyBalance,
    nodal: [&[Vector3<f64>]; 3],
    ties: &[RigidTie],
) -> Result<Checkpoint, SolverError> {
    let mut out = CheckpointWriter::new();
    out.f64(time);
    out.f64(increment);
    out.u64(easy as u64);
    out.f64(energy.kinetic);
    out.f64(energy.internal_work);
    out.f64(energy.external_work);
    nodal.iter().for_each(|values| out.matrices(values));
    if let Some(inertia) = &model.inertia {
        out.matrices(&inertia.velocity);
        out.matrices(&inertia.acceleration);
    }
    for run in &model.runs {
        run.chunks
            .iter()
            .for_each(|chunk| chunk.save_state(&mut out));
    }
    for interaction in model.interactions.iter_mut() {
        interaction.save_state(&mut out)?;
    }
    let pairs: Vec<u32> = model
        .coupled_pairs
        .iter()
        .flat_map(|&(a, b)| [a, b])
        .collect();
    out.u32s(&pairs);
    save_follower_states(ties, &mut out);
    Ok(Checkpoint {
        solver: "implicit".to_string(),
        time,
        state: out.into_bytes(),
    })
}
