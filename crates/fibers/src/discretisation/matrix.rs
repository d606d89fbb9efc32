//! The orthogonal part of the discrete Laplacian as a sparse matrix, and its
//! fixed-potential right-hand side.

use sprs::CsMatI;

use super::coefficients::Coefficients;
use crate::boundary::BoundaryKind;
use crate::fv_mesh::{FaceRef, FvMesh};

/// A sparse matrix in compressed rows with `u32` column indices (sprs).
pub(crate) type SparseMatrix = CsMatI<f64, u32, usize>;

/// The matrix A [m] of the orthogonal part, in compressed rows with sorted columns:
///
/// A_PP = Σ_interior a_f + Σ_fixed a_b,   A_PN = −a_f for the face f between P and N,
///
/// so that (A φ)_P − b_P is minus the orthogonal part of the net flux out of P.
/// Symmetric, with positive diagonal and non-positive off-diagonal entries, diagonally
/// dominant; positive definite when every part of the mesh has a fixed-potential face.
pub(crate) fn orthogonal_matrix(
    fv: &FvMesh,
    coefficients: &Coefficients,
    kinds: &[BoundaryKind],
) -> SparseMatrix {
    let n = fv.cell_count();
    let mut indptr = Vec::with_capacity(n + 1);
    indptr.push(0usize);
    // Each interior face is two off-diagonal entries.
    let nnz = n + 2 * fv.interior.len();
    let mut indices = Vec::with_capacity(nnz);
    let mut data = Vec::with_capacity(nnz);
    // One row: (column, value), at most 1 + 6 entries (a hexahedron's faces).
    let mut row: Vec<(u32, f64)> = Vec::with_capacity(7);
    for cell in 0..n {
        row.clear();
        let mut diagonal = 0.0;
        for &face in fv.faces_of(cell) {
            match face {
                FaceRef::Interior(f) => {
                    let face = &fv.interior[f as usize];
                    let a = coefficients.interior[f as usize].orthogonal;
                    let other = if face.owner as usize == cell {
                        face.neighbour
                    } else {
                        face.owner
                    };
                    row.push((other, -a));
                    diagonal += a;
                }
                FaceRef::Boundary(b) => {
                    if kinds[b as usize].potential().is_some() {
                        diagonal += coefficients.boundary[b as usize].orthogonal;
                    }
                }
            }
        }
        row.push((cell as u32, diagonal));
        row.sort_unstable_by_key(|&(column, _)| column);
        for (k, &(column, value)) in row.iter().enumerate() {
            if k > 0 && row[k - 1].0 == column {
                // Two faces to the same neighbour (only in a degenerate mesh): one entry.
                if let Some(last) = data.last_mut() {
                    *last += value;
                }
            } else {
                indices.push(column);
                data.push(value);
            }
        }
        indptr.push(indices.len());
    }
    match SparseMatrix::try_new((n, n), indptr, indices, data) {
        Ok(matrix) => matrix,
        Err((_, _, _, error)) => {
            panic!("the face loop builds sorted rows of distinct columns in range: {error}")
        }
    }
}

/// The right-hand side b [m] of the fixed potentials: b_P = Σ_fixed a_b φ_b.
pub(crate) fn fixed_potential_rhs(
    fv: &FvMesh,
    coefficients: &Coefficients,
    kinds: &[BoundaryKind],
) -> Vec<f64> {
    let mut rhs = vec![0.0; fv.cell_count()];
    for (b, face) in fv.boundary.iter().enumerate() {
        if let Some(value) = kinds[b].potential() {
            rhs[face.cell as usize] += coefficients.boundary[b].orthogonal * value;
        }
    }
    rhs
}
