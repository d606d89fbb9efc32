//! A 1-D dilatational wave in a bar, explicit solver: the front must travel at
//! c = √((κ + 4μ/3)/ρ₀), the P-wave speed of the small-strain neo-Hookean solid.
//!
//! Setup: a bar of 100 × 1 × 1 fully integrated hex8 (side h = 1 mm, length L = 100 mm)
//! along x, every node held laterally (u_y = u_z = 0), so the motion is uniaxial strain;
//! the end x = 0 is pulled at the constant velocity −v₀ e_x from t = 0 (u_x = −v₀ t).
//! Behind the front the strain is ε₀ = v₀/c = 1e-4 (small strain: the speed differs from
//! the small-strain c by O(ε₀)).
//!
//! Strain gauges: with u_y held everywhere, the lateral reaction of the nodes on the face
//! y = h at station x_i (2 nodes) is σ_yy h², averaged over the two elements next to the
//! station, and σ_yy = λ ε_xx with λ = κ − 2μ/3 the Lamé constant. Its arrival time t_i is
//! when it first reaches half of its value behind the front, λ ε₀ h².
//!
//! Why not exactly x_i/c: the discrete bar (lumped mass, linear elements, central
//! differences at Courant number C = cΔt/h) has the dispersion relation
//! sin(ωΔt/2) = C sin(kh/2), i.e. ω ≈ ck − a k³ with a = c h² (1 − C²)/24: short waves
//! lag, and a step front spreads into the Airy profile
//! ε/ε₀ = ∫_y^∞ Ai(s) ds, y = (x − ct)/(3at)^{1/3}. Its half value lies at
//! y½ = −0.4096 (∫_{y½}^0 Ai = 1/6, since ∫_0^∞ Ai = 1/3), so the half-value arrival is
//! late by δt = 0.41 (3 a t)^{1/3} / c = 0.41 (n (1 − C²)/8)^{1/3} h/c at n = x/h
//! elements: 0.54 h/c at n = 25 (2.2 % of the travel time), 0.78 h/c at n = 75 (1.0 %)
//! for C ≈ 0.52 (the explicit solver's 0.9 × h/√3 / c). The test checks (a) the arrival within 3 % of x/c (the dispersion lag
//! plus margin; a wave speed from κ alone, or from κ + μ, would make the front 27 % or 5 %
//! late), and
//! (b) the lag t_i − x_i/c against the Airy prediction within 0.15 h/c (the asymptotic
//! profile leaves out start-up terms of O(1) steps; measured: 0.05–0.07 h/c).

use std::collections::BTreeMap;
use std::sync::Arc;

use musclefem_core::element::Technology;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit};
use musclefem_core::solver::{Loads, Part, PrescribedDisplacement};
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

/// Element side h [m] and number of elements along the bar.
const H: f64 = 1e-3;
const ELEMENTS: usize = 100;
/// Shear modulus μ [Pa], bulk modulus κ [Pa] (ν = 0.3) and density ρ₀ [kg/m³].
const MU: f64 = 1e6;
const KAPPA: f64 = 2.0 * MU * 1.3 / (3.0 * 0.4);
const DENSITY: f64 = 1000.0;
/// Strain behind the front.
const STRAIN: f64 = 1e-4;
/// Stations, in elements from the pulled end.
const STATIONS: [usize; 3] = [25, 50, 75];
/// Half-value point of the Airy step profile: ∫_{y½}^∞ Ai(s) ds = 1/2.
const AIRY_HALF: f64 = -0.4096;

fn neo_hookean() -> Arc<dyn Material> {
    let params = BTreeMap::from([("mu".to_string(), MU), ("D".to_string(), 2.0 / KAPPA)]);
    MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap()
}

/// Lattice node (i, j, k) of a box of ELEMENTS × 1 × 1 cells.
fn node(i: usize, j: usize, k: usize) -> u32 {
    (i + (ELEMENTS + 1) * (j + 2 * k)) as u32
}

