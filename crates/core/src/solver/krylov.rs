//! Conjugate gradients preconditioned with the Cholesky factor of an earlier stiffness.
//! Between Newton iterations and neighbouring increments a smooth tangent changes little,
//! so an old factor M ≈ K makes M⁻¹K close to the identity and a handful of iterations
//! (each one product with K and one pair of triangular solves) replaces a numeric
//! factorization.
//!
//! The same with GMRES and an old LU factor (for the knee's unsymmetric, indefinite
//! tangents) was tried and dropped: on the coarse passive squat 70 % of the attempts did
//! not converge within 10 iterations (contact and cohesive bonds change the tangent too
//! much between iterations), and the run was no faster than one LU per iteration.
//!
//! GMRES is used instead with the Cholesky factor of the *current* tangent's symmetric
//! part ½(K + Kᵀ) as the preconditioner ([`preconditioned_gmres`]): the knee's tangents
//! are unsymmetric only through the contact along smooth normals, so M⁻¹K is the identity
//! plus a small, local perturbation (see `sparse.rs` for the measurements).

/// ‖v‖₂.
pub(crate) fn norm(v: &[f64]) -> f64 {
    dot(v, v).sqrt()
}

/// aᵀb.
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Conjugate gradients on K x = `rhs`, K symmetric positive definite, preconditioned with
/// `precondition` (v ← M⁻¹ v): stops when ‖b − K x‖ ≤ `tolerance` ‖b‖ and writes x into
/// `rhs`, returning the iterations; returns `None` (leaving `rhs` unchanged) after
/// `max_iterations` or when pᵀ K p ≤ 0 (K not positive definite).
pub(crate) fn preconditioned_cg(
    rhs: &mut [f64],
    tolerance: f64,
    max_iterations: usize,
    multiply: impl FnMut(&[f64], &mut [f64]),
    mut precondition: impl FnMut(&mut [f64]),
) -> Option<usize> {
    if tolerance * norm(rhs) == 0.0 {
        return Some(0);
    }
    conjugate_gradients(
        rhs,
        tolerance,
        max_iterations,
        dot,
        multiply,
        |residual, z| {
            z.copy_from_slice(residual);
            precondition(z);
        },
    )
    .ok()
}

/// Why [`conjugate_gradients`] stopped without a solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum CgFailure {
    /// pᵀ K p ≤ 0 (or not a number) at this iteration: K is not positive definite.
    NotPositiveDefinite { iteration: usize },
    /// rᵀ M⁻¹ r ≤ 0 (or not a number) at this iteration: the preconditioner is not.
    PreconditionerIndefinite { iteration: usize },
    /// `max_iterations` reached, or the residual stopped being finite; the relative
    /// residual ‖b − K x‖ / ‖b‖ at the end.
    TooManyIterations { relative_residual: f64 },
}

/// Preconditioned conjugate gradients, the one loop behind [`preconditioned_cg`] and the
/// multigrid solver: K x = `rhs` with K = `multiply`, z = M⁻¹ r by `precondition(r, z)`,
/// inner products by `dot` (so a caller chooses its summation order, e.g. fixed chunks
/// for results independent of the thread count). Stops when ‖r‖ ≤ `tolerance` ‖b‖ and
/// writes x into `rhs`, returning the iterations; on failure `rhs` is unchanged.
/// Allocates its four work vectors once per call.
pub(crate) fn conjugate_gradients(
    rhs: &mut [f64],
    tolerance: f64,
    max_iterations: usize,
    dot: impl Fn(&[f64], &[f64]) -> f64,
    mut multiply: impl FnMut(&[f64], &mut [f64]),
    mut precondition: impl FnMut(&[f64], &mut [f64]),
) -> Result<usize, CgFailure> {
    let n = rhs.len();
    let b_norm = dot(rhs, rhs).sqrt();
    if b_norm == 0.0 {
        return Ok(0);
    }
    let target = tolerance * b_norm;
    let mut x = vec![0.0; n];
    let mut r = rhs.to_vec();
    let mut z = vec![0.0; n];
    let mut q = vec![0.0; n];
    precondition(&r, &mut z);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut residual = b_norm;
    for iteration in 1..=max_iterations {
        multiply(&p, &mut q);
        let curvature = dot(&p, &q);
        if curvature.is_nan() || curvature <= 0.0 {
            return Err(CgFailure::NotPositiveDefinite { iteration });
        }
        if rz.is_nan() || rz <= 0.0 {
            return Err(CgFailure::PreconditionerIndefinite { iteration });
        }
        let alpha = rz / curvature;
        for ((xi, ri), (pi, qi)) in x.iter_mut().zip(r.iter_mut()).zip(p.iter().zip(&q)) {
            *xi += alpha * pi;
            *ri -= alpha * qi;
        }
        residual = dot(&r, &r).sqrt();
        if residual <= target {
            rhs.copy_from_slice(&x);
            return Ok(iteration);
        }
        if !residual.is_finite() {
            break;
        }
        precondition(&r, &mut z);
        let rz_next = dot(&r, &z);
        let beta = rz_next / rz;
        rz = rz_next;
        for (pi, zi) in p.iter_mut().zip(&z) {
            *pi = zi + beta * *pi;
        }
    }
    Err(CgFailure::TooManyIterations {
        relative_residual: residual / b_norm,
    })
}

