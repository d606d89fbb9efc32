//! Classifying the boundary faces as inlet, outlet or wall, with the checks that make the
//! potential well defined.

use musclefem_mesh::{Mesh, MeshError};

use super::{BoundaryRegion, FlowBoundary};
use crate::error::{FiberError, MissingEnd, Side};
use crate::fv_mesh::components::Components;
use crate::fv_mesh::{FaceRef, FvMesh};

/// Potential φ on the inlet faces (dimensionless).
pub(crate) const INLET_POTENTIAL: f64 = 1.0;
/// Potential φ on the outlet faces (dimensionless).
pub(crate) const OUTLET_POTENTIAL: f64 = 0.0;

/// What a boundary face is in the flow problem.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BoundaryKind {
    /// Impermeable: zero normal flux, ∇φ·n = 0.
    Wall,
    /// Fixed potential φ = 1.
    Inlet,
    /// Fixed potential φ = 0.
    Outlet,
}

impl BoundaryKind {
    /// The fixed potential of the face, `None` on walls.
    #[inline]
    pub fn potential(self) -> Option<f64> {
        match self {
            BoundaryKind::Wall => None,
            BoundaryKind::Inlet => Some(INLET_POTENTIAL),
            BoundaryKind::Outlet => Some(OUTLET_POTENTIAL),
        }
    }
}

/// The boundary faces of a flow problem: what each one is, and which named region it
/// came from.
#[derive(Clone, Debug)]
pub(crate) struct ClassifiedBoundary {
    /// The kind of every boundary face, in the order of [`FvMesh::boundary`].
    pub kinds: Vec<BoundaryKind>,
    /// The regions: the inlet regions in the order given, then the outlet regions.
    pub regions: Vec<(Side, String)>,
    /// For every boundary face, its index in `regions` (`None` on walls). A face
    /// selected by several regions of the same end belongs to the first of them.
    pub region_of_face: Vec<Option<usize>>,
}

/// Classifies every boundary face of `fv` as inlet, outlet or wall and records the
/// region it belongs to. Then checks that every part of the mesh has both an inlet and an
/// outlet face.
///
/// Errors (naming the region, face or element): an end without region, an empty region,
/// a region face or node that the mesh does not have, a surface face inside the mesh, a
/// region without boundary face, a face in both the inlet and the outlet, and a part of
/// the mesh without inlet or outlet.
pub(crate) fn classify_boundary(
    mesh: &Mesh,
    fv: &FvMesh,
    boundary: &FlowBoundary,
) -> Result<ClassifiedBoundary, FiberError> {
    let mut kinds = vec![BoundaryKind::Wall; fv.boundary.len()];
    let mut region_of_face: Vec<Option<usize>> = vec![None; fv.boundary.len()];
    let mut regions = Vec::with_capacity(boundary.inlet.len() + boundary.outlet.len());
    for (side, side_regions) in [
        (Side::Inlet, &boundary.inlet),
        (Side::Outlet, &boundary.outlet),
    ] {
        if side_regions.is_empty() {
            return Err(FiberError::NoRegion { side });
        }
        for region in side_regions {
            let index = regions.len();
            regions.push((side, region.name().to_string()));
            for face in region_faces(mesh, fv, side, region)? {
                match (side, kinds[face]) {
                    (Side::Outlet, BoundaryKind::Inlet) => {
                        let b = &fv.boundary[face];
                        let inlet = region_of_face[face].map_or("", |r| regions[r].1.as_str());
                        return Err(FiberError::InletOutletOverlap {
                            inlet: inlet.to_string(),
                            outlet: region.name().to_string(),
                            face: fv.face_label(mesh, b.cell as usize, b.local_face),
                        });
                    }
                    (Side::Inlet, _) => kinds[face] = BoundaryKind::Inlet,
                    (Side::Outlet, _) => kinds[face] = BoundaryKind::Outlet,
                }
                region_of_face[face].get_or_insert(index);
            }
        }
    }
    check_components(mesh, fv, &kinds)?;
    Ok(ClassifiedBoundary {
        kinds,
        regions,
        region_of_face,
    })
}

/// Indices in [`FvMesh::boundary`] of the faces of one region (possibly repeated).
fn region_faces(
    mesh: &Mesh,
    fv: &FvMesh,
    side: Side,
    region: &BoundaryRegion,
) -> Result<Vec<usize>, FiberError> {
    let name = region.name().to_string();
    let invalid = |error: MeshError| FiberError::InvalidRegion {
        side,
        name: name.clone(),
        error: Box::new(error),
    };
    let mut selected = Vec::new();
    match region {
        BoundaryRegion::Faces { faces, .. } => {
            if faces.is_empty() {
                return Err(FiberError::EmptyRegion { side, name });
            }
            for &face in faces {
                mesh.face_nodes(face).map_err(invalid)?;
                let cell = fv.cell_of(face.element).ok_or_else(|| {
                    invalid(MeshError::BlockOutOfRange {
                        block: face.element.block,
                        count: mesh.blocks.len(),
                    })
                })?;
                match fv.faces_of(cell)[face.face as usize] {
                    FaceRef::Boundary(b) => selected.push(b as usize),
                    FaceRef::Interior(_) => {
                        return Err(FiberError::InteriorFace {
                            side,
                            name,
                            face: fv.face_label(mesh, cell, face.face),
                        });
                    }
                }
            }
        }
        BoundaryRegion::Nodes { nodes, .. } => {
            if nodes.is_empty() {
                return Err(FiberError::EmptyRegion { side, name });
            }
            let node_count = mesh.nodes.len();
            let mut in_set = vec![false; node_count];
            for &node in nodes {
                if node as usize >= node_count {
                    return Err(invalid(MeshError::UnknownNode { node, node_count }));
                }
                in_set[node as usize] = true;
            }
            for (b, face) in fv.boundary.iter().enumerate() {
                let corners = fv.corner_ids(mesh, face.cell as usize, face.local_face);
                if corners.iter().all(|&id| in_set[id as usize]) {
                    selected.push(b);
                }
            }
        }
    }
    if selected.is_empty() {
        return Err(FiberError::NoBoundaryFace { side, name });
    }
    Ok(selected)
}

/// Errors on the first part of the mesh (connected through interior faces, in the order
/// of its first cell) that lacks an inlet or an outlet face.
fn check_components(mesh: &Mesh, fv: &FvMesh, kinds: &[BoundaryKind]) -> Result<(), FiberError> {
    let components = Components::new(fv.cell_count(), &fv.interior);
    let mut has_inlet = vec![false; components.count()];
    let mut has_outlet = vec![false; components.count()];
    for (face, kind) in fv.boundary.iter().zip(kinds) {
        let c = components.of_cell[face.cell as usize] as usize;
        match kind {
            BoundaryKind::Inlet => has_inlet[c] = true,
            BoundaryKind::Outlet => has_outlet[c] = true,
            BoundaryKind::Wall => {}
        }
    }
    for c in 0..components.count() {
        let missing = match (has_inlet[c], has_outlet[c]) {
            (true, true) => continue,
            (false, true) => MissingEnd::Inlet,
            (true, false) => MissingEnd::Outlet,
            (false, false) => MissingEnd::Both,
        };
        let (block, element) = fv.name_of(mesh, components.first_cell[c]);
        return Err(FiberError::DisconnectedPart {
            block,
            element,
            cells: components.sizes[c],
            missing,
        });
    }
    Ok(())
}
