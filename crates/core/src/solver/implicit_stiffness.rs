//! The implicit solver's stiffness: built only when a solve (or the round-off test) needs
//! it ([`Model::ensure_stiffness`]; `docs/implicit-speed.md`), from the element matrices
//! computed in parallel chunks and added into the sparse matrix in parallel by columns,
//! a wave of chunks at a time (so that the tangents and element matrices of only a few
//! chunks exist at once).
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

use super::SolverError;
use super::implicit_chunk::{ImplicitChunk, StiffnessWork};
use super::implicit_model::Model;
use super::sparse::PRESCRIBED;

/// Chunks whose element matrices are computed (in parallel) before they are added into
/// the matrix (in parallel by columns), per thread: enough work between the two to keep
/// the threads busy, few enough that the matrices of 64-element chunks take a few
/// megabytes instead of all the mesh's (124 MB for 30³ F-bar hex8).
const CHUNKS_PER_THREAD_IN_A_WAVE: usize = 8;

impl Model<'_> {
    /// Builds the stiffness due since the last evaluation with stiffness, if it is not
    /// built yet (see [`Self::evaluate`]). A material error while its tangents are
    /// computed leaves it unbuilt, and the next [`Self::solve`] reports it.
    pub fn ensure_stiffness(&mut self) {
        if self.stiffness_due {
            match self.scatter_element_stiffness() {
                Ok(()) => self.finish_stiffness(),
                Err(failure) => {
                    self.stiffness_due = false;
                    self.stiffness_scale = 0.0;
                    self.stiffness_failure = Some(failure);
                }
            }
        }
    }

    /// The elements' stiffness at the positions of the last evaluation with stiffness,
    /// added into the cleared matrix (and K_fp Δū into the cleared lift). Chunks go in
    /// waves in element order: their tangents and element matrices are computed in
    /// parallel into [`Self::stiffness_work`], then added in parallel column ranges,
    /// each range walking the wave's elements in element order (the lift serially), so
    /// every entry sums its elements in element order, as one serial loop would. The
    /// adding of one wave overlaps the computing of the next; the time of both counts
    /// as the elements', the last wave's adding as assembly.
    pub(super) fn scatter_element_stiffness(&mut self) -> Result<(), SolverError> {
        let mesh = self.mesh;
        let start = Instant::now();
        let mut element_seconds = 0.0;
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
        slices
            .par_iter_mut()
            .for_each(|(_, _, values)| values.fill(0.0));
        self.lift.fill(0.0);
        let wave = CHUNKS_PER_THREAD_IN_A_WAVE * rayon::current_num_threads().max(1);
        if self.stiffness_work.len() < 2 * wave {
            self.stiffness_work
                .resize_with(2 * wave, StiffnessWork::default);
        }
        let (even, odd) = self.stiffness_work.split_at_mut(wave);
        let positions = &self.stiffness_positions;
        let equation = &self.equation;
        let delta = self.stiffness_delta.as_deref();
        let lift = &mut self.lift;
        let mut symmetric = true;
        for run in &mut self.runs {
            let block = &mesh.blocks[run.block];
            let (kernel, material) = (&run.kernel, run.material);
            let matrix = ElementMatrices {
                block,
                scatter: &run.scatter,
                nodes_per_element: kernel.nodes_per_element(),
                dofs: kernel.element_dofs(),
            };
            let chunk_count = run.chunks.len();
            let waves: Vec<Range<usize>> = (0..chunk_count)
                .step_by(wave)
                .map(|first| first..(first + wave).min(chunk_count))
                .collect();
            // Wave k is computed into one half of the work while wave k − 1, in the
            // other, is added into the matrix: the adding touches the few column ranges
            // of a wave's slab of elements, and the computing keeps the other threads
            // busy meanwhile.
            for (k, current) in waves.iter().enumerate() {
                let (done, rest) = run.chunks.split_at_mut(current.start);
                let chunks = &mut rest[..current.len()];
                let (work, previous_work) = if k.is_multiple_of(2) {
                    (&mut *even, &*odd)
                } else {
                    (&mut *odd, &*even)
                };
                let previous = k.checked_sub(1).map(|p| &done[waves[p].clone()]);
                let join_start = Instant::now();
                let (computed, ()) = rayon::join(
                    || {
                        chunks.par_iter_mut().zip(work.par_iter_mut()).try_for_each(
                            |(chunk, work)| {
                                chunk.compute_stiffness(kernel, block, material, positions, work)
                            },
                        )
                    },
                    || {
                        if let Some(previous) = previous {
                            let work = &previous_work[..previous.len()];
                            matrix.add_wave(previous, work, equation, delta, &mut slices, lift);
                        }
                    },
                );
                element_seconds += join_start.elapsed().as_secs_f64();
                computed.map_err(|(element, cause)| SolverError::Material {
                    time: chunks.first().map_or(0.0, |c| c.last_time()),
                    block: block.name.clone(),
                    element,
                    cause,
                })?;
                symmetric &= chunks.iter().all(|chunk| chunk.symmetric);
            }
            if let Some(last) = waves.last() {
                let work = if (waves.len() - 1).is_multiple_of(2) {
                    &*even
                } else {
                    &*odd
                };
                let chunks = &run.chunks[last.clone()];
                matrix.add_wave(
                    chunks,
                    &work[..chunks.len()],
                    equation,
                    delta,
                    &mut slices,
                    lift,
                );
            }
        }
        self.symmetric = symmetric;
        self.times.element_seconds += element_seconds;
        self.times.stiffness_seconds += element_seconds;
        self.times.assembly_seconds += start.elapsed().as_secs_f64() - element_seconds;
        Ok(())
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

/// How one part's element matrices go into the sparse matrix: its block's
/// connectivity and scatter map.
struct ElementMatrices<'r> {
    block: &'r crate::mesh::ElementBlock,
    scatter: &'r [u32],
    nodes_per_element: usize,
    dofs: usize,
}

