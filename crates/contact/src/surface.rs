//! Deformable surfaces: the triangles and nodes of a part's boundary, built from mesh faces,
//! and [`ContactTarget`], the main side of a contact (deformable or rigid).
//!
//! Triangulation of the element faces (every face's node list runs counter-clockwise seen
//! from outside, [`musclefem_core::mesh::ElementShape::faces`], so every triangle's
//! right-hand normal (x₂ − x₁) × (x₃ − x₁) points out of the body):
//! - tri3 (tet4) faces are one triangle;
//! - quad4 (hex8) faces `[a, b, c, d]` are split along the diagonal a–c (first to third
//!   node) into `[a, b, c]` and `[a, c, d]`;
//! - tri6 (tet10) faces `[c₁, c₂, c₃, m₁₂, m₂₃, m₃₁]` are split through the mid-side nodes
//!   into four: `[c₁, m₁₂, m₃₁]`, `[m₁₂, c₂, m₂₃]`, `[m₃₁, m₂₃, c₃]`, `[m₁₂, m₂₃, m₃₁]`.
//!
//! Tributary areas [m²] are lumped per face in the reference configuration and sum to the
//! surface's area:
//! - a quad4 face gives a quarter of its area (the sum of its two triangles) to each
//!   corner: the consistent share of a uniform pressure on a parallelogram, so a uniform
//!   penetration gives a uniform pressure, whichever diagonal split the face;
//! - every other triangle (tri3 faces, the four triangles of a tri6 face, triangles given
//!   directly to [`DeformableSurface::from_triangles`]) gives a third of its area A_t to
//!   each of its nodes, A_a = Σ_{t ∋ a} A_t / 3. For tri6 faces this is not the consistent
//!   load vector (which puts nothing on the corners): a node-to-surface penalty needs an
//!   area at every node that can touch.

use std::collections::{BTreeSet, HashMap};

use nalgebra::Vector3;

use musclefem_core::mesh::{ElementRef, Face, FaceShape, Mesh};

use crate::error::ContactError;
use crate::rigid_surface::RigidSurface;

/// The boundary of a deformable part, as triangles between mesh nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct DeformableSurface {
    /// Name in messages and outputs.
    pub name: String,
    /// The mesh nodes of the surface (global ids), sorted, without repeats.
    pub nodes: Vec<u32>,
    /// Triangles by global node ids, right-hand normal pointing out of the body.
    pub triangles: Vec<[u32; 3]>,
    /// Reference area of each triangle [m²].
    pub triangle_area: Vec<f64>,
    /// Tributary reference area of each node of [`Self::nodes`] [m²] (lumped per face, see
    /// the module docs).
    pub node_area: Vec<f64>,
    /// Per triangle, bit `i` set when its edge `i` (vertex `i` to vertex `i + 1`) belongs to
    /// no other triangle: the rim of an open surface.
    pub boundary_edges: Vec<u8>,
}

impl DeformableSurface {
    /// The surface made of `faces` of `mesh`, named `name`.
    ///
    /// Errors if `faces` is empty, a face does not exist in `mesh`, or a triangle has no
    /// area in the reference configuration.
    pub fn from_faces(mesh: &Mesh, name: &str, faces: &[Face]) -> Result<Self, ContactError> {
        let mesh_error = |source| ContactError::Mesh {
            surface: name.to_string(),
            source,
        };
        if faces.is_empty() {
            return Err(ContactError::EmptySurface(name.to_string()));
        }
        let mut triangles = Vec::with_capacity(2 * faces.len());
        let mut quads = Vec::new();
        for &face in faces {
            let ids = mesh.face_nodes(face).map_err(mesh_error)?;
            let shape = mesh
                .block(face.element.block)
                .map_err(mesh_error)?
                .shape
                .face_shape(face.face as usize);
            if shape == FaceShape::Quad4 {
                quads.push(triangles.len());
            }
            triangulate(shape, &ids, &mut triangles);
        }
        let mut surface = Self::from_triangles(mesh, name, triangles)?;
        // Quad4 faces: a quarter of the face to each corner instead of the triangles' thirds.
        for &first in &quads {
            let [a, b, c] = surface.triangles[first];
            let d = surface.triangles[first + 1][2];
            let area = surface.triangle_area[first] + surface.triangle_area[first + 1];
            let thirds = [
                (
                    a,
                    (surface.triangle_area[first] + surface.triangle_area[first + 1]) / 3.0,
                ),
                (b, surface.triangle_area[first] / 3.0),
                (c, area / 3.0),
                (d, surface.triangle_area[first + 1] / 3.0),
            ];
            for (node, third) in thirds {
                let local = surface
                    .nodes
                    .binary_search(&node)
                    .expect("a node of the surface");
                surface.node_area[local] += 0.25 * area - third;
            }
        }
        Ok(surface)
    }

