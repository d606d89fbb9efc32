//! Parallel vector kernels over fixed chunks of rows. Sums are formed per chunk and the
//! chunk sums added in order, so the results do not depend on the number of threads.

use rayon::prelude::*;

use crate::discretisation::matrix::SparseMatrix;

/// Rows per parallel task (and per partial sum).
pub(crate) const CHUNK: usize = 4096;

/// Number of partial sums for vectors of length `n`.
pub(crate) fn chunk_count(n: usize) -> usize {
    n.div_ceil(CHUNK)
}

/// y = A x, and returns x·y (the A-norm² of x). `partials` holds one entry per chunk.
pub(crate) fn multiply_and_dot(
    matrix: &SparseMatrix,
    x: &[f64],
    y: &mut [f64],
    partials: &mut [f64],
) -> f64 {
    let indptr = matrix.indptr();
    let indptr = indptr.raw_storage();
    let (indices, data) = (matrix.indices(), matrix.data());
    y.par_chunks_mut(CHUNK)
        .zip(partials.par_iter_mut())
        .enumerate()
        .for_each(|(chunk, (y, partial))| {
            let first = chunk * CHUNK;
            let mut dot = 0.0;
            for (i, y) in y.iter_mut().enumerate() {
                let row = first + i;
                let mut sum = 0.0;
                for k in indptr[row]..indptr[row + 1] {
                    sum += data[k] * x[indices[k] as usize];
                }
                *y = sum;
                dot += x[row] * sum;
            }
            *partial = dot;
        });
    partials.iter().sum()
}

/// y = A x.
pub(crate) fn multiply(matrix: &SparseMatrix, x: &[f64], y: &mut [f64]) {
    let indptr = matrix.indptr();
    let indptr = indptr.raw_storage();
    let (indices, data) = (matrix.indices(), matrix.data());
    y.par_chunks_mut(CHUNK).enumerate().for_each(|(chunk, y)| {
        let first = chunk * CHUNK;
        for (i, y) in y.iter_mut().enumerate() {
            let row = first + i;
            let mut sum = 0.0;
            for k in indptr[row]..indptr[row + 1] {
                sum += data[k] * x[indices[k] as usize];
            }
            *y = sum;
        }
    });
}

/// r = b − A x, and returns r·r.
pub(crate) fn residual(
    matrix: &SparseMatrix,
    b: &[f64],
    x: &[f64],
    r: &mut [f64],
    partials: &mut [f64],
) -> f64 {
    let indptr = matrix.indptr();
    let indptr = indptr.raw_storage();
    let (indices, data) = (matrix.indices(), matrix.data());
    r.par_chunks_mut(CHUNK)
        .zip(partials.par_iter_mut())
        .enumerate()
        .for_each(|(chunk, (r, partial))| {
            let first = chunk * CHUNK;
            let mut dot = 0.0;
            for (i, r) in r.iter_mut().enumerate() {
                let row = first + i;
                let mut sum = b[row];
                for k in indptr[row]..indptr[row + 1] {
                    sum -= data[k] * x[indices[k] as usize];
                }
                *r = sum;
                dot += sum * sum;
            }
            *partial = dot;
        });
    partials.iter().sum()
}

/// x·y.
pub(crate) fn dot(x: &[f64], y: &[f64], partials: &mut [f64]) -> f64 {
    partials
        .par_iter_mut()
        .zip(x.par_chunks(CHUNK).zip(y.par_chunks(CHUNK)))
        .for_each(|(partial, (x, y))| {
            *partial = x.iter().zip(y).map(|(a, b)| a * b).sum();
        });
    partials.iter().sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kernels_match_dense_arithmetic() {
        // Tridiagonal [−1 2 −1] of size n, spread over several chunks.
        let n = 2 * CHUNK + 17;
        let mut indptr = vec![0usize];
        let (mut indices, mut data) = (Vec::new(), Vec::new());
        for i in 0..n {
            for (j, v) in [(i.wrapping_sub(1), -1.0), (i, 2.0), (i + 1, -1.0)] {
                if j < n {
                    indices.push(j as u32);
                    data.push(v);
                }
            }
            indptr.push(indices.len());
        }
        let matrix = SparseMatrix::new((n, n), indptr, indices, data);
        let x: Vec<f64> = (0..n).map(|i| ((i * 7919) % 101) as f64 / 101.0).collect();
        let mut y = vec![0.0; n];
        let mut partials = vec![0.0; chunk_count(n)];
        let xax = multiply_and_dot(&matrix, &x, &mut y, &mut partials);
        let mut expected_xax = 0.0;
        for i in 0..n {
            let left = if i > 0 { x[i - 1] } else { 0.0 };
            let right = if i + 1 < n { x[i + 1] } else { 0.0 };
            let ax = 2.0 * x[i] - left - right;
            assert!((y[i] - ax).abs() < 1e-14);
            expected_xax += x[i] * ax;
        }
        assert!((xax - expected_xax).abs() < 1e-10);
        let b = vec![1.0; n];
        let mut r = vec![0.0; n];
        let rr = residual(&matrix, &b, &x, &mut r, &mut partials);
        let expected: f64 = y.iter().map(|ax| (1.0 - ax) * (1.0 - ax)).sum();
        assert!((rr - expected).abs() < 1e-9 * expected);
        assert!((dot(&r, &r, &mut partials) - rr).abs() < 1e-9 * rr);
    }
}
