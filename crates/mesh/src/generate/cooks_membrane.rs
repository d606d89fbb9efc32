//! Cook's membrane: the tapered panel of Cook (1974) used to test elements for shear and
//! volumetric locking, extruded one element thick.
//!
//! The panel has the corners A = (0, 0), B = (48, 44), C = (48, 60), D = (0, 44) mm
//! ([`COOKS_MEMBRANE_CORNERS`], stored in metres), area 1440 mm² = 1.44e-3 m². The left
//! edge AD (x = 0) is clamped, the right edge BC (x = 48 mm, 16 mm long) carries a
//! shear load, and the displacement read is that of the top-right corner C.
//!
//! The mesh maps a box lattice [0, 1]² × [0, t] of `n × n × 1` cells (from
//! [`super::box_of_hexes`] or [`super::box_of_tets`]) bilinearly onto the panel:
//!
//! x(ξ, η) = (1 − ξ)(1 − η) A + ξ(1 − η) B + ξη C + (1 − ξ)η D,   z = z,
//!
//! with ξ the lattice x (A→B) and η the lattice y (A→D). The map is linear along the
//! lattice lines, so every cell becomes a prism over a convex quadrilateral with straight
//! sides, and the cells tile the panel exactly. Tet10 mid-edge nodes are put at the
//! midpoints of their (mapped) edge ends, so every tet is straight-sided (the diagonal
//! edges of the Kuhn split would otherwise bow, as the map is quadratic along them).
//!
//! Names: the box's node sets, element set and surfaces (`x0 … z1`, `all`, `outer`) are
//! kept, with aliases for the benchmark: node sets and surfaces `clamped` (= `x0`, edge
//! AD) and `loaded` (= `x1`, edge BC), and node set `tip`: the nodes at corner C (one per
//! lattice layer in z, so 2 nodes; with the panel in plane strain they move alike).

use std::collections::BTreeMap;

use nalgebra::{Vector2, Vector3};

use super::{TetOrder, box_of_hexes, box_of_tets};
use crate::{ElementShape, FaceShape, Mesh, MeshError};

/// Corners A, B, C, D of the panel [m] (x, y), counter-clockwise.
pub const COOKS_MEMBRANE_CORNERS: [[f64; 2]; 4] =
    [[0.0, 0.0], [0.048, 0.044], [0.048, 0.060], [0.0, 0.044]];

/// Area of the panel [m²]: 1440 mm² (shoelace formula on [`COOKS_MEMBRANE_CORNERS`]).
pub const COOKS_MEMBRANE_AREA: f64 = 1.44e-3;

/// Cook's membrane of `divisions × divisions` cells, one cell of `thickness` [m] through
/// the thickness, as hex8 (one per cell), tet4 or tet10 (six per cell, Kuhn split).
///
/// Errors if `thickness` is not finite and positive or `divisions` is zero.
pub fn cooks_membrane(
    shape: ElementShape,
    divisions: usize,
    thickness: f64,
) -> Result<Mesh, MeshError> {
    let size = [1.0, 1.0, thickness];
    let cells = [divisions, divisions, 1];
    let mut mesh = match shape {
        ElementShape::Hex8 => box_of_hexes(size, cells)?,
        ElementShape::Tet4 => box_of_tets(size, cells, TetOrder::Linear)?,
        ElementShape::Tet10 => box_of_tets(size, cells, TetOrder::Quadratic)?,
    };
    let nodes = &mut mesh.nodes;
    for i in 0..nodes.len() {
        let p = nodes.position(i);
        let xy = panel_point(p.x, p.y);
        nodes.set_position(i, Vector3::new(xy.x, xy.y, p.z));
    }
    if shape.is_quadratic() {
        // Straight-sided tets: each mid-edge node at the midpoint of its edge's ends.
        let block = &mesh.blocks[0];
        for ids in block.elements() {
            for (edge, &[a, b]) in shape.edges().iter().enumerate() {
                if let Some(mid) = shape.mid_edge_node(edge) {
                    let (a, b) = (ids[a as usize] as usize, ids[b as usize] as usize);
                    let midpoint = 0.5 * (mesh.nodes.position(a) + mesh.nodes.position(b));
                    mesh.nodes
                        .set_position(ids[mid as usize] as usize, midpoint);
                }
            }
        }
    }
    for (alias, name) in [("clamped", "x0"), ("loaded", "x1")] {
        let nodes = mesh.node_set(name)?.to_vec();
        let faces = mesh.surface(name)?.to_vec();
        mesh.node_sets.insert(alias.to_string(), nodes);
        mesh.surfaces.insert(alias.to_string(), faces);
    }
    let tip: Vec<u32> = (0..2)
        .map(|layer| (divisions + (divisions + 1) * (divisions + (divisions + 1) * layer)) as u32)
        .collect();
    mesh.node_sets.insert("tip".to_string(), tip);
    Ok(mesh)
}

