//! Element shapes and their local topology: node counts, edges, faces, reference nodes.
//!
//! Local node numbering follows Abaqus (0-based here, 1-based in the Abaqus manual):
//!
//! - hex8 (C3D8): nodes 1–4 the face ζ = −1 counter-clockwise seen from +ζ, 5–8 above them;
//! - tet4 (C3D4): nodes 1, 2, 3 counter-clockwise seen from node 4;
//! - tet10 (C3D10): corners as tet4, mid-edge nodes 5:(1,2) 6:(2,3) 7:(3,1) 8:(1,4)
//!   9:(2,4) 10:(3,4).
//!
//! Faces are numbered as Abaqus numbers them (face `i` here is Abaqus face S(i+1)) and keep
//! the first node Abaqus lists, but their nodes run the other way round: the Abaqus lists
//! (C3D8 S1 1-2-3-4, S2 5-8-7-6, S3 1-5-6-2, S4 2-6-7-3, S5 3-7-8-4, S6 4-8-5-1; C3D4 S1
//! 1-2-3, S2 1-4-2, S3 2-4-3, S4 3-4-1) run clockwise seen from outside, so their
//! right-hand normal points into the element. Here every face's right-hand normal points
//! OUT of the element, which is what surfaces, contact and tractions need.

use std::fmt;

/// Largest number of nodes of one element over all shapes (tet10).
pub const MAX_NODES_PER_ELEMENT: usize = 10;
/// Largest number of nodes of one element face over all shapes (6-node triangle).
pub const MAX_FACE_NODES: usize = 6;

/// The shape (node layout and interpolation) of the elements of a block. The element
/// technology (full or reduced integration, F-bar) is chosen by the solver, not here.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ElementShape {
    /// 8-node trilinear hexahedron (Abaqus C3D8 node order).
    Hex8,
    /// 4-node linear tetrahedron (Abaqus C3D4 node order).
    Tet4,
    /// 10-node quadratic tetrahedron (Abaqus C3D10 node order).
    Tet10,
}

/// The shape of an element face.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FaceShape {
    /// 4-node bilinear quadrilateral.
    Quad4,
    /// 3-node linear triangle.
    Tri3,
    /// 6-node quadratic triangle: corners 1-2-3, then mid-edge nodes (1,2), (2,3), (3,1).
    Tri6,
}

const HEX8_FACES: [&[u8]; 6] = [
    &[0, 3, 2, 1], // S1, Abaqus 1-2-3-4
    &[4, 5, 6, 7], // S2, Abaqus 5-8-7-6
    &[0, 1, 5, 4], // S3, Abaqus 1-5-6-2
    &[1, 2, 6, 5], // S4, Abaqus 2-6-7-3
    &[2, 3, 7, 6], // S5, Abaqus 3-7-8-4
    &[3, 0, 4, 7], // S6, Abaqus 4-8-5-1
];

const TET4_FACES: [&[u8]; 4] = [
    &[0, 2, 1], // S1, Abaqus 1-2-3
    &[0, 1, 3], // S2, Abaqus 1-4-2
    &[1, 2, 3], // S3, Abaqus 2-4-3
    &[2, 0, 3], // S4, Abaqus 3-4-1
];

/// Corners as [`TET4_FACES`], then the mid-edge nodes of edges (c1,c2), (c2,c3), (c3,c1).
const TET10_FACES: [&[u8]; 4] = [
    &[0, 2, 1, 6, 5, 4],
    &[0, 1, 3, 4, 8, 7],
    &[1, 2, 3, 5, 9, 8],
    &[2, 0, 3, 6, 7, 9],
];

/// Edges in the order of the C3D20 mid-edge nodes (bottom ring, top ring, verticals).
const HEX8_EDGES: [[u8; 2]; 12] = [
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
    [4, 5],
    [5, 6],
    [6, 7],
    [7, 4],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];

