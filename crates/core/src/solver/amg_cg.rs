//! Conjugate gradients preconditioned with smoothed-aggregation multigrid (`amg/`) for
//! the implicit solver's symmetric positive definite tangents, and the choice between it
//! and the sparse direct solver ([`LinearSolver`]).
//!
//! Each solve stops at ‖b − K x‖₂ ≤ tol ‖b‖₂ ([`AmgCgSettings::tolerance`]); the work per
//! iteration is one product with K and one V-cycle, so the time grows about linearly with
//! the unknowns where a sparse factorization's grows as n² in 3-D. The hierarchy's
//! aggregates and tentative prolongators are built from the first tangent of a pattern and
//! kept; its numeric part is redone when the iterations have doubled ([`HierarchyReuse`]).
//!
//! Measured on the cube of issue #36 (`examples/cube_scaling.rs`: [0, 10 mm]³ of F-bar
//! hex8, neo-Hookean μ = 10 kPa, symmetry planes, x1 pulled to λ = 1.5 in 10 steps; 2
//! busy cores, 2 threads, direct and AMG-CG back to back, 2026-11-27; 40³ AMG-CG in a
//! later window than its direct run). Seconds of the whole run (linear solver alone in
//! brackets), 30–32 Newton iterations either way, CG iterations per solve, peak memory;
//! the end forces agree to 1.4e-14 relative or better:
//!
//! | cube | unknowns | ν | direct [s] | AMG-CG [s] | CG/solve | peak direct / AMG |
//! |---|---|---|---|---|---|---|
//! | 10³ | 3 509 | 0.3 | 1.18 (0.28) | 1.45 (0.67) | 10.6 | 36 / 35 MB |
//! | 10³ | 3 509 | 0.49 | 1.03 (0.20) | 2.45 (1.65) | 28.5 | 36 / 35 MB |
//! | 20³ | 26 019 | 0.3 | 11.0 (5.0) | 10.1 (5.0) | 12.1 | 328 / 252 MB |
//! | 20³ | 26 019 | 0.49 | 11.6 (5.4) | 18.2 (12.1) | 32.1 | 328 / 252 MB |
//! | 30³ | 85 529 | 0.3 | 51.0 (29.7) | 46.9 (25.1) | 12.7 | 1.28 / 0.86 GB |
//! | 30³ | 85 529 | 0.49 | 56.4 (35.6) | 63.7 (45.4) | 34.2 | 1.28 / 0.86 GB |
//! | 40³ | 200 039 | 0.3 | 136 (98) | 97 (50) | 13.7 | 3.63 / 2.04 GB |
//! | 40³ | 200 039 | 0.49 | 171 (127) | 138 (98) | 34.0 | 3.63 / 2.04 GB |
//!
//! From 20³ to 40³ AMG-CG's linear-solver time grows as n^1.13 (ν = 0.3) and n^1.03
//! (ν = 0.49), the direct solver's as n^1.46 and n^1.50. The CG iterations hardly grow
//! with the mesh, but are 2.5 times as many at ν = 0.49 (Chebyshev–Jacobi smoothing does
//! not reach the nearly incompressible modes); [`AmgCgSettings::auto_unknowns`] sits
//! where AMG-CG won at both ratios.
//!
//! Deterministic: products and V-cycles are parallel over fixed row chunks, dot products
//! summed in fixed chunks in order, so that a run is the same bit for bit on 1 and on 2
//! threads.

use std::cell::RefCell;
use std::time::Instant;

use super::amg::Multigrid;
use super::amg::csr::{Csr, dot};
use super::amg::tentative::{MODES, rigid_body_modes};
use super::krylov::{self, CgFailure};

/// Which linear solver the implicit solver uses for its symmetric tangents.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LinearSolver {
    /// Sparse factorizations (faer), with factor reuse ([`super::FactorReuse`]).
    #[default]
    Direct,
    /// Conjugate gradients preconditioned with smoothed-aggregation multigrid; the direct
    /// solver when CG does not converge (the tangent is not positive definite, or too
    /// many iterations), and for unsymmetric tangents.
    AmgCg,
    /// AMG-CG from [`AmgCgSettings::auto_unknowns`] unknowns on, direct below.
    Auto,
}

/// When the multigrid hierarchy is rebuilt.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HierarchyReuse {
    /// Numeric set-up (smoothed prolongators, Galerkin products) for every tangent.
    EveryTangent,
    /// Only the finest matrix is updated while a solve takes at most twice the
    /// iterations of the last one after a numeric set-up; then the set-up is redone.
    WhileFast,
}

