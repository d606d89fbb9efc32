//! Mass scaling, bulk viscosity and the hourglass-energy output of the explicit solver,
//! each against a closed-form reference.

use std::collections::BTreeMap;
use std::sync::Arc;

use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::bulk_viscosity::BulkViscosity;
use musclefem_core::solver::explicit::{ExplicitResult, ExplicitSettings, run_explicit};
use musclefem_core::solver::{Loads, NodalForce, Part, PrescribedDisplacement};
use musclefem_materials::driver::{StretchHistory, run_uniaxial_stress};
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

const SIDE: f64 = 0.01;
const DENSITY: f64 = 1000.0;
const MU: f64 = 1e4;
const BULK: f64 = 1e5;

/// Compressible neo-Hookean, μ = 10 kPa, K = 2/D = 100 kPa.
fn neo_hookean() -> Arc<dyn Material> {
    let params = BTreeMap::from([("mu".to_string(), MU), ("D".to_string(), 2.0 / BULK)]);
    MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap()
}

fn parts(technology: Technology) -> Vec<Part> {
    vec![Part {
        block: 0,
        technology,
        material: neo_hookean(),
        density: DENSITY,
    }]
}

fn held(mesh: &Mesh, set: &str, dof: usize) -> PrescribedDisplacement {
    PrescribedDisplacement {
        nodes: mesh.node_set(set).unwrap().to_vec(),
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    }
}

/// Symmetry planes x0, y0, z0; x1 pulled to `stretch` along a smooth ramp over
/// `duration`.
fn uniaxial(mesh: &Mesh, stretch: f64, duration: f64) -> Loads {
    let knots = (0..=40)
        .map(|i| {
            let s = i as f64 / 40.0;
            (
                s * duration,
                (stretch - 1.0) * SIDE * s * s * (3.0 - 2.0 * s),
            )
        })
        .collect();
    Loads::from(vec![
        PrescribedDisplacement {
            nodes: mesh.node_set("x1").unwrap().to_vec(),
            dof: 0,
            amplitude: Amplitude::new(knots).unwrap(),
        },
        held(mesh, "x0", 0),
        held(mesh, "y0", 1),
        held(mesh, "z0", 2),
    ])
}

fn final_reaction(result: &ExplicitResult) -> f64 {
    result.history.last().unwrap().reactions[0]
}

/// On a uniform mesh every element has the same stable step Δt_e, so a target of 4 Δt_e
/// (× safety) raises every density 16-fold: the added mass is exactly 15 × the physical
/// one, the run takes a quarter of the steps, and a slow stretch still gives the
/// homogeneous reaction of the material-point driver within 1 %.
#[test]
fn mass_scaling_to_four_times_the_step_adds_fifteen_times_the_mass() {
    let mesh = box_of_hexes([SIDE; 3], [2; 3]).unwrap();
    let (stretch, duration) = (1.3, 2.0);
    let loads = uniaxial(&mesh, stretch, duration);
    // A row every step, so that the second row holds the first step (the step shrinks
    // later as the material stiffens).
    let mut every_step = ExplicitSettings::new(duration);
    every_step.history_interval = 1e-9;
    let plain = run_explicit(&mesh, &parts(Technology::Hex8Full), &loads, &every_step).unwrap();
    let first_step = plain.history[1].time_step;
    let mut settings = every_step.clone();
    settings.mass_scaling_time_step = Some(4.0 * first_step);
    let scaled = run_explicit(&mesh, &parts(Technology::Hex8Full), &loads, &settings).unwrap();
    assert!(
        (scaled.added_mass_fraction - 15.0).abs() < 1e-9,
        "added mass fraction {}",
        scaled.added_mass_fraction
    );
    assert!((scaled.history[1].time_step - 4.0 * first_step).abs() < 1e-12 * first_step);
    let ratio = plain.steps as f64 / scaled.steps as f64;
    assert!((3.5..=4.2).contains(&ratio), "step ratio {ratio}");

    let history = StretchHistory::parse(&format!("0:1,1:{stretch}")).unwrap();
    let driver = run_uniaxial_stress(neo_hookean().as_ref(), &history, 0.01).unwrap();
    let expected = driver.last().unwrap().engineering_stress * SIDE * SIDE;
    for (label, result) in [("plain", &plain), ("mass-scaled", &scaled)] {
        let reaction = final_reaction(result);
        assert!(
            (reaction - expected).abs() < 0.01 * expected,
            "{label}: reaction {reaction} N, homogeneous {expected} N"
        );
    }
    // The added inertia shows as kinetic energy, still small against the internal.
    let last = scaled.history.last().unwrap();
    assert!(last.kinetic_energy < 1e-3 * last.internal_energy);
}

