//! One level's transfer to the next coarser: the smoothed prolongator
//! P = (I − ω D⁻¹A) P̂ and the Galerkin coarse operator A_c = Pᵀ A P.
//!
//! Both need a product with A, A P̂ and A P, each as large as P or larger (at 85 529
//! unknowns A P held 104 MB). They are computed [`FINE_ROWS`] fine rows at a time and
//! used at once, so that neither is ever held whole:
//! - P's rows are the merge of P̂'s rows with those of the block of A P̂;
//! - A_c's rows are accumulated block after block: row c of A_c gains, from each block of
//!   A P, Σ_k R_ck (A P)_k over the block's fine rows k, in increasing k, added onto
//!   what the earlier blocks gave.
//!
//! Every entry of A_c is therefore the sum Σ_k R_ck (A P)_kj in increasing k that the
//! row-by-row product R (A P) forms (`csr.rs`, [`Csr::product_of_rows`]), operation for
//! operation: the coarse operator is the same bit for bit as the one of the whole
//! products, on any number of threads and for any block size.

use rayon::prelude::*;

use super::csr::{Csr, ROWS, SparseAccumulator};

/// Fine rows of A P̂ or A P held at once.
pub(crate) const FINE_ROWS: usize = 16 * ROWS;

/// P = P̂ − ω D⁻¹ (A P̂), merging the sorted rows of P̂ and of A P̂ block by block.
pub(super) fn smoothed_prolongator(
    a: &Csr,
    tentative: &Csr,
    inverse_diagonal: &[f64],
    omega: f64,
) -> Csr {
    let mut ptr = Vec::with_capacity(tentative.rows + 1);
    ptr.push(0);
    let mut idx = Vec::new();
    let mut val = Vec::new();
    for first in (0..tentative.rows).step_by(FINE_ROWS) {
        let rows = first..(first + FINE_ROWS).min(tentative.rows);
        let a_tentative = a.product_of_rows(tentative, rows.clone());
        for i in rows {
            let (t_cols, t_vals) = tentative.row(i);
            let (a_cols, a_vals) = a_tentative.row(i - first);
            let scale = omega * inverse_diagonal[i];
            let mut k = 0;
            for (&j, &v) in a_cols.iter().zip(a_vals) {
                let mut value = -scale * v;
                while k < t_cols.len() && t_cols[k] < j {
                    idx.push(t_cols[k]);
                    val.push(t_vals[k]);
                    k += 1;
                }
                if k < t_cols.len() && t_cols[k] == j {
                    value += t_vals[k];
                    k += 1;
                }
                idx.push(j);
                val.push(value);
            }
            for k in k..t_cols.len() {
                idx.push(t_cols[k]);
                val.push(t_vals[k]);
            }
            ptr.push(idx.len());
        }
    }
    Csr {
        rows: tentative.rows,
        cols: tentative.cols,
        ptr,
        idx,
        val,
    }
}

/// One row of the coarse operator while it is accumulated: sorted columns, values.
#[derive(Default)]
struct CoarseRow {
    idx: Vec<u32>,
    val: Vec<f64>,
}

