//! The implicit solver's linear system: the free degrees of freedom, the sparsity pattern of
//! the stiffness built once from the element connectivity, and the direct solve with faer
//! (sparse Cholesky LLᵀ whose symbolic analysis is reused, LU when Cholesky fails or the
//! tangent is not symmetric).
//!
//! The matrix holds only free degrees of freedom (prescribed ones are eliminated) and
//! stores both triangles, so that LU can use it; Cholesky reads the lower one.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{SymbolicCholesky, factorize_symbolic_cholesky};
use faer::sparse::linalg::lu::{NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::{Conj, Par, Side};

use crate::mesh::ElementBlock;

/// Marks a prescribed degree of freedom in the equation map.
pub(crate) const PRESCRIBED: u32 = u32::MAX;

/// Which factorization solved a system.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Factorization {
    /// Sparse Cholesky LLᵀ (symmetric positive definite).
    Cholesky,
    /// Sparse LU with partial pivoting.
    Lu,
}

/// The stiffness of the free degrees of freedom and its factorizations.
pub(crate) struct SparseSystem {
    matrix: SparseColMat<usize, f64>,
    /// Parallelism of the factorizations and solves.
    par: Par,
    llt: Option<Cholesky>,
    lu: Option<Lu>,
}

/// The symbolic Cholesky analysis (AMD ordering, elimination tree, supernodes), done once,
/// with room for the numeric factor and the scratch memory.
struct Cholesky {
    symbolic: SymbolicCholesky<usize>,
    factor: Vec<f64>,
    scratch: MemBuffer,
}

/// The symbolic LU analysis (COLAMD ordering), done once, with the numeric factor and the
/// scratch memory.
struct Lu {
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    scratch: MemBuffer,
}