/// Edges in the order of the C3D10 mid-edge nodes: tet10 node `4 + i` sits on edge `i`.
const TET_EDGES: [[u8; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];

/// Hex8 reference nodes: the corners of [−1, 1]³.
pub(crate) const HEX8_REFERENCE: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// Tet10 reference nodes in the unit tetrahedron (the first four are the tet4 ones).
pub(crate) const TET10_REFERENCE: [[f64; 3]; 10] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.5, 0.0, 0.0],
    [0.5, 0.5, 0.0],
    [0.0, 0.5, 0.0],
    [0.0, 0.0, 0.5],
    [0.5, 0.0, 0.5],
    [0.0, 0.5, 0.5],
];

impl ElementShape {
    /// Every shape.
    pub const ALL: [ElementShape; 3] =
        [ElementShape::Hex8, ElementShape::Tet4, ElementShape::Tet10];

    /// Lower-case name used in messages and files: "hex8", "tet4", "tet10".
    pub fn name(self) -> &'static str {
        match self {
            ElementShape::Hex8 => "hex8",
            ElementShape::Tet4 => "tet4",
            ElementShape::Tet10 => "tet10",
        }
    }

    /// Number of nodes of one element.
    pub fn nodes_per_element(self) -> usize {
        match self {
            ElementShape::Hex8 => 8,
            ElementShape::Tet4 => 4,
            ElementShape::Tet10 => 10,
        }
    }

    /// Number of corner (vertex) nodes; they come first in the element's node list.
    pub fn corner_count(self) -> usize {
        match self {
            ElementShape::Hex8 => 8,
            ElementShape::Tet4 | ElementShape::Tet10 => 4,
        }
    }

    /// True for shapes with mid-edge nodes.
    pub fn is_quadratic(self) -> bool {
        self.nodes_per_element() > self.corner_count()
    }

    /// Local node lists of the faces, in Abaqus face order (S1 first), each running
    /// counter-clockwise seen from outside (right-hand normal outward): corners first,
    /// then, for quadratic shapes, the mid-edge nodes of consecutive corner pairs.
    pub fn faces(self) -> &'static [&'static [u8]] {
        match self {
            ElementShape::Hex8 => &HEX8_FACES,
            ElementShape::Tet4 => &TET4_FACES,
            ElementShape::Tet10 => &TET10_FACES,
        }
    }

    /// Number of faces.
    pub fn face_count(self) -> usize {
        self.faces().len()
    }

    /// Local nodes of face `face` (0-based, Abaqus S(face+1)), or `None` if there is none.
    pub fn face(self, face: usize) -> Option<&'static [u8]> {
        self.faces().get(face).copied()
    }

    /// Shape of face `face` (all faces of the current shapes have the same shape).
    pub fn face_shape(self, _face: usize) -> FaceShape {
        match self {
            ElementShape::Hex8 => FaceShape::Quad4,
            ElementShape::Tet4 => FaceShape::Tri3,
            ElementShape::Tet10 => FaceShape::Tri6,
        }
    }

    /// Edges as pairs of local corner nodes.
    pub fn edges(self) -> &'static [[u8; 2]] {
        match self {
            ElementShape::Hex8 => &HEX8_EDGES,
            ElementShape::Tet4 | ElementShape::Tet10 => &TET_EDGES,
        }
    }

    /// Local id of the mid-edge node on edge `edge` (index into [`Self::edges`]), if the
    /// shape has mid-edge nodes.
    pub fn mid_edge_node(self, edge: usize) -> Option<u8> {
        match self {
            ElementShape::Tet10 if edge < TET_EDGES.len() => Some(4 + edge as u8),
            _ => None,
        }
    }

    /// Coordinates of the nodes in the reference element: [−1, 1]³ for hex8, the unit
    /// tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1) for tets.
    pub fn reference_nodes(self) -> &'static [[f64; 3]] {
        match self {
            ElementShape::Hex8 => &HEX8_REFERENCE,
            ElementShape::Tet4 => &TET10_REFERENCE[..4],
            ElementShape::Tet10 => &TET10_REFERENCE,
        }
    }
}

