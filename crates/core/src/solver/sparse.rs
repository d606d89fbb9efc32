//! The implicit solver's linear system: the free degrees of freedom, the sparsity pattern of
//! the stiffness built once from the element connectivity, and the solves with faer:
//! supernodal Cholesky LLᵀ, symbolic analysis done once per pattern and reused, in the
//! fill-reducing order that gives the smallest factor: geometric nested dissection of the
//! nodes, METIS's multilevel nested dissection of the nodes (both in `ordering.rs`) or
//! faer's approximate minimum degree (AMD). A symmetric tangent that is not positive
//! definite (contact, an active muscle, F-bar) is factorized LBLᵀ with Bunch–Kaufman
//! pivoting inside the supernodes of the same analysis; LU when that solve is not accurate
//! or the tangent is not symmetric. While the last Cholesky factor is a good
//! preconditioner, conjugate gradients preconditioned with it (`krylov.rs`) instead of a
//! new factorization ([`FactorReuse`]).
//!
//! The matrix holds only free degrees of freedom (prescribed ones are eliminated) and
//! stores both triangles, so that LU and the product K x can use it; Cholesky reads the
//! lower one.
//!
//! Factor entries of the three orders (2026-11-24):
//!
//! | system | unknowns | geometric | METIS | AMD |
//! |---|---|---|---|---|
//! | free 20 × 20 × 20 hex8 block | 27 783 | 1.79e7 | 1.82e7 | 2.97e7 |
//! | coarse knee (four bonded, curved muscles) | 5 412 | 2.52e6 | 0.96e6 | 1.22e6 |
//! | medium knee | 31 428 | 3.39e7 | 1.17e7 | 1.83e7 |
//!
//! A numeric factorization of the medium knee's first tangent alone (serial, 2-core AMD
//! EPYC) took 1.0 s in the geometric order, 0.36 s in AMD's and 0.18 s in METIS's (of the
//! equation graph); in the medium active squat 0.10 s on average in METIS's order of the
//! nodes against 0.17 s in AMD's, run after run on the same machine (the whole default run
//! 307 s against 386 s).
//!
//! One preconditioned conjugate-gradient iteration on a 26 019-unknown cube (a pair of
//! triangular solves and a product) costs 0.04–0.06 s, and within a load step of the
//! uniaxial stretch 5–7 of them reach 1e-12.

use std::time::Instant;

use faer::Par;
use faer::sparse::{SparseColMat, SymbolicSparseColMat};

use nalgebra::Vector3;

use super::amg_cg::{AmgCg, AmgCgSettings, AmgCgStatistics};
#[cfg(feature = "metis")]
use super::ordering::multilevel_nested_dissection;
use super::ordering::{NodeGraph, nested_dissection};
use crate::mesh::ElementBlock;

/// Marks a prescribed degree of freedom in the equation map.
pub(crate) const PRESCRIBED: u32 = u32::MAX;

/// Factors s of the mass term tried on an indefinite dynamic tangent: K + (s − 1) M c is
/// the tangent of an increment √s times shorter. Measured on the active knee squat
/// (2026-11-24): coarse 190 increments, 955 iterations, 27 cuts (8 after an indefinite
/// tangent), against 240, 1241 and 38 (26) with LBLᵀ on K; medium 174, 917 and 20 (12)
/// against 184, 951 and 26 (21).
pub const MASS_SHIFTS: [f64; 3] = [4.0, 16.0, 64.0];

/// Which factorization solved a system.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Factorization {
    /// Sparse Cholesky LLᵀ (symmetric positive definite).
    Cholesky,
    /// Sparse LBLᵀ (symmetric indefinite; Bunch–Kaufman pivoting within supernodes).
    SymmetricIndefinite,
    /// Sparse LU with partial pivoting.
    Lu,
    /// GMRES on an unsymmetric K, preconditioned with the Cholesky factor of its
    /// symmetric part ½(K + Kᵀ) ([`GMRES_TOLERANCE`]).
    SymmetricPartGmres,
    /// Conjugate gradients preconditioned with smoothed-aggregation multigrid
    /// (`amg_cg.rs`), no factorization.
    AmgCg,
}

/// Relative residual ‖b − K x‖ / ‖b‖ at which GMRES on an unsymmetric tangent stops
/// (LU's solves reach ~1e-14; Newton's convergence tests sit far above both).
pub const GMRES_TOLERANCE: f64 = 1e-10;

/// Most GMRES iterations on an unsymmetric tangent before LU takes over.
pub const GMRES_MAX_ITERATIONS: usize = 40;

/// The factor of an unsymmetric tangent's symmetric part that preconditions GMRES.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum SymmetricFactor {
    /// LLᵀ: the symmetric part is positive definite.
    Cholesky,
    /// LBLᵀ (Bunch–Kaufman within supernodes): it is indefinite.
    Lblt,
}

