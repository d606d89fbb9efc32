//! The deferred-correction solve of A φ = b + c(φ): A and b the orthogonal part and the
//! fixed potentials ([`crate::discretisation::matrix`]), c(φ) the explicit non-orthogonal
//! correction of the gradient of φ ([`crate::discretisation::correction`]).
//!
//! A sweep from the iterate φₖ updates the gradients and the correction c(φₖ), and solves
//! A G(φₖ) = b + c(φₖ) by CG started from φₖ (c(0) = 0: the first sweep is the
//! orthogonal problem). The next iterate mixes the recent sweeps ([`anderson`]). The
//! solve stops when the residual of the corrected system, ‖b + c(φ) − Aφ‖₂ / ‖b‖₂, is at
//! most the tolerance. Inner solves are inexact: each reduces the residual it starts from
//! by [`INNER_REDUCTION`] (or to half the tolerance), since the correction changes the
//! right-hand side anyway.

mod anderson;

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::boundary::BoundaryKind;
use crate::discretisation::coefficients::Coefficients;
use crate::discretisation::correction::non_orthogonal_correction;
use crate::discretisation::gradient::LeastSquaresGradient;
use crate::discretisation::matrix::{fixed_potential_rhs, orthogonal_matrix};
use crate::error::FiberError;
use crate::fv_mesh::FvMesh;
use crate::linear::cg::ConjugateGradient;
use crate::linear::kernels::{chunk_count, dot};
use crate::settings::FlowSettings;
use anderson::AndersonMixing;

/// Each sweep's CG stops when its residual is this fraction of the residual the sweep
/// started from (dimensionless).
pub(crate) const INNER_REDUCTION: f64 = 0.03;

/// Sweeps remembered by the Anderson mixing.
const ANDERSON_DEPTH: usize = 5;

/// A residual this many times the previous one restarts the mixing from a plain sweep.
const RESTART_GROWTH: f64 = 2.0;

/// A converged potential with its gradients.
pub(crate) struct FlowSolution {
    /// φ of every cell (dimensionless).
    pub potential: Vec<f64>,
    /// ∇φ of every cell, of the final φ [1/m].
    pub gradient: Vec<Vector3<f64>>,
    /// CG solves done (the first one without correction).
    pub linear_solves: usize,
    /// CG iterations over all solves.
    pub linear_iterations: usize,
    /// ‖b + c(φ) − Aφ‖₂ / ‖b‖₂ of the final φ.
    pub residual: f64,
}

/// Solves for the potential. Errors if a CG solve does not reach its target in
/// `settings.max_linear_iterations`, or the corrected residual is above the tolerance
/// after `settings.max_correction_sweeps` solves.
pub(crate) fn solve_potential(
    fv: &FvMesh,
    coefficients: &Coefficients,
    kinds: &[BoundaryKind],
    least_squares: &LeastSquaresGradient,
    settings: &FlowSettings,
) -> Result<FlowSolution, FiberError> {
    let n = fv.cell_count();
    let matrix = orthogonal_matrix(fv, coefficients, kinds);
    let fixed = fixed_potential_rhs(fv, coefficients, kinds);
    let mut cg = ConjugateGradient::new(&matrix, settings.preconditioner);
    let mut partials = vec![0.0; chunk_count(n)];
    // ‖b‖ > 0: every part of the mesh has an inlet face, where φ = 1.
    let fixed_norm = dot(&fixed, &fixed, &mut partials).sqrt();

    let mut potential = vec![0.0; n];
    let mut image = vec![0.0; n];
    let mut gradient = vec![Vector3::zeros(); n];
    let mut correction = vec![0.0; n];
    let mut rhs = vec![0.0; n];
    let mut mixing = AndersonMixing::new(n, ANDERSON_DEPTH);
    let mut linear_iterations = 0;
    let mut previous_residual = f64::INFINITY;
    let mut sweep = 0;
    loop {
        least_squares.compute(fv, kinds, &potential, &mut gradient);
        non_orthogonal_correction(fv, coefficients, kinds, &gradient, &mut correction);
        rhs.par_iter_mut()
            .zip(fixed.par_iter().zip(&correction))
            .for_each(|(rhs, (b, c))| *rhs = b + c);
        let residual = cg.residual_norm(&matrix, &rhs, &potential) / fixed_norm;
        if residual <= settings.tolerance {
            return Ok(FlowSolution {
                potential,
                gradient,
                linear_solves: sweep,
                linear_iterations,
                residual,
            });
        }
        if sweep == settings.max_correction_sweeps || !residual.is_finite() {
            return Err(FiberError::NotConverged {
                sweeps: sweep,
                linear_iterations,
                residual,
                tolerance: settings.tolerance,
            });
        }
        if residual > RESTART_GROWTH * previous_residual {
            mixing.reset();
        }
        previous_residual = residual;

        let target = (INNER_REDUCTION * residual).max(0.5 * settings.tolerance) * fixed_norm;
        image.copy_from_slice(&potential);
        let outcome = cg.solve(
            &matrix,
            &rhs,
            &mut image,
            target,
            settings.max_linear_iterations,
        );
        linear_iterations += outcome.iterations;
        sweep += 1;
        if !outcome.converged {
            return Err(FiberError::NotConverged {
                sweeps: sweep,
                linear_iterations,
                residual: outcome.residual_norm / fixed_norm,
                tolerance: settings.tolerance,
            });
        }
        mixing.step(&mut potential, &image);
    }
}
