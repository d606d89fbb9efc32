//! The finite-volume view of a finite-element mesh: every element is a cell, and the
//! element faces, matched across all blocks by their corner nodes, are the cell faces.
//!
//! - [`cells`]: cell centroids, from the volumes (tet10 uses its four corners, so every cell is
//!   a straight-sided tetrahedron or a trilinear hexahedron), and the inverted-element
//!   check;
//! - [`faces`]: matching element faces into interior faces (two cells) and boundary faces
//!   (one cell), with their area vectors and centres;
//! - [`components`]: the parts of the mesh connected through interior faces.
//!
//! Cells are numbered block after block, element after element: cell
//! `block_offsets[b] + e` is element `e` of block `b`.

pub(crate) mod cells;
pub(crate) mod components;
pub(crate) mod faces;

use musclefem_mesh::{ElementRef, Mesh, MeshError};
use nalgebra::Vector3;

use crate::error::{FaceLabel, FiberError};

/// A face between two cells. Its area vector points out of the owner, the cell with the
/// smaller index, into the neighbour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct InteriorFace {
    /// The cell the area vector points out of.
    pub owner: u32,
    /// The cell on the other side.
    pub neighbour: u32,
    /// Local face index of the face in the owner's element.
    pub owner_face: u8,
    /// ∫ n dA over the face, n out of the owner [m²].
    pub area_vector: Vector3<f64>,
    /// Area-weighted centre of the face [m].
    pub centre: Vector3<f64>,
}

/// A face of one cell only: on the outer surface of the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BoundaryFace {
    /// The cell the face belongs to.
    pub cell: u32,
    /// Local face index in the cell's element.
    pub local_face: u8,
    /// ∫ n dA over the face, n out of the mesh [m²].
    pub area_vector: Vector3<f64>,
    /// Area-weighted centre of the face [m].
    pub centre: Vector3<f64>,
}

/// One face of a cell: an index into [`FvMesh::interior`] or [`FvMesh::boundary`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FaceRef {
    Interior(u32),
    Boundary(u32),
}

/// Cells and faces of a mesh, with the geometry the finite-volume scheme needs.
#[derive(Clone, Debug)]
pub(crate) struct FvMesh {
    /// Index of the first cell of each block, and the cell count last (blocks + 1 entries).
    pub block_offsets: Vec<usize>,
    /// Volume centroid of each cell [m].
    pub cell_centre: Vec<Vector3<f64>>,
    /// Faces shared by two cells.
    pub interior: Vec<InteriorFace>,
    /// Faces on the boundary of the mesh, in (cell, local face) order.
    pub boundary: Vec<BoundaryFace>,
    /// The faces of cell `c` are `cell_faces[face_offsets[c]..face_offsets[c + 1]]`, in
    /// the local face order of its element.
    face_offsets: Vec<usize>,
    cell_faces: Vec<FaceRef>,
}

impl FvMesh {
    /// The cells and faces of `mesh`. Errors on malformed connectivity, inverted or flat
    /// elements, and faces shared by more than two elements.
    pub fn new(mesh: &Mesh) -> Result<Self, FiberError> {
        check_connectivity(mesh)?;
        let mut block_offsets = Vec::with_capacity(mesh.blocks.len() + 1);
        block_offsets.push(0);
        for block in &mesh.blocks {
            block_offsets.push(block_offsets.last().copied().unwrap_or(0) + block.len());
        }
        let cell_count = block_offsets.last().copied().unwrap_or(0);
        if cell_count == 0 {
            return Err(FiberError::EmptyMesh);
        }
        if cell_count > u32::MAX as usize {
            return Err(MeshError::TooManyElements {
                block: "(all blocks)".to_string(),
                count: cell_count,
            }
            .into());
        }
        let cell_centre = cells::cell_geometry(mesh)?.0;
        let matched = faces::match_faces(mesh, &block_offsets)?;
        Ok(Self {
            block_offsets,
            cell_centre,
            interior: matched.interior,
            boundary: matched.boundary,
            face_offsets: matched.face_offsets,
            cell_faces: matched.cell_faces,
        })
    }