/// A_c = R A P with R = Pᵀ (module documentation): A P a block of fine rows at a time.
pub(super) fn galerkin_product(r: &Csr, a: &Csr, p: &Csr) -> Csr {
    assert_eq!(r.cols, a.rows, "R and A do not fit");
    let width = p.cols;
    let mut rows: Vec<CoarseRow> = (0..r.rows).map(|_| CoarseRow::default()).collect();
    for first in (0..a.rows).step_by(FINE_ROWS) {
        let block = first..(first + FINE_ROWS).min(a.rows);
        let a_p = a.product_of_rows(p, block.clone());
        rows.par_chunks_mut(ROWS).enumerate().for_each_init(
            || SparseAccumulator::new(width),
            |accumulator, (chunk, rows)| {
                for (offset, row) in rows.iter_mut().enumerate() {
                    let (r_cols, r_vals) = r.row(chunk * ROWS + offset);
                    let from = r_cols.partition_point(|&k| (k as usize) < block.start);
                    let to = r_cols.partition_point(|&k| (k as usize) < block.end);
                    if from == to {
                        continue;
                    }
                    for (&j, &v) in row.idx.iter().zip(&row.val) {
                        accumulator.set(j, v);
                    }
                    for (&k, &rv) in r_cols[from..to].iter().zip(&r_vals[from..to]) {
                        let (ap_cols, ap_vals) = a_p.row(k as usize - first);
                        for (&j, &x) in ap_cols.iter().zip(ap_vals) {
                            accumulator.add(j, rv * x);
                        }
                    }
                    row.idx.clear();
                    row.val.clear();
                    accumulator.drain_sorted_into(&mut row.idx, &mut row.val);
                }
            },
        );
    }
    let entries = rows.iter().map(|row| row.idx.len()).sum();
    let mut ptr = Vec::with_capacity(r.rows + 1);
    ptr.push(0);
    let mut idx = Vec::with_capacity(entries);
    let mut val = Vec::with_capacity(entries);
    for row in rows {
        idx.extend_from_slice(&row.idx);
        val.extend_from_slice(&row.val);
        ptr.push(idx.len());
    }
    Csr {
        rows: r.rows,
        cols: width,
        ptr,
        idx,
        val,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A banded symmetric matrix of `n` rows and a prolongator onto `n / 3` aggregates of
    /// three rows, each row also reaching the next aggregate: entries with distinct bits.
    fn operators(n: usize) -> (Csr, Csr) {
        let mut a = (vec![0], Vec::new(), Vec::new());
        for i in 0..n {
            for j in i.saturating_sub(4)..(i + 5).min(n) {
                a.1.push(j as u32);
                a.2.push(if i == j {
                    10.0 + (i % 7) as f64 * 0.1
                } else {
                    -1.0 / (1.0 + (i + j) as f64 * 0.37)
                });
            }
            a.0.push(a.1.len());
        }
        let coarse = n / 3;
        let mut p = (vec![0], Vec::new(), Vec::new());
        for i in 0..n {
            let c = (i / 3).min(coarse - 1);
            p.1.push(c as u32);
            p.2.push(1.0 + (i % 5) as f64 * 0.01);
            if c + 1 < coarse {
                p.1.push(c as u32 + 1);
                p.2.push(0.3 - (i % 3) as f64 * 0.05);
            }
            p.0.push(p.1.len());
        }
        let csr = |(ptr, idx, val): (Vec<usize>, Vec<u32>, Vec<f64>), cols| Csr {
            rows: ptr.len() - 1,
            cols,
            ptr,
            idx,
            val,
        };
        (csr(a, n), csr(p, coarse))
    }

    /// Over several blocks of fine rows, the block-wise products give the bits of the
    /// whole products: P = P̂ − ω D⁻¹ (A P̂) and Pᵀ A P = R (A P).
    #[test]
    fn the_block_wise_products_are_the_whole_products_bit_for_bit() {
        let n = 2 * FINE_ROWS + 1000;
        let (a, tentative) = operators(n);
        let inverse_diagonal: Vec<f64> = a.diagonal().iter().map(|d| 1.0 / d).collect();
        let omega = 0.61;

        let p = smoothed_prolongator(&a, &tentative, &inverse_diagonal, omega);
        let a_tentative = a.product(&tentative);
        for i in 0..n {
            let (t_cols, t_vals) = tentative.row(i);
            let (p_cols, p_vals) = p.row(i);
            let (a_cols, a_vals) = a_tentative.row(i);
            for (&j, &v) in p_cols.iter().zip(p_vals) {
                let t = t_cols
                    .iter()
                    .position(|&c| c == j)
                    .map_or(0.0, |k| t_vals[k]);
                let at = a_cols
                    .iter()
                    .position(|&c| c == j)
                    .map_or(0.0, |k| a_vals[k]);
                let expected = if a_cols.contains(&j) {
                    -(omega * inverse_diagonal[i]) * at + t
                } else {
                    t
                };
                assert_eq!(v.to_bits(), expected.to_bits(), "P[{i}, {j}]");
            }
        }

        let r = p.transpose();
        let whole = r.product(&a.product(&p));
        let blocks = galerkin_product(&r, &a, &p);
        assert!(
            blocks.rows > 2 * ROWS,
            "the coarse rows span several chunks"
        );
        assert_eq!(blocks.ptr, whole.ptr);
        assert_eq!(blocks.idx, whole.idx);
        let bits = |m: &Csr| m.val.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&blocks), bits(&whole));
    }
}
