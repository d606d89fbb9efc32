//! Tests of the sparse system (`sparse.rs`).
use faer::Side;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{SymmetricOrdering, factorize_symbolic_cholesky};

use super::*;
use crate::mesh::generate::box_of_hexes;

/// A system over the 24 unknowns of one free hex8 (full 24 × 24 pattern), with the
/// values `entry(row, column)`; solves K x = K 1 and returns the factorization used
/// and the largest error of x.
fn solve_one_hex(entry: impl Fn(usize, usize) -> f64, symmetric: bool) -> (Factorization, f64) {
    let mut system = one_hex_system();
    assert_eq!(system.entries(), 24 * 24);
    let mut rhs = fill(&mut system, entry);
    let used = system.solve(&mut rhs, symmetric, None, None).unwrap();
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

/// A system over the 24 unknowns of one free hex8.
fn one_hex_system() -> SparseSystem {
    let mesh = box_of_hexes([1.0; 3], [1, 1, 1]).unwrap();
    let equation: Vec<u32> = (0..24).collect();
    let positions: Vec<_> = (0..8).map(|n| mesh.nodes.position(n)).collect();
    SparseSystem::new(
        &positions,
        &equation,
        24,
        mesh.blocks.iter(),
        &[],
        usize::MAX,
    )
}

/// Set the values of `system` to `entry(row, column)`; returns K 1.
fn fill(system: &mut SparseSystem, entry: impl Fn(usize, usize) -> f64) -> Vec<f64> {
    for row in 0..24 {
        for column in 0..24 {
            let p = system.position(row, column);
            system.values_mut()[p] = entry(row, column);
        }
    }
    (0..24)
        .map(|r| (0..24).map(|c| entry(r, c)).sum())
        .collect()
}

/// Diagonal 4 and `scale` × the coupling off it.
fn nearby(scale: f64) -> impl Fn(usize, usize) -> f64 {
    move |r, c| if r == c { 4.0 } else { scale * coupling(r, c) }
}

/// After a factorization of K₀, K₁ = K₀ + 10 % off-diagonal coupling is solved by
/// conjugate gradients preconditioned with K₀'s factor, to the direct solution of
/// K₁ x = K₁ 1 within 1e-11, without a new factorization.
#[test]
fn a_nearby_matrix_is_solved_with_the_factor_at_hand() {
    let mut system = one_hex_system();
    let reuse = FactorReuse::default();
    let mut rhs = fill(&mut system, nearby(1.0));
    system.solve(&mut rhs, true, Some(&reuse), None).unwrap();
    assert_eq!(system.statistics().numeric_factorizations, 1);
    let mut rhs = fill(&mut system, nearby(1.1));
    assert_eq!(
        system.solve(&mut rhs, true, Some(&reuse), None).unwrap(),
        Factorization::Cholesky
    );
    let statistics = system.statistics();
    assert_eq!(statistics.numeric_factorizations, 1);
    assert_eq!(statistics.krylov_solves, 1);
    assert!(statistics.krylov_iterations >= 1);
    let error = rhs.iter().map(|x| (x - 1.0).abs()).fold(0.0, f64::max);
    assert!(error < 1e-11, "{error}");
}

#[test]
fn indefinite_symmetric_systems_use_lblt() {
    let indefinite = |r: usize, c: usize| match (r == c, r % 2) {
        (true, 0) => 4.0,
        (true, _) => -4.0,
        _ => coupling(r, c),
    };
    let (used, error) = solve_one_hex(indefinite, true);
    assert_eq!(used, Factorization::SymmetricIndefinite);
    assert!(error < 1e-13, "{error}");
}

/// A zero diagonal (a saddle point: unknowns coupled only to others) needs 2 × 2 pivots.
/// faer factorizes a system this small simplicially, LDLᵀ without pivoting: it meets a
/// zero pivot, the solve is rejected and LU takes it, accurately.
#[test]
fn a_symmetric_system_lblt_cannot_pivot_goes_to_lu() {
    let saddle = |r: usize, c: usize| {
        if r == c {
            0.0
        } else if r / 2 == c / 2 {
            3.0
        } else {
            coupling(r, c)
        }
    };
    let (used, error) = solve_one_hex(saddle, true);
    assert_eq!(used, Factorization::Lu);
    assert!(error < 1e-13, "{error}");
}

/// An unsymmetric K whose symmetric part is positive definite: GMRES preconditioned
/// with the symmetric part's Cholesky factor, to [`GMRES_TOLERANCE`]; no LU.
#[test]
fn unsymmetric_systems_with_a_definite_symmetric_part_use_gmres() {
    let unsymmetric = |r: usize, c: usize| {
        if r == c {
            4.0
        } else {
            coupling(r, c) * if r < c { 2.0 } else { 0.5 }
        }
    };
    let mut system = one_hex_system();
    let mut rhs = fill(&mut system, unsymmetric);
    let used = system.solve(&mut rhs, false, None, None).unwrap();
    assert_eq!(used, Factorization::SymmetricPartGmres);
    let error = rhs.iter().map(|x| (x - 1.0).abs()).fold(0.0, f64::max);
    assert!(error < 1e-9, "{error}");
    let statistics = system.statistics();
    assert_eq!(statistics.krylov_solves, 1);
    assert!(statistics.krylov_iterations <= 24);
    // The matrix is left as it was (not symmetrized): K 1 is still K 1.
    let mut product = vec![0.0; 24];
    factorizations::multiply(&system.matrix, &[1.0; 24], &mut product);
    for (row, p) in product.iter().enumerate() {
        let expected: f64 = (0..24).map(|c| unsymmetric(row, c)).sum();
        assert!((p - expected).abs() < 1e-15);
    }
}

/// An unsymmetric K whose symmetric part is indefinite (a strongly skew coupling of
/// two unknowns): GMRES preconditioned with the symmetric part's LBLᵀ factor.
#[test]
fn unsymmetric_systems_with_an_indefinite_symmetric_part_use_gmres_with_lblt() {
    let unsymmetric = |r: usize, c: usize| match (r, c) {
        _ if r == c => 4.0,
        (0, 1) => 50.0,
        (1, 0) => -30.0,
        _ => coupling(r, c),
    };
    let mut system = one_hex_system();
    let mut rhs = fill(&mut system, unsymmetric);
    let used = system.solve(&mut rhs, false, None, None).unwrap();
    assert_eq!(used, Factorization::SymmetricPartGmres);
    let statistics = system.statistics();
    assert_eq!(statistics.indefinite_factorizations, 1);
    assert_eq!(statistics.krylov_solves, 1);
    let error = rhs.iter().map(|x| (x - 1.0).abs()).fold(0.0, f64::max);
    assert!(error < 1e-9, "{error}");
}

/// A K whose symmetric part is a poor preconditioner (10⁻³ I under a skew coupling of
/// order 1 over 2187 unknowns): GMRES does not converge in [`GMRES_MAX_ITERATIONS`]
/// and LU solves it.
#[test]
fn an_unsymmetric_system_gmres_cannot_solve_goes_to_lu() {
    let skew = |r: usize, c: usize| {
        if r == c {
            1e-3
        } else if r < c {
            0.1 + coupling(r, c)
        } else {
            -0.1 - coupling(c, r)
        }
    };
    let (mut system, mut rhs) = hex_block_system(skew);
    let used = system.solve(&mut rhs, false, None, None).unwrap();
    assert_eq!(used, Factorization::Lu);
    assert_eq!(system.statistics().krylov_failures, 1);
    let error = rhs.iter().map(|x| (x - 1.0).abs()).fold(0.0, f64::max);
    assert!(error < 1e-8, "{error}");
}

/// A system over the 2187 unknowns of a free 8 × 8 × 8 block of hexes with the values
/// `entry(row, column)` on its pattern; returns it and K 1.
fn hex_block_system(entry: impl Fn(usize, usize) -> f64) -> (SparseSystem, Vec<f64>) {
    let mesh = box_of_hexes([1.0; 3], [8, 8, 8]).unwrap();
    let nodes = mesh.nodes.len();
    let positions: Vec<_> = (0..nodes).map(|n| mesh.nodes.position(n)).collect();
    let equation: Vec<u32> = (0..3 * nodes as u32).collect();
    let mut system = SparseSystem::new(
        &positions,
        &equation,
        3 * nodes,
        mesh.blocks.iter(),
        &[],
        usize::MAX,
    );
    let mut k_one = vec![0.0; system.size()];
    for column in 0..system.size() {
        let symbolic = system.matrix.symbolic();
        let range = symbolic.col_ptr()[column]..symbolic.col_ptr()[column + 1];
        let rows: Vec<usize> = symbolic.row_idx()[range.clone()].to_vec();
        for (offset, row) in range.zip(rows) {
            system.values_mut()[offset] = entry(row, column);
            k_one[row] += entry(row, column);
        }
    }
    (system, k_one)
}

/// The Cholesky analysis keeps whichever of the two nested dissections and AMD gives the
/// smallest factor; on a block of hexes that is a nested dissection, and AMD's factor is
/// larger.
#[test]
fn the_cholesky_order_is_the_one_with_the_smallest_factor() {
    // A diagonally dominant symmetric matrix on the pattern.
    let (mut system, mut rhs) = hex_block_system(|r, c| if r == c { 100.0 } else { -0.5 });
    assert_eq!(
        system.solve(&mut rhs, true, None, None).unwrap(),
        Factorization::Cholesky
    );
    let analysed = |ordering| {
        factorize_symbolic_cholesky(
            system.matrix.symbolic(),
            Side::Lower,
            ordering,
            Default::default(),
        )
        .unwrap()
        .len_val()
    };
    let amd = analysed(SymmetricOrdering::Amd);
    let mut smallest = (amd, FillReducingOrder::MinimumDegree);
    for candidate in &system.orders {
        let permutation = PermRef::new_checked(&candidate.order, &candidate.inverse, system.size());
        let entries = analysed(SymmetricOrdering::Custom(permutation));
        println!("{:?}: {entries} factor entries", candidate.kind);
        if entries < smallest.0 {
            smallest = (entries, candidate.kind);
        }
    }
    let statistics = system.statistics();
    println!(
        "{} unknowns: {:?} factor {} entries, AMD {amd}",
        system.size(),
        statistics.ordering,
        statistics.factor_entries,
    );
    assert_eq!(system.orders.len(), 2);
    assert_eq!(statistics.ordering, Some(smallest.1));
    assert_eq!(statistics.factor_entries, smallest.0);
    assert_ne!(smallest.1, FillReducingOrder::MinimumDegree);
    assert!(statistics.factor_entries < amd);
}

/// A symmetric indefinite system of a 2187-unknown pattern (diagonal ±100, so Cholesky
/// fails) is solved by LBLᵀ, supernodal with Bunch–Kaufman pivoting at this size, to the
/// exact solution within 1e-12.
#[test]
fn a_large_symmetric_indefinite_system_is_solved_by_lblt() {
    let (mut system, mut rhs) = hex_block_system(|row, column| match (row == column, row % 3) {
        (true, 0) => -100.0,
        (true, _) => 100.0,
        _ => 0.5 + 0.01 * ((row + column) % 7) as f64,
    });
    assert_eq!(
        system.solve(&mut rhs, true, None, None).unwrap(),
        Factorization::SymmetricIndefinite
    );
    assert!(matches!(
        system.llt.as_ref().unwrap().symbolic.raw(),
        faer::sparse::linalg::cholesky::SymbolicCholeskyRaw::Supernodal(_)
    ));
    let error = rhs.iter().map(|x| (x - 1.0).abs()).fold(0.0, f64::max);
    assert!(error < 1e-12, "{error}");
}

/// An indefinite K (one diagonal entry −1) with a mass term of 1 per equation: K + 3 M c
/// (the first shift, s = 4) is positive definite, so the correction solves
/// (K + 3 M c) x = b by Cholesky.
#[test]
fn an_indefinite_tangent_is_solved_with_the_first_mass_shift_cholesky_accepts() {
    let entry = |r: usize, c: usize| match (r == c, r) {
        (true, 5) => -1.0,
        (true, _) => 4.0,
        _ => coupling(r, c),
    };
    let mut system = one_hex_system();
    let rhs = fill(&mut system, entry);
    let positions: Vec<usize> = (0..24).map(|e| system.position(e, e)).collect();
    let masses = vec![1.0; 24];
    let mut x = rhs.clone();
    let used = system
        .solve(&mut x, true, None, Some((&positions, &masses)))
        .unwrap();
    assert_eq!(used, Factorization::Cholesky);
    assert_eq!(system.statistics().mass_shifted_factorizations, 1);
    // (K + 3 I) x = K 1.
    for (row, &b) in rhs.iter().enumerate() {
        let shifted: f64 = (0..24)
            .map(|c| (entry(row, c) + if row == c { 3.0 } else { 0.0 }) * x[c])
            .sum();
        assert!(
            (shifted - b).abs() < 1e-12,
            "row {row}: {shifted} against {b}"
        );
    }
    // K itself, refilled (as every evaluation does) and solved without the shift, needs
    // LBLᵀ: the shift was needed.
    let mut again = rhs.clone();
    fill(&mut system, entry);
    assert_eq!(
        system.solve(&mut again, true, None, None).unwrap(),
        Factorization::SymmetricIndefinite
    );
}

/// When no mass shift makes K definite (a diagonal entry −1000, shifts of at most 63),
/// LBLᵀ solves K itself: the exact solution of K x = K 1.
#[test]
fn a_tangent_no_mass_shift_makes_definite_is_solved_as_it_is() {
    let entry = |r: usize, c: usize| match (r == c, r) {
        (true, 5) => -1000.0,
        (true, _) => 4.0,
        _ => coupling(r, c),
    };
    let mut system = one_hex_system();
    let mut x = fill(&mut system, entry);
    let positions: Vec<usize> = (0..24).map(|e| system.position(e, e)).collect();
    let masses = vec![1.0; 24];
    let used = system
        .solve(&mut x, true, None, Some((&positions, &masses)))
        .unwrap();
    assert_eq!(used, Factorization::SymmetricIndefinite);
    assert_eq!(system.statistics().mass_shifted_factorizations, 0);
    let error = x.iter().map(|v| (v - 1.0).abs()).fold(0.0, f64::max);
    assert!(error < 1e-12, "{error}");
}

/// An unsymmetric K with one diagonal entry −1 and a mass term of 1 per equation, and
/// b = e₅: K's own correction has negative curvature (x₅ < 0), its symmetric part is
/// indefinite and that of K + 3 M c is not, so the correction is taken from K + 3 M c
/// (by GMRES with the latter's Cholesky factor); a definite one is solved as it is.
#[test]
fn an_unsymmetric_tangent_with_an_indefinite_symmetric_part_is_shifted_by_the_mass() {
    let entry = |r: usize, c: usize| match (r == c, r) {
        (true, 5) => -1.0,
        (true, _) => 4.0,
        _ => coupling(r, c) * if r < c { 2.0 } else { 0.5 },
    };
    let mut system = one_hex_system();
    fill(&mut system, entry);
    let positions: Vec<usize> = (0..24).map(|e| system.position(e, e)).collect();
    let masses = vec![1.0; 24];
    let b: Vec<f64> = (0..24).map(|r| if r == 5 { 1.0 } else { 0.0 }).collect();
    let mut x = b.clone();
    let used = system
        .solve(&mut x, false, None, Some((&positions, &masses)))
        .unwrap();
    assert_eq!(used, Factorization::SymmetricPartGmres);
    assert_eq!(system.statistics().mass_shifted_factorizations, 1);
    assert!(x[5] > 0.0, "{x:?}");
    for (row, &b) in b.iter().enumerate() {
        let shifted: f64 = (0..24)
            .map(|c| (entry(row, c) + if row == c { 3.0 } else { 0.0 }) * x[c])
            .sum();
        assert!(
            (shifted - b).abs() < GMRES_TOLERANCE,
            "row {row}: {shifted} against {b}"
        );
    }
    // A definite unsymmetric K (diagonal 4): K itself (by GMRES, its symmetric part being
    // definite), the solution of K x = K 1 to GMRES's tolerance.
    let definite = |r: usize, c: usize| if r == c { 4.0 } else { entry(r, c) };
    let mut system = one_hex_system();
    let mut x = fill(&mut system, definite);
    let used = system
        .solve(&mut x, false, None, Some((&positions, &masses)))
        .unwrap();
    assert_eq!(used, Factorization::SymmetricPartGmres);
    assert_eq!(system.statistics().mass_shifted_factorizations, 0);
    assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-9), "{x:?}");
}