    /// Number of cells (elements over all blocks).
    pub fn cell_count(&self) -> usize {
        self.cell_centre.len()
    }

    /// The faces of cell `cell`, in the local face order of its element.
    #[inline]
    pub fn faces_of(&self, cell: usize) -> &[FaceRef] {
        &self.cell_faces[self.face_offsets[cell]..self.face_offsets[cell + 1]]
    }

    /// The cell of an element, if the element exists.
    pub fn cell_of(&self, element: ElementRef) -> Option<usize> {
        let block = element.block as usize;
        let first = *self.block_offsets.get(block)?;
        let cell = first + element.element as usize;
        (cell < *self.block_offsets.get(block + 1)?).then_some(cell)
    }

    /// The element of cell `cell`.
    pub fn element_of(&self, cell: usize) -> ElementRef {
        // The last block whose first cell is at most `cell` (empty blocks are skipped).
        let block = self.block_offsets.partition_point(|&first| first <= cell) - 1;
        ElementRef::new(block as u32, (cell - self.block_offsets[block]) as u32)
    }

    /// Block name and element index of cell `cell`, for messages.
    pub fn name_of(&self, mesh: &Mesh, cell: usize) -> (String, usize) {
        let element = self.element_of(cell);
        let name = mesh
            .blocks
            .get(element.block as usize)
            .map_or_else(String::new, |b| b.name.clone());
        (name, element.element as usize)
    }

    /// Face `local_face` of cell `cell`, named for messages.
    pub fn face_label(&self, mesh: &Mesh, cell: usize, local_face: u8) -> FaceLabel {
        let (block, element) = self.name_of(mesh, cell);
        FaceLabel {
            block,
            element,
            face: local_face,
        }
    }

    /// The corner node ids of face `local_face` of cell `cell`, in face order.
    pub fn corner_ids(&self, mesh: &Mesh, cell: usize, local_face: u8) -> faces::CornerIds {
        let element = self.element_of(cell);
        let block = &mesh.blocks[element.block as usize];
        let ids = block.element_nodes(element.element as usize);
        faces::corner_ids(block.shape, ids, local_face as usize)
    }

    /// The mesh face of boundary face `face`.
    #[cfg(test)]
    pub fn boundary_mesh_face(&self, face: &BoundaryFace) -> musclefem_mesh::Face {
        musclefem_mesh::Face::new(self.element_of(face.cell as usize), face.local_face)
    }
}

