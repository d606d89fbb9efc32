//! The implicit solver's linear system: the free degrees of freedom, the sparsity pattern of
//! the stiffness built once from the element connectivity, and the solves with faer:
//! supernodal Cholesky LLᵀ, symbolic analysis done once per pattern and reused, in the
//! fill-reducing order that gives the smaller factor: nested dissection of the nodes
//! (`ordering.rs`) or faer's approximate minimum degree (AMD). A symmetric tangent that is
//! not positive definite (contact, an active muscle, F-bar) is factorized LBLᵀ with
//! Bunch–Kaufman pivoting inside the supernodes of the same analysis; LU when that solve
//! is not accurate or the tangent is not symmetric. While the last Cholesky factor is a
//! good preconditioner, conjugate gradients preconditioned with it (`krylov.rs`) instead
//! of a new factorization ([`FactorReuse`]).
//!
//! The matrix holds only free degrees of freedom (prescribed ones are eliminated) and
//! stores both triangles, so that LU and the product K x can use it; Cholesky reads the
//! lower one.
//!
//! Measured on a 20 × 20 × 20 hex8 cube (26 019 unknowns, 1.88e6 stored entries), 2 busy
//! cores: faer's default AMD order gives a factor of 2.84e7 entries and 4.0 s per numeric
//! factorization; the nested-dissection order 1.64e7 entries and 1.0 s. One preconditioned
//! conjugate-gradient iteration (a pair of triangular solves and a product) costs
//! 0.04–0.06 s, and within a load step of the uniaxial stretch 5–7 of them reach 1e-12.
//! On the coarse knee (5412 unknowns; four bonded, curved muscles) the order is reversed:
//! nested dissection 2.52e6 entries, AMD 1.22e6.

use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    LltRef, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::linalg::lu::{NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::{Conj, Par, Side};

use nalgebra::Vector3;

use super::krylov::preconditioned_cg;
use super::ordering::{NodeGraph, nested_dissection};
use crate::mesh::ElementBlock;

/// Marks a prescribed degree of freedom in the equation map.
pub(crate) const PRESCRIBED: u32 = u32::MAX;

/// Which factorization solved a system.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Factorization {
    /// Sparse Cholesky LLᵀ (symmetric positive definite).
    Cholesky,
    /// Sparse LBLᵀ (symmetric indefinite; Bunch–Kaufman pivoting within supernodes).
    SymmetricIndefinite,
    /// Sparse LU with partial pivoting.
    Lu,
}

/// The stiffness of the free degrees of freedom and its factorizations.
pub(crate) struct SparseSystem {
    matrix: SparseColMat<usize, f64>,
    /// Parallelism of the factorizations and solves.
    par: Par,
    /// Nested-dissection order of the equations (see `ordering.rs`): `order[k]` is the
    /// equation eliminated k-th, `inverse` its inverse. One of the two candidates for the
    /// Cholesky's order.
    order: Vec<usize>,
    inverse: Vec<usize>,
    llt: Option<Cholesky>,
    lu: Option<Lu>,
    /// Whether `llt` holds a factor of an earlier matrix of this pattern that is still a
    /// good preconditioner (the last conjugate-gradient solve with it took at most
    /// [`FactorReuse::refactor_above`] iterations).
    cholesky_is_fresh: bool,
    statistics: LinearSolveStatistics,
}

/// Reuse of the last Cholesky factor: while it is fresh, a symmetric system is solved by
/// conjugate gradients preconditioned with the factor of an earlier stiffness M = L Lᵀ
/// (each iteration one product with K and one pair of triangular solves, a few percent
/// of a numeric factorization), to ‖b − K x‖ ≤ `tolerance` ‖b‖, so Newton's corrections
/// are those of the current tangent and its convergence stays quadratic. When the
/// iterations do not converge within `max_iterations`, K is factorized afresh and solved
/// directly; after a solve that took more than `refactor_above` iterations the next one
/// factorizes afresh.
#[derive(Debug, Clone, PartialEq)]
pub struct FactorReuse {
    pub tolerance: f64,
    pub max_iterations: usize,
    pub refactor_above: usize,
}

