//! A block pressed onto a rigid plane and onto a rigid sphere, implicit (quasi-static) and
//! explicit, with the default penalty ε = 10 E/h.
//!
//! The quarter block [0, L]² × [0, L] has symmetry planes x = 0 and y = 0 and its top face
//! pushed down by δ; its bottom face z = 0 is the secondary surface.
//! - On the frictionless plane the state is homogeneous uniaxial stress: the contact force
//!   must be the material-point driver's engineering stress at the stretch
//!   λ = 1 − (δ − g)/L times L², g the uniform penetration, and g = F/(ε L²).
//! - On both, the contact force must balance the top reaction, and the penetration must
//!   stay below 1 % of the element size.

mod common;

use nalgebra::Vector3;

use musclefem_contact::{DeformableSurface, PenaltyContact, RigidSurface};
use musclefem_core::mesh::Mesh;
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit_with};
use musclefem_core::solver::implicit::{ImplicitSettings, run_implicit_with};
use musclefem_core::solver::{Interaction, Loads};
use musclefem_materials::Amplitude;
use musclefem_materials::driver::{StretchHistory, run_uniaxial_stress};

use common::*;

const SIDE: f64 = 0.01;
const DIVISIONS: usize = 6;
const H: f64 = SIDE / DIVISIONS as f64;

fn block() -> Mesh {
    box_at(Vector3::zeros(), [SIDE; 3], [DIVISIONS; 3])
}

fn pressed(mesh: &Mesh, top: Amplitude) -> Loads {
    Loads {
        displacements: vec![
            held(mesh.node_set("x0").unwrap(), 0),
            held(mesh.node_set("y0").unwrap(), 1),
            prescribed(mesh.node_set("z1").unwrap(), 2, top),
        ],
        ..Loads::default()
    }
}

/// A plane at z = 0 facing +z, its vertices away from the block's nodes.
fn floor() -> RigidSurface {
    let centre = Vector3::new(0.37 * H, 0.21 * H, 0.0);
    RigidSurface::plane("floor", centre, Vector3::z(), 4.0 * SIDE, 7).unwrap()
}

fn contact(mesh: &Mesh, target: RigidSurface) -> Vec<Box<dyn Interaction>> {
    let bottom = DeformableSurface::from_mesh_surface(mesh, "z0").unwrap();
    assert!((bottom.element_size() - H).abs() < 1e-12 * H);
    vec![Box::new(
        PenaltyContact::with_default_penalty("bottom on rigid", bottom, target, YOUNGS).unwrap(),
    )]
}

/// Engineering stress of the material in uniaxial stress at `stretch` [Pa].
fn driver_stress(stretch: f64) -> f64 {
    let history = StretchHistory::parse(&format!("0:1,1:{stretch}")).unwrap();
    let rows = run_uniaxial_stress(neo_hookean().as_ref(), &history, 0.01).unwrap();
    rows.last().unwrap().engineering_stress
}

/// Largest penetration of the bottom nodes below z = 0 [m].
fn plane_penetration(mesh: &Mesh, displacement: &[Vector3<f64>]) -> f64 {
    mesh.node_set("z0")
        .unwrap()
        .iter()
        .map(|&n| -displacement[n as usize].z)
        .fold(f64::NEG_INFINITY, f64::max)
}