/// Settings of AMG-preconditioned conjugate gradients.
#[derive(Debug, Clone, PartialEq)]
pub struct AmgCgSettings {
    /// Relative residual ‖b − K x‖ / ‖b‖ at which CG stops (default 1e-8: on the cube of
    /// issue #36, 20³ at ν = 0.3 and 0.49, the same Newton iterations as the direct
    /// solver and the end force to 1e-14; 1e-10 took 22 % more CG iterations).
    pub tolerance: f64,
    /// Iterations after which CG gives up and the direct solver takes over (default 300).
    pub max_iterations: usize,
    /// With [`LinearSolver::Auto`]: unknowns from which AMG-CG is used (default 150 000).
    pub auto_unknowns: usize,
    /// Default [`HierarchyReuse::WhileFast`]: on the 20³ cube at ν = 0.3 it took 15 CG
    /// iterations per solve against 12 with a numeric set-up for every tangent, but 0.85 s
    /// of set-up against 5.9 s (30 solves).
    pub reuse: HierarchyReuse,
}

impl Default for AmgCgSettings {
    fn default() -> Self {
        AmgCgSettings {
            tolerance: 1e-8,
            max_iterations: 300,
            auto_unknowns: 150_000,
            reuse: HierarchyReuse::WhileFast,
        }
    }
}

/// Counts and times of a run's AMG-CG solves.
#[derive(Debug, Clone, Default)]
pub struct AmgCgStatistics {
    /// Systems solved by AMG-preconditioned conjugate gradients.
    pub solves: usize,
    /// Their CG iterations.
    pub iterations: usize,
    /// Attempts that failed (the direct solver followed), and the first reasons.
    pub failures: usize,
    pub failure_reasons: Vec<String>,
    /// Unknowns of the multigrid levels and the operator complexity (last hierarchy).
    pub levels: Vec<usize>,
    pub operator_complexity: f64,
    /// Multigrid set-up (numeric included) and the CG iterations [s].
    pub setup_seconds: f64,
    pub solve_seconds: f64,
}

/// What a run's linear solves say for its log: `None` when AMG-CG was not tried, else
/// one line with its solves, CG iterations per solve, levels, operator complexity and
/// times, and the reasons it fell back to the direct solver.
pub fn amg_cg_summary(statistics: &super::sparse::LinearSolveStatistics) -> Option<String> {
    let (s, a) = (statistics, &statistics.amg);
    if a.solves == 0 && a.failures == 0 {
        return None;
    }
    let mut line = format!(
        "AMG-CG solved {} of {} systems, {:.1} CG iterations per solve, levels {:?}, \
         operator complexity {:.2}, set-up {:.2} s, iterations {:.2} s; {} direct \
         factorizations",
        a.solves,
        s.solves,
        a.iterations as f64 / a.solves.max(1) as f64,
        a.levels,
        a.operator_complexity,
        a.setup_seconds,
        a.solve_seconds,
        s.numeric_factorizations
    );
    if a.failures > 0 {
        line += &format!(
            "; {} fell back to the direct solver: {}",
            a.failures,
            a.failure_reasons.join("; ")
        );
    }
    Some(line)
}

/// The iterative solver of one sparsity pattern: the near-null space and the hierarchy.
pub(crate) struct AmgCg {
    /// Unknowns of every node with a free one, in turn (`block_ptr[b]..block_ptr[b + 1]`).
    block_ptr: Vec<usize>,
    modes: Vec<[f64; MODES]>,
    multigrid: Option<Multigrid>,
    /// Iterations of the last solve after a numeric set-up.
    fresh_iterations: Option<usize>,
}

/// Why AMG-CG did not solve a system.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum AmgCgFailure {
    /// pᵀ K p ≤ 0: K is not positive definite.
    NotPositiveDefinite { iteration: usize },
    /// rᵀ M⁻¹ r ≤ 0: the multigrid cycle is not positive definite (a smoother's
    /// eigenvalue bound too low).
    PreconditionerIndefinite { iteration: usize },
    /// No convergence within the limit; the relative residual reached.
    TooManyIterations { residual: f64 },
    /// The hierarchy could not be built.
    SetUp(String),
}

impl std::fmt::Display for AmgCgFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AmgCgFailure::NotPositiveDefinite { iteration } => write!(
                f,
                "CG met a direction of non-positive curvature at iteration {iteration} \
                 (the tangent is not positive definite)"
            ),
            AmgCgFailure::PreconditionerIndefinite { iteration } => write!(
                f,
                "the multigrid preconditioner was not positive definite at CG iteration \
                 {iteration}"
            ),
            AmgCgFailure::TooManyIterations { residual } => write!(
                f,
                "CG did not converge within the iteration limit (relative residual \
                 {residual:.2e})"
            ),
            AmgCgFailure::SetUp(reason) => write!(f, "multigrid set-up failed: {reason}"),
        }
    }
}

/// Iterations and set-up time [s] of one AMG-CG solve.
pub(crate) struct AmgCgOutcome {
    pub iterations: usize,
    pub setup_seconds: f64,
}

