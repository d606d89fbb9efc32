//! The implicit solver's stiffness: built only when a solve (or the round-off test) needs
//! it ([`Model::ensure_stiffness`]; `docs/implicit-speed.md`), from the element matrices
//! computed in parallel chunks and added into the sparse matrix in parallel by columns.
//!
//! **Same bits on any number of threads.** Each thread owns a contiguous range of the
//! matrix's columns (whose values are contiguous, the matrix being stored by columns) and
//! walks every element in element order, adding only the entries of its columns. Every
//! entry thus receives its elements' contributions in element order, one addition per
//! element, as the serial loop did: the sums, and the matrix, are the same bit for bit
//! whatever the split. The lift K_fp Δū sums over prescribed columns into shared rows, so
//! it stays serial (the predictor's evaluation only).

use std::ops::Range;
use std::time::Instant;

use rayon::prelude::*;

use super::implicit_model::{Model, PartRun};
use super::sparse::PRESCRIBED;

impl Model<'_> {
    /// Builds the stiffness due since the last evaluation with stiffness, if it is not
    /// built yet (see [`Self::evaluate`]).
    pub fn ensure_stiffness(&mut self) {
        if self.stiffness_due {
            self.scatter_element_stiffness();
            self.finish_stiffness();
        }
    }

    /// The elements' stiffness at the positions of the last evaluation with stiffness,
    /// computed in parallel chunks and added into the cleared matrix in parallel column
    /// ranges (and K_fp Δū into the cleared lift, serially).
    pub(super) fn scatter_element_stiffness(&mut self) {
        let mesh = self.mesh;
        let update_start = Instant::now();
        let positions = &self.stiffness_positions;
        for run in &mut self.runs {
            let block = &mesh.blocks[run.block];
            let kernel = &run.kernel;
            run.chunks
                .par_iter_mut()
                .for_each(|chunk| chunk.compute_stiffness(kernel, block, positions));
        }
        let element_seconds = update_start.elapsed().as_secs_f64();
        self.symmetric = self
            .runs
            .iter()
            .all(|run| run.chunks.iter().all(|chunk| chunk.symmetric));
        // Column ranges of about equal size, a few per thread for balance.
        let unknowns = self.residual.len();
        let ranges = (4 * rayon::current_num_threads()).clamp(1, unknowns.max(1));
        let bounds: Vec<usize> = (0..=ranges).map(|p| p * unknowns / ranges).collect();
        let mut slices = Vec::with_capacity(ranges);
        let mut rest = self.system.values_mut();
        let mut offset = 0;
        for columns in bounds.windows(2) {
            let end = self.column_starts[columns[1]];
            let (values, tail) = rest.split_at_mut(end - offset);
            slices.push((columns[0]..columns[1], offset, values));
            rest = tail;
            offset = end;
        }
        let (runs, equation) = (&self.runs, &self.equation);
        slices
            .into_par_iter()
            .for_each(|(columns, offset, values)| {
                values.fill(0.0);
                for run in runs {
                    add_columns(run, mesh, equation, &columns, offset, values);
                }
            });
        self.lift.fill(0.0);
        if let Some(delta) = self.stiffness_delta.as_deref() {
            for run in &self.runs {
                add_lift(run, mesh, &self.equation, delta, &mut self.lift);
            }
        }
        self.times.element_seconds += element_seconds;
        self.times.stiffness_seconds += element_seconds;
        self.times.assembly_seconds += update_start.elapsed().as_secs_f64() - element_seconds;
    }

    /// Completes the stiffness after the elements' (and the interactions') blocks: the
    /// mass term of a dynamic run on the diagonal, and the scale max |K_ii|.
    pub(super) fn finish_stiffness(&mut self) {
        if let Some(inertia) = &self.inertia {
            let values = self.system.values_mut();
            self.mass_diagonal.resize(self.diagonal.len(), 0.0);
            for (d, &eq) in self.equation.iter().enumerate() {
                if eq != PRESCRIBED {
                    let mass = inertia.mass[d / 3] * inertia.coefficient;
                    values[self.diagonal[eq as usize]] += mass;
                    self.mass_diagonal[eq as usize] = mass;
                }
            }
        }
        let values = self.system.values_mut();
        self.stiffness_scale = self
            .diagonal
            .iter()
            .fold(0.0, |m, &p| m.max(values[p].abs()));
        self.stiffness_due = false;
        self.times.stiffness_builds += 1;
    }
}

/// The element matrices of `run` in element order: (block element, its nodes, its matrix
/// of `element_dofs()`² values, row-major).
fn element_matrices<'r>(
    run: &'r PartRun,
    mesh: &'r crate::mesh::Mesh,
) -> impl Iterator<Item = (usize, &'r [u32], &'r [f64])> {
    let block = &mesh.blocks[run.block];
    let size = run.kernel.element_dofs().pow(2);
    run.chunks.iter().flat_map(move |chunk| {
        chunk.elements().enumerate().map(move |(local, element)| {
            (
                element,
                block.element_nodes(element),
                &chunk.stiffness[local * size..(local + 1) * size],
            )
        })
    })
}

/// Adds the element matrices of `run` to the entries of the free `columns` (equations),
/// whose values start at position `offset` of the matrix's values, in element order.
fn add_columns(
    run: &PartRun,
    mesh: &crate::mesh::Mesh,
    equation: &[u32],
    columns: &Range<usize>,
    offset: usize,
    values: &mut [f64],
) {
    let npe = run.kernel.nodes_per_element();
    let dofs = run.kernel.element_dofs();
    for (element, ids, k) in element_matrices(run, mesh) {
        let map = &run.scatter[element * dofs * npe..(element + 1) * dofs * npe];
        for (c, starts) in map.chunks_exact(npe).enumerate() {
            let column = equation[3 * ids[c / 3] as usize + c % 3];
            if column == PRESCRIBED || !columns.contains(&(column as usize)) {
                continue;
            }
            for (a, (&id, &start)) in ids.iter().zip(starts).enumerate() {
                let rows = &equation[3 * id as usize..3 * id as usize + 3];
                let Some(&first) = rows.iter().find(|&&r| r != PRESCRIBED) else {
                    continue;
                };
                for (i, &row) in rows.iter().enumerate() {
                    if row != PRESCRIBED {
                        values[(start + row - first) as usize - offset] +=
                            k[(3 * a + i) * dofs + c];
                    }
                }
            }
        }
    }
}

/// Adds K_fp Δū of `run`'s elements to `lift` (rows of free equations), in element order.
fn add_lift(
    run: &PartRun,
    mesh: &crate::mesh::Mesh,
    equation: &[u32],
    delta: &[f64],
    lift: &mut [f64],
) {
    let dofs = run.kernel.element_dofs();
    for (_, ids, k) in element_matrices(run, mesh) {
        for c in 0..dofs {
            let dof = 3 * ids[c / 3] as usize + c % 3;
            if equation[dof] != PRESCRIBED {
                continue;
            }
            for (a, &id) in ids.iter().enumerate() {
                for i in 0..3 {
                    let row = equation[3 * id as usize + i];
                    if row != PRESCRIBED {
                        lift[row as usize] += k[(3 * a + i) * dofs + c] * delta[dof];
                    }
                }
            }
        }
    }
}