/// The stiffness of the free degrees of freedom and its factorizations.
pub(crate) struct SparseSystem {
    matrix: SparseColMat<usize, f64>,
    /// Parallelism of the factorizations and solves.
    par: Par,
    /// Nested-dissection orders of the equations (see `ordering.rs`), candidates for the
    /// Cholesky's order besides faer's AMD.
    orders: Vec<EquationOrder>,
    llt: Option<Cholesky>,
    lu: Option<Lu>,
    /// Whether `llt` holds a factor of an earlier matrix of this pattern that is still a
    /// good preconditioner (the last conjugate-gradient solve with it took at most
    /// [`FactorReuse::refactor_above`] iterations).
    cholesky_is_fresh: bool,
    /// For every stored entry (r, c), where (c, r) is stored (`None` until an unsymmetric
    /// K is first shifted; `Some(empty)` when the pattern is not symmetric).
    transpose: Option<Vec<usize>>,
    statistics: LinearSolveStatistics,
    /// Per unknown: its node's reference coordinates [m], direction and node (for the
    /// multigrid's rigid-body modes and nodal blocks).
    geometry: (Vec<[f64; 3]>, Vec<u8>, Vec<u32>),
    /// AMG-CG settings when the next symmetric solves should try it first.
    iterative: Option<AmgCgSettings>,
    /// AMG-CG's hierarchy for this pattern (built at its first use).
    amg: Option<AmgCg>,
    /// AMG-CG ran out of iterations: the direct solver from then on.
    amg_given_up: bool,
    /// Relative residual at which the next iterative solve may stop, when looser than
    /// its own tolerance (Newton's forcing term, [`Self::set_forcing`]); 0: its own.
    forcing: f64,
}

/// Reuse of the last Cholesky factor: while it is fresh, a symmetric system is solved by
/// conjugate gradients preconditioned with the factor of an earlier stiffness M = L Lᵀ
/// (each iteration one product with K and one pair of triangular solves, a few percent
/// of a numeric factorization), to ‖b − K x‖ ≤ `tolerance` ‖b‖, so Newton's corrections
/// are those of the current tangent and its convergence stays quadratic. When the
/// iterations do not converge within `max_iterations`, K is factorized afresh and solved
/// directly; after a solve that took more than `refactor_above` iterations the next one
/// factorizes afresh (for a solve stopped at a looser tolerance η by Newton's forcing
/// term, more than `refactor_above` · ln η / ln `tolerance`, rounded up: the same mean
/// reduction per iteration).
#[derive(Debug, Clone, PartialEq)]
pub struct FactorReuse {
    pub tolerance: f64,
    pub max_iterations: usize,
    pub refactor_above: usize,
}

