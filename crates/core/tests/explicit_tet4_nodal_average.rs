//! The nodally averaged tet4 in the explicit solver: a slow uniaxial stretch against the
//! closed-form homogeneous solution, bit-identical results on 1 and 2 threads, and the
//! implicit solver's refusal.

use std::collections::BTreeMap;
use std::sync::Arc;

use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::{TetOrder, box_of_tets, distort};
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit};
use musclefem_core::solver::implicit::{ImplicitSettings, run_quasi_static};
use musclefem_core::solver::{Part, PrescribedDisplacement, SolverError};
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

const SIDE: f64 = 0.01;
/// Shear modulus μ [Pa] and bulk modulus κ = 2/D [Pa] of the test material.
const SHEAR_MODULUS: f64 = 1e4;
const BULK_MODULUS: f64 = 1e5;

fn neo_hookean() -> Arc<dyn Material> {
    let params = BTreeMap::from([
        ("mu".to_string(), SHEAR_MODULUS),
        ("D".to_string(), 2.0 / BULK_MODULUS),
    ]);
    MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap()
}

/// Smooth ramp 0 → `value` over `duration` (3s² − 2s³, 41 knots).
fn smooth_ramp(duration: f64, value: f64) -> Amplitude {
    let knots = (0..=40)
        .map(|i| {
            let s = i as f64 / 40.0;
            (s * duration, value * s * s * (3.0 - 2.0 * s))
        })
        .collect();
    Amplitude::new(knots).unwrap()
}

/// Symmetry on x0, y0, z0 and the x1 face pulled along x by `stretch − 1` of the side.
fn uniaxial(mesh: &Mesh, stretch: f64, duration: f64) -> Vec<PrescribedDisplacement> {
    let fixed = |set: &str, dof: usize| PrescribedDisplacement {
        nodes: mesh.node_set(set).unwrap().to_vec(),
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    };
    vec![
        PrescribedDisplacement {
            nodes: mesh.node_set("x1").unwrap().to_vec(),
            dof: 0,
            amplitude: smooth_ramp(duration, (stretch - 1.0) * SIDE),
        },
        fixed("x0", 0),
        fixed("y0", 1),
        fixed("z0", 2),
    ]
}

fn parts(technology: Technology) -> Vec<Part> {
    vec![Part {
        block: 0,
        technology,
        material: neo_hookean(),
        density: 1000.0,
    }]
}

/// Closed-form uniaxial stress of the neo-Hookean solid σ = (μ/J) dev B̄ + κ(J − 1) I at
/// F = diag(λ, t, t): the lateral stretch t solves σ₂₂ = 0 (bisection), and the nominal
/// stress is P₁₁ = J σ₁₁ / λ [Pa]. Returns (P₁₁, t).
fn uniaxial_stress(stretch: f64) -> (f64, f64) {
    let cauchy = |t: f64| {
        let j = stretch * t * t;
        let scale = SHEAR_MODULUS / j * j.powf(-2.0 / 3.0);
        let mean = (stretch * stretch + 2.0 * t * t) / 3.0;
        let pressure = BULK_MODULUS * (j - 1.0);
        (
            scale * (stretch * stretch - mean) + pressure,
            scale * (t * t - mean) + pressure,
        )
    };
    let (mut low, mut high) = (0.5, 1.0);
    for _ in 0..100 {
        let mid = 0.5 * (low + high);
        // σ₂₂ grows with t.
        if cauchy(mid).1 > 0.0 {
            high = mid;
        } else {
            low = mid;
        }
    }
    let t = 0.5 * (low + high);
    (stretch * t * t * cauchy(t).0 / stretch, t)
}

/// A distorted 2 × 2 × 2 tet cube (48 tets) stretched slowly to λ = 1.5 with free
/// lateral faces: the reaction on x1 matches P₁₁(1.5) A₀ of the closed form within 0.1 %,
/// and the lateral stretch its t within 0.1 % (the slow ramp leaves 3e-5).
#[test]
fn slow_uniaxial_stretch_matches_the_closed_form() {
    let mut mesh = box_of_tets([SIDE; 3], [2, 2, 2], TetOrder::Linear).unwrap();
    assert!(distort(&mut mesh, 0.3, 5).unwrap() > 0);
    let result = run_explicit(
        &mesh,
        &parts(Technology::Tet4NodalAverage),
        &uniaxial(&mesh, 1.5, 2.0).into(),
        &ExplicitSettings::new(2.0),
    )
    .unwrap();
    let (nominal, lateral) = uniaxial_stress(1.5);
    let expected = nominal * SIDE * SIDE;
    let last = result.history.last().unwrap();
    let reaction = last.reactions[0];
    let y1 = mesh.node_set("y1").unwrap()[0] as usize;
    let t = 1.0 + result.displacement[y1][1] / SIDE;
    println!(
        "{} steps, reaction {reaction:.6} N, closed form {expected:.6} N; lateral stretch \
         {t:.5} vs {lateral:.5}; W_int {:.3e} J, W_ext {:.3e} J, K {:.3e} J",
        result.steps, last.internal_energy, last.external_work, last.kinetic_energy
    );
    assert!(
        (reaction - expected).abs() < 1e-3 * expected,
        "{reaction} vs {expected}"
    );
    assert!((t - lateral).abs() < 1e-3 * lateral, "{t} vs {lateral}");
}