/// One hex8 squeezed along x at a constant strain rate ε̇ with every node prescribed
/// (uniaxial strain): the motion is the same with and without bulk viscosity, so the
/// reactions differ by exactly the viscous pressure times the face area,
/// q A₀ = ρ₀ L₀ (b₁ c |ε̇_v| + b₂² L₀ ε̇_v²) A₀, with L₀ = h/√3, c = √((K + 4μ/3)/ρ₀) at
/// small strain and ε̇_v = v̇/v.
#[test]
fn bulk_viscosity_adds_the_linear_and_quadratic_pressure_in_compression() {
    let mesh = box_of_hexes([SIDE; 3], [1; 3]).unwrap();
    let rate = 2.0; // 1/s
    let duration = 1e-3; // 0.2 % compression: the acoustic modulus stays at its reference
    let mut displacements = vec![held(&mesh, "x0", 0), held(&mesh, "y0", 1)];
    displacements.push(held(&mesh, "z0", 2));
    displacements.push(held(&mesh, "y1", 1));
    displacements.push(held(&mesh, "z1", 2));
    displacements.insert(
        0,
        PrescribedDisplacement {
            nodes: mesh.node_set("x1").unwrap().to_vec(),
            dof: 0,
            amplitude: Amplitude::new(vec![(0.0, 0.0), (1.0, -rate * SIDE)]).unwrap(),
        },
    );
    let loads = Loads::from(displacements);
    let run = |viscosity: Option<BulkViscosity>| {
        let mut settings = ExplicitSettings::new(duration);
        settings.bulk_viscosity = viscosity;
        settings.fixed_time_step = Some(1e-5);
        run_explicit(&mesh, &parts(Technology::Hex8Full), &loads, &settings).unwrap()
    };
    let coefficients = BulkViscosity::default();
    let plain = run(None);
    let viscous = run(Some(coefficients));
    let strain = rate * duration;
    let volumetric_rate = -rate / (1.0 - strain);
    let length = SIDE / 3f64.sqrt();
    let speed = ((BULK + 4.0 * MU / 3.0) / DENSITY).sqrt();
    let q = DENSITY
        * length
        * (coefficients.linear * speed * volumetric_rate.abs()
            + coefficients.quadratic.powi(2) * length * volumetric_rate.powi(2));
    let difference = final_reaction(&viscous) - final_reaction(&plain);
    assert!(
        (difference + q * SIDE * SIDE).abs() < 0.01 * q * SIDE * SIDE,
        "viscous reaction {difference} N, expected {} N",
        -q * SIDE * SIDE
    );
    let last = viscous.history.last().unwrap();
    assert!(last.viscous_energy > 0.0);
    // The dissipated work is ∫ q v̇ dt ≈ q A₀ × (shortening), to first order.
    let dissipated = q * SIDE * SIDE * strain * SIDE;
    assert!(
        (last.viscous_energy - dissipated).abs() < 0.02 * dissipated,
        "viscous energy {} J, expected {dissipated} J",
        last.viscous_energy
    );
}

