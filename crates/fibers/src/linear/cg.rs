//! Preconditioned conjugate gradients, with a Jacobi (diagonal) or an aggregation
//! multigrid preconditioner.

use rayon::prelude::*;

use super::amg::AggregationMultigrid;
use super::kernels::{CHUNK, chunk_count, dot, multiply_and_dot, residual};
use crate::discretisation::matrix::SparseMatrix;
use crate::settings::Preconditioner;

/// How one CG solve ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CgOutcome {
    /// Iterations done (matrix–vector products after the initial residual).
    pub iterations: usize,
    /// ‖b − A x‖₂ of the recurrence at the end (same units as b).
    pub residual_norm: f64,
    /// True if the residual reached the target.
    pub converged: bool,
}

/// The preconditioner M⁻¹ ≈ A⁻¹, built once per matrix.
enum Operator {
    /// z = D⁻¹ r, with the inverse diagonal.
    Jacobi(Vec<f64>),
    /// z = one multigrid V-cycle applied to r.
    Multigrid(Box<AggregationMultigrid>),
}

/// Preconditioned CG for one symmetric positive definite matrix, with its work vectors
/// allocated once: the iterations allocate nothing.
pub(crate) struct ConjugateGradient {
    preconditioner: Operator,
    /// r = b − A x.
    residual: Vec<f64>,
    /// z = M⁻¹ r.
    preconditioned: Vec<f64>,
    /// p, the search direction.
    direction: Vec<f64>,
    /// q = A p.
    product: Vec<f64>,
    /// Per-chunk sums of the reductions.
    partials: Vec<f64>,
}

impl ConjugateGradient {
    /// The preconditioner of `matrix` (positive diagonal) and the work space.
    pub fn new(matrix: &SparseMatrix, preconditioner: Preconditioner) -> Self {
        let n = matrix.rows();
        let preconditioner = match preconditioner {
            Preconditioner::Jacobi => Operator::Jacobi(inverse_diagonal(matrix)),
            Preconditioner::AggregationMultigrid => {
                Operator::Multigrid(Box::new(AggregationMultigrid::new(matrix)))
            }
        };
        Self {
            preconditioner,
            residual: vec![0.0; n],
            preconditioned: vec![0.0; n],
            direction: vec![0.0; n],
            product: vec![0.0; n],
            partials: vec![0.0; chunk_count(n)],
        }
    }

    /// ‖b − A x‖₂.
    pub fn residual_norm(&mut self, matrix: &SparseMatrix, b: &[f64], x: &[f64]) -> f64 {
        residual(matrix, b, x, &mut self.residual, &mut self.partials).sqrt()
    }

    /// Improves `x` towards the solution of A x = b until ‖b − A x‖₂ ≤ `target` or
    /// `max_iterations` iterations, starting from the given `x`:
    ///
    /// z = M⁻¹ r, p = z; then α = r·z / p·Ap, x += α p, r −= α Ap, z = M⁻¹ r,
    /// β = r·z (new) / r·z (old), p = z + β p.
    pub fn solve(
        &mut self,
        matrix: &SparseMatrix,
        b: &[f64],
        x: &mut [f64],
        target: f64,
        max_iterations: usize,
    ) -> CgOutcome {
        let mut rr = residual(matrix, b, x, &mut self.residual, &mut self.partials);
        let mut rz = self.precondition();
        self.direction.copy_from_slice(&self.preconditioned);
        let mut iterations = 0;
        while rr.sqrt() > target && iterations < max_iterations {
            let p_ap = multiply_and_dot(
                matrix,
                &self.direction,
                &mut self.product,
                &mut self.partials,
            );
            if p_ap <= 0.0 || p_ap.is_nan() {
                // Not positive definite along p (or round-off at the solution): stop.
                break;
            }
            let alpha = rz / p_ap;
            rr = self.update(x, alpha);
            let rz_new = self.precondition();
            let beta = rz_new / rz;
            rz = rz_new;
            self.next_direction(beta);
            iterations += 1;
        }
        CgOutcome {
            iterations,
            residual_norm: rr.sqrt(),
            converged: rr.sqrt() <= target,
        }
    }

