//! Interactions (contact, cohesion) in the implicit solver: their forces join the internal
//! forces, their stiffness blocks the sparse tangent. The pairs are searched once per
//! Newton iteration (with the stiffness) and reused by the line search's trials. A block
//! that couples two nodes not yet coupled in the sparse pattern grows the pattern (the
//! pairs stay in it for the rest of the run, so it is rebuilt only a few times), and the
//! evaluation is repeated.

use nalgebra::{Matrix3, Vector3};

use super::SolverError;
use super::implicit_model::Model;
use super::sparse::PRESCRIBED;

impl Model<'_> {
    /// Adds the interactions' forces to the internal forces at `positions` and `time`,
    /// searching first when `with_stiffness`, and their stiffness to the matrix (and
    /// K_fp Δū to the lift with `delta`). Returns `false` when the stiffness coupled new
    /// node pairs: the pattern has been rebuilt and the evaluation must be repeated.
    pub(super) fn add_interactions(
        &mut self,
        positions: &[Vector3<f64>],
        time: f64,
        with_stiffness: bool,
        delta: Option<&[f64]>,
    ) -> Result<bool, SolverError> {
        for interaction in self.interactions.iter_mut() {
            if with_stiffness {
                interaction.search(time, positions)?;
            }
            interaction.forces(time, positions, with_stiffness, &mut self.force)?;
        }
        if !with_stiffness {
            return Ok(true);
        }
        let mut blocks: Vec<(u32, u32, Matrix3<f64>)> = Vec::new();
        for interaction in self.interactions.iter() {
            interaction.stiffness(&mut |a, b, k| blocks.push((a, b, *k)));
            self.symmetric &= interaction.symmetric_stiffness();
        }
        let mut missing: Vec<(u32, u32)> = Vec::new();
        let values_len = self.system.entries();
        for &(a, b, k) in &blocks {
            for j in 0..3 {
                let column_dof = 3 * b as usize + j;
                let column = self.equation[column_dof];
                for i in 0..3 {
                    let row = self.equation[3 * a as usize + i];
                    if row == PRESCRIBED || k[(i, j)] == 0.0 {
                        continue;
                    }
                    if column == PRESCRIBED {
                        if let Some(delta) = delta {
                            self.lift[row as usize] += k[(i, j)] * delta[column_dof];
                        }
                        continue;
                    }
                    match self.system.find(row as usize, column as usize) {
                        Some(position) if position < values_len => {
                            self.system.values_mut()[position] += k[(i, j)];
                        }
                        _ => missing.push((a.min(b), a.max(b))),
                    }
                }
            }
        }
        if missing.is_empty() {
            return Ok(true);
        }
        self.coupled_pairs.extend(missing);
        self.coupled_pairs.sort_unstable();
        self.coupled_pairs.dedup();
        self.build_system()
            .map_err(|reason| SolverError::LinearSolve { time, reason })?;
        Ok(false)
    }
}
