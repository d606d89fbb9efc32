//! The prolongation and the Galerkin coarse matrix of one level.

use crate::discretisation::matrix::SparseMatrix;

/// The piecewise-constant prolongation P [rows × aggregates]: P_ij = 1 if row i is in
/// aggregate j (constants, the null space of the Laplacian without fixed potentials,
/// are interpolated exactly).
pub(crate) fn aggregate_prolongation(aggregate_of: &[u32], aggregates: usize) -> SparseMatrix {
    let n = aggregate_of.len();
    SparseMatrix::new(
        (n, aggregates),
        (0..=n).collect(),
        aggregate_of.to_vec(),
        vec![1.0; n],
    )
}

/// The restriction R = Pᵀ and the Galerkin coarse matrix A_c = Pᵀ A P (sprs products):
/// for a piecewise-constant P, (A_c)_IJ is the sum of a_ij over i in aggregate I and j in
/// aggregate J.
pub(crate) fn galerkin(
    matrix: &SparseMatrix,
    prolongation: &SparseMatrix,
) -> (SparseMatrix, SparseMatrix) {
    let restriction = prolongation.transpose_view().to_csr();
    let ap = matrix * prolongation;
    let coarse = &restriction * &ap;
    (restriction, coarse)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coarse_matrix_sums_the_aggregate_blocks() {
        // [2 −1 0; −1 2 −1; 0 −1 2] with aggregates {0, 1} and {2}.
        let matrix = SparseMatrix::new(
            (3, 3),
            vec![0, 2, 5, 7],
            vec![0, 1, 0, 1, 2, 1, 2],
            vec![2.0, -1.0, -1.0, 2.0, -1.0, -1.0, 2.0],
        );
        let p = aggregate_prolongation(&[0, 0, 1], 2);
        let (r, coarse) = galerkin(&matrix, &p);
        assert_eq!(r.rows(), 2);
        let dense: Vec<f64> = (0..2)
            .flat_map(|i| (0..2).map(move |j| (i, j)))
            .map(|(i, j)| coarse.get(i, j).copied().unwrap_or(0.0))
            .collect();
        assert_eq!(dense, vec![2.0, -1.0, -1.0, 2.0]);
    }
}
