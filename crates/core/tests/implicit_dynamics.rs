//! Implicit dynamics (Newmark, trapezoidal rule, lumped mass) against the first
//! longitudinal mode of a slender bar.

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::sync::Arc;

use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::implicit::{ImplicitSettings, Newmark, run_quasi_static};
use musclefem_core::solver::{Loads, NodalForce, Part, PrescribedDisplacement};
use musclefem_materials::{Amplitude, MaterialLibrary};

/// Bar length along x and side of its square section [m].
const LENGTH: f64 = 0.1;
const SIDE: f64 = 0.01;
/// Neo-Hookean μ [Pa], D [1/Pa] (K = 2/D = 100 kPa) and density [kg/m³].
const MU: f64 = 1e4;
const D: f64 = 2e-5;
const DENSITY: f64 = 1000.0;

/// Young's modulus E = 9Kμ/(3K + μ) [Pa].
fn young_modulus() -> f64 {
    let bulk = 2.0 / D;
    9.0 * bulk * MU / (3.0 * bulk + MU)
}

/// The bar fixed along x at x0 (y0, z0 symmetry planes: a quarter of a 2 × SIDE square
/// bar), a constant force switched on at t = 0 on the nodes of the free end x1.
fn bar() -> (Mesh, Vec<Part>, Loads) {
    let mesh = box_of_hexes([LENGTH, SIDE, SIDE], [20, 2, 2]).unwrap();
    let params = BTreeMap::from([("mu".to_string(), MU), ("D".to_string(), D)]);
    let material: Arc<_> = MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap();
    let parts = vec![Part {
        block: 0,
        technology: Technology::Hex8Full,
        material,
        density: DENSITY,
    }];
    let fixed = |set: &str, dof: usize| PrescribedDisplacement {
        nodes: mesh.node_set(set).unwrap().to_vec(),
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    };
    // 1e-4 strain: E A ε over 9 nodes.
    let end = mesh.node_set("x1").unwrap().to_vec();
    let per_node = young_modulus() * SIDE * SIDE * 1e-4 / end.len() as f64;
    let loads = Loads {
        displacements: vec![fixed("x0", 0), fixed("y0", 1), fixed("z0", 2)],
        forces: vec![NodalForce {
            nodes: end,
            dof: 0,
            amplitude: Amplitude::new(vec![(0.0, per_node)]).unwrap(),
        }],
        ..Loads::default()
    };
    (mesh, parts, loads)
}

/// Times of the local maxima of `values` sampled every `dt` from `dt` on, refined by a
/// parabola through each maximum and its neighbours [s].
fn maxima(values: &[f64], dt: f64) -> Vec<f64> {
    values
        .windows(3)
        .enumerate()
        .filter(|(_, w)| w[1] > w[0] && w[1] >= w[2])
        .map(|(k, w)| {
            let shift = 0.5 * (w[0] - w[2]) / (w[0] - 2.0 * w[1] + w[2]);
            (k as f64 + 2.0 + shift) * dt
        })
        .collect()
}

/// The step-loaded fixed–free bar oscillates in its first longitudinal mode with the
/// period T = 4L/c, c = √(E/ρ) of the slender-bar theory. The mode's amplitude
/// q(t) = Σ m_a u_x,a sin(π X_a / 2L) (which filters the higher modes) has its maxima one
/// period apart: measured within 1 % of T (expected: +0.03 % from the lumped-mass
/// dispersion of 20 elements, +0.03 % period elongation of the trapezoidal rule at
/// Δt = T/100, +0.2 % from the lateral inertia (Rayleigh) of this section). The energy
/// balance T + W_int − W_ext of the trapezoidal rule stays within 1e-6 of the largest
/// kinetic energy.
#[test]
fn a_step_loaded_bar_oscillates_with_the_period_of_its_first_mode() {
    let (mesh, parts, loads) = bar();
    let wave_speed = (young_modulus() / DENSITY).sqrt();
    let period = 4.0 * LENGTH / wave_speed;
    let steps_per_period = 100;
    let dt = period / steps_per_period as f64;
    let mut settings = ImplicitSettings::new(3.0 * period, 3 * steps_per_period);
    settings.dynamics = Some(Newmark::default());
    settings.record_displacements = true;
    let result = run_quasi_static(&mesh, &parts, &loads, &settings).unwrap();
    // Mode amplitude with the lumped masses of a regular mesh (shape: sin(π X / 2L)).
    let weights: Vec<f64> = (0..mesh.nodes.len())
        .map(|n| (PI * mesh.nodes.position(n).x / (2.0 * LENGTH)).sin())
        .collect();
    let amplitude: Vec<f64> = result
        .displacement_history
        .iter()
        .map(|u| u.iter().zip(&weights).map(|(u, w)| u.x * w).sum())
        .collect();
    let peaks = maxima(&amplitude, dt);
    println!("period {period:.6e} s, maxima at {peaks:.6?}");
    assert!(peaks.len() >= 3, "{peaks:?}");
    let measured = (peaks[2] - peaks[0]) / 2.0;
    let error = (measured - period) / period;
    println!("measured period {measured:.6e} s, relative error {error:+.3e}");
    assert!(error.abs() < 0.01, "{measured} vs {period}");
    // Phase: the first maximum at T/2.
    assert!(
        (peaks[0] - 0.5 * period).abs() < 0.01 * period,
        "{}",
        peaks[0]
    );

    let largest_kinetic = result
        .history
        .iter()
        .map(|r| r.energy.kinetic)
        .fold(0.0, f64::max);
    let drift = result
        .history
        .iter()
        .map(|r| r.energy.total().abs())
        .fold(0.0, f64::max);
    let last = result.history.last().unwrap().energy;
    println!(
        "largest kinetic energy {largest_kinetic:.4e} J, largest |T + W_int - W_ext| \
         {drift:.3e} J, last {last:?}"
    );
    assert!(largest_kinetic > 0.0);
    assert!(
        drift < 1e-6 * largest_kinetic,
        "{drift} vs {largest_kinetic}"
    );
}