/// The bilinear map of the unit square onto the panel [m].
fn panel_point(xi: f64, eta: f64) -> Vector2<f64> {
    let [a, b, c, d] = COOKS_MEMBRANE_CORNERS.map(Vector2::from);
    a * ((1.0 - xi) * (1.0 - eta))
        + b * (xi * (1.0 - eta))
        + c * (xi * eta)
        + d * ((1.0 - xi) * eta)
}

/// The consistent nodal weights of a uniform traction on surface `surface` of `mesh`:
/// w_a = ∫_S N_a dA [m²] over the reference surface, so that a traction t [Pa] gives the
/// nodal forces f_a = t w_a [N] and a total force F the forces F w_a / Σ_b w_b.
///
/// Per face, of reference area A_f (|area vector|, the faces must be flat):
/// - quad4 (hex8): A_f/4 at each corner — exact for parallelograms (the bilinear N_a
///   integrate to A/4 when the Jacobian is constant);
/// - tri3 (tet4): A_f/3 at each corner;
/// - tri6 (tet10): 0 at the corners and A_f/3 at the mid-side nodes. With area
///   coordinates L_i, ∫ L_i^a L_j^b dA = 2A a! b!/(a + b + 2)!, so a corner's
///   N = L₁(2L₁ − 1) integrates to 2·(A/6) − A/3 = 0 and a mid-side node's N = 4L₁L₂
///   to 4·(A/12) = A/3.
///
/// Returns (node, w) in increasing node order.
pub fn consistent_nodal_areas(mesh: &Mesh, surface: &str) -> Result<Vec<(u32, f64)>, MeshError> {
    let mut weights: BTreeMap<u32, f64> = BTreeMap::new();
    for &face in mesh.surface(surface)? {
        let ids = mesh.face_nodes(face)?;
        let area = mesh.face_area_vector(face)?.norm();
        let shape = mesh
            .block(face.element.block)?
            .shape
            .face_shape(face.face as usize);
        let shares: &[f64] = match shape {
            FaceShape::Quad4 => &[0.25; 4],
            FaceShape::Tri3 => &[1.0 / 3.0; 3],
            FaceShape::Tri6 => &[0.0, 0.0, 0.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
        };
        for (&id, share) in ids.iter().zip(shares) {
            *weights.entry(id).or_default() += share * area;
        }
    }
    Ok(weights.into_iter().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    const THICKNESS: f64 = 1e-3;

    fn meshes(divisions: usize) -> Vec<Mesh> {
        ElementShape::ALL
            .iter()
            .map(|&shape| cooks_membrane(shape, divisions, THICKNESS).unwrap())
            .collect()
    }

    #[test]
    fn the_corners_give_the_stated_area() {
        let c = COOKS_MEMBRANE_CORNERS;
        let twice: f64 = (0..4)
            .map(|i| {
                let (p, q) = (c[i], c[(i + 1) % 4]);
                p[0] * q[1] - q[0] * p[1]
            })
            .sum();
        assert!((0.5 * twice - COOKS_MEMBRANE_AREA).abs() < 1e-15);
    }

    /// The elements tile the panel: volumes are positive and sum to area × thickness.
    #[test]
    fn elements_are_valid_and_fill_the_panel() {
        for divisions in [1, 2, 5] {
            for mesh in meshes(divisions) {
                let shape = mesh.blocks[0].shape;
                mesh.validate()
                    .unwrap_or_else(|e| panic!("{shape:?} {divisions}: {e}"));
                let exact = COOKS_MEMBRANE_AREA * THICKNESS;
                let total = mesh.total_volume().unwrap();
                assert!((total - exact).abs() < 1e-12 * exact, "{shape:?}: {total}");
                for &r in mesh.element_set("all").unwrap() {
                    let v = mesh.element_volume(r).unwrap();
                    assert!(v > 0.0, "{shape:?} {divisions} {r}: {v}");
                }
            }
        }
    }

    /// The named sets sit where they should: the clamped edge at x = 0, the loaded edge at
    /// x = 48 mm between y = 44 and 60 mm, the tip at C.
    #[test]
    fn node_sets_lie_on_their_edges() {
        let n = 4;
        for mesh in meshes(n) {
            let shape = mesh.blocks[0].shape;
            let at = |id: &u32| mesh.nodes.position(*id as usize);
            let clamped = mesh.node_set("clamped").unwrap();
            let loaded = mesh.node_set("loaded").unwrap();
            assert!(clamped.iter().all(|id| at(id).x == 0.0));
            assert!(loaded.iter().all(|id| (at(id).x - 0.048).abs() < 1e-15));
            let on_bc = |id: &u32| (0.044 - 1e-15..=0.060 + 1e-15).contains(&at(id).y);
            assert!(loaded.iter().all(on_bc));
            if !shape.is_quadratic() {
                // n + 1 lattice nodes along the edge, in each of the 2 layers.
                assert_eq!(clamped.len(), 2 * (n + 1), "{shape:?}");
                assert_eq!(loaded.len(), 2 * (n + 1), "{shape:?}");
            }
            let tip = mesh.node_set("tip").unwrap();
            assert_eq!(tip.len(), 2);
            for id in tip {
                assert!((at(id).xy() - Vector2::new(0.048, 0.060)).norm() < 1e-15);
            }
            assert_eq!(at(&tip[1]).z, THICKNESS);
        }
    }

    /// The weights of a uniform traction sum to the loaded area (16 mm × t) and follow the
    /// stated shares: on the rectangle faces of the loaded edge every quad4 corner gets a
    /// quarter; tri6 corners get nothing.
    #[test]
    fn consistent_nodal_areas_sum_to_the_loaded_area() {
        let n = 4;
        let area = 0.016 * THICKNESS;
        for mesh in meshes(n) {
            let shape = mesh.blocks[0].shape;
            let weights = consistent_nodal_areas(&mesh, "loaded").unwrap();
            let total: f64 = weights.iter().map(|(_, w)| w).sum();
            assert!((total - area).abs() < 1e-14 * area, "{shape:?}: {total}");
            let face_area = area
                / n as f64
                / if shape == ElementShape::Hex8 {
                    1.0
                } else {
                    2.0
                };
            match shape {
                ElementShape::Hex8 => {
                    // Interior edge nodes are shared by two faces, the end ones by one.
                    for (id, w) in &weights {
                        let y = mesh.nodes.position(*id as usize).y;
                        let end = (y - 0.044).abs() < 1e-15 || (y - 0.060).abs() < 1e-15;
                        let faces = if end { 1.0 } else { 2.0 };
                        assert!((w - faces * face_area / 4.0).abs() < 1e-15, "{id}: {w}");
                    }
                }
                ElementShape::Tet10 => {
                    let corners = mesh.blocks[0].connectivity.chunks_exact(10);
                    let is_corner = |id: u32| corners.clone().any(|e| e[..4].contains(&id));
                    for (id, w) in &weights {
                        if is_corner(*id) {
                            assert_eq!(*w, 0.0, "corner {id}");
                        }
                    }
                    assert!(weights.iter().any(|(_, w)| *w > 0.0));
                }
                ElementShape::Tet4 => {}
            }
        }
    }
}
