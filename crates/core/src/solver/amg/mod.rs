//! Smoothed-aggregation algebraic multigrid for the implicit solver's symmetric positive
//! definite tangents (Vaněk, Mandel & Brezina 1996), a preconditioner of conjugate
//! gradients (`amg_cg.rs`).
//!
//! Set-up, level after level, until at most [`COARSEST`] unknowns are left:
//! - aggregates of strongly coupled nodal blocks (`aggregation.rs`);
//! - the tentative prolongator P̂ from the rigid-body modes by a QR per aggregate
//!   (`tentative.rs`);
//! - the smoothed prolongator P = (I − ω D⁻¹A) P̂, ω = 4 / (3 λ_max(D⁻¹A)), which lowers
//!   the energy of the coarse basis functions;
//! - the Galerkin coarse operator A_c = Pᵀ A P (sparse products, `csr.rs`, taken a block
//!   of fine rows at a time, `galerkin.rs`).
//!
//! The coarsest matrix is factorized by dense Cholesky. One application of the
//! preconditioner is a V-cycle from zero with [`DEGREE`]-step Chebyshev smoothing
//! (`chebyshev.rs`) before and after the coarse correction: symmetric positive definite.
//!
//! The aggregates and tentative prolongators depend on the pattern and on the strengths
//! of the first matrix only; [`Multigrid::refresh`] redoes the numeric part (smoothed
//! prolongators, Galerkin products, smoothers, coarsest factor) for a new matrix of the
//! same pattern, as between Newton iterations.
//!
//! Every kernel is parallel over fixed chunks of rows with serial, ordered sums inside
//! (`csr.rs`): the hierarchy and its applications are the same, bit for bit, on any
//! number of threads.

mod aggregation;
mod chebyshev;
pub(crate) mod csr;
mod galerkin;
pub(crate) mod tentative;

use nalgebra::{Cholesky, DMatrix, DVector, Dyn};

use chebyshev::{Smoother, largest_eigenvalue};
use csr::Csr;
use galerkin::{galerkin_product, smoothed_prolongator};
use tentative::{MODES, tentative_prolongator};

/// Unknowns of the coarsest level, solved directly.
pub(crate) const COARSEST: usize = 600;
/// At most this many levels.
const MAX_LEVELS: usize = 12;
/// Coarsening stops when a level keeps more than this fraction of the unknowns.
const MIN_REDUCTION: f64 = 0.7;
/// Chebyshev steps before and after each coarse correction. On the 20³ cube (26 019
/// unknowns, tolerance 1e-8) CG took 21, 16, 12 and 11 iterations per solve with degrees
/// 1–4 at ν = 0.3, 70, 43 and 31 with degrees 1–3 at ν = 0.49: 3 is the robust choice
/// (at ν = 0.3 degree 1 costs about as much: fewer products per iteration).
pub(crate) const DEGREE: usize = 3;

/// One level: its matrix, smoother data, the prolongator to it from the next coarser
/// level, and the work vectors of a cycle.
struct Level {
    a: Csr,
    inverse_diagonal: Vec<f64>,
    lambda_max: f64,
    /// P and R = Pᵀ to the next coarser level (absent on the coarsest).
    transfer: Option<(Csr, Csr)>,
    b: Vec<f64>,
    x: Vec<f64>,
    r: Vec<f64>,
    d: Vec<f64>,
}

impl Level {
    fn new(a: Csr) -> Self {
        let n = a.rows;
        let inverse_diagonal = a
            .diagonal()
            .iter()
            .map(|&d| if d > 0.0 { 1.0 / d } else { 0.0 })
            .collect::<Vec<_>>();
        let lambda_max = largest_eigenvalue(&a, &inverse_diagonal);
        Level {
            a,
            inverse_diagonal,
            lambda_max,
            transfer: None,
            b: vec![0.0; n],
            x: vec![0.0; n],
            r: vec![0.0; n],
            d: vec![0.0; n],
        }
    }
}

/// The multigrid hierarchy of one matrix.
pub(crate) struct Multigrid {
    /// The tentative prolongator of each level but the coarsest.
    tentatives: Vec<Csr>,
    levels: Vec<Level>,
    coarsest: Cholesky<f64, Dyn>,
}

impl Multigrid {
    /// The hierarchy of `a` (symmetric positive definite) with nodal blocks `block_ptr`
    /// (block b holds unknowns `block_ptr[b]..block_ptr[b + 1]`) and near-null space
    /// `modes` (a row per unknown). Errors when the coarsest matrix is not positive
    /// definite, handing `a`'s values back.
    pub fn new(
        a: Csr,
        block_ptr: &[usize],
        modes: &[[f64; MODES]],
    ) -> Result<Self, (String, Vec<f64>)> {
        let mut tentatives = Vec::new();
        let mut levels = vec![Level::new(a)];
        let mut blocks = block_ptr.to_vec();
        let mut modes = modes.to_vec();
        while levels.len() < MAX_LEVELS {
            let Some(fine) = levels.last_mut() else { break };
            let n = fine.a.rows;
            if n <= COARSEST {
                break;
            }
            let strong = aggregation::strong_graph(&fine.a, &blocks);
            let (aggregate_of, count) = aggregation::aggregate(&strong);
            let (tentative, coarse_blocks, coarse_modes) =
                tentative_prolongator(&aggregate_of, count, &blocks, &modes);
            if tentative.cols as f64 > MIN_REDUCTION * n as f64 || tentative.cols == 0 {
                break;
            }
            let coarse = galerkin(fine, &tentative);
            tentatives.push(tentative);
            levels.push(Level::new(coarse));
            blocks = coarse_blocks;
            modes = coarse_modes;
        }
        let coarsest = match factorize(&levels[levels.len() - 1].a) {
            Ok(coarsest) => coarsest,
            Err(reason) => return Err((reason, std::mem::take(&mut levels[0].a.val))),
        };
        Ok(Multigrid {
            tentatives,
            levels,
            coarsest,
        })
    }

