//! Derived topology: the elements around each node, and the faces on the boundary.

use std::collections::HashMap;

use super::Mesh;
use super::error::MeshError;
use super::refs::{ElementRef, Face};

/// The elements attached to each node, in compressed rows: the elements of node `i` are
/// `elements[offsets[i]..offsets[i + 1]]`, in (block, element) order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NodeElements {
    offsets: Vec<usize>,
    elements: Vec<ElementRef>,
}

impl NodeElements {
    /// The elements that have node `node`.
    ///
    /// # Panics
    /// If `node` is not a node of the mesh this was built from.
    pub fn of(&self, node: usize) -> &[ElementRef] {
        &self.elements[self.offsets[node]..self.offsets[node + 1]]
    }
}

/// Key of a face independent of its element and orientation: its corner node ids
/// sorted, padded with `u32::MAX` (a triangle has three corners, a quadrilateral four).
pub(crate) fn face_key(corners: &[u32]) -> [u32; 4] {
    let mut key = [u32::MAX; 4];
    key[..corners.len()].copy_from_slice(corners);
    key.sort_unstable();
    key
}

impl Mesh {
    /// The elements attached to each node. Errors if a connectivity entry is not a node.
    pub fn node_elements(&self) -> Result<NodeElements, MeshError> {
        self.check_connectivity_range()?;
        let mut offsets = vec![0usize; self.nodes.len() + 1];
        for block in &self.blocks {
            for &id in &block.connectivity {
                offsets[id as usize + 1] += 1;
            }
        }
        for i in 0..self.nodes.len() {
            offsets[i + 1] += offsets[i];
        }
        let mut next = offsets.clone();
        let mut elements = vec![ElementRef::new(0, 0); offsets[self.nodes.len()]];
        for (b, block) in self.blocks.iter().enumerate() {
            for (e, ids) in block.elements().enumerate() {
                for &id in ids {
                    elements[next[id as usize]] = ElementRef::new(b as u32, e as u32);
                    next[id as usize] += 1;
                }
            }
        }
        Ok(NodeElements { offsets, elements })
    }

    /// The element faces that no other element shares (matched by their corner nodes),
    /// in (block, element, face) order: the boundary of a conforming mesh. Errors if a
    /// connectivity entry is not a node.
    pub fn boundary_faces(&self) -> Result<Vec<Face>, MeshError> {
        self.check_connectivity_range()?;
        let mut count: HashMap<[u32; 4], u32> = HashMap::new();
        self.for_each_face(|_, key| *count.entry(key).or_insert(0) += 1);
        let mut boundary = Vec::new();
        self.for_each_face(|face, key| {
            if count[&key] == 1 {
                boundary.push(face);
            }
        });
        Ok(boundary)
    }

    /// Calls `f` with every element face and its [`face_key`], in (block, element, face)
    /// order. The connectivity must be in range.
    fn for_each_face(&self, mut f: impl FnMut(Face, [u32; 4])) {
        let mut corners = [0u32; 4];
        for (b, block) in self.blocks.iter().enumerate() {
            let shape = block.shape;
            for (e, ids) in block.elements().enumerate() {
                for (k, local) in shape.faces().iter().enumerate() {
                    let n = shape.face_shape(k).corner_count();
                    for (c, &l) in corners[..n].iter_mut().zip(*local) {
                        *c = ids[l as usize];
                    }
                    let face = Face::new(ElementRef::new(b as u32, e as u32), k as u8);
                    f(face, face_key(&corners[..n]));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::generate::{TetOrder, box_of_hexes, box_of_tets};
    use super::*;

    #[test]
    fn node_elements_lists_the_attached_elements() {
        let mesh = box_of_hexes([1.0, 1.0, 1.0], [2, 2, 2]).unwrap();
        let adjacency = mesh.node_elements().unwrap();
        // Corner node 0 touches one hex, the centre node (1,1,1) = 13 all eight.
        assert_eq!(adjacency.of(0), &[ElementRef::new(0, 0)]);
        assert_eq!(adjacency.of(13).len(), 8);
        for (i, r) in adjacency.of(13).iter().enumerate() {
            assert_eq!(*r, ElementRef::new(0, i as u32));
        }
    }

    #[test]
    fn boundary_faces_are_the_outer_surface() {
        for mesh in [
            box_of_hexes([1.0, 2.0, 3.0], [2, 3, 1]).unwrap(),
            box_of_tets([1.0, 2.0, 3.0], [2, 3, 1], TetOrder::Linear).unwrap(),
            box_of_tets([1.0, 2.0, 3.0], [2, 1, 2], TetOrder::Quadratic).unwrap(),
        ] {
            let mut outer = mesh.surface("outer").unwrap().to_vec();
            outer.sort();
            assert_eq!(mesh.boundary_faces().unwrap(), outer);
        }
    }
}
