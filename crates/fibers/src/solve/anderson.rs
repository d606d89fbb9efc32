//! Anderson acceleration of the deferred-correction sweeps.
//!
//! A sweep is a map φ ↦ G(φ) = A⁻¹ (b + c(φ)) whose fixed point is the corrected
//! solution; plain sweeps converge at the rate of the mesh's non-orthogonality (about 0.4
//! per sweep on Kuhn tetrahedra). Anderson mixing of depth m keeps the last m differences
//! of the residuals fₖ = G(φₖ) − φₖ and of the images G(φₖ) and takes
//!
//! φₖ₊₁ = G(φₖ) − Σᵢ γᵢ ΔGᵢ,   γ = argmin ‖fₖ − Σᵢ γᵢ ΔFᵢ‖₂,
//!
//! which for a linear map is GMRES on the fixed-point residual (Walker & Ni, SIAM J.
//! Numer. Anal. 49, 2011).

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use crate::linear::kernels::{CHUNK, chunk_count, dot};

/// Relative Tikhonov term added to the Gram matrix of the least-squares problem.
const REGULARISATION: f64 = 1e-12;

/// History and work space of Anderson mixing for vectors of one length.
pub(crate) struct AndersonMixing {
    /// ΔFᵢ = fᵢ₊₁ − fᵢ, in a ring of `depth` slots.
    delta_residual: Vec<Vec<f64>>,
    /// ΔGᵢ = G(φᵢ₊₁) − G(φᵢ), in the same slots.
    delta_image: Vec<Vec<f64>>,
    /// Number of filled slots.
    columns: usize,
    /// The slot the next difference goes into.
    next: usize,
    /// f and G(φ) of the previous iterate, if there is one.
    previous_residual: Vec<f64>,
    previous_image: Vec<f64>,
    has_previous: bool,
    /// f of the current iterate.
    residual: Vec<f64>,
    partials: Vec<f64>,
}

impl AndersonMixing {
    /// Mixing of depth `depth` (at least 1) for vectors of length `n`.
    pub fn new(n: usize, depth: usize) -> Self {
        let depth = depth.max(1);
        Self {
            delta_residual: vec![vec![0.0; n]; depth],
            delta_image: vec![vec![0.0; n]; depth],
            columns: 0,
            next: 0,
            previous_residual: vec![0.0; n],
            previous_image: vec![0.0; n],
            has_previous: false,
            residual: vec![0.0; n],
            partials: vec![0.0; chunk_count(n)],
        }
    }

    /// Forgets the history: the next step is a plain sweep.
    pub fn reset(&mut self) {
        self.columns = 0;
        self.next = 0;
        self.has_previous = false;
    }

    /// Replaces the iterate φₖ in `potential` by φₖ₊₁, given its image G(φₖ) in `image`.
    pub fn step(&mut self, potential: &mut [f64], image: &[f64]) {
        let depth = self.delta_residual.len();
        self.residual
            .par_iter_mut()
            .zip(image.par_iter().zip(potential.par_iter()))
            .with_min_len(CHUNK)
            .for_each(|(f, (g, phi))| *f = g - phi);
        if self.has_previous {
            let slot = self.next;
            difference(
                &mut self.delta_residual[slot],
                &self.residual,
                &self.previous_residual,
            );
            difference(&mut self.delta_image[slot], image, &self.previous_image);
            self.next = (slot + 1) % depth;
            self.columns = (self.columns + 1).min(depth);
        }
        self.previous_residual.copy_from_slice(&self.residual);
        self.previous_image.copy_from_slice(image);
        self.has_previous = true;

        potential.copy_from_slice(image);
        let Some(gamma) = self.coefficients() else {
            return;
        };
        for (column, &g) in self.delta_image[..self.columns].iter().zip(gamma.iter()) {
            potential
                .par_iter_mut()
                .zip(column.par_iter())
                .with_min_len(CHUNK)
                .for_each(|(phi, dg)| *phi -= g * dg);
        }
    }

    /// γ of the least-squares problem by its normal equations, `None` without history or
    /// if they are singular (the history is then dropped).
    fn coefficients(&mut self) -> Option<DVector<f64>> {
        let m = self.columns;
        if m == 0 {
            return None;
        }
        let mut gram = DMatrix::zeros(m, m);
        let mut rhs = DVector::zeros(m);
        for i in 0..m {
            for j in 0..=i {
                let value = dot(
                    &self.delta_residual[i],
                    &self.delta_residual[j],
                    &mut self.partials,
                );
                gram[(i, j)] = value;
                gram[(j, i)] = value;
            }
            rhs[i] = dot(&self.delta_residual[i], &self.residual, &mut self.partials);
        }
        let shift = REGULARISATION * gram.trace();
        for i in 0..m {
            gram[(i, i)] += shift;
        }
        match gram.cholesky() {
            Some(cholesky) => Some(cholesky.solve(&rhs)),
            None => {
                self.reset();
                None
            }
        }
    }
}

/// out = a − b.
fn difference(out: &mut [f64], a: &[f64], b: &[f64]) {
    out.par_iter_mut()
        .zip(a.par_iter().zip(b.par_iter()))
        .with_min_len(CHUNK)
        .for_each(|(o, (a, b))| *o = a - b);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accelerates_a_slow_linear_fixed_point() {
        // G(x) = M x + c with M diagonal of three distinct eigenvalues up to 0.95: plain
        // iteration needs ~450 steps for 1e-10; for a linear map Anderson of depth 5 is
        // GMRES, exact after (distinct eigenvalues + 1) steps up to round-off.
        let n = 30;
        let rate = |i: usize| [0.95, 0.5, -0.3][i % 3];
        let c: Vec<f64> = (0..n).map(|i| 1.0 + i as f64 / n as f64).collect();
        let exact: Vec<f64> = (0..n).map(|i| c[i] / (1.0 - rate(i))).collect();
        let map = |x: &[f64], out: &mut [f64]| {
            for i in 0..n {
                out[i] = rate(i) * x[i] + c[i];
            }
        };
        let mut mixing = AndersonMixing::new(n, 5);
        let mut x = vec![0.0; n];
        let mut image = vec![0.0; n];
        for _ in 0..6 {
            map(&x, &mut image);
            mixing.step(&mut x, &image);
        }
        let error = x
            .iter()
            .zip(&exact)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(error < 1e-8, "error {error}");
        // Without history it is the plain iteration.
        mixing.reset();
        let before = x.clone();
        map(&before, &mut image);
        mixing.step(&mut x, &image);
        assert_eq!(x, image);
    }
}