/// First time `series` (time, value) reaches `level`, linear between samples.
fn crossing(series: &[(f64, f64)], level: f64) -> Option<f64> {
    series.windows(2).find_map(|w| {
        let ((t0, v0), (t1, v1)) = (w[0], w[1]);
        (v0 < level && v1 >= level).then(|| t0 + (t1 - t0) * (level - v0) / (v1 - v0))
    })
}

#[test]
fn a_dilatational_front_travels_at_the_p_wave_speed() {
    let wave_speed = ((KAPPA + 4.0 * MU / 3.0) / DENSITY).sqrt();
    let velocity = STRAIN * wave_speed;
    // Stop before the front reaches the free far end (no reflection at the stations).
    let end_time = 0.9 * ELEMENTS as f64 * H / wave_speed;
    let mesh = box_of_hexes([ELEMENTS as f64 * H, H, H], [ELEMENTS, 1, 1]).unwrap();
    let every_node: Vec<u32> = (0..mesh.node_count() as u32).collect();
    let held = |nodes: Vec<u32>, dof: usize| PrescribedDisplacement {
        nodes,
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    };
    let mut displacements = vec![
        PrescribedDisplacement {
            nodes: mesh.node_set("x0").unwrap().to_vec(),
            dof: 0,
            amplitude: Amplitude::ramp(end_time, -velocity * end_time).unwrap(),
        },
        held(every_node.clone(), 1),
        held(every_node, 2),
    ];
    // The gauges: u_y = 0 again on the y = h nodes of each station, for its reaction.
    for &n in &STATIONS {
        displacements.push(held(vec![node(n, 1, 0), node(n, 1, 1)], 1));
    }
    let parts = [Part {
        block: 0,
        technology: Technology::Hex8Full,
        material: neo_hookean(),
        density: DENSITY,
    }];
    let mut settings = ExplicitSettings::new(end_time);
    settings.history_interval = end_time * 1e-6; // every step
    let result = run_explicit(&mesh, &parts, &Loads::from(displacements), &settings).unwrap();
    // The stable step (the last one is shortened to end at end_time).
    let time_step = result.history[result.history.len() / 2].time_step;
    let courant = wave_speed * time_step / H;
    println!(
        "c = {wave_speed:.4} m/s, {} steps of {time_step:.4e} s, Courant number {courant:.4}",
        result.steps
    );
    assert!(result.history.len() > result.steps / 2);

    let lame = KAPPA - 2.0 * MU / 3.0;
    let behind_front = lame * STRAIN * H * H;
    let transit = H / wave_speed;
    for (g, &n) in STATIONS.iter().enumerate() {
        let series: Vec<(f64, f64)> = result
            .history
            .iter()
            .map(|row| (row.time, row.reactions[3 + g]))
            .collect();
        let arrival = crossing(&series, 0.5 * behind_front)
            .unwrap_or_else(|| panic!("the front never reached station {n}"));
        let expected = n as f64 * transit;
        let relative = (arrival - expected) / expected;
        let airy_lag = -AIRY_HALF * (n as f64 * (1.0 - courant * courant) / 8.0).cbrt();
        let lag = (arrival - expected) / transit;
        println!(
            "station x = {n} h: arrival {arrival:.5e} s, x/c = {expected:.5e} s, error \
             {:+.2} %; lag {lag:.3} h/c, Airy prediction {airy_lag:.3} h/c",
            100.0 * relative
        );
        assert!(relative.abs() < 0.03, "station {n}: {relative}");
        assert!(
            (lag - airy_lag).abs() < 0.15,
            "station {n}: lag {lag} h/c, dispersion predicts {airy_lag} h/c"
        );
    }
    // Behind the front the gauge at the first station has settled at λ ε₀ h² (the mean
    // over the last fifth of the run, where the trailing lattice oscillations are small).
    let late: Vec<f64> = result
        .history
        .iter()
        .filter(|row| row.time > 0.8 * end_time)
        .map(|row| row.reactions[3])
        .collect();
    let mean = late.iter().sum::<f64>() / late.len() as f64;
    println!(
        "gauge at {} h behind the front: {mean:.5e} N, λ ε₀ h² = {behind_front:.5e} N",
        STATIONS[0]
    );
    assert!((mean - behind_front).abs() < 0.02 * behind_front, "{mean}");
}
