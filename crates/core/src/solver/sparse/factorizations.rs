//! The factorizations of the implicit solver's sparse system (see `sparse.rs`): the
//! Cholesky analysis in the order that fills less, Cholesky, LBLᵀ for symmetric
//! indefinite tangents (accepted by its backward error), LU, and conjugate gradients
//! preconditioned with the last Cholesky factor.

use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::SparseColMat;
use faer::sparse::linalg::cholesky::{
    IntranodeLbltRef, LltRef, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::linalg::lu::{NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::{Conj, Par, Side};

use super::super::krylov::{preconditioned_cg, preconditioned_gmres};
use super::{EquationOrder, FactorReuse, SparseSystem, SymmetricFactor};

/// The fill-reducing order of a symmetric factorization.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FillReducingOrder {
    /// Geometric nested dissection of the nodes (`ordering.rs`).
    NestedDissection,
    /// METIS's multilevel nested dissection of the nodes (`ordering.rs`).
    MultilevelNestedDissection,
    /// faer's approximate minimum degree.
    MinimumDegree,
}

impl FillReducingOrder {
    pub fn name(self) -> &'static str {
        match self {
            FillReducingOrder::NestedDissection => "geometric nested dissection",
            FillReducingOrder::MultilevelNestedDissection => "METIS nested dissection",
            FillReducingOrder::MinimumDegree => "approximate minimum degree",
        }
    }
}

/// The symbolic Cholesky analysis (given ordering, elimination tree, supernodes), done once,
/// with room for the numeric factor and the scratch memory.
pub(super) struct Cholesky {
    pub(super) symbolic: SymbolicCholesky<usize>,
    order: FillReducingOrder,
    factor: Vec<f64>,
    /// LBLᵀ's subdiagonal of B and its pivoting permutation (used only for indefinite
    /// tangents), and a copy of the right-hand side and room for K x to check that solve.
    subdiagonal: Vec<f64>,
    pivot_forward: Vec<usize>,
    pivot_inverse: Vec<usize>,
    right_hand_side: Vec<f64>,
    product: Vec<f64>,
    scratch: MemBuffer,
}

/// Largest normwise backward error ‖b − K x‖∞ / (‖K‖∞ ‖x‖∞ + ‖b‖∞) of an accepted LBLᵀ
/// solve; a larger one (pivoting restricted to a supernode can fail to contain growth)
/// goes to LU. A stable factorization reaches ~1e-16.
const LBLT_BACKWARD_ERROR: f64 = 1e-12;

/// The symbolic LU analysis (COLAMD ordering), done once, with the numeric factor and the
/// scratch memory.
pub(super) struct Lu {
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    scratch: MemBuffer,
}

impl SparseSystem {
    /// The symbolic Cholesky analysis, on the first call.
    fn analyse_cholesky(&mut self) -> Result<(), String> {
        if self.llt.is_none() {
            let start = Instant::now();
            let cholesky = Cholesky::new(&self.matrix, &self.orders, self.par)?;
            self.statistics.factor_entries = cholesky.factor.len();
            self.statistics.ordering = Some(cholesky.order);
            self.llt = Some(cholesky);
            self.statistics.symbolic_seconds += start.elapsed().as_secs_f64();
        }
        Ok(())
    }

    /// Cholesky of K and the solve of K x = `rhs` in place; faer's reason when K is not
    /// positive definite (then `rhs` is unchanged).
    pub(super) fn factorize_cholesky(&mut self, rhs: &mut [f64]) -> Result<(), String> {
        let (n, par) = (self.size(), self.par);
        self.analyse_cholesky()?;
        let start = Instant::now();
        let cholesky = self.llt.as_mut().expect("just built");
        let stack = MemStack::new(&mut cholesky.scratch);
        let numeric = cholesky.symbolic.factorize_numeric_llt(
            &mut cholesky.factor,
            self.matrix.as_ref(),
            Side::Lower,
            Default::default(),
            par,
            stack,
            Default::default(),
        );
        self.statistics.numeric_factorizations += 1;
        self.statistics.numeric_seconds += start.elapsed().as_secs_f64();
        let llt = numeric.map_err(|e| format!("{e:?}"))?;
        let start = Instant::now();
        llt.solve_in_place_with_conj(
            Conj::No,
            faer::MatMut::from_column_major_slice_mut(rhs, n, 1),
            par,
            stack,
        );
        self.statistics.substitution_seconds += start.elapsed().as_secs_f64();
        Ok(())
    }