/// The same run gives bit-identical displacements and histories on 1 and 2 threads
/// (750 tets: 12 chunks updated in parallel in each pass).
#[test]
fn results_do_not_depend_on_the_thread_count() {
    let mesh = box_of_tets([SIDE; 3], [5, 5, 5], TetOrder::Linear).unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            run_explicit(
                &mesh,
                &parts(Technology::Tet4NodalAverage),
                &uniaxial(&mesh, 1.1, 0.02).into(),
                &ExplicitSettings::new(0.02),
            )
            .unwrap()
        })
    };
    let (one, two) = (run(1), run(2));
    assert!(one.steps > 10);
    assert!(one.displacement.iter().any(|u| u[1] != 0.0));
    assert_eq!(one.displacement, two.displacement);
    assert_eq!(one.history, two.history);
}

/// The implicit solver has no tangent for the nodally averaged tet4 and says so, naming
/// the technology.
#[test]
fn the_implicit_solver_refuses_it_by_name() {
    let mesh = box_of_tets([SIDE; 3], [1, 1, 1], TetOrder::Linear).unwrap();
    let parts = parts(Technology::Tet4NodalAverage);
    let err = run_quasi_static(
        &mesh,
        &parts,
        &uniaxial(&mesh, 1.1, 1.0).into(),
        &ImplicitSettings::new(1.0, 2),
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            SolverError::NoConsistentTangent {
                technology: Technology::Tet4NodalAverage,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("Tet4NodalAverage"), "{err}");
}

/// The plain tet4 stable step also bounds the averaged tet4 (the averaging only lowers the
/// volumetric stiffness, see `element/tet4_nodal_average.rs`): a nearly incompressible
/// (κ/μ = 500) distorted tet box, pulled to 5 % stretch in 2 ms and left to ring, runs
/// 0.03 s at the full stable step (safety 1); the energy balance W_int + K − W_ext stays
/// within 1 % of W_ext after the ramp (an instability would grow without bound).
#[test]
fn the_plain_tet4_stable_step_is_stable() {
    let mut mesh = box_of_tets([SIDE; 3], [3, 3, 3], TetOrder::Linear).unwrap();
    assert!(distort(&mut mesh, 0.3, 9).unwrap() > 0);
    let params = BTreeMap::from([
        ("mu".to_string(), SHEAR_MODULUS),
        ("D".to_string(), 2.0 / (500.0 * SHEAR_MODULUS)),
    ]);
    let material = MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap();
    let parts = vec![Part {
        block: 0,
        technology: Technology::Tet4NodalAverage,
        material,
        density: 1000.0,
    }];
    let prescribed = uniaxial(&mesh, 1.05, 0.002);
    let mut settings = ExplicitSettings::new(0.03);
    settings.safety_factor = 1.0;
    let result = run_explicit(&mesh, &parts, &prescribed.clone().into(), &settings).unwrap();
    let balance = |row: &musclefem_core::solver::explicit::HistoryRow| {
        row.internal_energy + row.kinetic_energy - row.external_work
    };
    let after_ramp: Vec<_> = result.history.iter().filter(|r| r.time > 0.0025).collect();
    let drift = after_ramp
        .iter()
        .map(|r| (balance(r) - balance(after_ramp[0])).abs())
        .fold(0.0, f64::max);
    let last = result.history.last().unwrap();
    println!(
        "{} steps, W_int {:.3e} J, K {:.3e} J, W_ext {:.3e} J, drift of the balance after \
         the ramp {drift:.2e} J",
        result.steps, last.internal_energy, last.kinetic_energy, last.external_work
    );
    assert!(result.steps > 1000, "{}", result.steps);
    // It rings (no damping) and the balance holds after the ramp.
    assert!(last.kinetic_energy > 1e-2 * last.internal_energy);
    assert!(drift < 1e-2 * last.external_work, "{drift}");
}