impl SparseSystem {
    /// The pattern of the stiffness of the `blocks`' elements over the free degrees of
    /// freedom: `equation[3 node + dof]` is the equation number or [`PRESCRIBED`], numbered
    /// node after node, so each column's rows come out sorted. Factorizations run on
    /// rayon's threads from `parallel_unknowns` unknowns on, serially below.
    pub fn new<'a>(
        node_count: usize,
        equation: &[u32],
        free: usize,
        blocks: impl Iterator<Item = &'a ElementBlock>,
        parallel_unknowns: usize,
    ) -> Self {
        let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); node_count];
        for block in blocks {
            for ids in block.elements() {
                for &a in ids {
                    neighbours[a as usize].extend_from_slice(ids);
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(free + 1);
        col_ptr.push(0usize);
        let mut row_idx = Vec::new();
        for (node, list) in neighbours.iter_mut().enumerate() {
            list.sort_unstable();
            list.dedup();
            for dof in 0..3 {
                if equation[3 * node + dof] == PRESCRIBED {
                    continue;
                }
                for &m in list.iter() {
                    for i in 0..3 {
                        let row = equation[3 * m as usize + i];
                        if row != PRESCRIBED {
                            row_idx.push(row as usize);
                        }
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        debug_assert_eq!(col_ptr.len(), free + 1);
        let values = vec![0.0; row_idx.len()];
        let symbolic = SymbolicSparseColMat::new_checked(free, free, col_ptr, None, row_idx);
        SparseSystem {
            matrix: SparseColMat::new(symbolic, values),
            par: if free >= parallel_unknowns {
                Par::rayon(0)
            } else {
                Par::Seq
            },
            llt: None,
            lu: None,
        }
    }

    /// Number of unknowns.
    pub fn size(&self) -> usize {
        self.matrix.ncols()
    }

    /// Stored entries (both triangles).
    pub fn entries(&self) -> usize {
        self.matrix.symbolic().row_idx().len()
    }

    /// Set every stored value to zero.
    pub fn clear(&mut self) {
        self.matrix.val_mut().fill(0.0);
    }

    /// Where entry (`row`, `column`) is stored; it must be in the pattern.
    #[inline]
    pub fn position(&self, row: usize, column: usize) -> usize {
        let symbolic = self.matrix.symbolic();
        let start = symbolic.col_ptr()[column];
        let rows = &symbolic.row_idx()[start..symbolic.col_ptr()[column + 1]];
        match rows.binary_search(&row) {
            Ok(offset) => start + offset,
            Err(_) => unreachable!("({row}, {column}) is coupled by an element"),
        }
    }

    pub fn values_mut(&mut self) -> &mut [f64] {
        self.matrix.val_mut()
    }

    /// Solve K x = `rhs` in place: Cholesky when `symmetric` (symbolic analysis done on the
    /// first call and reused), LU when it is not or when Cholesky finds the matrix not
    /// positive definite. Errors with faer's reason when neither works.
    pub fn solve(&mut self, rhs: &mut [f64], symmetric: bool) -> Result<Factorization, String> {
        let n = self.size();
        let par = self.par;
        let mut cholesky_error = None;
        if symmetric {
            if self.llt.is_none() {
                self.llt = Some(Cholesky::new(&self.matrix, par)?);
            }
            let cholesky = self.llt.as_mut().expect("just built");
            let stack = MemStack::new(&mut cholesky.scratch);
            match cholesky.symbolic.factorize_numeric_llt(
                &mut cholesky.factor,
                self.matrix.as_ref(),
                Side::Lower,
                Default::default(),
                par,
                stack,
                Default::default(),
            ) {
                Ok(llt) => {
                    llt.solve_in_place_with_conj(
                        Conj::No,
                        faer::MatMut::from_column_major_slice_mut(rhs, n, 1),
                        par,
                        stack,
                    );
                    return Ok(Factorization::Cholesky);
                }
                Err(e) => cholesky_error = Some(format!("{e:?}")),
            }
        }
        if self.lu.is_none() {
            self.lu = Some(Lu::new(&self.matrix, par)?);
        }
        let lu = self.lu.as_mut().expect("just built");
        let stack = MemStack::new(&mut lu.scratch);
        let factor = lu
            .symbolic
            .factorize_numeric_lu(
                &mut lu.numeric,
                self.matrix.as_ref(),
                par,
                stack,
                Default::default(),
            )
            .map_err(|e| match &cholesky_error {
                Some(c) => format!("Cholesky failed ({c}), then LU failed ({e:?})"),
                None => format!("LU failed ({e:?})"),
            })?;
        factor.solve_in_place_with_conj(
            Conj::No,
            faer::MatMut::from_column_major_slice_mut(rhs, n, 1),
            par,
            stack,
        );
        if rhs.iter().any(|x| !x.is_finite()) {
            return Err("the LU solution is not finite (singular stiffness)".to_string());
        }
        Ok(Factorization::Lu)
    }
}

impl Cholesky {
    fn new(matrix: &SparseColMat<usize, f64>, par: Par) -> Result<Self, String> {
        let symbolic = factorize_symbolic_cholesky(
            matrix.symbolic(),
            Side::Lower,
            Default::default(),
            Default::default(),
        )
        .map_err(|e| format!("symbolic Cholesky: {e:?}"))?;
        let scratch = symbolic
            .factorize_numeric_llt_scratch::<f64>(par, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, par));
        let scratch = MemBuffer::try_new(scratch)
            .map_err(|e| format!("scratch memory of the Cholesky factorization: {e:?}"))?;
        let factor = vec![0.0; symbolic.len_val()];
        Ok(Cholesky {
            symbolic,
            factor,
            scratch,
        })
    }
}

impl Lu {
    fn new(matrix: &SparseColMat<usize, f64>, par: Par) -> Result<Self, String> {
        let symbolic = factorize_symbolic_lu(matrix.symbolic(), Default::default())
            .map_err(|e| format!("symbolic LU: {e:?}"))?;
        let scratch = symbolic
            .factorize_numeric_lu_scratch::<f64>(par, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, par));
        let scratch = MemBuffer::try_new(scratch)
            .map_err(|e| format!("scratch memory of the LU factorization: {e:?}"))?;
        Ok(Lu {
            symbolic,
            numeric: NumericLu::new(),
            scratch,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::box_of_hexes;

    /// A system over the 24 unknowns of one free hex8 (full 24 × 24 pattern), with the
    /// values `entry(row, column)`; solves K x = K 1 and returns the factorization used
    /// and the largest error of x.
    fn solve_one_hex(entry: impl Fn(usize, usize) -> f64, symmetric: bool) -> (Factorization, f64) {
        let mesh = box_of_hexes([1.0; 3], [1, 1, 1]).unwrap();
        let equation: Vec<u32> = (0..24).collect();
        let mut system = SparseSystem::new(8, &equation, 24, mesh.blocks.iter(), usize::MAX);
        assert_eq!(system.entries(), 24 * 24);
        for row in 0..24 {
            for column in 0..24 {
                let p = system.position(row, column);
                system.values_mut()[p] = entry(row, column);
            }
        }
        let mut rhs: Vec<f64> = (0..24)
            .map(|row| (0..24).map(|c| entry(row, c)).sum())
            .collect();
        let used = system.solve(&mut rhs, symmetric).unwrap();
        (
            used,
            rhs.iter().map(|x| (x - 1.0).abs()).fold(0.0, f64::max),
        )
    }

    fn coupling(row: usize, column: usize) -> f64 {
        0.1 / (1.0 + row as f64 + column as f64)
    }

    #[test]
    fn positive_definite_systems_use_cholesky() {
        let spd = |r: usize, c: usize| if r == c { 4.0 } else { coupling(r, c) };
        let (used, error) = solve_one_hex(spd, true);
        assert_eq!(used, Factorization::Cholesky);
        assert!(error < 1e-13, "{error}");
    }

    #[test]
    fn indefinite_systems_fall_back_to_lu() {
        let indefinite = |r: usize, c: usize| match (r == c, r % 2) {
            (true, 0) => 4.0,
            (true, _) => -4.0,
            _ => coupling(r, c),
        };
        let (used, error) = solve_one_hex(indefinite, true);
        assert_eq!(used, Factorization::Lu);
        assert!(error < 1e-13, "{error}");
    }

    #[test]
    fn unsymmetric_systems_use_lu() {
        let unsymmetric = |r: usize, c: usize| {
            if r == c {
                4.0
            } else {
                coupling(r, c) * if r < c { 2.0 } else { 0.5 }
            }
        };
        let (used, error) = solve_one_hex(unsymmetric, false);
        assert_eq!(used, Factorization::Lu);
        assert!(error < 1e-13, "{error}");
    }
}
