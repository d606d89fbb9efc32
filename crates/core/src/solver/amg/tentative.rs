//! The near-null space of elasticity and the tentative prolongator.
//!
//! The six rigid-body modes (three translations e_k, three rotations e_k × (x − x̄), x̄
//! the centroid of the nodes, units m) have no strain energy: K B ≈ 0 for the unsupported
//! body. Smoothed aggregation interpolates them exactly: per aggregate, the rows of B of
//! its unknowns (m × 6) are factorized B_a = Q_a R_a (modified Gram–Schmidt, twice, columns
//! whose remainder is below [`DEPENDENT`] of their norm dropped: an aggregate of one node
//! keeps 3 columns, of two nodes 5); Q_a becomes the aggregate's block of the tentative
//! prolongator P̂ (orthonormal columns, one coarse unknown each) and R_a its rows of the
//! coarse near-null space, so that P̂ B_c = B.

use super::csr::Csr;

/// Columns of the near-null space.
pub(crate) const MODES: usize = 6;

/// Relative remainder below which a near-null column is taken as dependent.
const DEPENDENT: f64 = 1e-8;

/// Rigid-body modes of unknowns at `coordinates` [m] in directions `dofs` (0, 1, 2 for
/// x, y, z): one row of B per unknown.
pub(crate) fn rigid_body_modes(coordinates: &[[f64; 3]], dofs: &[u8]) -> Vec<[f64; MODES]> {
    let n = coordinates.len().max(1) as f64;
    let mut centroid = [0.0; 3];
    for x in coordinates {
        for k in 0..3 {
            centroid[k] += x[k] / n;
        }
    }
    coordinates
        .iter()
        .zip(dofs)
        .map(|(x, &d)| {
            let r = [x[0] - centroid[0], x[1] - centroid[1], x[2] - centroid[2]];
            let mut row = [0.0; MODES];
            row[d as usize] = 1.0;
            // Rotation about axis k: (e_k × r)_d.
            let rotation = |k: usize| match (k, d) {
                (0, 1) => -r[2],
                (0, 2) => r[1],
                (1, 0) => r[2],
                (1, 2) => -r[0],
                (2, 0) => -r[1],
                (2, 1) => r[0],
                _ => 0.0,
            };
            for k in 0..3 {
                row[3 + k] = rotation(k);
            }
            row
        })
        .collect()
}

/// The tentative prolongator of the aggregation `aggregate_of` (one entry per block of
/// `block_ptr`, `count` aggregates) and near-null space `modes` (a row per unknown):
/// P̂, the coarse blocks (one per aggregate) and the coarse near-null space.
pub(crate) fn tentative_prolongator(
    aggregate_of: &[u32],
    count: usize,
    block_ptr: &[usize],
    modes: &[[f64; MODES]],
) -> (Csr, Vec<usize>, Vec<[f64; MODES]>) {
    let rows = modes.len();
    // The unknowns of every aggregate, in block order.
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); count];
    for (b, &a) in aggregate_of.iter().enumerate() {
        members[a as usize].extend(block_ptr[b]..block_ptr[b + 1]);
    }
    let mut coarse_ptr = Vec::with_capacity(count + 1);
    coarse_ptr.push(0usize);
    let mut coarse_modes = Vec::new();
    // Each fine row's entries: (first coarse column, Q row).
    let mut q_rows: Vec<(usize, Vec<f64>)> = vec![(0, Vec::new()); rows];
    for rows_of in &members {
        let m = rows_of.len();
        // Columns of B_a, then orthonormalized in place.
        let mut columns: Vec<Vec<f64>> = (0..MODES)
            .map(|j| rows_of.iter().map(|&i| modes[i][j]).collect())
            .collect();
        let original = columns.clone();
        let mut kept: Vec<Vec<f64>> = Vec::new();
        for column in columns.iter_mut() {
            let norm0 = column.iter().map(|v| v * v).sum::<f64>().sqrt();
            for _ in 0..2 {
                for q in &kept {
                    let h: f64 = q.iter().zip(column.iter()).map(|(a, b)| a * b).sum();
                    for (c, qv) in column.iter_mut().zip(q) {
                        *c -= h * qv;
                    }
                }
            }
            let norm = column.iter().map(|v| v * v).sum::<f64>().sqrt();
            if norm > DEPENDENT * norm0 && norm > 0.0 && kept.len() < m {
                kept.push(column.iter().map(|v| v / norm).collect());
            }
        }
        let first = *coarse_ptr.last().unwrap_or(&0);
        // R_a = Q_aᵀ B_a.
        for q in &kept {
            let mut r = [0.0; MODES];
            for (j, column) in original.iter().enumerate() {
                r[j] = q.iter().zip(column).map(|(a, b)| a * b).sum();
            }
            coarse_modes.push(r);
        }
        for (local, &i) in rows_of.iter().enumerate() {
            q_rows[i] = (first, kept.iter().map(|q| q[local]).collect());
        }
        coarse_ptr.push(first + kept.len());
    }
    let coarse = *coarse_ptr.last().unwrap_or(&0);
    let mut ptr = Vec::with_capacity(rows + 1);
    ptr.push(0);
    let mut idx = Vec::new();
    let mut val = Vec::new();
    for (first, q) in q_rows {
        for (k, v) in q.into_iter().enumerate() {
            idx.push((first + k) as u32);
            val.push(v);
        }
        ptr.push(idx.len());
    }
    let p = Csr {
        rows,
        cols: coarse,
        ptr,
        idx,
        val,
    };
    (p, coarse_ptr, coarse_modes)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two aggregates of two and one 3-D nodes: 5 and 3 coarse unknowns, P̂ B_c = B.
    #[test]
    fn tentative_prolongator_interpolates_the_rigid_modes() {
        let coordinates = [[0.0, 0.0, 0.0], [1.0, 0.5, 0.0], [0.0, 2.0, 1.0]];
        let mut xs = Vec::new();
        let mut dofs = Vec::new();
        for x in coordinates {
            for d in 0..3u8 {
                xs.push(x);
                dofs.push(d);
            }
        }
        let modes = rigid_body_modes(&xs, &dofs);
        let (p, coarse_ptr, coarse_modes) =
            tentative_prolongator(&[0, 0, 1], 2, &[0, 3, 6, 9], &modes);
        assert_eq!(coarse_ptr, vec![0, 5, 8]);
        for i in 0..9 {
            let (cols, vals) = p.row(i);
            for j in 0..MODES {
                let pb: f64 = cols
                    .iter()
                    .zip(vals)
                    .map(|(&c, &v)| v * coarse_modes[c as usize][j])
                    .sum();
                assert!((pb - modes[i][j]).abs() < 1e-12, "row {i} mode {j}");
            }
        }
    }
}