impl AmgCg {
    /// For the unknowns at `coordinates` [m] in directions `dofs`, numbered node after
    /// node (`node_of[i]` the node of unknown i).
    pub fn new(coordinates: &[[f64; 3]], dofs: &[u8], node_of: &[u32]) -> Self {
        let mut block_ptr = vec![0];
        for i in 1..=node_of.len() {
            if i == node_of.len() || node_of[i] != node_of[i - 1] {
                block_ptr.push(i);
            }
        }
        if node_of.is_empty() {
            block_ptr.truncate(1);
        }
        AmgCg {
            block_ptr,
            modes: rigid_body_modes(coordinates, dofs),
            multigrid: None,
            fresh_iterations: None,
        }
    }

    /// Solve K x = `rhs` in place, K given by its symmetric pattern (`col_ptr`,
    /// `row_idx`: both triangles, rows sorted) and `values`. `rhs` is unchanged on failure.
    ///
    /// The multigrid works on `values` itself, lent to its finest level for the solve and
    /// handed back before it returns (on failure too): the finest matrix's values are not
    /// copied (51 MB for the 30³ cube; `docs/implicit-speed.md`, "Memory").
    pub fn solve(
        &mut self,
        col_ptr: &[usize],
        row_idx: &[usize],
        values: &mut Vec<f64>,
        rhs: &mut [f64],
        settings: &AmgCgSettings,
    ) -> Result<AmgCgOutcome, AmgCgFailure> {
        let start = Instant::now();
        let mut fresh = true;
        match self.multigrid.as_mut() {
            None => {
                let a = Csr {
                    rows: rhs.len(),
                    cols: rhs.len(),
                    ptr: col_ptr.to_vec(),
                    idx: row_idx.iter().map(|&i| i as u32).collect(),
                    val: std::mem::take(values),
                };
                match Multigrid::new(a, &self.block_ptr, &self.modes) {
                    // It holds `values` as if lent, until the solve hands them back.
                    Ok(multigrid) => self.multigrid = Some(multigrid),
                    Err((reason, lent)) => {
                        *values = lent;
                        return Err(AmgCgFailure::SetUp(reason));
                    }
                }
            }
            Some(multigrid) => {
                multigrid.lend_finest(values);
                let keep =
                    settings.reuse == HierarchyReuse::WhileFast && self.fresh_iterations.is_some();
                if keep {
                    multigrid.update_finest();
                    fresh = false;
                } else if let Err(reason) = multigrid.refresh() {
                    multigrid.return_finest(values);
                    self.multigrid = None;
                    return Err(AmgCgFailure::SetUp(reason));
                }
            }
        }
        let setup_seconds = start.elapsed().as_secs_f64();
        let multigrid = self.multigrid.as_mut().expect("built above");
        let outcome = conjugate_gradients(multigrid, rhs, settings);
        multigrid.return_finest(values);
        match &outcome {
            Ok(iterations) if fresh => self.fresh_iterations = Some(*iterations),
            Ok(iterations) => {
                if self
                    .fresh_iterations
                    .is_some_and(|f| *iterations > 2 * f.max(1))
                {
                    self.fresh_iterations = None;
                }
            }
            Err(_) => self.fresh_iterations = None,
        }
        outcome.map(|iterations| AmgCgOutcome {
            iterations,
            setup_seconds,
        })
    }

    /// Unknowns of each multigrid level and the operator complexity (after a solve).
    pub fn describe(&self) -> Option<(Vec<usize>, f64)> {
        self.multigrid
            .as_ref()
            .map(|m| (m.level_sizes(), m.operator_complexity()))
    }
}

/// Preconditioned conjugate gradients on the multigrid's finest matrix, one V-cycle per
/// iteration (`krylov::conjugate_gradients` with the thread-count-independent `dot`).
fn conjugate_gradients(
    multigrid: &mut Multigrid,
    rhs: &mut [f64],
    settings: &AmgCgSettings,
) -> Result<usize, AmgCgFailure> {
    // The product reads the finest matrix and the V-cycle writes the levels' work
    // vectors, one after the other: a RefCell lends the multigrid to both closures.
    let multigrid = RefCell::new(multigrid);
    krylov::conjugate_gradients(
        rhs,
        settings.tolerance,
        settings.max_iterations,
        dot,
        |p, q| multigrid.borrow().matrix().multiply(p, q),
        |r, z| multigrid.borrow_mut().apply(r, z),
    )
    .map_err(|failure| match failure {
        CgFailure::NotPositiveDefinite { iteration } => {
            AmgCgFailure::NotPositiveDefinite { iteration }
        }
        CgFailure::PreconditionerIndefinite { iteration } => {
            AmgCgFailure::PreconditionerIndefinite { iteration }
        }
        CgFailure::TooManyIterations { relative_residual } => AmgCgFailure::TooManyIterations {
            residual: relative_residual,
        },
    })
}
