//! Compressed sparse rows for the multigrid hierarchy: products y = A x and C = A B, and
//! the transpose. Every parallel kernel splits the rows into fixed chunks of [`ROWS`] and
//! computes each row serially in a fixed order (a row of y = A x in four interleaved
//! partial sums, [`row_dot`]), so the results are the same, bit for bit, on any number of
//! threads.

use std::ops::Range;

use rayon::prelude::*;

/// Rows per parallel chunk.
pub(crate) const ROWS: usize = 512;

/// A sparse matrix in compressed rows (column indices sorted within each row).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Csr {
    pub rows: usize,
    pub cols: usize,
    pub ptr: Vec<usize>,
    pub idx: Vec<u32>,
    pub val: Vec<f64>,
}

impl Csr {
    /// Stored entries.
    pub fn entries(&self) -> usize {
        self.idx.len()
    }

    /// The columns and values of `row`.
    #[inline]
    pub fn row(&self, row: usize) -> (&[u32], &[f64]) {
        let range = self.ptr[row]..self.ptr[row + 1];
        (&self.idx[range.clone()], &self.val[range])
    }

    /// The diagonal (zero where not stored).
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.rows)
            .map(|i| {
                let (cols, vals) = self.row(i);
                cols.binary_search(&(i as u32)).map_or(0.0, |k| vals[k])
            })
            .collect()
    }

    /// y = A x.
    pub fn multiply(&self, x: &[f64], y: &mut [f64]) {
        y.par_chunks_mut(ROWS).enumerate().for_each(|(chunk, y)| {
            for (offset, yi) in y.iter_mut().enumerate() {
                let (cols, vals) = self.row(chunk * ROWS + offset);
                *yi = row_dot(cols, vals, x);
            }
        });
    }

    /// r = b − A x.
    pub fn residual(&self, b: &[f64], x: &[f64], r: &mut [f64]) {
        r.par_chunks_mut(ROWS).enumerate().for_each(|(chunk, r)| {
            for (offset, ri) in r.iter_mut().enumerate() {
                let i = chunk * ROWS + offset;
                let (cols, vals) = self.row(i);
                *ri = b[i] - row_dot(cols, vals, x);
            }
        });
    }

    /// Aᵀ (serial counting sort: rows of the transpose come out sorted).
    pub fn transpose(&self) -> Csr {
        let mut counts = vec![0usize; self.cols + 1];
        for &j in &self.idx {
            counts[j as usize + 1] += 1;
        }
        for j in 0..self.cols {
            counts[j + 1] += counts[j];
        }
        let ptr = counts.clone();
        let mut next = counts;
        let mut idx = vec![0u32; self.entries()];
        let mut val = vec![0.0; self.entries()];
        for i in 0..self.rows {
            let (cols, vals) = self.row(i);
            for (&j, &a) in cols.iter().zip(vals) {
                let k = next[j as usize];
                idx[k] = i as u32;
                val[k] = a;
                next[j as usize] += 1;
            }
        }
        Csr {
            rows: self.cols,
            cols: self.rows,
            ptr,
            idx,
            val,
        }
    }

    /// C = A B (Gustavson: each row of C accumulated in a dense row of B's width, in the
    /// order of A's and B's stored entries). The multigrid takes its products a block of
    /// rows at a time (`galerkin.rs`); the tests compare with the whole product.
    #[cfg(test)]
    pub fn product(&self, b: &Csr) -> Csr {
        self.product_of_rows(b, 0..self.rows)
    }

    /// The rows `rows` of A B, as a matrix of `rows.len()` rows: each row computed as
    /// [`Self::product`] computes it, so the values are the same bit for bit.
    pub fn product_of_rows(&self, b: &Csr, rows: Range<usize>) -> Csr {
        assert_eq!(self.cols, b.rows, "inner dimensions of a product");
        let first = rows.start;
        let count = rows.len();
        let width = b.cols;
        let chunks: Vec<(Vec<usize>, Vec<u32>, Vec<f64>)> = (0..count.div_ceil(ROWS))
            .into_par_iter()
            .map_init(
                || SparseAccumulator::new(width),
                |accumulator, chunk| {
                    let rows = first + chunk * ROWS..first + ((chunk + 1) * ROWS).min(count);
                    let mut lengths = Vec::with_capacity(rows.len());
                    let mut idx = Vec::new();
                    let mut val = Vec::new();
                    for i in rows {
                        let start = idx.len();
                        let (a_cols, a_vals) = self.row(i);
                        for (&k, &a) in a_cols.iter().zip(a_vals) {
                            let (b_cols, b_vals) = b.row(k as usize);
                            for (&j, &bv) in b_cols.iter().zip(b_vals) {
                                accumulator.add(j, a * bv);
                            }
                        }
                        accumulator.drain_sorted_into(&mut idx, &mut val);
                        lengths.push(idx.len() - start);
                    }
                    (lengths, idx, val)
                },
            )
            .collect();
        let entries: usize = chunks.iter().map(|c| c.1.len()).sum();
        let mut ptr = Vec::with_capacity(count + 1);
        ptr.push(0);
        let mut idx = Vec::with_capacity(entries);
        let mut val = Vec::with_capacity(entries);
        for (lengths, chunk_idx, chunk_val) in chunks {
            for length in lengths {
                ptr.push(ptr[ptr.len() - 1] + length);
            }
            idx.extend_from_slice(&chunk_idx);
            val.extend_from_slice(&chunk_val);
        }
        Csr {
            rows: count,
            cols: width,
            ptr,
            idx,
            val,
        }
    }
}

