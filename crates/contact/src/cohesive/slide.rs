//! Sliding bonds ([`super::TangentialMode::FreeSlide`]): at every search the bonded point
//! moves to the point of the main surface closest to the secondary node, found by a walk
//! from the bond's triangle over the triangles that share a vertex with it. The walk
//! moves to the closest triangle of the ring while that is strictly closer (a tie keeps
//! the current triangle), so it is deterministic and stops; it covers sliding of any
//! length over a connected surface in steps of one ring, up to [`MAX_HOPS`] rings per
//! search (an implicit Newton iteration or an explicit step).
//!
//! The bond (its node, area and damage) stays with the secondary node: the damage of a
//! bond is that of the secondary surface's patch, wherever it slides.
//!
//! A sliding bond's separation is its signed gap g to its triangle (re-projected at every
//! force evaluation, so line-search trials see the gap of their positions) less the gap
//! at formation (the bond's rest state), and its
//! traction acts along the direction ν of the gap ([`evaluate_sliding`]): the triangle's
//! normal n over the face, the unit vector from the closest point to the node over an
//! interior edge or vertex (the gradient of the distance, continuous across a convex
//! edge, so a node sliding over it feels a force that turns smoothly), and n again past
//! the rim of an open surface: there the node keeps the plane of its rim triangle, g is
//! its distance to that plane and it is not pulled sideways back to the rim; its reaction
//! acts at the closest rim point, so forces balance but a node that overhangs the rim by
//! d leaves a couple d × f_s unbalanced (projecting on the plane past the rim balances it
//! but hands the corners reactions growing like d/h, which tipped the rim triangles over
//! in the tests). Across a concave edge the closest point jumps between the faces, and so
//! does the direction of the force.

use nalgebra::{Isometry3, Matrix3, Vector3};
use rayon::prelude::*;

use super::bonds::{Bond, BondState};
use super::law::CohesiveLaw;
use super::slide_tangent::{Footing, pivot_tangent, sliding_tangent};
use crate::main_side::MainSide;
use crate::projection::{Feature, project_on_triangle};
use crate::surface::ContactTarget;

/// Rings a walk may cross per search.
pub const MAX_HOPS: usize = 64;

/// For each triangle, the other triangles that share a vertex with it, in increasing
/// order (compressed rows).
#[derive(Debug, Clone, PartialEq)]
pub struct Neighbours {
    offsets: Vec<usize>,
    triangles: Vec<u32>,
}

impl Neighbours {
    /// The vertex rings of `triangles` (vertex ids per triangle).
    pub fn new(triangles: &[[u32; 3]]) -> Self {
        let vertex_count = triangles
            .iter()
            .flatten()
            .map(|&v| v as usize + 1)
            .max()
            .unwrap_or(0);
        let mut by_vertex: Vec<Vec<u32>> = vec![Vec::new(); vertex_count];
        for (t, vertices) in triangles.iter().enumerate() {
            for &v in vertices {
                by_vertex[v as usize].push(t as u32);
            }
        }
        let mut offsets = Vec::with_capacity(triangles.len() + 1);
        let mut list = Vec::new();
        offsets.push(0);
        let mut ring = Vec::new();
        for (t, vertices) in triangles.iter().enumerate() {
            ring.clear();
            for &v in vertices {
                ring.extend(by_vertex[v as usize].iter().filter(|&&o| o as usize != t));
            }
            ring.sort_unstable();
            ring.dedup();
            list.extend_from_slice(&ring);
            offsets.push(list.len());
        }
        Neighbours {
            offsets,
            triangles: list,
        }
    }

    /// The triangles sharing a vertex with `triangle`.
    pub fn of(&self, triangle: usize) -> &[u32] {
        &self.triangles[self.offsets[triangle]..self.offsets[triangle + 1]]
    }
}

/// [`slide`] for every bond, in parallel over fixed blocks of bonds (each bond on its own,
/// so the result does not depend on the number of threads).
pub fn slide_all(
    bonds: &mut [Bond],
    main: &ContactTarget,
    neighbours: &Neighbours,
    positions: &[Vector3<f64>],
    placement: &Isometry3<f64>,
) {
    bonds
        .par_iter_mut()
        .with_min_len(64)
        .for_each(|bond| slide(bond, main, neighbours, positions, placement));
}

/// Moves `bond` to the point of the `main` surface (placed by `placement`, vertices at
/// nodal `positions` [m]) closest to its node, walking from its current triangle.
pub fn slide(
    bond: &mut Bond,
    main: &ContactTarget,
    neighbours: &Neighbours,
    positions: &[Vector3<f64>],
    placement: &Isometry3<f64>,
) {
    let x = positions[bond.node as usize];
    let project = |triangle: usize| {
        let projection = project_on_triangle(&x, &main.corners(triangle, positions, placement));
        (
            Vector3::from(projection.barycentric),
            (x - projection.point).norm_squared(),
        )
    };
    let mut current = bond.triangle as usize;
    let (mut coordinates, mut distance2) = project(current);
    for _ in 0..MAX_HOPS {
        let mut best = current;
        for &other in neighbours.of(current) {
            if main
                .nodes(other as usize)
                .is_some_and(|n| n.contains(&bond.node))
            {
                continue;
            }
            let (xi, d2) = project(other as usize);
            if d2 < distance2 {
                best = other as usize;
                coordinates = xi;
                distance2 = d2;
            }
        }
        if best == current {
            break;
        }
        current = best;
    }
    bond.triangle = current as u32;
    bond.coordinates = coordinates;
}

