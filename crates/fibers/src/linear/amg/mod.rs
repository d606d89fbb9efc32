//! Aggregation algebraic multigrid as a CG preconditioner for the orthogonal Laplacian.
//!
//! Each level groups strongly connected rows into aggregates ([`aggregation`]) and forms
//! the Galerkin coarse matrix Pᵀ A P of the piecewise-constant prolongation
//! ([`prolongation`]), until at most [`COARSEST`] rows are left, which a dense Cholesky
//! factor solves. One application is a V(1,1) cycle with damped Jacobi smoothing
//! (ω = 4/(3ρ), ρ ≥ ρ(D⁻¹A) by Gershgorin), the same before and after the coarse
//! correction, so the preconditioner is symmetric positive definite as CG needs. The
//! cycle allocates nothing: every level keeps its work vectors.
//!
//! Unsmoothed aggregation: a cycle alone reduces the error slowly, but as a CG
//! preconditioner it cuts the iterations several times (they still grow with the mesh,
//! more slowly than with Jacobi) at a low cost per cycle. (Smoothing the prolongation,
//! as in smoothed aggregation, made the coarse matrices of tetrahedral meshes nearly
//! dense: slower overall.)

mod aggregation;
mod prolongation;

use nalgebra::{Cholesky, DMatrix, DVector, Dyn};
use rayon::prelude::*;

use super::kernels::{CHUNK, multiply, residual};
use crate::discretisation::matrix::SparseMatrix;

/// Rows of the coarsest level, solved directly.
const COARSEST: usize = 400;
/// At most this many levels.
const MAX_LEVELS: usize = 20;
/// Coarsening stops when a level keeps more than this fraction of the rows.
const MIN_REDUCTION: f64 = 0.8;
/// Jacobi smoothing steps before and after the coarse correction.
const SMOOTHING_STEPS: usize = 1;

/// One level of the hierarchy with its work vectors.
struct Level {
    matrix: SparseMatrix,
    inverse_diagonal: Vec<f64>,
    /// Damping ω of the Jacobi smoother.
    omega: f64,
    /// P to the next coarser level, and R = Pᵀ (absent on the coarsest level).
    prolongation: Option<(SparseMatrix, SparseMatrix)>,
    /// Right-hand side, solution and residual of this level in a cycle.
    rhs: Vec<f64>,
    solution: Vec<f64>,
    residual: Vec<f64>,
    partials: Vec<f64>,
}

/// The multigrid hierarchy of one matrix.
pub(crate) struct AggregationMultigrid {
    levels: Vec<Level>,
    /// Dense Cholesky factor of the coarsest matrix (`None` if it was not positive
    /// definite: the coarsest level is then only smoothed).
    coarsest: Option<Cholesky<f64, Dyn>>,
}

impl AggregationMultigrid {
    /// The hierarchy of `matrix` (symmetric, positive diagonal).
    pub fn new(matrix: &SparseMatrix) -> Self {
        let mut levels = vec![Level::new(matrix.clone())];
        while levels.len() < MAX_LEVELS {
            let Some(fine) = levels.last_mut() else { break };
            let n = fine.matrix.rows();
            if n <= COARSEST {
                break;
            }
            let (aggregate_of, count) = aggregation::aggregate(&fine.matrix);
            if count as f64 > MIN_REDUCTION * n as f64 || count == 0 {
                break;
            }
            let p = prolongation::aggregate_prolongation(&aggregate_of, count);
            let (r, coarse) = prolongation::galerkin(&fine.matrix, &p);
            fine.prolongation = Some((p, r));
            levels.push(Level::new(coarse));
        }
        let coarsest = levels.last().and_then(|level| {
            let n = level.matrix.rows();
            (n <= 4 * COARSEST)
                .then(|| dense(&level.matrix))
                .and_then(|m| m.cholesky())
        });
        Self { levels, coarsest }
    }

    /// Rows of each level, finest first.
    #[cfg(test)]
    pub fn level_sizes(&self) -> Vec<usize> {
        self.levels.iter().map(|l| l.matrix.rows()).collect()
    }

    /// z = M⁻¹ r: one V-cycle from zero.
    pub fn apply(&mut self, r: &[f64], z: &mut [f64]) {
        self.levels[0].rhs.copy_from_slice(r);
        cycle(&mut self.levels, self.coarsest.as_ref());
        z.copy_from_slice(&self.levels[0].solution);
    }
}

impl Level {
    fn new(matrix: SparseMatrix) -> Self {
        let n = matrix.rows();
        let indptr = matrix.indptr();
        let indptr = indptr.raw_storage();
        let mut inverse_diagonal = vec![0.0; n];
        // ρ(D⁻¹A) ≤ max_i Σ_j |a_ij| / a_ii (Gershgorin).
        let mut rho: f64 = 0.0;
        for row in 0..n {
            let mut diagonal = 0.0;
            let mut row_sum = 0.0;
            for k in indptr[row]..indptr[row + 1] {
                row_sum += matrix.data()[k].abs();
                if matrix.indices()[k] as usize == row {
                    diagonal = matrix.data()[k];
                }
            }
            inverse_diagonal[row] = if diagonal > 0.0 { 1.0 / diagonal } else { 0.0 };
            rho = rho.max(row_sum * inverse_diagonal[row]);
        }
        let omega = if rho > 0.0 { 4.0 / (3.0 * rho) } else { 0.0 };
        Self {
            matrix,
            inverse_diagonal,
            omega,
            prolongation: None,
            rhs: vec![0.0; n],
            solution: vec![0.0; n],
            residual: vec![0.0; n],
            partials: vec![0.0; super::kernels::chunk_count(n)],
        }
    }