    /// The surface named `surface` in `mesh` (see [`Mesh::surface`]).
    pub fn from_mesh_surface(mesh: &Mesh, surface: &str) -> Result<Self, ContactError> {
        let faces = mesh.surface(surface).map_err(|source| ContactError::Mesh {
            surface: surface.to_string(),
            source,
        })?;
        Self::from_faces(mesh, surface, faces)
    }

    /// The outer surface of the blocks named `blocks`: the faces of their elements that no
    /// other element of these blocks shares (matched by their corner nodes), in (block,
    /// element, face) order. Named after the blocks, joined by `+`.
    pub fn outer_surface(mesh: &Mesh, blocks: &[&str]) -> Result<Self, ContactError> {
        let name = blocks.join("+");
        let mut indices = Vec::with_capacity(blocks.len());
        for block in blocks {
            let (index, _) = mesh
                .block_by_name(block)
                .map_err(|source| ContactError::Mesh {
                    surface: name.clone(),
                    source,
                })?;
            indices.push(index);
        }
        let indices: BTreeSet<u32> = indices.into_iter().collect();
        let mut count: HashMap<[u32; 4], u32> = HashMap::new();
        let mut all = Vec::new();
        for &b in &indices {
            let block = &mesh.blocks[b as usize];
            for (e, ids) in block.elements().enumerate() {
                for (k, local) in block.shape.faces().iter().enumerate() {
                    let corners = block.shape.face_shape(k).corner_count();
                    let mut key = [u32::MAX; 4];
                    for (slot, &l) in key.iter_mut().zip(&local[..corners]) {
                        *slot = ids[l as usize];
                    }
                    key.sort_unstable();
                    *count.entry(key).or_insert(0) += 1;
                    all.push((Face::new(ElementRef::new(b, e as u32), k as u8), key));
                }
            }
        }
        let faces: Vec<Face> = all
            .into_iter()
            .filter(|(_, key)| count[key] == 1)
            .map(|(face, _)| face)
            .collect();
        Self::from_faces(mesh, &name, &faces)
    }

    /// The triangles whose centroids (the mean of their corners at the reference
    /// positions of `mesh`) lie at heights x · `axis` between `heights` [m], both
    /// included, in this surface's order; `axis` is a unit vector.
    pub fn triangles_between_heights(
        &self,
        mesh: &Mesh,
        axis: &Vector3<f64>,
        heights: [f64; 2],
    ) -> Vec<[u32; 3]> {
        let height = |triangle: &[u32; 3]| {
            let [a, b, c] = triangle.map(|n| mesh.nodes.position(n as usize));
            let centroid = Vector3::from_fn(|k, _| (a[k] + b[k] + c[k]) / 3.0);
            centroid.dot(axis)
        };
        self.triangles
            .iter()
            .filter(|t| (heights[0]..=heights[1]).contains(&height(t)))
            .copied()
            .collect()
    }

