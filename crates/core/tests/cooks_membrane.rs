//! Cook's membrane, plane strain, nearly incompressible neo-Hookean (E = 240.565 MPa,
//! ν = 0.499), 100 N shear on the right edge in 5 quasi-static load steps: the locking
//! benchmark. The problem is set up in `musclefem_core::verification::cooks_membrane`; the table over
//! meshes up to 32 per side is `examples/cooks_membrane.rs`.
//!
//! Reference: the tip displacement u_y(C) ≈ 6.89 mm of the literature (F-bar hex8 at 30
//! elements per side, ν = 0.4999). It is itself a finite-element value and for a slightly
//! less compressible solid; the converged value of this problem, estimated by Richardson
//! extrapolation of the tet10 (8, 16, 32 per side: 6.494, 6.775, 6.872 mm → 6.92 mm) and
//! one-point hex8 runs (6.797, 6.918, 6.935 mm → 6.94 mm) of the table tool, is ≈ 6.93 mm,
//! 0.6 % above it; ν = 0.4999 instead of 0.499 lowers the one-point hex8 values by only
//! 0.09 % (6.911 and 6.929 mm at 16 and 32 per side). So a converging element must land
//! within a few percent of 6.89 mm at 16 per side, and a locking one far below.

use musclefem_core::element::Technology;
use musclefem_core::verification::cooks_membrane::{
    LITERATURE_TIP_DISPLACEMENT, Outcome, POISSON, solve, technologies,
};

const INCREMENTS: usize = 5;

fn run(label: &str, technology: Technology, divisions: usize) -> Outcome {
    let outcome = solve(technology, divisions, POISSON, INCREMENTS)
        .unwrap_or_else(|e| panic!("{label}, {divisions} per side: {e}"));
    println!(
        "{label:>15}, {divisions:>2} per side: tip u_y = {:.4} mm ({:.4} of 6.89 mm), \
         {} Newton iterations in {} steps ({} cuts)",
        1e3 * outcome.tip_displacement,
        outcome.tip_displacement / LITERATURE_TIP_DISPLACEMENT,
        outcome.iterations,
        outcome.steps,
        outcome.cuts
    );
    outcome
}

fn technology(label: &str) -> Technology {
    technologies(POISSON)
        .into_iter()
        .find(|(l, _)| *l == label)
        .unwrap_or_else(|| panic!("no technology '{label}'"))
        .1
}

/// Fully integrated hex8 and plain tet4 lock: at 8 elements per side (a mesh on which
/// the one-point hex8 is within 1.5 % of the reference) they reach less than half of
/// it (measured: 2.64 and 2.28 mm, i.e. 38 % and 33 %), and refining to 16 per side does
/// not bring them within 30 % either (3.48 and 2.58 mm).
#[test]
fn fully_integrated_hex8_and_tet4_lock() {
    for label in ["hex8 full", "tet4"] {
        let moderate = run(label, technology(label), 8).tip_displacement;
        assert!(
            moderate < 0.5 * LITERATURE_TIP_DISPLACEMENT,
            "{label} at 8 per side: {moderate} m does not lock"
        );
        let fine = run(label, technology(label), 16).tip_displacement;
        assert!(
            fine < 0.7 * LITERATURE_TIP_DISPLACEMENT,
            "{label} at 16 per side: {fine} m does not lock"
        );
        // Locking, not a wrong load: refining still moves the tip the right way.
        assert!(fine > moderate, "{label}: {fine} m after {moderate} m");
    }
}

/// The technologies that do not lock converge toward the reference: within 2.5 % of
/// 6.89 mm at 16 per side (measured: one-point hex8 +0.4 %, F-bar −1.0 %, tet10 −1.7 %), and closer at
/// 16 than at 8 per side. 2.5 % allows the 0.6 % between the reference and this problem's
/// converged value plus the 16-per-side discretization error of tet10 (Richardson:
/// 6.92 − 6.77 mm ≈ 2.1 %); a locking element is off by 50 % or more.
#[test]
fn one_point_hex8_fbar_and_tet10_converge_to_the_reference() {
    for label in ["hex8 one-point", "hex8 F-bar", "tet10"] {
        let coarse = run(label, technology(label), 8).tip_displacement;
        let fine = run(label, technology(label), 16).tip_displacement;
        let error = |u: f64| (u - LITERATURE_TIP_DISPLACEMENT).abs() / LITERATURE_TIP_DISPLACEMENT;
        assert!(
            error(fine) < 0.025,
            "{label} at 16 per side: {fine} m, {:.2} % off",
            100.0 * error(fine)
        );
        assert!(
            error(fine) < error(coarse),
            "{label}: no closer at 16 ({fine} m) than at 8 per side ({coarse} m)"
        );
    }
}

/// Every listed technology solves the coarsest mesh (2 per side) in its 5 steps without
/// a cut, so that a new technology added to the list is at least exercised here.
#[test]
fn every_listed_technology_solves_the_coarse_membrane() {
    for (label, technology) in technologies(POISSON) {
        let outcome = run(label, technology, 2);
        assert_eq!(outcome.steps, INCREMENTS, "{label}");
        assert!(
            outcome.tip_displacement > 0.0 && outcome.tip_displacement.is_finite(),
            "{label}"
        );
    }
}
