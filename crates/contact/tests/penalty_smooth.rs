//! A block pressed onto a folded rigid surface and slid across its fold, implicit
//! (quasi-static), with penalty contact along the smooth normal field of the main surface
//! (`PenaltyContact::with_smooth_normals`), and the same at the closest point.
//!
//! The block [−3, 3]² × [0, 3] mm (6 × 6 × 3 hexes, h = 1 mm) rests on a rigid sheet folded
//! along the y axis (2 mm facets): a convex ridge (a condyle, a 30° fold) under its
//! middle, or a concave valley (a trochlea, an 8° fold) whose flanks touch its bottom
//! edges. Its top
//! is pushed down by δ over the first half of the run and slid along x over the second
//! half; the fold then passes under the bottom nodes. At every step the contact force on
//! the block must balance the reaction of its top (the only other load), and the
//! penetration must stay small. The run is also repeated on 1 and 3 threads, bit for bit.

mod common;

use nalgebra::Vector3;

use musclefem_contact::{DeformableSurface, PenaltyContact, RigidSurface};
use musclefem_core::mesh::Mesh;
use musclefem_core::solver::implicit::{ImplicitResult, ImplicitSettings, run_implicit_with};
use musclefem_core::solver::{Interaction, Loads};
use musclefem_materials::Amplitude;

use common::*;

const MM: f64 = 1e-3;
/// Element size of the block [m].
const H: f64 = 1.0 * MM;

fn block() -> Mesh {
    box_at(
        Vector3::new(-3.0 * MM, -3.0 * MM, 0.0),
        [6.0 * MM, 6.0 * MM, 3.0 * MM],
        [6, 6, 3],
    )
}

/// The sheet z = `slope` |x| + `lift` over x ∈ [−14, 14] mm, y ∈ [−6, 6] mm in 2 mm
/// squares, facing +z: a ridge for a negative slope, a valley for a positive one.
fn fold(slope: f64, lift: f64) -> RigidSurface {
    let (nx, ny) = (14u32, 6u32);
    let mut vertices = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            let x = 2.0 * MM * (f64::from(i) - f64::from(nx) / 2.0);
            let y = 2.0 * MM * (f64::from(j) - f64::from(ny) / 2.0);
            vertices.push(Vector3::new(x, y, slope * x.abs() + lift));
        }
    }
    let id = |i: u32, j: u32| i + (nx + 1) * j;
    let triangles = (0..ny)
        .flat_map(|j| {
            (0..nx).flat_map(move |i| {
                [
                    [id(i, j), id(i + 1, j), id(i + 1, j + 1)],
                    [id(i, j), id(i + 1, j + 1), id(i, j + 1)],
                ]
            })
        })
        .collect();
    RigidSurface::new("fold", vertices, triangles).unwrap()
}

/// The top pushed down by `push` over [0, 0.5] s, then slid along x by `slide` over
/// [0.5, 1] s; y held.
fn loads(mesh: &Mesh, push: f64, slide: f64) -> Loads {
    let top = mesh.node_set("z1").unwrap();
    let knots = |values: [f64; 3]| {
        Amplitude::new(vec![(0.0, values[0]), (0.5, values[1]), (1.0, values[2])]).unwrap()
    };
    Loads {
        displacements: vec![
            prescribed(top, 0, knots([0.0, 0.0, slide])),
            held(top, 1),
            prescribed(top, 2, knots([0.0, -push, -push])),
        ],
        ..Loads::default()
    }
}

fn contact(mesh: &Mesh, main: RigidSurface, smooth: bool) -> Vec<Box<dyn Interaction>> {
    let bottom = DeformableSurface::from_mesh_surface(mesh, "z0").unwrap();
    let contact = PenaltyContact::with_default_penalty("block on fold", bottom, main, YOUNGS)
        .unwrap()
        .with_search_distance(0.5 * H)
        .unwrap();
    vec![Box::new(if smooth {
        contact.with_smooth_normals()
    } else {
        contact
    })]
}

/// A fold: its slope, the lift of its crease, and the top's push and slide [m].
#[derive(Clone, Copy)]
struct Case {
    name: &'static str,
    slope: f64,
    lift: f64,
    push: f64,
    slide: f64,
}

/// A concave valley (an 8° fold) whose flanks touch the block's bottom edges: pushed
/// 0.3 mm, deeper than the flanks rise under the block (0.21 mm), so the bottom reaches
/// the crease; slid 2 mm.
const VALLEY: Case = Case {
    name: "concave valley (8°)",
    slope: 0.069_926_811_943_510_4, // tan 4°
    lift: -3.0 * 0.069_926_811_943_510_4 * MM,
    push: 0.3 * MM,
    slide: 2.0 * MM,
};

