//! Aggregation: groups of strongly connected rows that become one coarse unknown.
//!
//! Row j is strongly connected to row i when |a_ij| ≥ θ √(a_ii a_jj). Three passes in
//! row order (Vaněk, Mandel & Brezina, Computing 56, 1996):
//!
//! 1. a row whose strong neighbours are all free starts an aggregate with them;
//! 2. every row still free joins the pass-1 aggregate it is most strongly connected to;
//! 3. the rows left (no strong neighbour in an aggregate) start aggregates with their
//!    free strong neighbours.

use crate::discretisation::matrix::SparseMatrix;

/// Strength threshold θ (dimensionless).
const STRENGTH: f64 = 0.08;

/// No aggregate yet.
const FREE: u32 = u32::MAX;

/// The aggregate of every row and the number of aggregates.
pub(crate) fn aggregate(matrix: &SparseMatrix) -> (Vec<u32>, usize) {
    let n = matrix.rows();
    let indptr = matrix.indptr();
    let indptr = indptr.raw_storage();
    let (indices, data) = (matrix.indices(), matrix.data());
    let mut diagonal = vec![0.0; n];
    for (row, d) in diagonal.iter_mut().enumerate() {
        for k in indptr[row]..indptr[row + 1] {
            if indices[k] as usize == row {
                *d = data[k];
            }
        }
    }
    // The strong neighbours of `row` and the strength |a_ij| / √(a_ii a_jj).
    let diagonal = &diagonal[..];
    let strong = move |row: usize| {
        (indptr[row]..indptr[row + 1]).filter_map(move |k| {
            let column = indices[k] as usize;
            let strength = data[k].abs() / (diagonal[row] * diagonal[column]).sqrt();
            (column != row && strength >= STRENGTH).then_some((column, strength))
        })
    };

    let mut aggregate_of = vec![FREE; n];
    let mut count = 0u32;
    for row in 0..n {
        if aggregate_of[row] == FREE && strong(row).all(|(j, _)| aggregate_of[j] == FREE) {
            aggregate_of[row] = count;
            for (j, _) in strong(row) {
                aggregate_of[j] = count;
            }
            count += 1;
        }
    }
    let first_pass = aggregate_of.clone();
    for row in 0..n {
        if aggregate_of[row] != FREE {
            continue;
        }
        let best = strong(row)
            .filter(|&(j, _)| first_pass[j] != FREE)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((j, _)) = best {
            aggregate_of[row] = first_pass[j];
        }
    }
    for row in 0..n {
        if aggregate_of[row] == FREE {
            aggregate_of[row] = count;
            for (j, _) in strong(row) {
                if aggregate_of[j] == FREE {
                    aggregate_of[j] = count;
                }
            }
            count += 1;
        }
    }
    (aggregate_of, count as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chain_forms_runs_of_neighbours() {
        // The 1-D Laplacian on 10 rows: pass 1 takes 0-1, 2-3-4, 5-6-7, 8-9 or similar
        // runs; every row is in an aggregate and every aggregate is a run of rows.
        let n: usize = 10;
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
        let (aggregates, count) = aggregate(&matrix);
        assert!((3..=5).contains(&count), "{count}: {aggregates:?}");
        for a in 0..count as u32 {
            let rows: Vec<usize> = (0..n).filter(|&i| aggregates[i] == a).collect();
            assert!(!rows.is_empty() && rows.len() <= 3, "{aggregates:?}");
            assert_eq!(
                rows[rows.len() - 1] - rows[0] + 1,
                rows.len(),
                "{aggregates:?}"
            );
        }
    }
}