/// One hex8 in uniaxial strain (lateral components held, x0 held along x) and a force
/// pulse on x1 that sets it ringing: (mesh, loads, acoustic modulus M [Pa], period [s]).
fn ringing_hex() -> (Mesh, Loads, f64, f64) {
    let mesh = box_of_hexes([SIDE; 3], [1; 3]).unwrap();
    let mut loads = Loads::from(vec![
        held(&mesh, "x0", 0),
        held(&mesh, "y0", 1),
        held(&mesh, "z0", 2),
        held(&mesh, "y1", 1),
        held(&mesh, "z1", 2),
    ]);
    let modulus = BULK + 4.0 * MU / 3.0;
    let omega = (2.0 * modulus / (DENSITY * SIDE * SIDE)).sqrt();
    let period = 2.0 * std::f64::consts::PI / omega;
    // A pulse of a fifth of a period, small enough that the strain stays near 1e-4 (the
    // quadratic term is then ~0.2 % of the linear one).
    let pulse = 0.2 * period;
    let force = 1e-4 * modulus * SIDE * SIDE / 4.0;
    loads.forces.push(NodalForce {
        nodes: mesh.node_set("x1").unwrap().to_vec(),
        dof: 0,
        amplitude: Amplitude::new(vec![(0.0, force), (pulse, force), (pulse * 1.0001, 0.0)])
            .unwrap(),
    });
    (mesh, loads, modulus, period)
}

/// One hex8 in uniaxial strain (lateral components held, x0 held along x) set ringing by
/// a short force pulse on x1: a single mode, m ẍ + c_v ẋ + k x = 0 with m = ρ₀V/2 on the
/// face, k = M A/h and c_v = ρ₀ L₀ b₁ c A/h from the linear term, whose damping ratio is
/// ζ = b₁ L₀/(√2 h) = b₁/√6. The kinetic-energy peaks then decay as e^{−2ζωt}: over five
/// periods by e^{−20πζ/√(1−ζ²)}. Without viscosity they do not decay.
#[test]
fn bulk_viscosity_damps_a_single_mode_at_the_predicted_ratio() {
    let (mesh, loads, _, period) = ringing_hex();
    let run = |viscosity: Option<BulkViscosity>| {
        let mut settings = ExplicitSettings::new(8.0 * period);
        settings.bulk_viscosity = viscosity;
        settings.fixed_time_step = Some(period / 400.0);
        settings.history_interval = period / 400.0;
        run_explicit(&mesh, &parts(Technology::Hex8Full), &loads, &settings).unwrap()
    };
    let peak = |r: &ExplicitResult, from: f64| {
        r.history
            .iter()
            .filter(|row| row.time >= from * period && row.time < (from + 1.0) * period)
            .map(|row| row.kinetic_energy)
            .fold(0.0, f64::max)
    };
    let coefficients = BulkViscosity::default();
    let zeta = coefficients.linear / 6f64.sqrt();
    let expected = (-20.0 * std::f64::consts::PI * zeta / (1.0 - zeta * zeta).sqrt()).exp();
    let damped = run(Some(coefficients));
    let ratio = peak(&damped, 6.0) / peak(&damped, 1.0);
    assert!(
        (ratio - expected).abs() < 0.03 * expected,
        "kinetic-energy peaks decay by {ratio} over five periods, expected {expected}"
    );
    let plain = run(None);
    let undamped = peak(&plain, 6.0) / peak(&plain, 1.0);
    assert!((undamped - 1.0).abs() < 0.01, "undamped ratio {undamped}");
    assert!(damped.history.last().unwrap().viscous_energy > 0.0);
    assert!(plain.history.iter().all(|row| row.viscous_energy == 0.0));
}