/// Checks what the cell and face loops index with: node arrays of one length, whole
/// elements, and node ids in range.
fn check_connectivity(mesh: &Mesh) -> Result<(), FiberError> {
    let nodes = &mesh.nodes;
    if nodes.x.len() != nodes.y.len() || nodes.x.len() != nodes.z.len() {
        return Err(MeshError::NodeArrayLengths {
            x: nodes.x.len(),
            y: nodes.y.len(),
            z: nodes.z.len(),
        }
        .into());
    }
    let node_count = nodes.len();
    for block in &mesh.blocks {
        let n = block.shape.nodes_per_element();
        if !block.connectivity.len().is_multiple_of(n) {
            return Err(MeshError::ConnectivityLength {
                block: block.name.clone(),
                shape: block.shape,
                len: block.connectivity.len(),
            }
            .into());
        }
        if let Some(i) = block
            .connectivity
            .iter()
            .position(|&id| id as usize >= node_count)
        {
            return Err(MeshError::NodeOutOfRange {
                block: block.name.clone(),
                element: i / n,
                local: i % n,
                node: block.connectivity[i],
                node_count,
            }
            .into());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use musclefem_mesh::generate::{TetOrder, box_of_hexes, box_of_tets};

    use super::*;

    #[test]
    fn box_faces_match_and_close_every_cell() {
        for mesh in [
            box_of_hexes([1.0, 2.0, 3.0], [3, 2, 2]).unwrap(),
            box_of_tets([1.0, 2.0, 3.0], [2, 2, 3], TetOrder::Linear).unwrap(),
            box_of_tets([1.0, 2.0, 3.0], [2, 1, 2], TetOrder::Quadratic).unwrap(),
        ] {
            let fv = FvMesh::new(&mesh).unwrap();
            assert_eq!(fv.cell_count(), mesh.element_count());
            // Boundary faces are the generator's outer surface.
            let mut outer = mesh.surface("outer").unwrap().to_vec();
            outer.sort();
            let ours: Vec<musclefem_mesh::Face> = fv
                .boundary
                .iter()
                .map(|f| fv.boundary_mesh_face(f))
                .collect();
            assert_eq!(ours, outer);
            // The area vectors of each cell's faces, taken outward, sum to zero, and the
            // volumes add up to the box.
            for cell in 0..fv.cell_count() {
                let mut sum = Vector3::zeros();
                for face in fv.faces_of(cell) {
                    sum += match *face {
                        FaceRef::Interior(f) => {
                            let f = &fv.interior[f as usize];
                            let sign = if f.owner as usize == cell { 1.0 } else { -1.0 };
                            sign * f.area_vector
                        }
                        FaceRef::Boundary(f) => fv.boundary[f as usize].area_vector,
                    };
                }
                assert!(sum.norm() < 1e-14, "cell {cell}: {sum}");
            }
            let volume: f64 = cells::cell_geometry(&mesh).unwrap().1.iter().sum();
            assert!((volume - 6.0).abs() < 1e-12, "{volume}");
            for f in &fv.interior {
                assert!(f.owner < f.neighbour);
            }
        }
    }

    #[test]
    fn cells_and_elements_correspond_across_blocks() {
        let mut mesh = box_of_tets([1.0; 3], [1, 1, 1], TetOrder::Linear).unwrap();
        // Split the six tets into blocks of 0, 2 and 4 elements.
        let block = mesh.blocks.remove(0);
        let empty = musclefem_mesh::ElementBlock::new("empty", block.shape, vec![]).unwrap();
        let first =
            musclefem_mesh::ElementBlock::new("a", block.shape, block.connectivity[..8].to_vec())
                .unwrap();
        let second =
            musclefem_mesh::ElementBlock::new("b", block.shape, block.connectivity[8..].to_vec())
                .unwrap();
        mesh.blocks = vec![empty, first, second];
        mesh.surfaces.clear();
        let fv = FvMesh::new(&mesh).unwrap();
        assert_eq!(fv.block_offsets, vec![0, 0, 2, 6]);
        assert_eq!(fv.element_of(1), ElementRef::new(1, 1));
        assert_eq!(fv.element_of(2), ElementRef::new(2, 0));
        assert_eq!(fv.cell_of(ElementRef::new(2, 3)), Some(5));
        assert_eq!(fv.cell_of(ElementRef::new(2, 4)), None);
        assert_eq!(fv.cell_of(ElementRef::new(0, 0)), None);
        assert_eq!(fv.cell_of(ElementRef::new(3, 0)), None);
        assert_eq!(fv.name_of(&mesh, 3), ("b".to_string(), 1));
        // The six tets of a cube share 6 interior faces and have 12 boundary triangles.
        assert_eq!(fv.interior.len(), 6);
        assert_eq!(fv.boundary.len(), 12);
    }

    #[test]
    fn connectivity_errors_are_mesh_errors() {
        let mut mesh = box_of_hexes([1.0; 3], [1, 1, 1]).unwrap();
        mesh.blocks[0].connectivity[3] = 99;
        let err = FvMesh::new(&mesh).unwrap_err();
        assert!(matches!(
            err,
            FiberError::Mesh(MeshError::NodeOutOfRange { node: 99, .. })
        ));
        mesh.blocks.clear();
        assert_eq!(FvMesh::new(&mesh).unwrap_err(), FiberError::EmptyMesh);
    }
}