/// GMRES on K x = `rhs` for a general (unsymmetric) K, right-preconditioned with
/// `precondition` (v ← M⁻¹ v, M ≈ K): minimizes ‖b − K x‖ over x = M⁻¹ V y with V the
/// Arnoldi basis of K M⁻¹ (modified Gram–Schmidt, Givens rotations), without restarts.
/// Stops when the residual ‖b − K x‖ ≤ `tolerance` ‖b‖ (checked with a last product)
/// and writes x into `rhs`, returning the iterations; returns `None` (leaving `rhs`
/// unchanged) after `max_iterations` or on a breakdown that does not solve the system.
/// Memory: 2 `max_iterations` vectors of the system's size.
pub(crate) fn preconditioned_gmres(
    rhs: &mut [f64],
    tolerance: f64,
    max_iterations: usize,
    mut multiply: impl FnMut(&[f64], &mut [f64]),
    mut precondition: impl FnMut(&mut [f64]),
) -> Option<usize> {
    let n = rhs.len();
    let beta = norm(rhs);
    if beta == 0.0 {
        return Some(0);
    }
    let target = tolerance * beta;
    let m = max_iterations;
    // Arnoldi basis V, preconditioned directions Z = M⁻¹ V, Hessenberg H (column j has
    // j + 2 entries), Givens rotations (c, s) and the rotated right-hand side g.
    let mut basis: Vec<Vec<f64>> = vec![rhs.iter().map(|b| b / beta).collect()];
    let mut directions: Vec<Vec<f64>> = Vec::with_capacity(m);
    let mut hessenberg: Vec<Vec<f64>> = Vec::with_capacity(m);
    let mut rotations: Vec<(f64, f64)> = Vec::with_capacity(m);
    let mut g = vec![beta];
    for j in 0..m {
        let mut z = basis[j].clone();
        precondition(&mut z);
        let mut w = vec![0.0; n];
        multiply(&z, &mut w);
        directions.push(z);
        let mut column = Vec::with_capacity(j + 2);
        for v in &basis {
            let h = dot(&w, v);
            for (wi, vi) in w.iter_mut().zip(v) {
                *wi -= h * vi;
            }
            column.push(h);
        }
        let subdiagonal = norm(&w);
        column.push(subdiagonal);
        for (i, &(c, s)) in rotations.iter().enumerate() {
            let (a, b) = (column[i], column[i + 1]);
            column[i] = c * a + s * b;
            column[i + 1] = -s * a + c * b;
        }
        let (a, b) = (column[j], column[j + 1]);
        let r = a.hypot(b);
        if !r.is_finite() || r == 0.0 {
            return None;
        }
        let (c, s) = (a / r, b / r);
        column[j] = r;
        column[j + 1] = 0.0;
        rotations.push((c, s));
        g.push(-s * g[j]);
        g[j] *= c;
        hessenberg.push(column);
        let estimate = g[j + 1].abs();
        if estimate <= target || subdiagonal == 0.0 {
            // Back substitution H y = g, x = Z y.
            let k = j + 1;
            let mut y = vec![0.0; k];
            for i in (0..k).rev() {
                let sum: f64 = (i + 1..k).map(|l| hessenberg[l][i] * y[l]).sum();
                y[i] = (g[i] - sum) / hessenberg[i][i];
            }
            let mut x = vec![0.0; n];
            for (yi, z) in y.iter().zip(&directions) {
                for (xi, zi) in x.iter_mut().zip(z) {
                    *xi += yi * zi;
                }
            }
            // The estimate is exact only in exact arithmetic: check the true residual.
            let mut product = vec![0.0; n];
            multiply(&x, &mut product);
            let residual = rhs
                .iter()
                .zip(&product)
                .map(|(b, kx)| (b - kx) * (b - kx))
                .sum::<f64>()
                .sqrt();
            // (A NaN residual fails too.)
            if residual.is_nan() || residual > 10.0 * target {
                return None;
            }
            rhs.copy_from_slice(&x);
            return Some(k);
        }
        basis.push(w.iter().map(|wi| wi / subdiagonal).collect());
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// K = diag(1, 2, …, n), M = K: one iteration, the exact solution.
    #[test]
    fn conjugate_gradients_with_the_exact_preconditioner_take_one_iteration() {
        let n = 8;
        let diagonal: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let mut b: Vec<f64> = (0..n).map(|i| (i as f64).cos()).collect();
        let expected: Vec<f64> = b.iter().zip(&diagonal).map(|(b, d)| b / d).collect();
        let iterations = preconditioned_cg(
            &mut b,
            1e-12,
            5,
            |x, y| {
                for ((yi, xi), d) in y.iter_mut().zip(x).zip(&diagonal) {
                    *yi = d * xi;
                }
            },
            |v| {
                for (vi, d) in v.iter_mut().zip(&diagonal) {
                    *vi /= d;
                }
            },
        );
        assert_eq!(iterations, Some(1));
        for (x, e) in b.iter().zip(&expected) {
            assert!((x - e).abs() < 1e-14);
        }
    }

    #[test]
    fn conjugate_gradients_refuse_an_indefinite_matrix() {
        let mut b = vec![1.0, 1.0];
        let outcome = preconditioned_cg(
            &mut b,
            1e-12,
            10,
            |x, y| {
                y[0] = x[0];
                y[1] = -2.0 * x[1];
            },
            |_| {},
        );
        assert_eq!(outcome, None);
    }

    /// A convection–diffusion matrix (tridiagonal 2 + p, −1 − p, −1 + p: unsymmetric, a
    /// skew part p/2 of the symmetric one's scale) preconditioned with its symmetric part's
    /// exact inverse (dense Cholesky): GMRES reaches the dense LU solution to 1e-10 in 15
    /// iterations for 40 unknowns (p = 0.3: 20; the 1-D Laplacian preconditioner leaves
    /// the skew part's low modes large).
    #[test]
    fn gmres_preconditioned_with_the_symmetric_part_solves_an_unsymmetric_system() {
        use nalgebra::{DMatrix, DVector};
        let n = 40;
        let p = 0.1;
        let k = DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                2.0 + p
            } else if j == i + 1 {
                -1.0 - p
            } else if i == j + 1 {
                -1.0 + p
            } else {
                0.0
            }
        });
        let symmetric = (&k + k.transpose()) * 0.5;
        let cholesky = symmetric.clone().cholesky().expect("SPD");
        let b: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).sin() + 0.1).collect();
        let expected = k
            .clone()
            .lu()
            .solve(&DVector::from_column_slice(&b))
            .unwrap();
        let mut x = b.clone();
        let iterations = preconditioned_gmres(
            &mut x,
            1e-12,
            n,
            |v, out| out.copy_from_slice((&k * DVector::from_column_slice(v)).as_slice()),
            |v| {
                let solved = cholesky.solve(&DVector::from_column_slice(v));
                v.copy_from_slice(solved.as_slice());
            },
        )
        .expect("converges");
        assert!(iterations <= 16, "{iterations} iterations");
        for (xi, ei) in x.iter().zip(expected.iter()) {
            assert!((xi - ei).abs() < 1e-10 * expected.amax(), "{xi} vs {ei}");
        }
    }

    /// Without enough iterations GMRES says so and leaves the right-hand side alone.
    #[test]
    fn gmres_that_does_not_converge_returns_none() {
        let n = 30;
        let mut b: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let original = b.clone();
        // A cyclic shift: GMRES needs n iterations on it.
        let outcome = preconditioned_gmres(
            &mut b,
            1e-12,
            5,
            |x, y| {
                for i in 0..n {
                    y[(i + 1) % n] = x[i];
                }
            },
            |_| {},
        );
        assert_eq!(outcome, None);
        assert_eq!(b, original);
    }
}