/// One sparse row being summed (Gustavson's accumulator): a dense row of values of the
/// matrix's width, with the columns touched so far, in the order first touched.
pub(crate) struct SparseAccumulator {
    values: Vec<f64>,
    touched: Vec<bool>,
    columns: Vec<u32>,
}

impl SparseAccumulator {
    /// An empty row of `width` columns.
    pub fn new(width: usize) -> Self {
        SparseAccumulator {
            values: vec![0.0; width],
            touched: vec![false; width],
            columns: Vec::new(),
        }
    }

    /// Entry j ← `value` (j not touched yet).
    #[inline]
    pub fn set(&mut self, j: u32, value: f64) {
        debug_assert!(!self.touched[j as usize]);
        self.touched[j as usize] = true;
        self.values[j as usize] = value;
        self.columns.push(j);
    }

    /// Entry j ← entry j + `term` (from 0 when j is not touched yet).
    #[inline]
    pub fn add(&mut self, j: u32, term: f64) {
        let k = j as usize;
        if !self.touched[k] {
            self.touched[k] = true;
            self.values[k] = 0.0;
            self.columns.push(j);
        }
        self.values[k] += term;
    }

    /// Appends the touched columns, sorted, and their values to `idx` and `val`, and
    /// leaves the accumulator empty.
    pub fn drain_sorted_into(&mut self, idx: &mut Vec<u32>, val: &mut Vec<f64>) {
        self.columns.sort_unstable();
        for &j in &self.columns {
            idx.push(j);
            val.push(self.values[j as usize]);
            self.touched[j as usize] = false;
        }
        self.columns.clear();
    }
}

/// Σ_k a_k x[j_k] over one row's stored entries, in four interleaved partial sums
/// (entries k ≡ 0, 1, 2, 3 mod 4) added as (s₀ + s₁) + (s₂ + s₃): a single running sum
/// waits on each addition's latency, four keep the core's adders busy. The order is fixed,
/// so the result does not depend on the number of threads.
#[inline]
fn row_dot(cols: &[u32], vals: &[f64], x: &[f64]) -> f64 {
    let mut sums = [0.0f64; 4];
    let mut col_quads = cols.chunks_exact(4);
    let mut val_quads = vals.chunks_exact(4);
    for (c, a) in (&mut col_quads).zip(&mut val_quads) {
        sums[0] += a[0] * x[c[0] as usize];
        sums[1] += a[1] * x[c[1] as usize];
        sums[2] += a[2] * x[c[2] as usize];
        sums[3] += a[3] * x[c[3] as usize];
    }
    for (k, (&j, &a)) in col_quads
        .remainder()
        .iter()
        .zip(val_quads.remainder())
        .enumerate()
    {
        sums[k] += a * x[j as usize];
    }
    (sums[0] + sums[1]) + (sums[2] + sums[3])
}

/// aᵀb in fixed chunks summed in order (the same on any number of threads).
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    const CHUNK: usize = 4096;
    let partials: Vec<f64> = a
        .par_chunks(CHUNK)
        .zip(b.par_chunks(CHUNK))
        .map(|(a, b)| a.iter().zip(b).map(|(x, y)| x * y).sum())
        .collect();
    partials.iter().sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> Csr {
        // [1 2 0; 0 3 4; 5 0 6]
        Csr {
            rows: 3,
            cols: 3,
            ptr: vec![0, 2, 4, 6],
            idx: vec![0, 1, 1, 2, 0, 2],
            val: vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
        }
    }

    #[test]
    fn product_and_transpose_match_dense_arithmetic() {
        let a = small();
        let at = a.transpose();
        assert_eq!(at.idx, vec![0, 2, 0, 1, 1, 2]);
        assert_eq!(at.val, vec![1.0, 5.0, 2.0, 3.0, 4.0, 6.0]);
        let c = a.product(&at);
        // A Aᵀ row 0: [5, 6, 5]
        assert_eq!(c.row(0).1, &[5.0, 6.0, 5.0]);
        let mut y = vec![0.0; 3];
        a.multiply(&[1.0, 1.0, 1.0], &mut y);
        assert_eq!(y, vec![3.0, 7.0, 11.0]);
    }
}
