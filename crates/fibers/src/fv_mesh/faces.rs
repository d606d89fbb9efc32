//! Face matching and face geometry.
//!
//! Every element face is a half-face keyed by its corner node ids, sorted (so the key
//! does not depend on the element or on the orientation; a triangle's key is padded with
//! `u32::MAX`, so it never matches a quadrilateral). Sorting the half-faces of all
//! blocks by key puts the two halves of an interior face next to each other; a key seen
//! once is a boundary face, a key seen three or more times a non-manifold mesh.

use musclefem_mesh::{ElementShape, Mesh};
use nalgebra::Vector3;
use rayon::prelude::*;

use super::{BoundaryFace, FaceRef, InteriorFace};
use crate::error::{FaceLabel, FiberError};

/// Faces per parallel task.
const CHUNK: usize = 4096;

/// One element face seen from its element. Ordered by key first, so a sort groups the
/// halves of a face, and then by cell, so the owner (the smaller cell) comes first.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
struct HalfFace {
    key: [u32; 4],
    cell: u32,
    local: u8,
}

/// The faces of a mesh, matched: see [`super::FvMesh`] for the meaning of each field.
pub(crate) struct MatchedFaces {
    pub interior: Vec<InteriorFace>,
    pub boundary: Vec<BoundaryFace>,
    pub face_offsets: Vec<usize>,
    pub cell_faces: Vec<FaceRef>,
}

/// Matches the element faces of all blocks (cells numbered from `block_offsets`) and
/// computes their geometry. Errors if more than two faces share their corner nodes, or
/// two faces of one element do.
pub(crate) fn match_faces(
    mesh: &Mesh,
    block_offsets: &[usize],
) -> Result<MatchedFaces, FiberError> {
    let mut face_offsets = Vec::with_capacity(block_offsets.last().map_or(1, |n| n + 1));
    face_offsets.push(0);
    for block in &mesh.blocks {
        let count = block.shape.face_count();
        for _ in 0..block.len() {
            face_offsets.push(face_offsets.last().copied().unwrap_or(0) + count);
        }
    }
    let mut halves = half_faces(mesh, block_offsets, &face_offsets);
    halves.par_sort_unstable();

    let mut interior_halves = Vec::with_capacity(halves.len() / 2);
    let mut boundary_halves = Vec::new();
    let mut start = 0;
    while start < halves.len() {
        let key = halves[start].key;
        let end = start + halves[start..].iter().take_while(|h| h.key == key).count();
        match end - start {
            1 => boundary_halves.push(halves[start]),
            2 if halves[start].cell != halves[start + 1].cell => {
                interior_halves.push((halves[start], halves[start + 1]));
            }
            2 => {
                let (block, element) = name_of(mesh, block_offsets, halves[start].cell as usize);
                return Err(FiberError::DegenerateCell {
                    block,
                    element,
                    reason: format!(
                        "faces S{} and S{} have the same corner nodes",
                        halves[start].local + 1,
                        halves[start + 1].local + 1
                    ),
                });
            }
            _ => {
                let faces = halves[start..end]
                    .iter()
                    .map(|h| label(mesh, block_offsets, h))
                    .collect();
                return Err(FiberError::NonManifoldFace { faces });
            }
        }
        start = end;
    }
    drop(halves);
    interior_halves.par_sort_unstable_by_key(|(owner, _)| (owner.cell, owner.local));
    boundary_halves.par_sort_unstable_by_key(|h| (h.cell, h.local));

    let interior: Vec<InteriorFace> = interior_halves
        .par_iter()
        .with_min_len(CHUNK)
        .map(|(owner, neighbour)| {
            let (area_vector, centre) = face_geometry(mesh, block_offsets, owner);
            InteriorFace {
                owner: owner.cell,
                neighbour: neighbour.cell,
                owner_face: owner.local,
                area_vector,
                centre,
            }
        })
        .collect();
    let boundary: Vec<BoundaryFace> = boundary_halves
        .par_iter()
        .with_min_len(CHUNK)
        .map(|half| {
            let (area_vector, centre) = face_geometry(mesh, block_offsets, half);
            BoundaryFace {
                cell: half.cell,
                local_face: half.local,
                area_vector,
                centre,
            }
        })
        .collect();

    let mut cell_faces =
        vec![FaceRef::Boundary(u32::MAX); face_offsets.last().copied().unwrap_or(0)];
    for (i, (owner, neighbour)) in interior_halves.iter().enumerate() {
        for half in [owner, neighbour] {
            cell_faces[face_offsets[half.cell as usize] + half.local as usize] =
                FaceRef::Interior(i as u32);
        }
    }
    for (i, half) in boundary_halves.iter().enumerate() {
        cell_faces[face_offsets[half.cell as usize] + half.local as usize] =
            FaceRef::Boundary(i as u32);
    }
    Ok(MatchedFaces {
        interior,
        boundary,
        face_offsets,
        cell_faces,
    })
}

