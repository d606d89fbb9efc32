//! Two deformable blocks pressed together (the main surface deforms too), implicit and
//! explicit, and the explicit run repeated on 1 and 3 threads, at the closest point and
//! with smooth normals.
//!
//! The quarter model: a lower block [0, 10]² × [0, 5] mm (4 × 4 × 2 hexes) under a
//! narrower upper block [0, 6]² × [5, 9] mm (3 × 3 × 2, the secondary side), symmetry
//! planes x = 0 and y = 0, the lower bottom held, the upper top pushed down by 0.2 mm.

mod common;

use nalgebra::Vector3;

use musclefem_contact::{DeformableSurface, PenaltyContact};
use musclefem_core::mesh::Mesh;
use musclefem_core::solver::explicit::{ExplicitResult, ExplicitSettings, run_explicit_with};
use musclefem_core::solver::implicit::{ImplicitSettings, run_implicit_with};
use musclefem_core::solver::{Interaction, Loads};
use musclefem_materials::Amplitude;

use common::*;

const MM: f64 = 1e-3;
const PUSH: f64 = 0.2 * MM;
/// Element size of the upper block (the secondary side) [m].
const H: f64 = 2.0 * MM;

fn blocks() -> Mesh {
    two_boxes(
        box_at(
            Vector3::zeros(),
            [10.0 * MM, 10.0 * MM, 5.0 * MM],
            [4, 4, 2],
        ),
        box_at(
            Vector3::new(0.0, 0.0, 5.0 * MM),
            [6.0 * MM, 6.0 * MM, 4.0 * MM],
            [3, 3, 2],
        ),
    )
}

fn loads(mesh: &Mesh, top: Amplitude) -> Loads {
    let set = |name: &str| mesh.node_set(name).unwrap();
    Loads {
        displacements: vec![
            held(set("lower.x0"), 0),
            held(set("upper.x0"), 0),
            held(set("lower.y0"), 1),
            held(set("upper.y0"), 1),
            held(set("lower.z0"), 2),
            prescribed(set("upper.z1"), 2, top),
        ],
        ..Loads::default()
    }
}

fn contact(mesh: &Mesh) -> Vec<Box<dyn Interaction>> {
    contact_in_mode(mesh, false)
}

/// The contact at the closest point, or along the smooth normal field of the lower block's
/// top (`smooth`).
fn contact_in_mode(mesh: &Mesh, smooth: bool) -> Vec<Box<dyn Interaction>> {
    let secondary = DeformableSurface::from_mesh_surface(mesh, "upper.z0").unwrap();
    let main = DeformableSurface::from_mesh_surface(mesh, "lower.z1").unwrap();
    assert!((secondary.element_size() - H).abs() < 1e-12 * H);
    let contact =
        PenaltyContact::with_default_penalty("upper on lower", secondary, main, YOUNGS).unwrap();
    vec![Box::new(if smooth {
        contact.with_smooth_normals()
    } else {
        contact
    })]
}

/// Σ of the vector nodal field over the nodes of block `block` of `mesh`.
fn block_sum(mesh: &Mesh, block: usize, field: &[f64]) -> Vector3<f64> {
    let mut nodes: Vec<u32> = mesh.blocks[block].connectivity.clone();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
        .iter()
        .map(|&n| Vector3::from_column_slice(&field[3 * n as usize..3 * n as usize + 3]))
        .sum()
}

#[test]
fn implicit_blocks_pressed_together_balance_their_forces_with_a_small_penetration() {
    let mesh = blocks();
    let mut interactions = contact(&mesh);
    let mut fields = LastFields::default();
    let result = run_implicit_with(
        &mesh,
        &parts(&mesh),
        &loads(&mesh, Amplitude::ramp(1.0, -PUSH).unwrap()),
        &mut interactions,
        &ImplicitSettings::new(1.0, 4),
        &mut fields,
    )
    .expect("the pressed blocks converge");
    let last = result.history.last().unwrap();
    let report = &last.interactions[0];
    let force = fields.field("contact_force");
    let on_upper = block_sum(&mesh, 1, &force.values);
    let on_lower = block_sum(&mesh, 0, &force.values);
    let top_reaction = last.reactions[5];
    let bottom_reaction = last.reactions[4];
    let penetration = -fields
        .field("contact_gap")
        .values
        .iter()
        .fold(0.0f64, |m, &g| m.min(g));
    println!(
        "two blocks, implicit: on upper {on_upper:?} N, on lower {on_lower:?} N, resultant {:?}, \
         reactions top {top_reaction:.6e} bottom {bottom_reaction:.6e} N, penetration {:.3} % of h, \
         {} active nodes, iterations {:?}",
        report.force,
        100.0 * penetration / H,
        report.active_points,
        result
            .steps
            .iter()
            .map(|s| s.iterations)
            .collect::<Vec<_>>()
    );
    let scale = on_upper.z;
    assert!(scale > 0.0, "the lower block pushes the upper one up");
    assert!(
        (on_upper + on_lower).norm() < 1e-12 * scale,
        "action = reaction"
    );
    assert!(
        (report.force - on_upper).norm() < 1e-12 * scale,
        "the reported resultant is the force on the secondary (upper) surface"
    );
    assert!(
        (on_upper.z + top_reaction).abs() < 1e-6 * scale,
        "{top_reaction}"
    );
    assert!(
        (on_lower.z + bottom_reaction).abs() < 1e-6 * scale,
        "{bottom_reaction}"
    );
    assert!(
        penetration > 0.0 && penetration < 0.01 * H,
        "{penetration} m"
    );
    assert_eq!(
        report.active_points, 16,
        "the whole 4 × 4 node face of the upper block"
    );
}

