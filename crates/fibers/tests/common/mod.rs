//! Meshes with known flows for the verification tests, built from the box generators of
//! musclefem-core by moving their nodes.

#![allow(dead_code)]

use std::f64::consts::PI;

use musclefem_mesh::generate::{TetOrder, box_of_hexes, box_of_tets};
use musclefem_mesh::{ElementBlock, Mesh};
use nalgebra::Vector3;

/// The element shapes the tests run on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cells {
    Hex8,
    Tet4,
    Tet10,
}

impl Cells {
    pub const ALL: [Cells; 3] = [Cells::Hex8, Cells::Tet4, Cells::Tet10];
}

/// A box [0, size] with `divisions` of the chosen cells (tets: 6 per box cell).
pub fn box_mesh(cells: Cells, size: [f64; 3], divisions: [usize; 3]) -> Mesh {
    match cells {
        Cells::Hex8 => box_of_hexes(size, divisions),
        Cells::Tet4 => box_of_tets(size, divisions, TetOrder::Linear),
        Cells::Tet10 => box_of_tets(size, divisions, TetOrder::Quadratic),
    }
    .expect("valid box")
}

/// Inner radius of the annular sector [m].
pub const INNER_RADIUS: f64 = 1.0;
/// Outer radius [m].
pub const OUTER_RADIUS: f64 = 2.0;
/// Opening angle [rad].
pub const OPENING: f64 = PI / 2.0;
/// Height [m].
pub const HEIGHT: f64 = 0.5;

/// The annular sector r ∈ [1, 2] m, θ ∈ [0, π/2], z ∈ [0, 0.5] m: the unit box mapped by
/// (u, v, w) ↦ (r cos θ, r sin θ, z) with r = 1 + u, θ = (π/2) v, z = 0.5 w, so `divisions`
/// are (radial, angular, axial). Its surfaces `y0` and `y1` are the cut faces θ = 0 and
/// θ = π/2 (nodes on the circles: the walls are polygons through them).
pub fn annular_sector(cells: Cells, divisions: [usize; 3]) -> Mesh {
    let mut mesh = box_mesh(cells, [1.0, 1.0, 1.0], divisions);
    for i in 0..mesh.nodes.len() {
        let p = mesh.nodes.position(i);
        let r = INNER_RADIUS + (OUTER_RADIUS - INNER_RADIUS) * p.x;
        let theta = OPENING * p.y;
        mesh.nodes.set_position(
            i,
            Vector3::new(r * theta.cos(), r * theta.sin(), HEIGHT * p.z),
        );
    }
    mesh
}

/// The circumferential unit vector e_θ at `x`: the exact fiber direction in the sector.
pub fn circumferential(x: Vector3<f64>) -> Vector3<f64> {
    let theta = x.y.atan2(x.x);
    Vector3::new(-theta.sin(), theta.cos(), 0.0)
}

/// Angle between two vectors [degrees].
pub fn angle_degrees(a: Vector3<f64>, b: Vector3<f64>) -> f64 {
    a.cross(&b).norm().atan2(a.dot(&b)).to_degrees()
}

/// Centroid of the corner nodes of every element, block after block.
pub fn element_centres(mesh: &Mesh) -> Vec<Vector3<f64>> {
    let mut centres = Vec::new();
    for block in &mesh.blocks {
        let corners = block.shape.corner_count();
        for ids in block.elements() {
            let sum: Vector3<f64> = ids[..corners]
                .iter()
                .map(|&id| mesh.nodes.position(id as usize))
                .sum();
            centres.push(sum / corners as f64);
        }
    }
    centres
}

/// Half width of the slot between the arms of the Y [m].
pub const Y_SLOT: f64 = 0.25;
/// Radius of the inner wall of each arm's bend [m].
pub const Y_BEND: f64 = 1.5;
/// The branch point of the Y: the middle of the crotch [m].
pub const Y_BRANCH_POINT: [f64; 2] = [1.0, 2.0];

/// A Y-shaped (branched) domain, 0.5 m thick: a trunk x ∈ [0, 2], y ∈ [0, 2] and two
/// arms, each x ∈ [0, 0.75] or [1.25, 2] above y = 2, bent outward around a circle (like
/// the annular sector: the arm's wall x = 0 becomes an arc of radius 1.5 m, and the arm
/// turns by 2/1.875 rad ≈ 61°). The inlet is the foot of the trunk (node set `y0`), the
/// outlets are the arm ends (node sets `left_end` and `right_end`), each a cut square to
/// its arm. The junction has two re-entrant corners at (1 ∓ 0.25, 2), where ∇φ is
/// singular, with a stagnation point between them on the crotch wall.
///
/// `per_metre` divisions per metre, a multiple of 4 (so the slot edges are lattice lines).
pub fn y_domain(cells: Cells, per_metre: usize) -> Mesh {
    let n = per_metre;
    let mut mesh = box_mesh(cells, [2.0, 4.0, 0.5], [2 * n, 4 * n, n.div_ceil(2)]);
    let centres = element_centres(&mesh);
    let block = &mesh.blocks[0];
    let mut connectivity = Vec::new();
    for (ids, c) in block.elements().zip(&centres) {
        let in_slot = c.y > 2.0 && (c.x - 1.0).abs() < Y_SLOT;
        if !in_slot {
            connectivity.extend_from_slice(ids);
        }
    }
    mesh.blocks = vec![ElementBlock::new("y", block.shape, connectivity).expect("whole elements")];
    mesh.surfaces.clear();
    mesh.element_sets.clear();
    let top = mesh.node_sets.remove("y1").unwrap_or_default();
    let (left, right): (Vec<u32>, Vec<u32>) = top
        .into_iter()
        .partition(|&id| mesh.nodes.x[id as usize] < 1.0);
    mesh.node_sets.retain(|name, _| name == "y0");
    mesh.node_sets.insert("left_end".to_string(), left);
    mesh.node_sets.insert("right_end".to_string(), right);
    // Each arm bends around the centre of its wall's arc: arc length y − 2 along the
    // arm's middle line (radius Y_BEND + 0.375) becomes the angle.
    let middle_radius = Y_BEND + (1.0 - Y_SLOT) / 2.0;
    for i in 0..mesh.nodes.len() {
        let p = mesh.nodes.position(i);
        if p.y <= 2.0 {
            continue;
        }
        let angle = (p.y - 2.0) / middle_radius;
        let (sin, cos) = angle.sin_cos();
        let moved = if p.x < 1.0 {
            let r = Y_BEND + p.x;
            Vector3::new(-Y_BEND + r * cos, 2.0 + r * sin, p.z)
        } else {
            let r = Y_BEND + (2.0 - p.x);
            Vector3::new(2.0 + Y_BEND - r * cos, 2.0 + r * sin, p.z)
        };
        mesh.nodes.set_position(i, moved);
    }
    mesh
}