/// A convex ridge (a 30° fold) under the block's middle: pushed 0.3 mm, slid 2 mm. Both
/// contacts end in nearly the same state (at the closest point one more row of nodes
/// touches, by 0.2 µm: 14 active nodes against 7), but the horizontal force differs
/// (3.5e-4 N against 6.9e-3 N): the row riding the crease is pushed nearly vertically
/// along the smooth field, which turns over the facets beside the crease (2 mm) as on a
/// rounded ridge, and along the 15° face normal at the closest point.
const RIDGE: Case = Case {
    name: "convex ridge (30°)",
    slope: -0.267_949_192_431_122_7, // tan 15°
    lift: 0.0,
    push: 0.3 * MM,
    slide: 2.0 * MM,
};

fn run(case: Case, smooth: bool, increments: usize) -> Result<ImplicitResult, String> {
    let mesh = block();
    let mut interactions = contact(&mesh, fold(case.slope, case.lift), smooth);
    run_implicit_with(
        &mesh,
        &parts(&mesh),
        &loads(&mesh, case.push, case.slide),
        &mut interactions,
        &ImplicitSettings::new(1.0, increments).with_cutting(),
        &mut LastFields::default(),
    )
    .map_err(|e| e.to_string())
}

/// Runs `case` in both modes; the smooth one must converge with the contact force
/// balancing the top's reaction at every step (1e-6 of the largest), the block in
/// contact and the rms penetration below 2 % of h (the contact concentrates on the fold:
/// 0.3 mm is 10 % of the block's height, which the default penalty turns into a uniform
/// penetration of 1 % of h).
fn slide_over(case: Case) {
    let mut checks = Vec::new();
    for smooth in [true, false] {
        let mode = if smooth {
            "smooth normals"
        } else {
            "closest point"
        };
        let result = match run(case, smooth, 10) {
            Ok(result) => result,
            Err(e) if !smooth => {
                println!("{}, {mode}: did not converge: {e}", case.name);
                continue;
            }
            Err(e) => panic!("{}, {mode}: {e}", case.name),
        };
        let iterations: Vec<usize> = result.steps.iter().map(|s| s.iterations).collect();
        let factorization = &result.steps[0].factorization;
        let largest = result
            .history
            .iter()
            .map(|row| row.interactions[0].force.norm())
            .fold(0.0, f64::max);
        let mut imbalance = 0.0f64;
        for row in &result.history {
            let reaction = Vector3::new(row.reactions[0], row.reactions[1], row.reactions[2]);
            imbalance = imbalance.max((row.interactions[0].force + reaction).norm());
        }
        let last = result.history.last().unwrap();
        let force = last.interactions[0].force;
        let penetration = (2.0 * last.interactions[0].stored_energy
            / (10.0 * YOUNGS / H * last.interactions[0].active_area))
            .sqrt();
        println!(
            "{}, {mode}: iterations {iterations:?} ({factorization:?}), cuts {}, final contact force {:.4e} N \
             ({:.3e}, {:.3e}, {:.3e}), {} active nodes, rms penetration {:.3} % of h, force \
             + reaction at most {:.1e} of the largest force",
            case.name,
            result.cuts,
            force.norm(),
            force.x,
            force.y,
            force.z,
            last.interactions[0].active_points,
            100.0 * penetration / H,
            imbalance / largest
        );
        if smooth {
            checks.push((
                imbalance / largest,
                force.z,
                last.interactions[0].active_points,
            ));
            checks.push((penetration / H, 0.0, 0));
        }
    }
    let [(imbalance, lift, active), (penetration, _, _)] = checks[..] else {
        unreachable!()
    };
    assert!(
        imbalance < 1e-6,
        "force + reaction {imbalance:e} of the largest force"
    );
    assert!(lift > 0.0 && active > 6, "{lift} N on {active} nodes");
    assert!(penetration < 0.02, "rms penetration {penetration} h");
}

#[test]
fn a_block_slides_over_a_convex_ridge_with_the_reaction_balancing_the_contact_force() {
    slide_over(RIDGE);
}

#[test]
fn a_block_slides_in_a_concave_valley_with_the_reaction_balancing_the_contact_force() {
    slide_over(VALLEY);
}

/// The smooth run over the ridge (in 4 increments) gives the same displacements and
/// history, bit for bit, on 1 and 3 threads (49 secondary nodes, evaluated in chunks of
/// 32).
#[test]
fn smooth_runs_are_bitwise_the_same_on_one_and_three_threads() {
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run(RIDGE, true, 4).unwrap())
    };
    let (one, three) = (on(1), on(3));
    let bits = |r: &ImplicitResult| {
        r.displacement
            .iter()
            .flat_map(|u| u.iter().map(|x| x.to_bits()).collect::<Vec<_>>())
            .collect::<Vec<u64>>()
    };
    assert_eq!(bits(&one), bits(&three));
    assert_eq!(one.history, three.history);
}