    /// LBLᵀ of a symmetric indefinite K (after a failed Cholesky attempt, so the symbolic
    /// analysis exists) and the solve of K x = `rhs` in place, accepted when its backward
    /// error is at most [`LBLT_BACKWARD_ERROR`]; otherwise `rhs` is unchanged.
    pub(super) fn factorize_symmetric_indefinite(&mut self, rhs: &mut [f64]) -> Result<(), String> {
        let par = self.par;
        if self.llt.is_none() {
            return Err("no symbolic analysis (Cholesky was not attempted)".to_string());
        }
        self.numeric_lblt();
        let cholesky = self.llt.as_mut().expect("checked above");
        cholesky.right_hand_side.copy_from_slice(rhs);
        let start = Instant::now();
        cholesky.solve_lblt(rhs, par);
        // The backward error ‖b − K x‖∞ / (‖K‖∞ ‖x‖∞ + ‖b‖∞).
        let largest = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let product = &mut cholesky.product;
        multiply(&self.matrix, rhs, product);
        let r_norm = product
            .iter()
            .zip(&cholesky.right_hand_side)
            .fold(0.0_f64, |m, (kx, b)| m.max((b - kx).abs()));
        let (b_norm, x_norm) = (largest(&cholesky.right_hand_side), largest(rhs));
        let k_norm = infinity_norm(&self.matrix);
        self.statistics.substitution_seconds += start.elapsed().as_secs_f64();
        let backward_error = r_norm / (k_norm * x_norm + b_norm);
        // (A NaN would slip through the folds of maxima: check x itself.)
        let finite = rhs.iter().all(|x| x.is_finite());
        if finite && backward_error <= LBLT_BACKWARD_ERROR {
            return Ok(());
        }
        rhs.copy_from_slice(&cholesky.right_hand_side);
        Err(if finite {
            format!("backward error {backward_error:.1e}")
        } else {
            "the solution is not finite (a zero pivot)".to_string()
        })
    }

    /// LU of K and the solve of K x = `rhs` in place.
    pub(super) fn factorize_lu(&mut self, rhs: &mut [f64]) -> Result<(), String> {
        let (n, par) = (self.size(), self.par);
        if self.lu.is_none() {
            let start = Instant::now();
            self.lu = Some(Lu::new(&self.matrix, par)?);
            self.statistics.symbolic_seconds += start.elapsed().as_secs_f64();
        }
        let start = Instant::now();
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
            .map_err(|e| format!("{e:?}"))?;
        self.statistics.numeric_factorizations += 1;
        self.statistics.numeric_seconds += start.elapsed().as_secs_f64();
        let start = Instant::now();
        factor.solve_in_place_with_conj(
            Conj::No,
            faer::MatMut::from_column_major_slice_mut(rhs, n, 1),
            par,
            stack,
        );
        self.statistics.substitution_seconds += start.elapsed().as_secs_f64();
        if rhs.iter().any(|x| !x.is_finite()) {
            return Err("the solution is not finite (singular stiffness)".to_string());
        }
        Ok(())
    }

    /// Conjugate gradients preconditioned with the Cholesky factor at hand, to the
    /// relative residual `tolerance`.
    pub(super) fn cg_with_cholesky(
        &mut self,
        rhs: &mut [f64],
        reuse: &FactorReuse,
        tolerance: f64,
    ) -> Option<usize> {
        let (par, matrix) = (self.par, &self.matrix);
        let cholesky = self.llt.as_mut()?;
        preconditioned_cg(
            rhs,
            tolerance,
            reuse.max_iterations,
            |x, y| multiply(matrix, x, y),
            |v| cholesky.solve_llt(v, par),
        )
    }
}

impl SparseSystem {
    /// LBLᵀ of the stored (symmetric) K in the Cholesky analysis, kept for
    /// [`Self::gmres_with_factor`]; faer's reason when it fails or the factor is not
    /// finite.
    pub(super) fn factorize_lblt(&mut self) -> Result<(), String> {
        self.analyse_cholesky()?;
        self.numeric_lblt();
        let cholesky = self.llt.as_ref().expect("just built");
        if cholesky.factor.iter().all(|v| v.is_finite())
            && cholesky.subdiagonal.iter().all(|v| v.is_finite())
        {
            Ok(())
        } else {
            Err("the LBLᵀ factor is not finite".to_string())
        }
    }

    /// The numeric LBLᵀ factorization of the stored K into the Cholesky analysis's
    /// storage (the analysis must exist), counted and timed.
    fn numeric_lblt(&mut self) {
        let par = self.par;
        let cholesky = self.llt.as_mut().expect("the Cholesky analysis exists");
        let start = Instant::now();
        let stack = MemStack::new(&mut cholesky.scratch);
        cholesky.symbolic.factorize_numeric_intranode_lblt(
            &mut cholesky.factor,
            &mut cholesky.subdiagonal,
            &mut cholesky.pivot_forward,
            &mut cholesky.pivot_inverse,
            self.matrix.as_ref(),
            Side::Lower,
            par,
            stack,
            Default::default(),
        );
        self.statistics.numeric_factorizations += 1;
        self.statistics.indefinite_factorizations += 1;
        self.statistics.numeric_seconds += start.elapsed().as_secs_f64();
    }