    /// The surface of `triangles` (global node ids of `mesh`, outward right-hand normal).
    pub fn from_triangles(
        mesh: &Mesh,
        name: &str,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Self, ContactError> {
        if triangles.is_empty() {
            return Err(ContactError::EmptySurface(name.to_string()));
        }
        let count = mesh.node_count();
        let mut triangle_area = Vec::with_capacity(triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&vertex) = tri.iter().find(|&&n| n as usize >= count) {
                return Err(ContactError::VertexOutOfRange {
                    surface: name.to_string(),
                    triangle: t,
                    vertex,
                    count,
                });
            }
            let [a, b, c] = tri.map(|n| mesh.nodes.position(n as usize));
            let area = 0.5 * (b - a).cross(&(c - a)).norm();
            let scale = (b - a).norm_squared().max((c - a).norm_squared());
            if area.is_nan() || area <= 1e-12 * scale {
                return Err(ContactError::DegenerateTriangle {
                    surface: name.to_string(),
                    triangle: t,
                    nodes: *tri,
                });
            }
            triangle_area.push(area);
        }
        let nodes: Vec<u32> = triangles
            .iter()
            .flatten()
            .copied()
            .collect::<BTreeSet<u32>>()
            .into_iter()
            .collect();
        let mut node_area = vec![0.0; nodes.len()];
        for (tri, area) in triangles.iter().zip(&triangle_area) {
            for n in tri {
                let local = nodes.binary_search(n).expect("a node of the surface");
                node_area[local] += area / 3.0;
            }
        }
        let boundary_edges = boundary_edges(&triangles);
        Ok(DeformableSurface {
            name: name.to_string(),
            nodes,
            triangles,
            triangle_area,
            node_area,
            boundary_edges,
        })
    }

    /// Index of the global node `node` in [`Self::nodes`], if it is on the surface.
    pub fn local_index(&self, node: u32) -> Option<usize> {
        self.nodes.binary_search(&node).ok()
    }

    /// Total reference area [m²].
    pub fn area(&self) -> f64 {
        self.triangle_area.iter().sum()
    }

    /// A typical element size h = √(2 Ā) [m], Ā the mean reference triangle area: the side
    /// of the squares (hex8 faces) the right triangles come from.
    pub fn element_size(&self) -> f64 {
        (2.0 * self.area() / self.triangles.len() as f64).sqrt()
    }

    /// The current corners of triangle `t` at nodal `positions` [m].
    #[inline]
    pub fn corners(&self, t: usize, positions: &[Vector3<f64>]) -> [Vector3<f64>; 3] {
        self.triangles[t].map(|n| positions[n as usize])
    }
}

/// Appends the triangles of one face (node ids in face order, see the module docs).
fn triangulate(shape: FaceShape, ids: &[u32], triangles: &mut Vec<[u32; 3]>) {
    match shape {
        FaceShape::Tri3 => triangles.push([ids[0], ids[1], ids[2]]),
        FaceShape::Quad4 => {
            triangles.push([ids[0], ids[1], ids[2]]);
            triangles.push([ids[0], ids[2], ids[3]]);
        }
        FaceShape::Tri6 => {
            let [c1, c2, c3, m12, m23, m31] = [ids[0], ids[1], ids[2], ids[3], ids[4], ids[5]];
            triangles.extend([
                [c1, m12, m31],
                [m12, c2, m23],
                [m31, m23, c3],
                [m12, m23, m31],
            ]);
        }
    }
}

/// Per triangle, bit `i` set when edge `i` (vertex `i` to `i + 1`) belongs to no other
/// triangle.
pub fn boundary_edges(triangles: &[[u32; 3]]) -> Vec<u8> {
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut count: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * triangles.len());
    for t in triangles {
        for i in 0..3 {
            *count.entry(key(t[i], t[(i + 1) % 3])).or_insert(0) += 1;
        }
    }
    triangles
        .iter()
        .map(|t| {
            (0..3)
                .filter(|&i| count[&key(t[i], t[(i + 1) % 3])] == 1)
                .fold(0u8, |bits, i| bits | (1 << i))
        })
        .collect()
}

/// The main side of a contact: a deformable surface (its nodes move with the mesh) or a
/// rigid one (it moves with its prescribed [`musclefem_core::solver::RigidMotion`]).
#[derive(Debug, Clone)]
pub enum ContactTarget {
    Deformable(DeformableSurface),
    Rigid(RigidSurface),
}

impl ContactTarget {
    /// Name of the surface.
    pub fn name(&self) -> &str {
        match self {
            ContactTarget::Deformable(s) => &s.name,
            ContactTarget::Rigid(s) => &s.name,
        }
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        match self {
            ContactTarget::Deformable(s) => s.triangles.len(),
            ContactTarget::Rigid(s) => s.triangles.len(),
        }
    }
}