    /// z = M⁻¹ r; returns r·z.
    fn precondition(&mut self) -> f64 {
        match &mut self.preconditioner {
            Operator::Jacobi(inverse_diagonal) => {
                self.preconditioned
                    .par_chunks_mut(CHUNK)
                    .zip(
                        self.residual
                            .par_chunks(CHUNK)
                            .zip(inverse_diagonal.par_chunks(CHUNK)),
                    )
                    .for_each(|(z, (r, d))| {
                        for ((z, r), d) in z.iter_mut().zip(r).zip(d) {
                            *z = d * r;
                        }
                    });
            }
            Operator::Multigrid(amg) => amg.apply(&self.residual, &mut self.preconditioned),
        }
        dot(&self.residual, &self.preconditioned, &mut self.partials)
    }

    /// x += α p, r −= α q; returns r·r of the new residual.
    fn update(&mut self, x: &mut [f64], alpha: f64) -> f64 {
        let direction = &self.direction;
        let product = &self.product;
        self.partials
            .par_iter_mut()
            .zip(
                x.par_chunks_mut(CHUNK)
                    .zip(self.residual.par_chunks_mut(CHUNK)),
            )
            .enumerate()
            .for_each(|(chunk, (partial, (x, r)))| {
                let first = chunk * CHUNK;
                let mut rr = 0.0;
                for (i, (x, r)) in x.iter_mut().zip(r.iter_mut()).enumerate() {
                    let row = first + i;
                    *x += alpha * direction[row];
                    *r -= alpha * product[row];
                    rr += *r * *r;
                }
                *partial = rr;
            });
        self.partials.iter().sum()
    }

    /// p = z + β p.
    fn next_direction(&mut self, beta: f64) {
        self.direction
            .par_chunks_mut(CHUNK)
            .zip(self.preconditioned.par_chunks(CHUNK))
            .for_each(|(p, z)| {
                for (p, z) in p.iter_mut().zip(z) {
                    *p = z + beta * *p;
                }
            });
    }
}

/// 1/A_ii of every row (0 for a row without positive diagonal).
fn inverse_diagonal(matrix: &SparseMatrix) -> Vec<f64> {
    let indptr = matrix.indptr();
    let indptr = indptr.raw_storage();
    let mut inverse = vec![0.0; matrix.rows()];
    for (row, inverse) in inverse.iter_mut().enumerate() {
        for k in indptr[row]..indptr[row + 1] {
            if matrix.indices()[k] as usize == row && matrix.data()[k] > 0.0 {
                *inverse = 1.0 / matrix.data()[k];
            }
        }
    }
    inverse
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_one_dimensional_laplacian() {
        // −u'' = 0 on n cells with u = 1 left and 0 right (as fixed-potential faces of
        // coefficient 2): the exact cell values are linear.
        let n = 3 * CHUNK + 5;
        let mut indptr = vec![0usize];
        let (mut indices, mut data) = (Vec::new(), Vec::new());
        let mut b = vec![0.0; n];
        for i in 0..n {
            let mut diagonal = 0.0;
            if i > 0 {
                indices.push((i - 1) as u32);
                data.push(-1.0);
                diagonal += 1.0;
            } else {
                diagonal += 2.0;
                b[i] = 2.0;
            }
            indices.push(i as u32);
            let diagonal_at = data.len();
            data.push(0.0);
            if i + 1 < n {
                indices.push((i + 1) as u32);
                data.push(-1.0);
                diagonal += 1.0;
            } else {
                diagonal += 2.0;
            }
            data[diagonal_at] = diagonal;
            indptr.push(indices.len());
        }
        let matrix = SparseMatrix::new((n, n), indptr, indices, data);
        for preconditioner in [Preconditioner::Jacobi, Preconditioner::AggregationMultigrid] {
            let mut cg = ConjugateGradient::new(&matrix, preconditioner);
            let mut x = vec![0.0; n];
            let outcome = cg.solve(&matrix, &b, &mut x, 1e-12 * 2.0, 100 * n);
            assert!(outcome.converged, "{preconditioner:?}: {outcome:?}");
            let true_residual = cg.residual_norm(&matrix, &b, &x);
            assert!(true_residual < 1e-11, "{preconditioner:?}: {true_residual}");
            for (i, u) in x.iter().enumerate() {
                let exact = 1.0 - (i as f64 + 0.5) / n as f64;
                assert!(
                    (u - exact).abs() < 1e-4,
                    "{preconditioner:?} {i}: {u} vs {exact}"
                );
            }
            // A second solve from the solution does nothing.
            let again = cg.solve(&matrix, &b, &mut x, 1e-6, 10);
            assert_eq!(again.iterations, 0);
        }
    }
}