/// Vector area S = ∫ n dA [m²] and centre [m] of the face whose corners are `p`, in
/// order (right-hand normal = the direction of S).
///
/// - triangle: S = ½ (p₂ − p₁) × (p₃ − p₁), centre the mean of the corners;
/// - quadrilateral (possibly warped): the fan of triangles from the corner mean m,
///   S = Σ sᵢ with sᵢ = ½ (pᵢ − m) × (pᵢ₊₁ − m) (which is ½ d₁ × d₂ of the diagonals, the
///   exact ∫ n dA of the bilinear face), centre the mean of the triangle centroids
///   weighted by their areas projected on S.
pub(crate) fn face_area_vector_and_centre(p: &[Vector3<f64>]) -> (Vector3<f64>, Vector3<f64>) {
    let n = p.len();
    let mean = p.iter().sum::<Vector3<f64>>() / n as f64;
    if n == 3 {
        return (0.5 * (p[1] - p[0]).cross(&(p[2] - p[0])), mean);
    }
    let mut area_vector = Vector3::zeros();
    for i in 0..n {
        area_vector += 0.5 * (p[i] - mean).cross(&(p[(i + 1) % n] - mean));
    }
    let norm = area_vector.norm();
    if norm == 0.0 {
        return (area_vector, mean);
    }
    let unit = area_vector / norm;
    let mut weight_sum = 0.0;
    let mut weighted_centre = Vector3::zeros();
    for i in 0..n {
        let (a, b) = (p[i], p[(i + 1) % n]);
        let weight = 0.5 * (a - mean).cross(&(b - mean)).dot(&unit);
        weight_sum += weight;
        weighted_centre += weight * (a + b + mean) / 3.0;
    }
    let centre = if weight_sum > 0.0 {
        weighted_centre / weight_sum
    } else {
        mean
    };
    (area_vector, centre)
}

/// The half-faces of every cell, at `face_offsets[cell] + local face`.
fn half_faces(mesh: &Mesh, block_offsets: &[usize], face_offsets: &[usize]) -> Vec<HalfFace> {
    let mut halves = vec![HalfFace::default(); face_offsets.last().copied().unwrap_or(0)];
    for (b, block) in mesh.blocks.iter().enumerate() {
        let shape = block.shape;
        let first_cell = block_offsets[b];
        let faces = face_offsets[first_cell]..face_offsets[first_cell + block.len()];
        halves[faces]
            .par_chunks_mut(shape.face_count())
            .zip(
                block
                    .connectivity
                    .par_chunks_exact(shape.nodes_per_element()),
            )
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(e, (cell_halves, ids))| {
                for (local, half) in cell_halves.iter_mut().enumerate() {
                    let corners = corner_ids(shape, ids, local);
                    let mut key = [u32::MAX; 4];
                    key[..corners.len()].copy_from_slice(&corners);
                    key.sort_unstable();
                    *half = HalfFace {
                        key,
                        cell: (first_cell + e) as u32,
                        local: local as u8,
                    };
                }
            });
    }
    halves
}

/// The corner node ids of face `local` of an element with nodes `ids`, in face order.
pub(crate) fn corner_ids(shape: ElementShape, ids: &[u32], local: usize) -> CornerIds {
    let face = shape.faces()[local];
    let n = shape.face_shape(local).corner_count();
    let mut corners = CornerIds::default();
    for &l in &face[..n] {
        corners.push(ids[l as usize]);
    }
    corners
}

/// The corner node ids of one face (three or four), without allocation; derefs to a slice.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct CornerIds {
    ids: [u32; 4],
    len: usize,
}

impl CornerIds {
    fn push(&mut self, id: u32) {
        self.ids[self.len] = id;
        self.len += 1;
    }
}

impl std::ops::Deref for CornerIds {
    type Target = [u32];

    fn deref(&self) -> &[u32] {
        &self.ids[..self.len]
    }
}