#[test]
fn implicit_block_on_a_rigid_plane_is_in_uniaxial_stress_with_a_small_penetration() {
    let mesh = block();
    let delta = 0.05 * SIDE;
    let loads = pressed(&mesh, Amplitude::ramp(1.0, -delta).unwrap());
    let mut interactions = contact(&mesh, floor());
    let mut fields = LastFields::default();
    let result = run_implicit_with(
        &mesh,
        &parts(&mesh),
        &loads,
        &mut interactions,
        &ImplicitSettings::new(1.0, 4),
        &mut fields,
    )
    .expect("the pressed block converges");
    let last = result.history.last().unwrap();
    let report = &last.interactions[0];
    let force = report.force.z;
    let reaction = last.reactions[2];
    let balance = (force + reaction).abs() / force;
    let penetration = plane_penetration(&mesh, &result.displacement);
    // Uniform penetration g = F/(ε L²).
    let penalty = 10.0 * YOUNGS / H;
    let uniform = force / (penalty * SIDE * SIDE);
    let stretch = 1.0 - (delta - penetration) / SIDE;
    let expected = -driver_stress(stretch) * SIDE * SIDE;
    println!(
        "plane, implicit: F = {force:.6e} N, reaction {reaction:.6e} N (balance {balance:.1e}), \
         penetration {:.3} % of h (uniform {:.3} %), driver {expected:.6e} N ({:.1e}), \
         {} active nodes, iterations {:?}",
        100.0 * penetration / H,
        100.0 * uniform / H,
        (force - expected).abs() / expected,
        report.active_points,
        result
            .steps
            .iter()
            .map(|s| s.iterations)
            .collect::<Vec<_>>()
    );
    assert!(
        balance < 1e-6,
        "contact force {force} N against reaction {reaction} N"
    );
    assert!(
        penetration > 0.0 && penetration < 0.01 * H,
        "penetration {penetration} m"
    );
    assert!(
        (penetration - uniform).abs() < 1e-6 * uniform,
        "{penetration} vs {uniform}"
    );
    assert!(
        (force - expected).abs() < 1e-6 * expected,
        "{force} N vs driver {expected} N"
    );
    assert_eq!(report.active_points, (DIVISIONS + 1) * (DIVISIONS + 1));
    assert!((report.active_area - SIDE * SIDE).abs() < 1e-12 * SIDE * SIDE);
    let stored = 0.5 * penalty * penetration * penetration * SIDE * SIDE;
    assert!((report.stored_energy - stored).abs() < 1e-5 * stored);
    let pressure = fields.field("contact_pressure");
    let centre = mesh.node_set("z0").unwrap()[DIVISIONS + 2] as usize;
    assert!((pressure.values[centre] - force / (SIDE * SIDE)).abs() < 1e-6 * force / (SIDE * SIDE));
}

#[test]
fn implicit_block_on_a_rigid_sphere_balances_the_reaction_with_a_small_penetration() {
    let mesh = block();
    let radius = 5.0 * SIDE;
    let centre = Vector3::new(0.0, 0.0, -radius);
    let sphere = RigidSurface::sphere("ball", centre, radius, 5).unwrap();
    let loads = pressed(&mesh, Amplitude::ramp(1.0, -0.03 * SIDE).unwrap());
    let mut interactions = contact(&mesh, sphere.clone());
    let mut fields = LastFields::default();
    let result = run_implicit_with(
        &mesh,
        &parts(&mesh),
        &loads,
        &mut interactions,
        &ImplicitSettings::new(1.0, 4).with_cutting(),
        &mut fields,
    )
    .expect("the block pressed on the sphere converges");
    let last = result.history.last().unwrap();
    let report = &last.interactions[0];
    let force = report.force.z;
    let reaction = last.reactions[2];
    let balance = (force + reaction).abs() / force;
    let gap = fields.field("contact_gap");
    let penetration = -gap.values.iter().fold(0.0f64, |m, &g| m.min(g));
    // Independently of the facets: no node deeper in the exact sphere than the penetration
    // plus the largest sagitta of the facets.
    let chord = sphere
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| sphere.vertices[v as usize]);
            let n = (b - a).cross(&(c - a)).normalize();
            radius - (a - centre).dot(&n)
        })
        .fold(0.0, f64::max);
    let deepest = mesh
        .node_set("z0")
        .unwrap()
        .iter()
        .map(|&n| {
            radius
                - (mesh.nodes.position(n as usize) + result.displacement[n as usize] - centre)
                    .norm()
        })
        .fold(f64::NEG_INFINITY, f64::max);
    println!(
        "sphere, implicit: F = {force:.6e} N, reaction {reaction:.6e} N (balance {balance:.1e}), \
         penetration {:.3} % of h (deepest in the exact sphere {:.3} %), {} active nodes, \
         iterations {:?}, cuts {}",
        100.0 * penetration / H,
        100.0 * deepest / H,
        report.active_points,
        result
            .steps
            .iter()
            .map(|s| s.iterations)
            .collect::<Vec<_>>(),
        result.cuts
    );
    assert!(
        balance < 1e-6,
        "contact force {force} N against reaction {reaction} N"
    );
    assert!(
        penetration > 0.0 && penetration < 0.01 * H,
        "penetration {penetration} m"
    );
    assert!(deepest < penetration + chord, "{deepest} m");
    // A contact patch, not a point: several rings of nodes carry the load.
    assert!(report.active_points >= 6, "{}", report.active_points);
}