impl From<DeformableSurface> for ContactTarget {
    fn from(surface: DeformableSurface) -> Self {
        ContactTarget::Deformable(surface)
    }
}

impl From<RigidSurface> for ContactTarget {
    fn from(surface: RigidSurface) -> Self {
        ContactTarget::Rigid(surface)
    }
}

#[cfg(test)]
mod tests {
    use musclefem_core::mesh::generate::{TetOrder, box_of_hexes, box_of_tets};

    use super::*;

    /// The outer surface of a box: area 2(ab + bc + ca), every triangle's normal points
    /// away from the centre, and the node areas sum to the total.
    #[test]
    fn outer_surfaces_of_boxes_are_closed_outward_and_have_the_box_area() {
        let size = [1.0, 2.0, 3.0];
        let exact = 2.0 * (1.0 * 2.0 + 2.0 * 3.0 + 3.0 * 1.0);
        let centre = Vector3::new(0.5, 1.0, 1.5);
        for mesh in [
            box_of_hexes(size, [2, 3, 2]).unwrap(),
            box_of_tets(size, [2, 1, 2], TetOrder::Linear).unwrap(),
            box_of_tets(size, [1, 2, 1], TetOrder::Quadratic).unwrap(),
        ] {
            let block = mesh.blocks[0].name.clone();
            let surface = DeformableSurface::outer_surface(&mesh, &[&block]).unwrap();
            let from_set = DeformableSurface::from_mesh_surface(&mesh, "outer").unwrap();
            assert!((surface.area() - exact).abs() < 1e-12 * exact, "{block}");
            assert!((from_set.area() - exact).abs() < 1e-12 * exact);
            let lumped: f64 = surface.node_area.iter().sum();
            assert!((lumped - exact).abs() < 1e-12 * exact);
            assert!(surface.boundary_edges.iter().all(|&b| b == 0), "closed");
            let positions: Vec<_> = (0..mesh.node_count())
                .map(|i| mesh.nodes.position(i))
                .collect();
            for t in 0..surface.triangles.len() {
                let [a, b, c] = surface.corners(t, &positions);
                let normal = (b - a).cross(&(c - a));
                let middle = (a + b + c) / 3.0;
                assert!(normal.dot(&(middle - centre)) > 0.0, "{block} triangle {t}");
            }
        }
    }

    #[test]
    fn one_face_of_a_box_is_open_with_boundary_edges() {
        let mesh = box_of_hexes([1.0, 1.0, 1.0], [2, 2, 2]).unwrap();
        let top = DeformableSurface::from_mesh_surface(&mesh, "z1").unwrap();
        assert_eq!(top.triangles.len(), 8);
        assert_eq!(top.nodes.len(), 9);
        // 8 rim edges, each on one triangle.
        let rim: u32 = top.boundary_edges.iter().map(|b| b.count_ones()).sum();
        assert_eq!(rim, 8);
        // The centre node (1, 1, 2) = 22 has a quarter of each of its 4 faces; a corner one.
        let centre = top.local_index(22).unwrap();
        assert!((top.node_area[centre] - 0.25).abs() < 1e-15);
        let corner = top.local_index(26).unwrap();
        assert!((top.node_area[corner] - 0.0625).abs() < 1e-15);
    }

    #[test]
    fn empty_and_unknown_surfaces_are_named_in_the_error() {
        let mesh = box_of_hexes([1.0, 1.0, 1.0], [1, 1, 1]).unwrap();
        let empty = DeformableSurface::from_faces(&mesh, "nothing", &[]).unwrap_err();
        assert!(empty.to_string().contains("'nothing' is empty"), "{empty}");
        let unknown = DeformableSurface::from_mesh_surface(&mesh, "skin").unwrap_err();
        let text = unknown.to_string();
        assert!(text.contains("skin") && text.contains("outer"), "{text}");
        let block = DeformableSurface::outer_surface(&mesh, &["bone"]).unwrap_err();
        assert!(block.to_string().contains("bone"), "{block}");
    }
}