/// Area vector (out of the half-face's cell) and centre of a half-face.
fn face_geometry(
    mesh: &Mesh,
    block_offsets: &[usize],
    half: &HalfFace,
) -> (Vector3<f64>, Vector3<f64>) {
    let cell = half.cell as usize;
    let b = block_of(block_offsets, cell);
    let block = &mesh.blocks[b];
    let ids = block.element_nodes(cell - block_offsets[b]);
    let corners = corner_ids(block.shape, ids, half.local as usize);
    let mut p = [Vector3::zeros(); 4];
    mesh.nodes.gather(&corners, &mut p);
    face_area_vector_and_centre(&p[..corners.len()])
}

/// The block of cell `cell`: the last block whose first cell is at most `cell`.
fn block_of(block_offsets: &[usize], cell: usize) -> usize {
    block_offsets.partition_point(|&first| first <= cell) - 1
}

fn name_of(mesh: &Mesh, block_offsets: &[usize], cell: usize) -> (String, usize) {
    let b = block_of(block_offsets, cell);
    (mesh.blocks[b].name.clone(), cell - block_offsets[b])
}

fn label(mesh: &Mesh, block_offsets: &[usize], half: &HalfFace) -> FaceLabel {
    let (block, element) = name_of(mesh, block_offsets, half.cell as usize);
    FaceLabel {
        block,
        element,
        face: half.local,
    }
}

#[cfg(test)]
mod tests {
    use musclefem_mesh::generate::{TetOrder, box_of_tets};
    use musclefem_mesh::{ElementBlock, ElementShape};

    use super::*;

    #[test]
    fn warped_quad_area_vector_is_half_the_diagonal_cross_product() {
        let v = |x, y, z| Vector3::new(x, y, z);
        let p = [
            v(0.0, 0.0, 0.0),
            v(2.0, 0.0, 0.1),
            v(2.1, 1.0, -0.2),
            v(0.0, 1.2, 0.3),
        ];
        let (s, centre) = face_area_vector_and_centre(&p);
        let exact = 0.5 * (p[2] - p[0]).cross(&(p[3] - p[1]));
        assert!((s - exact).norm() < 1e-15);
        // A flat rectangle's centre is its middle.
        let q = [
            v(0.0, 0.0, 1.0),
            v(2.0, 0.0, 1.0),
            v(2.0, 1.0, 1.0),
            v(0.0, 1.0, 1.0),
        ];
        let (s, centre_q) = face_area_vector_and_centre(&q);
        assert!((s - v(0.0, 0.0, 2.0)).norm() < 1e-15);
        assert!((centre_q - v(1.0, 0.5, 1.0)).norm() < 1e-15);
        // A flat trapezoid's centre is its area centroid, not its corner mean.
        let t = [
            v(0.0, 0.0, 0.0),
            v(3.0, 0.0, 0.0),
            v(2.0, 1.0, 0.0),
            v(1.0, 1.0, 0.0),
        ];
        let (_, centre_t) = face_area_vector_and_centre(&t);
        // Centroid height of a trapezoid with parallel sides a = 3 (y = 0), b = 1 (y = 1):
        // h (a + 2b) / (3 (a + b)) = 5/12.
        assert!(
            (centre_t - v(1.5, 5.0 / 12.0, 0.0)).norm() < 1e-15,
            "{centre_t}"
        );
        assert!(centre.iter().all(|c| c.is_finite()));
    }

    #[test]
    fn three_elements_on_one_face_are_named() {
        let mut mesh = box_of_tets([1.0; 3], [1, 1, 1], TetOrder::Linear).unwrap();
        // A third tet on the first face of element 0, on its outer side.
        let ids = mesh.blocks[0].element_nodes(0).to_vec();
        let apex = mesh.nodes.push(Vector3::new(-1.0, -1.0, -1.0));
        let mut connectivity = mesh.blocks[0].connectivity.clone();
        connectivity.extend_from_slice(&[ids[0], ids[1], ids[2], apex]);
        connectivity.extend_from_slice(&[ids[0], ids[1], ids[2], apex]);
        mesh.blocks[0] = ElementBlock::new("tets", ElementShape::Tet4, connectivity).unwrap();
        let offsets = [0, mesh.blocks[0].len()];
        let Err(FiberError::NonManifoldFace { faces }) = match_faces(&mesh, &offsets) else {
            panic!("expected a non-manifold face");
        };
        assert_eq!(faces.len(), 3);
        assert_eq!(faces[0].element, 0);
        assert_eq!(faces[2].element, 7);
    }
}