/// The same plane, explicit, the top pushed down along a smooth step over many periods of
/// the block's lowest mode (about 7 ms): at the end the contact force balances the top
/// reaction and matches the quasi-static (driver) force within 1 %.
#[test]
fn explicit_block_on_a_rigid_plane_matches_the_quasi_static_force() {
    let mesh = block();
    let delta = 0.05 * SIDE;
    let end = 0.2;
    let loads = pressed(&mesh, smooth_ramp(end, -delta));
    let mut interactions = contact(&mesh, floor());
    let mut settings = ExplicitSettings::new(end);
    // The penalty springs stiffen the bottom nodes: see the stable-step note in `penalty`.
    settings.safety_factor = 0.7;
    let result = run_explicit_with(
        &mesh,
        &parts(&mesh),
        &loads,
        &mut interactions,
        &settings,
        &mut common::LastFields::default(),
    )
    .expect("the explicit run keeps its energy balance");
    let last = result.history.last().unwrap();
    let force = last.interactions[0].force.z;
    let reaction = last.reactions[2];
    let penetration = plane_penetration(&mesh, &result.displacement);
    let stretch = 1.0 - (delta - penetration) / SIDE;
    let expected = -driver_stress(stretch) * SIDE * SIDE;
    let drift =
        last.internal_energy + last.interaction_work + last.kinetic_energy - last.external_work;
    println!(
        "plane, explicit: {} steps, F = {force:.6e} N, reaction {reaction:.6e} N ({:.1e}), \
         driver {expected:.6e} N ({:.1e}), penetration {:.3} % of h, energy drift {:.1e} of W_ext",
        result.steps,
        (force + reaction).abs() / force,
        (force - expected).abs() / expected,
        100.0 * penetration / H,
        drift.abs() / last.external_work
    );
    assert!((force + reaction).abs() < 0.01 * force);
    assert!((force - expected).abs() < 0.01 * expected);
    assert!(penetration > 0.0 && penetration < 0.01 * H);
    assert!(drift.abs() < 0.01 * last.external_work);
}

/// The sphere, explicit: the force balances the reaction within 1 % at the end of a slow
/// push, and the penetration stays below 1 % of h.
#[test]
fn explicit_block_on_a_rigid_sphere_balances_the_reaction() {
    let mesh = block();
    let radius = 5.0 * SIDE;
    let sphere = RigidSurface::sphere("ball", Vector3::new(0.0, 0.0, -radius), radius, 5).unwrap();
    let end = 0.2;
    let loads = pressed(&mesh, smooth_ramp(end, -0.03 * SIDE));
    let mut interactions = contact(&mesh, sphere);
    let mut settings = ExplicitSettings::new(end);
    settings.safety_factor = 0.7;
    let mut fields = LastFields::default();
    let result = run_explicit_with(
        &mesh,
        &parts(&mesh),
        &loads,
        &mut interactions,
        &settings,
        &mut fields,
    )
    .expect("the explicit run keeps its energy balance");
    let last = result.history.last().unwrap();
    let force = last.interactions[0].force.z;
    let reaction = last.reactions[2];
    let penetration = -fields
        .field("contact_gap")
        .values
        .iter()
        .fold(0.0f64, |m, &g| m.min(g));
    println!(
        "sphere, explicit: {} steps, F = {force:.6e} N, reaction {reaction:.6e} N ({:.1e}), \
         penetration {:.3} % of h",
        result.steps,
        (force + reaction).abs() / force,
        100.0 * penetration / H
    );
    assert!((force + reaction).abs() < 0.01 * force);
    assert!(penetration > 0.0 && penetration < 0.01 * H);
}