impl Default for FactorReuse {
    /// Tolerance 1e-12, at most 30 iterations, refactorize after a solve of more than 12.
    fn default() -> Self {
        FactorReuse {
            tolerance: 1e-12,
            max_iterations: 30,
            refactor_above: 12,
        }
    }
}

/// Counts and wall-clock times [s] of a run's linear solves.
#[derive(Debug, Clone, Default)]
pub struct LinearSolveStatistics {
    /// Linear systems solved.
    pub solves: usize,
    /// Of which by a Krylov method preconditioned with an earlier factor.
    pub krylov_solves: usize,
    /// Iterations of the converged conjugate-gradient solves.
    pub krylov_iterations: usize,
    /// Conjugate-gradient attempts that did not converge (a factorization followed).
    pub krylov_failures: usize,
    /// Numeric factorizations (Cholesky or LU).
    pub numeric_factorizations: usize,
    /// Entries of the Cholesky factor (0 before the first).
    pub factor_entries: usize,
    /// The fill-reducing order of the Cholesky factor (`None` before the first).
    pub ordering: Option<FillReducingOrder>,
    /// Factorizations LBLᵀ of symmetric indefinite tangents (each after a failed
    /// Cholesky attempt, counted in `numeric_factorizations` too).
    pub indefinite_factorizations: usize,
    pub symbolic_seconds: f64,
    pub numeric_seconds: f64,
    /// Triangular solves, Krylov iterations included.
    pub substitution_seconds: f64,
}

/// The fill-reducing order of a symmetric factorization.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FillReducingOrder {
    /// Geometric nested dissection of the nodes (`ordering.rs`).
    NestedDissection,
    /// faer's approximate minimum degree.
    MinimumDegree,
}

impl FillReducingOrder {
    pub fn name(self) -> &'static str {
        match self {
            FillReducingOrder::NestedDissection => "nested dissection",
            FillReducingOrder::MinimumDegree => "approximate minimum degree",
        }
    }
}

