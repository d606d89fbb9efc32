//! Element blocks: elements of one shape stored as a flat connectivity array.

use nalgebra::Vector3;

use super::error::MeshError;
use super::shape::ElementShape;

/// Elements of one shape, with one fiber direction per element.
///
/// Element `e` has the nodes `connectivity[e * n..(e + 1) * n]`, `n` the shape's
/// [`ElementShape::nodes_per_element`], in Abaqus local order. The fields are public so
/// that importers and generators can fill them; [`super::Mesh::validate`] checks that
/// they are consistent.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementBlock {
    /// Name of the block (unique in a mesh), e.g. the part or the Abaqus element set.
    pub name: String,
    /// Shape of every element of the block.
    pub shape: ElementShape,
    /// Node ids of all elements, `nodes_per_element` consecutive entries per element.
    pub connectivity: Vec<u32>,
    /// Fiber direction of each element in the reference configuration (dimensionless,
    /// any finite non-zero vector; unit vectors by convention), one per element.
    pub fiber_direction: Vec<Vector3<f64>>,
}

impl ElementBlock {
    /// A block with the given connectivity and every fiber along e_x.
    ///
    /// Errors if the connectivity length is not a multiple of the shape's node count.
    pub fn new(
        name: impl Into<String>,
        shape: ElementShape,
        connectivity: Vec<u32>,
    ) -> Result<Self, MeshError> {
        let name = name.into();
        let nodes_per_element = shape.nodes_per_element();
        if !connectivity.len().is_multiple_of(nodes_per_element) {
            return Err(MeshError::ConnectivityLength {
                block: name,
                shape,
                len: connectivity.len(),
            });
        }
        let fiber_direction = vec![Vector3::x(); connectivity.len() / nodes_per_element];
        Ok(Self {
            name,
            shape,
            connectivity,
            fiber_direction,
        })
    }

    /// Number of elements (whole groups of `nodes_per_element` in the connectivity).
    pub fn len(&self) -> usize {
        self.connectivity.len() / self.shape.nodes_per_element()
    }

    /// True when the block has no element.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Node ids of element `e`, in local order.
    ///
    /// # Panics
    /// If `e` is out of range.
    #[inline]
    pub fn element_nodes(&self, e: usize) -> &[u32] {
        let n = self.shape.nodes_per_element();
        &self.connectivity[e * n..(e + 1) * n]
    }

    /// The node ids of every element, one slice per element, in element order.
    pub fn elements(&self) -> std::slice::ChunksExact<'_, u32> {
        self.connectivity
            .chunks_exact(self.shape.nodes_per_element())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn new_checks_the_connectivity_length() {
        let block =
            ElementBlock::new("b", ElementShape::Tet4, vec![0, 1, 2, 3, 1, 2, 3, 4]).unwrap();
        assert_eq!(block.len(), 2);
        assert_eq!(block.element_nodes(1), &[1, 2, 3, 4]);
        assert_eq!(block.elements().count(), 2);
        assert_eq!(block.fiber_direction, vec![Vector3::x(); 2]);
        let err = ElementBlock::new("b", ElementShape::Hex8, vec![0; 12]).unwrap_err();
        assert!(matches!(err, MeshError::ConnectivityLength { len: 12, .. }));
        assert!(err.to_string().contains("'b'"), "{err}");
    }
}