impl fmt::Display for ElementShape {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FaceShape {
    /// Number of nodes of the face.
    pub fn node_count(self) -> usize {
        match self {
            FaceShape::Quad4 => 4,
            FaceShape::Tri3 => 3,
            FaceShape::Tri6 => 6,
        }
    }

    /// Number of corner nodes (they come first).
    pub fn corner_count(self) -> usize {
        match self {
            FaceShape::Quad4 => 4,
            FaceShape::Tri3 | FaceShape::Tri6 => 3,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The face lists printed in the Abaqus manual (1-based, inward right-hand normal).
    fn abaqus_faces(shape: ElementShape) -> Vec<Vec<u8>> {
        let faces: &[&[u8]] = match shape {
            ElementShape::Hex8 => &[
                &[1, 2, 3, 4],
                &[5, 8, 7, 6],
                &[1, 5, 6, 2],
                &[2, 6, 7, 3],
                &[3, 7, 8, 4],
                &[4, 8, 5, 1],
            ],
            ElementShape::Tet4 | ElementShape::Tet10 => {
                &[&[1, 2, 3], &[1, 4, 2], &[2, 4, 3], &[3, 4, 1]]
            }
        };
        faces.iter().map(|f| f.to_vec()).collect()
    }

    #[test]
    fn faces_are_the_abaqus_faces_reversed() {
        for shape in ElementShape::ALL {
            for (ours, theirs) in shape.faces().iter().zip(abaqus_faces(shape)) {
                let corners = &ours[..shape.face_shape(0).corner_count()];
                // Same first node, then the Abaqus cycle walked backwards.
                let mut reversed = vec![theirs[0] - 1];
                reversed.extend(theirs[1..].iter().rev().map(|n| n - 1));
                assert_eq!(corners, reversed.as_slice(), "{shape}");
            }
            assert_eq!(shape.face_count(), abaqus_faces(shape).len());
            assert!(shape.face(shape.face_count()).is_none());
        }
    }

    #[test]
    fn tet10_mid_nodes_sit_on_their_edges() {
        let shape = ElementShape::Tet10;
        let reference = shape.reference_nodes();
        for (e, &[a, b]) in shape.edges().iter().enumerate() {
            let m = shape.mid_edge_node(e).unwrap() as usize;
            for d in 0..3 {
                let mid = 0.5 * (reference[a as usize][d] + reference[b as usize][d]);
                assert_eq!(reference[m][d], mid, "edge {e}");
            }
        }
        // Face mid nodes are those of the face's consecutive corner pairs.
        for face in shape.faces() {
            for k in 0..3 {
                let (a, b) = (face[k], face[(k + 1) % 3]);
                let edge = shape
                    .edges()
                    .iter()
                    .position(|&[p, q]| (p, q) == (a, b) || (p, q) == (b, a))
                    .unwrap();
                assert_eq!(face[3 + k], shape.mid_edge_node(edge).unwrap());
            }
        }
    }

    #[test]
    fn counts_are_consistent() {
        for shape in ElementShape::ALL {
            assert_eq!(shape.reference_nodes().len(), shape.nodes_per_element());
            assert!(shape.nodes_per_element() <= MAX_NODES_PER_ELEMENT);
            assert_eq!(shape.is_quadratic(), shape == ElementShape::Tet10);
            for (f, face) in shape.faces().iter().enumerate() {
                assert_eq!(face.len(), shape.face_shape(f).node_count());
                assert!(face.len() <= MAX_FACE_NODES);
            }
            // Every edge belongs to exactly two faces (closed polyhedron).
            for &[a, b] in shape.edges() {
                let count = shape
                    .faces()
                    .iter()
                    .filter(|f| {
                        let c = &f[..shape.face_shape(0).corner_count()];
                        c.contains(&a) && c.contains(&b)
                    })
                    .count();
                assert_eq!(count, 2, "{shape} edge {a}-{b}");
            }
        }
        assert_eq!(ElementShape::Tet4.mid_edge_node(0), None);
    }
}
