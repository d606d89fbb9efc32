//! References to elements and element faces across the blocks of a mesh.

use std::fmt;
use std::ops::Deref;

use super::Mesh;
use super::error::MeshError;
use super::shape::MAX_FACE_NODES;

/// One element of a mesh: element `element` of block `block` (both 0-based indices).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ElementRef {
    /// Index of the block in [`Mesh::blocks`].
    pub block: u32,
    /// Index of the element in its block.
    pub element: u32,
}

impl ElementRef {
    /// Element `element` of block `block`.
    pub fn new(block: u32, element: u32) -> Self {
        Self { block, element }
    }
}

/// One face of one element, the unit of which surfaces are made.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Face {
    /// The element the face belongs to.
    pub element: ElementRef,
    /// Local face index, 0-based: face `i` is Abaqus face S(i+1) (see
    /// [`super::ElementShape::faces`]).
    pub face: u8,
}

impl Face {
    /// Local face `face` of `element`.
    pub fn new(element: ElementRef, face: u8) -> Self {
        Self { element, face }
    }

    /// The node ids of the face, ordered so that the right-hand normal points out of
    /// the element. Errors if the block, element or face does not exist in `mesh`.
    pub fn nodes(&self, mesh: &Mesh) -> Result<FaceNodes, MeshError> {
        mesh.face_nodes(*self)
    }
}

impl fmt::Display for ElementRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "block {} element {}", self.block, self.element)
    }
}

impl fmt::Display for Face {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} face S{}", self.element, u32::from(self.face) + 1)
    }
}

/// The node ids of one face (at most [`MAX_FACE_NODES`]), without allocation; derefs to
/// a slice.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FaceNodes {
    ids: [u32; MAX_FACE_NODES],
    len: u8,
}

impl FaceNodes {
    /// The ids of `local` (local node indices of a face) looked up in `element_nodes`.
    ///
    /// # Panics
    /// If `local` has more than [`MAX_FACE_NODES`] entries or one is out of range.
    pub(crate) fn from_local(element_nodes: &[u32], local: &[u8]) -> Self {
        let mut ids = [0; MAX_FACE_NODES];
        for (id, &l) in ids.iter_mut().zip(local) {
            *id = element_nodes[l as usize];
        }
        Self {
            ids,
            len: local.len() as u8,
        }
    }
}

impl Deref for FaceNodes {
    type Target = [u32];

    fn deref(&self) -> &[u32] {
        &self.ids[..self.len as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_nodes_and_display() {
        let nodes = FaceNodes::from_local(&[10, 11, 12, 13], &[0, 2, 1]);
        assert_eq!(&*nodes, &[10, 12, 11]);
        let face = Face::new(ElementRef::new(1, 7), 3);
        assert_eq!(face.to_string(), "block 1 element 7 face S4");
    }
}