impl FactorReuse {
    /// Iterations a solve to the relative residual `tolerance` may take for the factor to
    /// stay fresh: `refactor_above` at [`FactorReuse::tolerance`], in proportion to
    /// ln `tolerance` at a looser one.
    pub fn iterations_allowed(&self, tolerance: f64) -> usize {
        if tolerance <= self.tolerance {
            return self.refactor_above;
        }
        (self.refactor_above as f64 * tolerance.ln() / self.tolerance.ln()).ceil() as usize
    }
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
    /// Indefinite tangents solved instead with a larger mass term
    /// ([`SparseSystem::solve`]'s `mass_shift`).
    pub mass_shifted_factorizations: usize,
    /// AMG-CG's solves (boxed: a run's result travels in an enum).
    pub amg: Box<AmgCgStatistics>,
    pub symbolic_seconds: f64,
    pub numeric_seconds: f64,
    /// Triangular solves, Krylov iterations included.
    pub substitution_seconds: f64,
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
        // Fill-reducing orders of the equations, from orders of the nodes.
        #[cfg(feature = "metis")]
        let unknowns: Vec<u8> = equation
            .chunks_exact(3)
            .map(|dofs| dofs.iter().filter(|&&eq| eq != PRESCRIBED).count() as u8)
            .collect();
        #[cfg_attr(not(feature = "metis"), allow(unused_mut))]
        let mut orders = vec![EquationOrder::of_nodes(
            FillReducingOrder::NestedDissection,
            &nested_dissection(&graph, positions),
            equation,
            free,
        )];
        #[cfg(feature = "metis")]
        match multilevel_nested_dissection(&graph, &unknowns) {
            Ok(nodes) => orders.push(EquationOrder::of_nodes(
                FillReducingOrder::MultilevelNestedDissection,
                &nodes,
                equation,
                free,
            )),
            Err(reason) => eprintln!("warning: {reason}; METIS's order is not tried"),
        }
        let mut geometry = (
            Vec::with_capacity(free),
            Vec::with_capacity(free),
            Vec::new(),
        );
        for (d, &eq) in equation.iter().enumerate() {
            if eq != PRESCRIBED {
                debug_assert_eq!(eq as usize, geometry.0.len(), "equations in node order");
                let x = positions[d / 3];
                geometry.0.push([x.x, x.y, x.z]);
                geometry.1.push((d % 3) as u8);
                geometry.2.push((d / 3) as u32);
            }
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
            orders,
            llt: None,
            lu: None,
            cholesky_is_fresh: false,
            transpose: None,
            statistics: LinearSolveStatistics::default(),
            geometry,
            iterative: None,
            amg: None,
            amg_given_up: false,
            forcing: 0.0,
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

    /// Where each column's entries start in [`Self::values_mut`] (n + 1 of them).
    pub fn column_starts(&self) -> &[usize] {
        self.matrix.symbolic().col_ptr()
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

    /// Offer no earlier factor for reuse: the next solve factorizes afresh (after a
    /// checkpoint, so that a run and its resumption take the same path).
    pub fn forget_factorization(&mut self) {
        self.cholesky_is_fresh = false;
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
    ///
    /// With `mass_shift` (per equation: where its diagonal entry is stored and its mass
    /// term m c [N/m]), an indefinite K is first retried as K + (s − 1) M c for s = 4, 16
    /// and 64, the tangents of increments 2, 4 and 8 times shorter, with the first that
    /// Cholesky accepts (see [`MASS_SHIFTS`]); LBLᵀ follows on K itself when none does.
    /// An unsymmetric K is shifted when its symmetric part is indefinite
    /// ([`Self::solve_unsymmetric`]).
    pub fn solve(
        &mut self,
        rhs: &mut [f64],
        symmetric: bool,
        reuse: Option<&FactorReuse>,
        mass_shift: Option<(&[usize], &[f64])>,
    ) -> Result<Factorization, String> {
        self.statistics.solves += 1;
        if symmetric && self.try_amg_cg(rhs) {
            return Ok(Factorization::AmgCg);
        }
        if let (Some(reuse), true, true) = (reuse, symmetric, self.cholesky_is_fresh) {
            let start = Instant::now();
            let tolerance = reuse.tolerance.max(self.forcing);
            let outcome = self.cg_with_cholesky(rhs, reuse, tolerance);
            self.statistics.substitution_seconds += start.elapsed().as_secs_f64();
            if let Some(iterations) = outcome {
                self.statistics.krylov_solves += 1;
                self.statistics.krylov_iterations += iterations;
                self.cholesky_is_fresh = iterations <= reuse.iterations_allowed(tolerance);
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
            if let Some((positions, masses)) = mass_shift
                && self.factorize_mass_shifted(rhs, positions, masses)
            {
                return Ok(Factorization::Cholesky);
            }
            match self.factorize_symmetric_indefinite(rhs) {
                Ok(()) => return Ok(Factorization::SymmetricIndefinite),
                Err(e) => symmetric_errors = Some((cholesky_error, e)),
            }
        }
        if !symmetric {
            return self.solve_unsymmetric(rhs, mass_shift);
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

    /// Cholesky of K + (s − 1) M c for the [`MASS_SHIFTS`] s in turn; true at the first
    /// that succeeds, with `rhs` solved in place and the matrix left shifted (the next
    /// evaluation refills it; the factor is not offered for reuse), else false with K and
    /// `rhs` unchanged.
    fn factorize_mass_shifted(
        &mut self,
        rhs: &mut [f64],
        positions: &[usize],
        masses: &[f64],
    ) -> bool {
        let mut added = 0.0;
        for shift in MASS_SHIFTS {
            let values = self.matrix.val_mut();
            for (&position, &mass) in positions.iter().zip(masses) {
                values[position] += (shift - 1.0 - added) * mass;
            }
            added = shift - 1.0;
            if self.factorize_cholesky(rhs).is_ok() {
                self.statistics.mass_shifted_factorizations += 1;
                return true;
            }
        }
        let values = self.matrix.val_mut();
        for (&position, &mass) in positions.iter().zip(masses) {
            values[position] -= added * mass;
        }
        false
    }

    /// Statistics of the solves so far.
    pub fn statistics(&self) -> &LinearSolveStatistics {
        &self.statistics
    }
}

/// An order of the equations: `order[k]` is the equation eliminated k-th, `inverse` its
/// inverse.
pub(crate) struct EquationOrder {
    kind: FillReducingOrder,
    order: Vec<usize>,
    inverse: Vec<usize>,
}

impl EquationOrder {
    /// The order that numbers the free unknowns of each node in turn, the nodes in
    /// `node_order`; `equation` as in [`SparseSystem::new`].
    fn of_nodes(
        kind: FillReducingOrder,
        node_order: &[u32],
        equation: &[u32],
        free: usize,
    ) -> Self {
        let mut order = Vec::with_capacity(free);
        for &node in node_order {
            for dof in 0..3 {
                let eq = equation[3 * node as usize + dof];
                if eq != PRESCRIBED {
                    order.push(eq as usize);
                }
            }
        }
        assert_eq!(order.len(), free, "the node order misses unknowns");
        let mut inverse = vec![0usize; free];
        for (new, &old) in order.iter().enumerate() {
            inverse[old] = new;
        }
        EquationOrder {
            kind,
            order,
            inverse,
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

mod factorizations;

mod unsymmetric;

mod iterative;

pub use factorizations::FillReducingOrder;
use factorizations::{Cholesky, Lu};

#[cfg(test)]
mod tests;
