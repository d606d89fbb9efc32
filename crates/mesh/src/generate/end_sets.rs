//! The named sets of a muscle swept from its origin (layer 0) to its insertion (layer
//! `axial`): node sets and surfaces `origin`, `insertion` and `lateral`, the surface
//! `outer` and the element set `all` (shared by the fusiform and swept generators).

use std::collections::BTreeSet;

use crate::{ElementRef, Face, Mesh, MeshError};

/// Sorts the boundary faces of block 0 of `mesh` by the layers of their corner nodes
/// (node id / `per_layer`; mid-edge nodes come after all corner nodes): all in layer 0 →
/// `origin`, all in layer `axial` → `insertion`, else `lateral`; inserts those node sets
/// and surfaces, the surface `outer` (every boundary face) and the element set `all`.
pub(super) fn insert_end_sets(
    mesh: &mut Mesh,
    per_layer: usize,
    axial: usize,
) -> Result<(), MeshError> {
    let shape = mesh.blocks[0].shape;
    let layer = |id: u32| id as usize / per_layer;
    let outer = mesh.boundary_faces()?;
    let (mut origin, mut insertion, mut lateral) = (Vec::new(), Vec::new(), Vec::new());
    for &face in &outer {
        let ids = mesh.face_nodes(face)?;
        let corners = &ids[..shape.face_shape(face.face as usize).corner_count()];
        if corners.iter().all(|&id| layer(id) == 0) {
            origin.push(face);
        } else if corners.iter().all(|&id| layer(id) == axial) {
            insertion.push(face);
        } else {
            lateral.push(face);
        }
    }
    for (name, faces) in [
        ("origin", origin),
        ("insertion", insertion),
        ("lateral", lateral),
    ] {
        let nodes = face_nodes(mesh, &faces)?;
        mesh.node_sets.insert(name.to_string(), nodes);
        mesh.surfaces.insert(name.to_string(), faces);
    }
    mesh.surfaces.insert("outer".to_string(), outer);
    let all = (0..mesh.blocks[0].len() as u32)
        .map(|e| ElementRef::new(0, e))
        .collect();
    mesh.element_sets.insert("all".to_string(), all);
    Ok(())
}

/// The nodes of `faces`, sorted, without duplicates.
fn face_nodes(mesh: &Mesh, faces: &[Face]) -> Result<Vec<u32>, MeshError> {
    let mut set = BTreeSet::new();
    for &face in faces {
        set.extend(mesh.face_nodes(face)?.iter().copied());
    }
    Ok(set.into_iter().collect())
}