/// The same single mode damped by the shear viscosity instead: σ_v,xx = 2η (2/3) ε̇ in
/// uniaxial strain, so c_v = (4/3) η A/h and ζ = (4/3) η / (h √(2 M ρ₀)). The energy
/// balance holds with the dissipated work, and the step is cut by √(1 + ζ_e²) − ζ_e with
/// the element's ζ_e = (4/3) η / (L₀ √(ρ₀ M)).
#[test]
fn shear_viscosity_damps_a_single_mode_at_the_predicted_ratio() {
    let (mesh, loads, modulus, period) = ringing_hex();
    let eta = 3.0;
    let zeta = 4.0 / 3.0 * eta / (SIDE * (2.0 * modulus * DENSITY).sqrt());
    let mut settings = ExplicitSettings::new(8.0 * period);
    settings.shear_viscosity = Some(eta);
    settings.fixed_time_step = Some(period / 400.0);
    settings.history_interval = period / 400.0;
    let damped = run_explicit(&mesh, &parts(Technology::Hex8Full), &loads, &settings).unwrap();
    let peak = |from: f64| {
        (damped.history.iter())
            .filter(|row| row.time >= from * period && row.time < (from + 1.0) * period)
            .map(|row| row.kinetic_energy)
            .fold(0.0, f64::max)
    };
    let expected = (-20.0 * std::f64::consts::PI * zeta / (1.0 - zeta * zeta).sqrt()).exp();
    let ratio = peak(6.0) / peak(1.0);
    println!("ζ = {zeta:.4}: peaks decay by {ratio:.4}, expected {expected:.4}");
    assert!(
        (ratio - expected).abs() < 0.03 * expected,
        "kinetic-energy peaks decay by {ratio} over five periods, expected {expected}"
    );
    let last = damped.history.last().unwrap();
    assert!(last.viscous_energy > 0.0);

    // The stable step with the viscosity: the cube's (L₀ = h/√3) with the factor above.
    settings.fixed_time_step = None;
    settings.end_time = 50.0 * period;
    settings.history_interval = period;
    let stepped = run_explicit(&mesh, &parts(Technology::Hex8Full), &loads, &settings).unwrap();
    let mut plain = settings.clone();
    plain.shear_viscosity = None;
    let unviscous = run_explicit(&mesh, &parts(Technology::Hex8Full), &loads, &plain).unwrap();
    let length = SIDE / 3f64.sqrt();
    let element_zeta = 4.0 / 3.0 * eta / (length * (DENSITY * modulus).sqrt());
    let factor = (1.0 + element_zeta * element_zeta).sqrt() - element_zeta;
    let steps_ratio = unviscous.steps as f64 / stepped.steps as f64;
    assert!(
        (steps_ratio - factor).abs() < 0.02 * factor,
        "steps {} with η, {} without: ratio {steps_ratio}, expected {factor}",
        stepped.steps,
        unviscous.steps
    );
}

/// One-point hex8: a slow homogeneous stretch excites no hourglass mode (its hourglass
/// energy is below 1e-8 of the internal energy: only the small inertial departures from
/// the affine motion), a corner load does (above 1e-3 of it, and a part of it).
#[test]
fn hourglass_energy_is_zero_in_a_homogeneous_stretch_and_positive_under_a_corner_load() {
    let technology = Technology::hex8_one_point(MU);
    let mesh = box_of_hexes([SIDE; 3], [2; 3]).unwrap();
    let stretch = run_explicit(
        &mesh,
        &parts(technology),
        &uniaxial(&mesh, 1.2, 1.0),
        &ExplicitSettings::new(1.0),
    )
    .unwrap();
    let last = stretch.history.last().unwrap();
    assert!(last.internal_energy > 0.0);
    assert!(
        last.hourglass_energy.abs() < 1e-8 * last.internal_energy,
        "hourglass energy {} J of {} J",
        last.hourglass_energy,
        last.internal_energy
    );

    let corner = (0..mesh.nodes.len())
        .find(|&n| (mesh.nodes.position(n) - nalgebra::Vector3::repeat(SIDE)).norm() < 1e-12)
        .unwrap() as u32;
    let mut loads = Loads::from(vec![
        held(&mesh, "x0", 0),
        held(&mesh, "x0", 1),
        held(&mesh, "x0", 2),
    ]);
    loads.forces.push(NodalForce {
        nodes: vec![corner],
        dof: 2,
        amplitude: Amplitude::new(vec![(0.0, 0.0), (0.2, 0.05)]).unwrap(),
    });
    let bent = run_explicit(
        &mesh,
        &parts(technology),
        &loads,
        &ExplicitSettings::new(0.2),
    )
    .unwrap();
    let last = bent.history.last().unwrap();
    assert!(
        last.hourglass_energy > 1e-3 * last.internal_energy
            && last.hourglass_energy < last.internal_energy,
        "hourglass energy {} J of {} J",
        last.hourglass_energy,
        last.internal_energy
    );
}