fn explicit_run() -> (Mesh, ExplicitResult, LastFields) {
    explicit_run_in_mode(false)
}

fn explicit_run_in_mode(smooth: bool) -> (Mesh, ExplicitResult, LastFields) {
    let mesh = blocks();
    let end = 0.05;
    let mut interactions = contact_in_mode(&mesh, smooth);
    let mut settings = ExplicitSettings::new(end);
    settings.safety_factor = 0.7;
    let mut fields = LastFields::default();
    let result = run_explicit_with(
        &mesh,
        &parts(&mesh),
        &loads(&mesh, smooth_ramp(end, -PUSH)),
        &mut interactions,
        &settings,
        &mut fields,
    )
    .expect("the explicit run keeps its energy balance");
    (mesh, result, fields)
}

/// The explicit run: forces balance at every row, the top reaction matches the contact
/// force at the end of the slow push (1 %), and the whole run is bitwise the same on 1 and
/// 3 threads.
#[test]
fn explicit_blocks_balance_and_do_not_depend_on_the_thread_count() {
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(explicit_run)
    };
    let (mesh, one, fields) = run(1);
    let (_, three, _) = run(3);
    assert_eq!(one.steps, three.steps);
    let bits = |r: &ExplicitResult| {
        r.displacement
            .iter()
            .flat_map(|u| u.iter().map(|x| x.to_bits()).collect::<Vec<_>>())
            .collect::<Vec<u64>>()
    };
    assert_eq!(
        bits(&one),
        bits(&three),
        "displacements differ between 1 and 3 threads"
    );
    assert_eq!(
        one.history, three.history,
        "histories differ between 1 and 3 threads"
    );

    let last = one.history.last().unwrap();
    let report = &last.interactions[0];
    let top_reaction = last.reactions[5];
    let penetration_bound = 0.01 * H;
    let push = -top_reaction;
    let on_upper = block_sum(&mesh, 1, &fields.field("contact_force").values);
    println!(
        "two blocks, explicit: {} steps, reaction {top_reaction:.6e} N, contact on upper {:.6e} N \
         ({:.1e}), {} active nodes, stored {:.3e} J, W_c {:.3e} J",
        one.steps,
        on_upper.z,
        (on_upper.z - push).abs() / push,
        report.active_points,
        report.stored_energy,
        last.interaction_work
    );
    assert!(push > 0.0);
    let reported = one.history.last().unwrap().interactions[0].force;
    assert!(
        (reported - on_upper).norm() < 1e-12 * push,
        "the reported resultant {reported:?} is the force on the secondary (upper) surface \
         {on_upper:?}"
    );
    // Equilibrium of the upper block at the end: its top reaction is the contact force,
    // and the stored energy ½ ε g² A bounds the penetration.
    assert!(
        (on_upper.z - push).abs() < 0.01 * push,
        "{} N vs {push} N",
        on_upper.z
    );
    let penalty = 10.0 * YOUNGS / H;
    let area = 36.0 * MM * MM;
    let mean_penetration = (2.0 * report.stored_energy / (penalty * area)).sqrt();
    assert!(mean_penetration < penetration_bound, "{mean_penetration} m");
    // The work of the contact forces is the energy they store (conservative forces).
    assert!(
        (last.interaction_work - report.stored_energy).abs() < 0.01 * report.stored_energy,
        "W_c {} J against stored {} J",
        last.interaction_work,
        report.stored_energy
    );
}

/// With smooth normals (the lower block's top deforms, its vertex normals with it) the
/// explicit run is bitwise the same on 1 and 3 threads, its top reaction balances the
/// contact force at the end (1 %), and the work of the contact forces is the energy they
/// store within 1 % (measured 0.7 %, against 1e-4 at the closest point: off a flat
/// surface, and with the vertex normals turning with the lower block's top, they are not
/// exactly the gradient of ½ ε d² A_s).
#[test]
fn explicit_blocks_with_smooth_normals_balance_and_do_not_depend_on_the_thread_count() {
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| explicit_run_in_mode(true))
    };
    let (mesh, one, fields) = run(1);
    let (_, three, _) = run(3);
    assert_eq!(one.steps, three.steps);
    assert_eq!(one.displacement, three.displacement);
    assert_eq!(one.history, three.history);
    let last = one.history.last().unwrap();
    let report = &last.interactions[0];
    let push = -last.reactions[5];
    let on_upper = block_sum(&mesh, 1, &fields.field("contact_force").values);
    println!(
        "two blocks, explicit, smooth normals: {} steps, reaction {:.6e} N, contact on upper \
         {:.6e} N ({:.1e}), {} active nodes, stored {:.3e} J, W_c {:.3e} J",
        one.steps,
        -push,
        on_upper.z,
        (on_upper.z - push).abs() / push,
        report.active_points,
        report.stored_energy,
        last.interaction_work
    );
    assert!(push > 0.0);
    assert!((report.force - on_upper).norm() < 1e-12 * push);
    assert!((on_upper.z - push).abs() < 0.01 * push);
    assert!(
        (last.interaction_work - report.stored_energy).abs() < 0.01 * report.stored_energy,
        "W_c {} J against stored {} J",
        last.interaction_work,
        report.stored_energy
    );
}
