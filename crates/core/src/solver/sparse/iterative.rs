//! The iterative path of [`SparseSystem`]: AMG-preconditioned conjugate gradients
//! (`amg_cg.rs`) tried before any factorization when the implicit solver asks for it.

use std::time::Instant;

use faer::sparse::{SparseColMat, SymbolicSparseColMat};

use super::SparseSystem;
use crate::solver::amg_cg::{AmgCg, AmgCgFailure, AmgCgSettings};

/// Failure reasons kept in the statistics (the count goes on).
const KEPT_REASONS: usize = 8;

/// A 0 × 0 matrix, standing in for the system's while its values are lent.
fn empty_matrix() -> SparseColMat<usize, f64> {
    let symbolic = SymbolicSparseColMat::new_checked(0, 0, vec![0], None, Vec::new());
    SparseColMat::new(symbolic, Vec::new())
}

impl SparseSystem {
    /// The next iterative solves (AMG-CG, or CG with an earlier Cholesky factor) may stop
    /// at the relative residual `forcing` when it is looser than their own tolerance
    /// (Newton's forcing term; 0 for their own). Direct solves are exact either way.
    pub fn set_forcing(&mut self, forcing: f64) {
        self.forcing = forcing;
    }

    /// Try AMG-CG on the next symmetric systems with `settings`, or not (`None`).
    pub fn set_iterative(&mut self, settings: Option<AmgCgSettings>) {
        self.iterative = settings.filter(|_| !self.amg_given_up);
    }

    /// With [`Self::set_iterative`] on: K x = `rhs` in place by AMG-CG, true when it
    /// converged; false (rhs unchanged, the reason in the statistics) when it did not,
    /// or when AMG-CG is off. After a solve that ran out of iterations AMG-CG is turned
    /// off for this system (the direct solver takes the rest of the run's solves).
    pub(super) fn try_amg_cg(&mut self, rhs: &mut [f64]) -> bool {
        let Some(mut settings) = self.iterative.clone() else {
            return false;
        };
        settings.tolerance = settings.tolerance.max(self.forcing);
        let start = Instant::now();
        let (coordinates, dofs, nodes) = &self.geometry;
        let amg = self
            .amg
            .get_or_insert_with(|| AmgCg::new(coordinates, dofs, nodes));
        // The matrix's values are lent to the multigrid for the solve, not copied.
        let (symbolic, mut values) =
            std::mem::replace(&mut self.matrix, empty_matrix()).into_parts();
        let outcome = amg.solve(
            symbolic.col_ptr(),
            symbolic.row_idx(),
            &mut values,
            rhs,
            &settings,
        );
        self.matrix = SparseColMat::new(symbolic, values);
        let elapsed = start.elapsed().as_secs_f64();
        if let Some((levels, complexity)) = amg.describe() {
            self.statistics.amg.levels = levels;
            self.statistics.amg.operator_complexity = complexity;
        }
        match outcome {
            Ok(outcome) => {
                self.statistics.amg.solves += 1;
                self.statistics.amg.iterations += outcome.iterations;
                self.statistics.amg.setup_seconds += outcome.setup_seconds;
                self.statistics.amg.solve_seconds += elapsed - outcome.setup_seconds;
                true
            }
            Err(failure) => {
                self.statistics.amg.failures += 1;
                self.statistics.amg.solve_seconds += elapsed;
                let give_up = matches!(failure, AmgCgFailure::TooManyIterations { .. });
                if self.statistics.amg.failure_reasons.len() < KEPT_REASONS {
                    let then = if give_up {
                        "; the direct solver from here on"
                    } else {
                        "; the direct solver for this system"
                    };
                    self.statistics
                        .amg
                        .failure_reasons
                        .push(format!("solve {}: {failure}{then}", self.statistics.solves));
                }
                if give_up {
                    self.iterative = None;
                    self.amg = None;
                    self.amg_given_up = true;
                }
                false
            }
        }
    }
}