    /// GMRES on K x = `rhs` (K as stored, unsymmetric), preconditioned with the
    /// Cholesky analysis's factor at hand, LLᵀ or LBLᵀ as `kind` says.
    pub(super) fn gmres_with_factor(
        &mut self,
        rhs: &mut [f64],
        kind: SymmetricFactor,
        tolerance: f64,
        max_iterations: usize,
    ) -> Option<usize> {
        let (par, matrix) = (self.par, &self.matrix);
        let cholesky = self.llt.as_mut()?;
        preconditioned_gmres(
            rhs,
            tolerance,
            max_iterations,
            |x, y| multiply(matrix, x, y),
            |v| match kind {
                SymmetricFactor::Cholesky => cholesky.solve_llt(v, par),
                SymmetricFactor::Lblt => cholesky.solve_lblt(v, par),
            },
        )
    }
}

/// ‖K‖∞, the largest row sum of |K_ij| (the largest column sum: K is symmetric here).
fn infinity_norm(matrix: &SparseColMat<usize, f64>) -> f64 {
    let col_ptr = matrix.symbolic().col_ptr();
    let values = matrix.val();
    (0..matrix.ncols())
        .map(|c| {
            values[col_ptr[c]..col_ptr[c + 1]]
                .iter()
                .map(|v| v.abs())
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}

/// y = K x (both triangles are stored; serial, so the sums do not depend on the thread
/// count).
pub(super) fn multiply(matrix: &SparseColMat<usize, f64>, x: &[f64], y: &mut [f64]) {
    let symbolic = matrix.symbolic();
    let (col_ptr, row_idx) = (symbolic.col_ptr(), symbolic.row_idx());
    let values = matrix.val();
    y.fill(0.0);
    for (column, &xc) in x.iter().enumerate() {
        let range = col_ptr[column]..col_ptr[column + 1];
        for (&row, &value) in row_idx[range.clone()].iter().zip(&values[range]) {
            y[row] += value * xc;
        }
    }
}

impl Cholesky {
    /// v ← (LLᵀ)⁻¹ v with the Cholesky factor held.
    fn solve_llt(&mut self, v: &mut [f64], par: Par) {
        let n = self.pivot_forward.len();
        let stack = MemStack::new(&mut self.scratch);
        LltRef::new(&self.symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            faer::MatMut::from_column_major_slice_mut(v, n, 1),
            par,
            stack,
        );
    }

    /// v ← (LBLᵀ)⁻¹ v with the LBLᵀ factor held.
    fn solve_lblt(&mut self, v: &mut [f64], par: Par) {
        let n = self.pivot_forward.len();
        let stack = MemStack::new(&mut self.scratch);
        IntranodeLbltRef::new(
            &self.symbolic,
            &self.factor,
            &self.subdiagonal,
            PermRef::new_checked(&self.pivot_forward, &self.pivot_inverse, n),
        )
        .solve_in_place_with_conj(
            Conj::No,
            faer::MatMut::from_column_major_slice_mut(v, n, 1),
            par,
            stack,
        );
    }

    /// The symbolic analysis in whichever of the `candidates` and faer's AMD order gives
    /// the factor fewer entries (the analyses cost a few percent of one numeric
    /// factorization).
    fn new(
        matrix: &SparseColMat<usize, f64>,
        candidates: &[EquationOrder],
        par: Par,
    ) -> Result<Self, String> {
        let n = matrix.ncols();
        let analyse = |ordering| {
            factorize_symbolic_cholesky(
                matrix.symbolic(),
                Side::Lower,
                ordering,
                Default::default(),
            )
            .map_err(|e| format!("symbolic Cholesky: {e:?}"))
        };
        let (mut symbolic, mut order) = (
            analyse(SymmetricOrdering::Amd)?,
            FillReducingOrder::MinimumDegree,
        );
        for candidate in candidates {
            let permutation = PermRef::new_checked(&candidate.order, &candidate.inverse, n);
            let analysis = analyse(SymmetricOrdering::Custom(permutation))?;
            if analysis.len_val() < symbolic.len_val() {
                (symbolic, order) = (analysis, candidate.kind);
            }
        }
        let scratch = symbolic
            .factorize_numeric_llt_scratch::<f64>(par, Default::default())
            .or(symbolic.factorize_numeric_intranode_lblt_scratch::<f64>(par, Default::default()))
            .or(symbolic.solve_in_place_scratch::<f64>(1, par));
        let scratch = MemBuffer::try_new(scratch)
            .map_err(|e| format!("scratch memory of the Cholesky factorization: {e:?}"))?;
        Ok(Cholesky {
            factor: vec![0.0; symbolic.len_val()],
            symbolic,
            order,
            subdiagonal: vec![0.0; n],
            pivot_forward: vec![0; n],
            pivot_inverse: vec![0; n],
            right_hand_side: vec![0.0; n],
            product: vec![0.0; n],
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
