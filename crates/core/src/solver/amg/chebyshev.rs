//! The smoother: Chebyshev polynomials in D⁻¹A (D the diagonal of A), which damp the
//! error components with eigenvalues of D⁻¹A in [λ_max / [`RATIO`], λ_max]; those below
//! are the coarse grid's to correct. A polynomial in A, so the V-cycle with the same
//! smoother before and after the coarse correction is symmetric, as conjugate gradients
//! need; only products with A (parallel by rows, deterministic). λ_max comes from
//! [`POWER_ITERATIONS`] power iterations from a fixed start, times [`SAFETY`].

use super::csr::{Csr, dot};

/// Ratio of the upper to the lower end of the smoothed interval.
pub(crate) const RATIO: f64 = 30.0;
/// Power iterations for λ_max(D⁻¹A).
const POWER_ITERATIONS: usize = 20;
/// Factor on the power iteration's estimate (which lies below λ_max). With 12 iterations
/// and 1.1 the cycle was not positive definite on the first tangents of the 40³ cube
/// (200 039 unknowns: CG met rᵀ M⁻¹ r ≤ 0 at its 4th–5th iteration).
const SAFETY: f64 = 1.2;

/// An upper estimate of the largest eigenvalue of D⁻¹A (A symmetric positive definite:
/// the power iteration on D^{-1/2} A D^{-1/2}, whose spectrum is D⁻¹A's).
pub(crate) fn largest_eigenvalue(a: &Csr, inverse_diagonal: &[f64]) -> f64 {
    let n = a.rows;
    if n == 0 {
        return 1.0;
    }
    let scale: Vec<f64> = inverse_diagonal.iter().map(|d| d.max(0.0).sqrt()).collect();
    // v (unit), w = D^{-1/2} A D^{-1/2} v, λ = vᵀ w.
    let mut v: Vec<f64> = (0..n)
        .map(|i| 1.0 + 0.5 * (i as f64 * 0.618).sin())
        .collect();
    let mut w = vec![0.0; n];
    let mut y = vec![0.0; n];
    let mut scaled = vec![0.0; n];
    let mut lambda: f64 = 0.0;
    for _ in 0..POWER_ITERATIONS {
        let norm = dot(&v, &v).sqrt();
        if norm == 0.0 || !norm.is_finite() {
            break;
        }
        v.iter_mut().for_each(|vi| *vi /= norm);
        for ((s, vi), d) in scaled.iter_mut().zip(&v).zip(&scale) {
            *s = vi * d;
        }
        a.multiply(&scaled, &mut y);
        for ((wi, yi), d) in w.iter_mut().zip(&y).zip(&scale) {
            *wi = yi * d;
        }
        lambda = dot(&v, &w);
        std::mem::swap(&mut v, &mut w);
    }
    SAFETY * lambda.max(f64::MIN_POSITIVE)
}

/// Work vectors of one level's smoother.
pub(crate) struct Smoother<'a> {
    pub a: &'a Csr,
    pub inverse_diagonal: &'a [f64],
    pub lambda_max: f64,
    pub degree: usize,
}

impl Smoother<'_> {
    /// x ← x + p(D⁻¹A) D⁻¹ (b − A x), the Chebyshev iteration of `degree` steps
    /// (x = 0 on entry when `from_zero`); `r` and `d` are scratch.
    pub fn smooth(&self, b: &[f64], x: &mut [f64], r: &mut [f64], d: &mut [f64], from_zero: bool) {
        let upper = self.lambda_max;
        let lower = upper / RATIO;
        let theta = 0.5 * (upper + lower);
        let delta = 0.5 * (upper - lower);
        let sigma = theta / delta;
        let mut rho = 1.0 / sigma;
        if from_zero {
            r.copy_from_slice(b);
            x.fill(0.0);
        } else {
            self.a.residual(b, x, r);
        }
        for ((di, ri), inv) in d.iter_mut().zip(r.iter()).zip(self.inverse_diagonal) {
            *di = ri * inv / theta;
        }
        for (xi, di) in x.iter_mut().zip(d.iter()) {
            *xi += di;
        }
        for _ in 1..self.degree {
            let rho_next = 1.0 / (2.0 * sigma - rho);
            self.a.residual(b, x, r);
            let (c1, c2) = (rho_next * rho, 2.0 * rho_next / delta);
            for ((di, ri), inv) in d.iter_mut().zip(r.iter()).zip(self.inverse_diagonal) {
                *di = c1 * *di + c2 * ri * inv;
            }
            for (xi, di) in x.iter_mut().zip(d.iter()) {
                *xi += di;
            }
            rho = rho_next;
        }
    }
}