/// The symbolic Cholesky analysis (given ordering, elimination tree, supernodes), done once,
/// with room for the numeric factor and the scratch memory.
struct Cholesky {
    symbolic: SymbolicCholesky<usize>,
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
    ///
    /// `coupled_pairs` are node pairs (a, b) coupled beyond the elements (interactions);
    /// each couples both ways.
    pub fn new<'a>(
        positions: &[Vector3<f64>],
        equation: &[u32],
        free: usize,
        blocks: impl Iterator<Item = &'a ElementBlock>,
        coupled_pairs: &[(u32, u32)],
        parallel_unknowns: usize,
    ) -> Self {
        let graph = node_graph(positions.len(), blocks, coupled_pairs);
        let mut col_ptr = Vec::with_capacity(free + 1);
        col_ptr.push(0usize);
        let mut row_idx = Vec::new();
        for node in 0..graph.len() {
            for dof in 0..3 {
                if equation[3 * node + dof] == PRESCRIBED {
                    continue;
                }
                for &m in graph.neighbours(node) {
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
        // Fill-reducing order of the equations: the nodes' nested-dissection order.
        let mut order = Vec::with_capacity(free);
        for node in nested_dissection(&graph, positions) {
            for dof in 0..3 {
                let eq = equation[3 * node as usize + dof];
                if eq != PRESCRIBED {
                    order.push(eq as usize);
                }
            }
        }
        let mut inverse = vec![0usize; free];
        for (new, &old) in order.iter().enumerate() {
            inverse[old] = new;
        }
        let values = vec![0.0; row_idx.len()];
        let symbolic = SymbolicSparseColMat::new_checked(free, free, col_ptr, None, row_idx);
        SparseSystem {
            matrix: SparseColMat::new(symbolic, values),
            par: if free >= parallel_unknowns {
                Par::rayon(0)
            } else {
                Par::Seq
            },
            order,
            inverse,
            llt: None,
            lu: None,
            cholesky_is_fresh: false,
            statistics: LinearSolveStatistics::default(),
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

    /// Where entry (`row`, `column`) is stored, `None` if it is not in the pattern.
    pub fn find(&self, row: usize, column: usize) -> Option<usize> {
        let symbolic = self.matrix.symbolic();
        let start = symbolic.col_ptr()[column];
        let rows = &symbolic.row_idx()[start..symbolic.col_ptr()[column + 1]];
        rows.binary_search(&row).ok().map(|offset| start + offset)
    }

    /// Carries the solve counts and times of `earlier` (a system this one replaces).
    pub fn continue_statistics(&mut self, earlier: &SparseSystem) {
        self.statistics = earlier.statistics.clone();
    }

    pub fn values_mut(&mut self) -> &mut [f64] {
        self.matrix.val_mut()
    }

    /// Solve K x = `rhs` in place. K symmetric, with `reuse` and the Cholesky factor of an
    /// earlier matrix of this pattern at hand and still fresh: by conjugate gradients
    /// preconditioned with it (see [`FactorReuse`]). Otherwise (or when that fails) a new
    /// factorization:
    /// Cholesky when K is symmetric (symbolic analysis done on the first call and reused),
    /// LBLᵀ on the same analysis when Cholesky finds K not positive definite; LU when K is
    /// not symmetric or the LBLᵀ solve is not accurate. Errors with faer's reason when
    /// none works. Cholesky is tried again at every factorization: on the coarse knee an
    /// LBLᵀ costs about 1.6 Cholesky factorizations, and going to LBLᵀ at once for the
    /// rest of a step after a failure made the passive squat's factorizations 9 % slower
    /// (584 LBLᵀ instead of 217).
    pub fn solve(
        &mut self,
        rhs: &mut [f64],
        symmetric: bool,
        reuse: Option<&FactorReuse>,
    ) -> Result<Factorization, String> {
        self.statistics.solves += 1;
        if let (Some(reuse), true, true) = (reuse, symmetric, self.cholesky_is_fresh) {
            let start = Instant::now();
            let outcome = self.cg_with_cholesky(rhs, reuse);
            self.statistics.substitution_seconds += start.elapsed().as_secs_f64();
            if let Some(iterations) = outcome {
                self.statistics.krylov_solves += 1;
                self.statistics.krylov_iterations += iterations;
                self.cholesky_is_fresh = iterations <= reuse.refactor_above;
                return Ok(Factorization::Cholesky);
            }
            self.statistics.krylov_failures += 1;
        }
        self.cholesky_is_fresh = false;
        let mut symmetric_errors = None;
        if symmetric {
            let cholesky_error = match self.factorize_cholesky(rhs) {
                Ok(()) => {
                    self.cholesky_is_fresh = true;
                    return Ok(Factorization::Cholesky);
                }
                Err(e) => e,
            };
            match self.factorize_symmetric_indefinite(rhs) {
                Ok(()) => return Ok(Factorization::SymmetricIndefinite),
                Err(e) => symmetric_errors = Some((cholesky_error, e)),
            }
        }
        self.factorize_lu(rhs)
            .map_err(|e| match &symmetric_errors {
                Some((c, b)) => {
                    format!("Cholesky failed ({c}), LBLᵀ failed ({b}), then LU failed ({e})")
                }
                None => format!("LU failed ({e})"),
            })?;
        Ok(Factorization::Lu)
    }

    /// Cholesky of K and the solve of K x = `rhs` in place; faer's reason when K is not
    /// positive definite (then `rhs` is unchanged).
    fn factorize_cholesky(&mut self, rhs: &mut [f64]) -> Result<(), String> {
        let (n, par) = (self.size(), self.par);
        if self.llt.is_none() {
            let start = Instant::now();
            let order = PermRef::new_checked(&self.order, &self.inverse, n);
            let cholesky = Cholesky::new(&self.matrix, order, par)?;
            self.statistics.factor_entries = cholesky.factor.len();
            self.statistics.ordering = Some(cholesky.order);
            self.llt = Some(cholesky);
            self.statistics.symbolic_seconds += start.elapsed().as_secs_f64();
        }
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
    fn factorize_symmetric_indefinite(&mut self, rhs: &mut [f64]) -> Result<(), String> {
        let (n, par) = (self.size(), self.par);
        let cholesky = self
            .llt
            .as_mut()
            .ok_or("no symbolic analysis (Cholesky was not attempted)")?;
        cholesky.right_hand_side.copy_from_slice(rhs);
        let start = Instant::now();
        let stack = MemStack::new(&mut cholesky.scratch);
        let factor = cholesky.symbolic.factorize_numeric_intranode_lblt(
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
        let start = Instant::now();
        factor.solve_in_place_with_conj(
            Conj::No,
            faer::MatMut::from_column_major_slice_mut(rhs, n, 1),
            par,
            stack,
        );
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
    fn factorize_lu(&mut self, rhs: &mut [f64]) -> Result<(), String> {
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

    /// Conjugate gradients preconditioned with the Cholesky factor at hand.
    fn cg_with_cholesky(&mut self, rhs: &mut [f64], reuse: &FactorReuse) -> Option<usize> {
        let (n, par, matrix) = (self.size(), self.par, &self.matrix);
        let cholesky = self.llt.as_mut()?;
        preconditioned_cg(
            rhs,
            reuse.tolerance,
            reuse.max_iterations,
            |x, y| multiply(matrix, x, y),
            |v| {
                let stack = MemStack::new(&mut cholesky.scratch);
                LltRef::new(&cholesky.symbolic, &cholesky.factor).solve_in_place_with_conj(
                    Conj::No,
                    faer::MatMut::from_column_major_slice_mut(v, n, 1),
                    par,
                    stack,
                );
            },
        )
    }

    /// Statistics of the solves so far.
    pub fn statistics(&self) -> &LinearSolveStatistics {
        &self.statistics
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
fn multiply(matrix: &SparseColMat<usize, f64>, x: &[f64], y: &mut [f64]) {
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

/// The node graph of the elements of `blocks` over `node_count` nodes.
fn node_graph<'a>(
    node_count: usize,
    blocks: impl Iterator<Item = &'a ElementBlock>,
    coupled_pairs: &[(u32, u32)],
) -> NodeGraph {
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); node_count];
    for block in blocks {
        for ids in block.elements() {
            for &a in ids {
                neighbours[a as usize].extend_from_slice(ids);
            }
        }
    }
    for &(a, b) in coupled_pairs {
        neighbours[a as usize].extend([a, b]);
        neighbours[b as usize].extend([a, b]);
    }
    let mut offsets = Vec::with_capacity(node_count + 1);
    offsets.push(0);
    let mut targets = Vec::new();
    for list in &mut neighbours {
        list.sort_unstable();
        list.dedup();
        targets.extend_from_slice(list);
        offsets.push(targets.len());
    }
    NodeGraph { offsets, targets }
}

impl Cholesky {
    /// The symbolic analysis in `nested_dissection` or in faer's AMD order, whichever
    /// gives the factor fewer entries (the analyses cost a few percent of one numeric
    /// factorization).
    fn new(
        matrix: &SparseColMat<usize, f64>,
        nested_dissection: PermRef<'_, usize>,
        par: Par,
    ) -> Result<Self, String> {
        let analyse = |ordering| {
            factorize_symbolic_cholesky(
                matrix.symbolic(),
                Side::Lower,
                ordering,
                Default::default(),
            )
            .map_err(|e| format!("symbolic Cholesky: {e:?}"))
        };
        let dissected = analyse(SymmetricOrdering::Custom(nested_dissection))?;
        let minimum_degree = analyse(SymmetricOrdering::Amd)?;
        let (symbolic, order) = if minimum_degree.len_val() < dissected.len_val() {
            (minimum_degree, FillReducingOrder::MinimumDegree)
        } else {
            (dissected, FillReducingOrder::NestedDissection)
        };
        let scratch = symbolic
            .factorize_numeric_llt_scratch::<f64>(par, Default::default())
            .or(symbolic.factorize_numeric_intranode_lblt_scratch::<f64>(par, Default::default()))
            .or(symbolic.solve_in_place_scratch::<f64>(1, par));
        let scratch = MemBuffer::try_new(scratch)
            .map_err(|e| format!("scratch memory of the Cholesky factorization: {e:?}"))?;
        let n = matrix.ncols();
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

#[cfg(test)]
#[path = "sparse_tests.rs"]
mod tests;