    /// Lends the finest matrix the values `values` of a matrix of its pattern (taken
    /// out, `values` left empty) until [`Self::return_finest`]. Between solves the
    /// hierarchy keeps no values of the finest matrix, only its pattern.
    pub fn lend_finest(&mut self, values: &mut Vec<f64>) {
        debug_assert!(self.levels[0].a.val.is_empty(), "values lent twice");
        std::mem::swap(&mut self.levels[0].a.val, values);
    }

    /// Hands the finest matrix's values back into `values` (empty before).
    pub fn return_finest(&mut self, values: &mut Vec<f64>) {
        std::mem::swap(&mut self.levels[0].a.val, values);
    }

    /// The same aggregates and tentative prolongators for the finest matrix's values
    /// lent last ([`Self::lend_finest`]): smoothed prolongators, coarse operators,
    /// smoothers and the coarsest factor anew. On an error the hierarchy keeps the lent
    /// values, to be returned.
    pub fn refresh(&mut self) -> Result<(), String> {
        let a = std::mem::replace(&mut self.levels[0].a, empty());
        let mut levels = vec![Level::new(a)];
        for tentative in &self.tentatives {
            let fine = levels.last_mut().expect("a level");
            let coarse = galerkin(fine, tentative);
            levels.push(Level::new(coarse));
        }
        match factorize(&levels[levels.len() - 1].a) {
            Ok(coarsest) => {
                self.coarsest = coarsest;
                self.levels = levels;
                Ok(())
            }
            Err(reason) => {
                self.levels[0].a = std::mem::replace(&mut levels[0].a, empty());
                Err(reason)
            }
        }
    }

    /// Only the finest matrix's smoother for the values lent last, of a matrix of the
    /// same pattern: the coarse levels stay those of an earlier matrix.
    pub fn update_finest(&mut self) {
        let fine = &mut self.levels[0];
        let transfer = fine.transfer.take();
        let a = std::mem::replace(&mut fine.a, empty());
        *fine = Level::new(a);
        fine.transfer = transfer;
    }

    /// Unknowns of each level, finest first.
    pub fn level_sizes(&self) -> Vec<usize> {
        self.levels.iter().map(|l| l.a.rows).collect()
    }

    /// Stored entries of all levels over those of the finest (operator complexity).
    pub fn operator_complexity(&self) -> f64 {
        let all: usize = self.levels.iter().map(|l| l.a.entries()).sum();
        all as f64 / self.levels[0].a.entries().max(1) as f64
    }

    /// The finest matrix.
    pub fn matrix(&self) -> &Csr {
        &self.levels[0].a
    }

    /// z = M⁻¹ r: one V-cycle from zero.
    pub fn apply(&mut self, r: &[f64], z: &mut [f64]) {
        self.levels[0].b.copy_from_slice(r);
        cycle(&mut self.levels, &self.coarsest);
        z.copy_from_slice(&self.levels[0].x);
    }
}

/// Sets `fine`'s smoothed prolongator from `tentative` (and its transpose) and returns
/// the Galerkin coarse operator Pᵀ A P (`galerkin.rs`).
fn galerkin(fine: &mut Level, tentative: &Csr) -> Csr {
    let omega = 4.0 / (3.0 * fine.lambda_max);
    let p = smoothed_prolongator(&fine.a, tentative, &fine.inverse_diagonal, omega);
    let r = p.transpose();
    let coarse = galerkin_product(&r, &fine.a, &p);
    fine.transfer = Some((p, r));
    coarse
}

fn empty() -> Csr {
    Csr {
        rows: 0,
        cols: 0,
        ptr: vec![0],
        idx: Vec::new(),
        val: Vec::new(),
    }
}

/// Dense Cholesky factor of a small sparse matrix.
fn factorize(a: &Csr) -> Result<Cholesky<f64, Dyn>, String> {
    let n = a.rows;
    let mut dense = DMatrix::zeros(n, n);
    for i in 0..n {
        let (cols, vals) = a.row(i);
        for (&j, &v) in cols.iter().zip(vals) {
            dense[(i, j as usize)] = v;
        }
    }
    dense.cholesky().ok_or_else(|| {
        format!("the coarsest multigrid matrix ({n} unknowns) is not positive definite")
    })
}

/// One V-cycle on `levels[0]` (its `b` in, its `x` out), recursively.
fn cycle(levels: &mut [Level], coarsest: &Cholesky<f64, Dyn>) {
    let Some((fine, coarser)) = levels.split_first_mut() else {
        return;
    };
    let Some(coarse) = coarser.first_mut() else {
        let x = coarsest.solve(&DVector::from_column_slice(&fine.b));
        fine.x.copy_from_slice(x.as_slice());
        return;
    };
    let smoother = Smoother {
        a: &fine.a,
        inverse_diagonal: &fine.inverse_diagonal,
        lambda_max: fine.lambda_max,
        degree: DEGREE,
    };
    smoother.smooth(&fine.b, &mut fine.x, &mut fine.r, &mut fine.d, true);
    fine.a.residual(&fine.b, &fine.x, &mut fine.r);
    let Some((p, r)) = &fine.transfer else { return };
    r.multiply(&fine.r, &mut coarse.b);
    cycle(coarser, coarsest);
    p.multiply(&coarser[0].x, &mut fine.d);
    for (x, c) in fine.x.iter_mut().zip(&fine.d) {
        *x += c;
    }
    smoother.smooth(&fine.b, &mut fine.x, &mut fine.r, &mut fine.d, false);
}

#[cfg(test)]
mod tests;