/// The sliding `bond` at secondary position `x` [m], its triangle at `corners` [m] with
/// the rim bits `rim` (see the module docs): f_s = A t_n(g) ν, with the full
/// linearization (`slide_tangent.rs`): the turning of the triangle or of ν, and the shift
/// of the closest point.
pub fn evaluate_sliding(
    bond: &Bond,
    law: &CohesiveLaw,
    corners: &[Vector3<f64>; 3],
    rim: u8,
    x: &Vector3<f64>,
    with_stiffness: bool,
) -> BondState {
    let projection = project_on_triangle(x, corners);
    let on_rim = |bits: u8| rim & bits != 0;
    // Interior edges and corners: (index, is a corner).
    let pivot = match projection.feature {
        Feature::Face => None,
        Feature::Edge(i) if !on_rim(1 << i) => Some((i as usize, false)),
        Feature::Vertex(i) if !on_rim((1 << i) | (1 << ((i + 2) % 3))) => Some((i as usize, true)),
        _ => None,
    };
    let coordinates = Vector3::from(projection.barycentric);
    let (gap, direction) = match pivot {
        Some(_) => (projection.gap, projection.direction),
        // The face, or past the rim (the plane of the rim triangle).
        None => (
            (x - projection.point).dot(&projection.normal),
            projection.normal,
        ),
    };
    // The law sees the opening from the bond's rest state, the gap at formation; the
    // geometry (how ν turns about a pivot) sees the gap itself.
    let opening = gap - bond.reference_separation.x;
    let response = law.evaluate(&Vector3::new(opening, 0.0, 0.0), bond.history);
    let traction = response.traction.x;
    let scalars = (bond.area * traction, bond.area * response.tangent[(0, 0)]);
    let (coupling, coordinate_gradients) = match pivot {
        _ if !with_stiffness => ([Matrix3::zeros(); 4], [Matrix3::zeros(); 4]),
        Some(pivot) => pivot_tangent(corners, pivot, x, &direction, gap, scalars),
        None => {
            let footing = Footing::of(projection.feature);
            sliding_tangent(corners, footing, x, &coordinates, &direction, gap, scalars)
        }
    };
    BondState {
        force: bond.area * traction * direction,
        coupling,
        coordinate_gradients,
        turning: [Matrix3::zeros(); 3],
        turning_curvature: [[Matrix3::zeros(); 3]; 3],
        traction: -traction * direction,
        separation: Vector3::new(opening, 0.0, 0.0),
        triangle: bond.triangle,
        coordinates,
        history: response.history,
        damage: response.damage,
        energy: bond.area * response.energy,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rigid_surface::RigidSurface;

    /// A fixed rigid strip of 2n triangles on the plane z = 0 along x, unit squares split
    /// in two.
    fn strip(n: u32) -> ContactTarget {
        let mut vertices = Vec::new();
        for i in 0..=n {
            vertices.push(Vector3::new(f64::from(i), 0.0, 0.0));
            vertices.push(Vector3::new(f64::from(i), 1.0, 0.0));
        }
        let triangles = (0..n)
            .flat_map(|i| {
                let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
                [[a, b, c], [a, c, d]]
            })
            .collect();
        RigidSurface::new("strip", vertices, triangles)
            .unwrap()
            .into()
    }

    #[test]
    fn a_bond_walks_to_the_closest_point_along_the_surface() {
        let main = strip(20);
        let neighbours = Neighbours::new(main.triangles());
        assert_eq!(neighbours.of(0), &[1, 2, 3]);
        let node = 0;
        let mut positions = vec![Vector3::new(0.2, 0.3, 0.5)];
        let mut bond = Bond {
            node,
            area: 1.0,
            triangle: 0,
            coordinates: Vector3::new(1.0, 0.0, 0.0),
            normal: Vector3::z(),
            history: 0.0,
            reference_separation: Vector3::zeros(),
        };
        // Slide 13.5 units along x: the walk crosses the strip in one search.
        positions[node as usize] = Vector3::new(13.7, 0.6, 0.5);
        slide(
            &mut bond,
            &main,
            &neighbours,
            &positions,
            &Isometry3::identity(),
        );
        let vertices = main.corners(bond.triangle as usize, &positions, &Isometry3::identity());
        let point = bond.main_point(&vertices);
        assert!(
            (point - Vector3::new(13.7, 0.6, 0.0)).norm() < 1e-14,
            "{point:?}"
        );
        assert_eq!(bond.triangle / 2, 13);
    }
}
