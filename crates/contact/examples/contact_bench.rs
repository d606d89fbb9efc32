//! Times one explicit step's contact work, `search` + `forces`, for about 5 × 10⁴ main
//! triangles against 5 × 10⁴ secondary nodes, on 1 and on all of rayon's threads:
//!
//! - deformable main: a 158 × 158 grid of 0.1 mm squares (49 928 triangles), gently
//!   waved, under a 224 × 224-node secondary grid (50 176 nodes, spacing 0.07 mm) that
//!   sits 1 µm into it, so every secondary node is in contact; the secondary grid slides
//!   by 0.2 µm per step, the main one waves in time (its leaves leave their fattened boxes
//!   now and then, so the tree is refitted);
//! - rigid main: the same grid as a rigid plane (49 928 triangles), translated each step.
//!
//! Run: `cargo run --release -p musclefem-contact --example contact_bench`.

use std::time::Instant;

use nalgebra::Vector3;

use musclefem_contact::{ContactTarget, DeformableSurface, PenaltyContact, RigidSurface};
use musclefem_core::mesh::{Mesh, Nodes};
use musclefem_core::solver::{Interaction, RigidMotion};
use musclefem_materials::Amplitude;

const MAIN: usize = 158;
const SECONDARY: usize = 224;
const SPACING: f64 = 1e-4;
const STEPS: usize = 30;

/// Triangles of an `n × n` grid of squares whose nodes start at `first`, normal +z.
fn grid_triangles(n: usize, first: u32) -> Vec<[u32; 3]> {
    let id = |i: usize, j: usize| first + (i + (n + 1) * j) as u32;
    let mut triangles = Vec::with_capacity(2 * n * n);
    for j in 0..n {
        for i in 0..n {
            triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    triangles
}

fn wave(x: f64, y: f64, t: f64) -> f64 {
    2e-6 * ((x / 1e-3 + t).sin() * (y / 1.3e-3).cos())
}

struct Problem {
    mesh: Mesh,
    main_nodes: usize,
}

fn problem() -> Problem {
    let mut nodes = Nodes::new();
    for j in 0..=MAIN {
        for i in 0..=MAIN {
            let (x, y) = (i as f64 * SPACING, j as f64 * SPACING);
            nodes.push(Vector3::new(x, y, wave(x, y, 0.0)));
        }
    }
    let main_nodes = nodes.len();
    let side = MAIN as f64 * SPACING;
    let step = 0.98 * side / (SECONDARY - 1) as f64;
    for j in 0..SECONDARY {
        for i in 0..SECONDARY {
            let (x, y) = (0.01 * side + i as f64 * step, 0.01 * side + j as f64 * step);
            nodes.push(Vector3::new(x, y, wave(x, y, 0.0) - 1e-6));
        }
    }
    Problem {
        mesh: Mesh::new(nodes, vec![]),
        main_nodes,
    }
}

/// Mean milliseconds of `search` and of `forces` over the steps.
fn time_steps(
    contact: &mut PenaltyContact,
    mut positions: impl FnMut(usize) -> Vec<Vector3<f64>>,
) -> (f64, f64, usize) {
    let mut force = vec![Vector3::zeros(); positions(0).len()];
    let (mut search, mut forces) = (0.0, 0.0);
    let mut active = 0;
    for step in 0..=STEPS {
        let x = positions(step);
        let time = step as f64 * 1e-6;
        let start = Instant::now();
        contact.search(time, &x).unwrap();
        let searched = Instant::now();
        force.fill(Vector3::zeros());
        contact.forces(time, &x, false, &mut force).unwrap();
        let done = Instant::now();
        contact.commit();
        // The first step builds the tree: timed apart.
        if step > 0 {
            search += (searched - start).as_secs_f64();
            forces += (done - searched).as_secs_f64();
        }
        active = contact.report().active_points;
    }
    (
        1e3 * search / STEPS as f64,
        1e3 * forces / STEPS as f64,
        active,
    )
}

fn main() {
    let Problem { mesh, main_nodes } = problem();
    let main_triangles = grid_triangles(MAIN, 0);
    let secondary_triangles = grid_triangles(SECONDARY - 1, main_nodes as u32);
    let main = DeformableSurface::from_triangles(&mesh, "main", main_triangles.clone()).unwrap();
    let secondary =
        DeformableSurface::from_triangles(&mesh, "secondary", secondary_triangles).unwrap();
    let reference: Vec<Vector3<f64>> = (0..mesh.node_count())
        .map(|i| mesh.nodes.position(i))
        .collect();
    println!(
        "{} main triangles, {} secondary nodes, search distance {:.3e} m, {} threads available",
        main.triangles.len(),
        secondary.nodes.len(),
        musclefem_contact::penalty::DEFAULT_SEARCH_FACTOR * secondary.element_size(),
        rayon::current_num_threads()
    );

    let moving = |step: usize| -> Vec<Vector3<f64>> {
        let t = step as f64 * 0.05;
        reference
            .iter()
            .enumerate()
            .map(|(n, p)| {
                if n < main_nodes {
                    Vector3::new(p.x, p.y, wave(p.x, p.y, t))
                } else {
                    let x = p.x + step as f64 * 2e-7;
                    Vector3::new(x, p.y, wave(x, p.y, t) - 1e-6)
                }
            })
            .collect()
    };
    let vertices: Vec<Vector3<f64>> = reference[..main_nodes]
        .iter()
        .map(|p| Vector3::new(p.x, p.y, 0.0))
        .collect();
    let motion = RigidMotion {
        translation: [Some(Amplitude::ramp(1.0, 1.0).unwrap()), None, None],
        rotation: None,
        follower: None,
    };
    let rigid = RigidSurface::new("plane", vertices, main_triangles)
        .unwrap()
        .with_motion(motion);
    let flat = |step: usize| -> Vec<Vector3<f64>> {
        reference
            .iter()
            .map(|p| Vector3::new(p.x + step as f64 * 1e-6, p.y, -1e-6))
            .collect()
    };

    let all = rayon::current_num_threads();
    for threads in [1, all] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        for (label, target) in [
            ("deformable main", ContactTarget::Deformable(main.clone())),
            ("rigid main     ", ContactTarget::Rigid(rigid.clone())),
        ] {
            let mut contact = PenaltyContact::new("bench", secondary.clone(), target, 1e9).unwrap();
            let deformable = label.starts_with("deformable");
            let (search, forces, active) = pool.install(|| {
                if deformable {
                    time_steps(&mut contact, moving)
                } else {
                    time_steps(&mut contact, flat)
                }
            });
            let statistics = contact.broadphase().statistics();
            println!(
                "{label} {threads} thread(s): search {search:.2} ms + forces {forces:.2} ms = {:.2} ms \
                 per step ({active} active nodes, {:.1} candidates per node, {} builds, {} refits \
                 in {} searches)",
                search + forces,
                contact.broadphase().candidate_count() as f64 / secondary.nodes.len() as f64,
                statistics.builds,
                statistics.refits,
                statistics.searches
            );
        }
    }
}