    /// solution += ω D⁻¹ (rhs − A solution), `steps` times (the first from zero if
    /// `from_zero`).
    fn smooth(&mut self, steps: usize, from_zero: bool) {
        for step in 0..steps {
            if step == 0 && from_zero {
                self.residual.copy_from_slice(&self.rhs);
                self.solution.fill(0.0);
            } else {
                residual(
                    &self.matrix,
                    &self.rhs,
                    &self.solution,
                    &mut self.residual,
                    &mut self.partials,
                );
            }
            let omega = self.omega;
            self.solution
                .par_chunks_mut(CHUNK)
                .zip(
                    self.residual
                        .par_chunks(CHUNK)
                        .zip(self.inverse_diagonal.par_chunks(CHUNK)),
                )
                .for_each(|(x, (r, d))| {
                    for ((x, r), d) in x.iter_mut().zip(r).zip(d) {
                        *x += omega * d * r;
                    }
                });
        }
    }
}

/// One V-cycle on `levels[0]` (its rhs in, its solution out), recursively.
fn cycle(levels: &mut [Level], coarsest: Option<&Cholesky<f64, Dyn>>) {
    let Some((fine, coarser)) = levels.split_first_mut() else {
        return;
    };
    if coarser.is_empty() {
        match coarsest {
            Some(factor) => {
                let x = factor.solve(&DVector::from_column_slice(&fine.rhs));
                fine.solution.copy_from_slice(x.as_slice());
            }
            None => fine.smooth(4 * SMOOTHING_STEPS, true),
        }
        return;
    }
    fine.smooth(SMOOTHING_STEPS, true);
    residual(
        &fine.matrix,
        &fine.rhs,
        &fine.solution,
        &mut fine.residual,
        &mut fine.partials,
    );
    let Some((p, r)) = &fine.prolongation else {
        return;
    };
    let coarse = &mut coarser[0];
    multiply(r, &fine.residual, &mut coarse.rhs);
    cycle(coarser, coarsest);
    // solution += P x_coarse, through the residual vector as scratch.
    multiply(p, &coarser[0].solution, &mut fine.residual);
    fine.solution
        .par_iter_mut()
        .zip(fine.residual.par_iter())
        .with_min_len(CHUNK)
        .for_each(|(x, correction)| *x += correction);
    fine.smooth(SMOOTHING_STEPS, false);
}

fn dense(matrix: &SparseMatrix) -> DMatrix<f64> {
    let n = matrix.rows();
    let mut dense = DMatrix::zeros(n, n);
    for (&value, (row, column)) in matrix.iter() {
        dense[(row as usize, column as usize)] = value;
    }
    dense
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linear::cg::ConjugateGradient;
    use crate::settings::Preconditioner;

    /// The 7-point Laplacian on an m³ grid with Dirichlet rows on one face.
    fn laplacian(m: usize) -> SparseMatrix {
        let id = |i: usize, j: usize, k: usize| i + m * (j + m * k);
        let n = m * m * m;
        let mut indptr = vec![0usize];
        let (mut indices, mut data) = (Vec::new(), Vec::new());
        for k in 0..m {
            for j in 0..m {
                for i in 0..m {
                    let mut row = Vec::new();
                    let mut diagonal = if i == 0 { 2.0 } else { 0.0 };
                    for (di, dj, dk) in [
                        (-1i64, 0i64, 0i64),
                        (1, 0, 0),
                        (0, -1, 0),
                        (0, 1, 0),
                        (0, 0, -1),
                        (0, 0, 1),
                    ] {
                        let (a, b, c) = (i as i64 + di, j as i64 + dj, k as i64 + dk);
                        if (0..m as i64).contains(&a)
                            && (0..m as i64).contains(&b)
                            && (0..m as i64).contains(&c)
                        {
                            row.push((id(a as usize, b as usize, c as usize) as u32, -1.0));
                            diagonal += 1.0;
                        }
                    }
                    row.push((id(i, j, k) as u32, diagonal));
                    row.sort_by_key(|e| e.0);
                    for (c, v) in row {
                        indices.push(c);
                        data.push(v);
                    }
                    indptr.push(indices.len());
                }
            }
        }
        SparseMatrix::new((n, n), indptr, indices, data)
    }

    #[test]
    fn multigrid_cuts_cg_iterations() {
        let mut iterations = Vec::new();
        for m in [12, 24] {
            let matrix = laplacian(m);
            let n = matrix.rows();
            let amg = AggregationMultigrid::new(&matrix);
            let sizes = amg.level_sizes();
            assert!(
                sizes.len() >= 2 && *sizes.last().unwrap() <= 4 * COARSEST,
                "{sizes:?}"
            );
            let b = vec![1.0; n];
            let mut counts = Vec::new();
            for preconditioner in [Preconditioner::Jacobi, Preconditioner::AggregationMultigrid] {
                let mut cg = ConjugateGradient::new(&matrix, preconditioner);
                let mut x = vec![0.0; n];
                let target = 1e-8 * (n as f64).sqrt();
                let outcome = cg.solve(&matrix, &b, &mut x, target, 10_000);
                assert!(outcome.converged);
                counts.push(outcome.iterations);
            }
            println!(
                "m = {m}: levels {sizes:?}, CG iterations Jacobi {} multigrid {}",
                counts[0], counts[1]
            );
            iterations.push(counts);
        }
        // Jacobi: iterations ~ m; multigrid: fewer than half, and growing more slowly.
        assert!(iterations[1][1] * 2 < iterations[1][0], "{iterations:?}");
        let growth = |k: usize| iterations[1][k] as f64 / iterations[0][k] as f64;
        assert!(growth(1) < growth(0), "{iterations:?}");
    }
}