impl ElementMatrices<'_> {
    /// Adds the matrices of a wave of `chunks` (in `work`) into the matrix's column
    /// ranges `slices` in parallel, each range in element order, and K_fp Δū into
    /// `lift` serially.
    fn add_wave(
        &self,
        chunks: &[ImplicitChunk],
        work: &[StiffnessWork],
        equation: &[u32],
        delta: Option<&[f64]>,
        slices: &mut [(Range<usize>, usize, &mut [f64])],
        lift: &mut [f64],
    ) {
        slices.par_iter_mut().for_each(|(columns, offset, values)| {
            for (chunk, work) in chunks.iter().zip(work) {
                self.add_columns(chunk, work, equation, columns, *offset, values);
            }
        });
        if let Some(delta) = delta {
            for (chunk, work) in chunks.iter().zip(work) {
                self.add_lift(chunk, work, equation, delta, lift);
            }
        }
    }

    /// The chunk's elements in element order with their nodes and matrices (of
    /// `dofs`² values, row-major) from `work`.
    fn elements<'w>(
        &'w self,
        chunk: &ImplicitChunk,
        work: &'w StiffnessWork,
    ) -> impl Iterator<Item = (usize, &'w [u32], &'w [f64])> {
        let size = self.dofs * self.dofs;
        chunk.elements().enumerate().map(move |(local, element)| {
            (
                element,
                self.block.element_nodes(element),
                &work.matrices[local * size..(local + 1) * size],
            )
        })
    }

    /// Adds the chunk's element matrices to the entries of the free `columns`
    /// (equations), whose values start at position `offset` of the matrix's values, in
    /// element order.
    fn add_columns(
        &self,
        chunk: &ImplicitChunk,
        work: &StiffnessWork,
        equation: &[u32],
        columns: &Range<usize>,
        offset: usize,
        values: &mut [f64],
    ) {
        let (npe, dofs) = (self.nodes_per_element, self.dofs);
        for (element, ids, k) in self.elements(chunk, work) {
            let map = &self.scatter[element * dofs * npe..(element + 1) * dofs * npe];
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

    /// Adds K_fp Δū of the chunk's elements to `lift` (rows of free equations), in
    /// element order.
    fn add_lift(
        &self,
        chunk: &ImplicitChunk,
        work: &StiffnessWork,
        equation: &[u32],
        delta: &[f64],
        lift: &mut [f64],
    ) {
        let dofs = self.dofs;
        for (_, ids, k) in self.elements(chunk, work) {
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
}
