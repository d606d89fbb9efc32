//! What a picture draws: the boundary of the deformed solid as flat facets, each with its
//! cell's value, and rigid surfaces as grey triangles.
//!
//! The boundary is the set of element faces used by exactly one drawn cell, matched by
//! their sorted corner nodes ([`Mesh::boundary_faces`] of the drawn blocks). A tet10 or a
//! hex8 face is drawn by its corners only (its linear face): a triangle, or a
//! quadrilateral split along the diagonal (0, 2) into two triangles whose diagonal is not
//! an outline.

use musclefem_mesh::{ElementBlock, Mesh};
use nalgebra::Vector3;

/// One triangle to draw, in the current configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct Facet {
    /// Corner positions [m].
    pub corners: [Vector3<f64>; 3],
    /// The unit normal of the face the triangle belongs to (of the whole quadrilateral
    /// for a hex8 face; zero for a degenerate face): it shades the triangle.
    pub normal: Vector3<f64>,
    /// Whether edge k (the one opposite corner k) is an edge of the face, drawn as an
    /// outline (a quadrilateral's diagonal is not).
    pub outline: [bool; 3],
    /// The value that colours it; `None` for a rigid surface (drawn grey).
    pub value: Option<f64>,
}

/// The boundary facets of the cells of `blocks` (all blocks if `None`), at the node
/// positions `current` (reference plus displacement) and coloured by `values` (one per
/// cell of the mesh, in block order). Errors name a block that does not exist.
pub fn boundary_facets(
    mesh: &Mesh,
    current: &[Vector3<f64>],
    values: &[f64],
    blocks: Option<&[usize]>,
) -> Result<Vec<Facet>, String> {
    let mut first_cell = Vec::with_capacity(mesh.blocks.len());
    let mut cells = 0;
    for block in &mesh.blocks {
        first_cell.push(cells);
        cells += block.len();
    }
    let drawn: Vec<usize> = match blocks {
        None => (0..mesh.blocks.len()).collect(),
        Some(list) => {
            if let Some(b) = list.iter().find(|&&b| b >= mesh.blocks.len()) {
                return Err(format!(
                    "there is no block {b}: the mesh has {} (0 to {})",
                    mesh.blocks.len(),
                    mesh.blocks.len().saturating_sub(1)
                ));
            }
            let mut list = list.to_vec();
            list.sort_unstable();
            list.dedup();
            list
        }
    };
    // The drawn blocks as a mesh of their own (the same nodes), so that a face between a
    // drawn and a hidden block is on its boundary.
    let part = Mesh::new(
        mesh.nodes.clone(),
        drawn
            .iter()
            .map(|&b| {
                let block = &mesh.blocks[b];
                ElementBlock {
                    fiber_direction: Vec::new(),
                    ..block.clone()
                }
            })
            .collect(),
    );
    let faces = part.boundary_faces().map_err(|e| e.to_string())?;
    let mut facets = Vec::with_capacity(2 * faces.len());
    for face in faces {
        let b = face.element.block as usize;
        let block = &part.blocks[b];
        let nodes = block.element_nodes(face.element.element as usize);
        let local = block.shape.faces()[face.face as usize];
        let corner_count = block.shape.face_shape(face.face as usize).corner_count();
        let corners: Vec<Vector3<f64>> = local[..corner_count]
            .iter()
            .map(|&l| current[nodes[l as usize] as usize])
            .collect();
        let value = values[first_cell[drawn[b]] + face.element.element as usize];
        push_polygon(&mut facets, &corners, Some(value));
    }
    Ok(facets)
}

/// The facets of a rigid surface: `triangles` by index into `vertices` [m]. Errors name
/// the first triangle with a missing vertex.
pub fn rigid_facets(
    vertices: &[Vector3<f64>],
    triangles: &[[u32; 3]],
) -> Result<Vec<Facet>, String> {
    triangles
        .iter()
        .enumerate()
        .map(|(t, triangle)| {
            let corner = |k: usize| {
                vertices.get(triangle[k] as usize).copied().ok_or_else(|| {
                    format!(
                        "rigid triangle {t} refers to vertex {} of {}",
                        triangle[k],
                        vertices.len()
                    )
                })
            };
            let corners = [corner(0)?, corner(1)?, corner(2)?];
            let normal = (corners[1] - corners[0]).cross(&(corners[2] - corners[0]));
            Ok(Facet {
                corners,
                normal: normal.try_normalize(0.0).unwrap_or_else(Vector3::zeros),
                outline: [false; 3],
                value: None,
            })
        })
        .collect()
}

/// Append the facets of a flat polygon of 3 or 4 corners (counter-clockwise seen from
/// outside) with `value`.
fn push_polygon(facets: &mut Vec<Facet>, corners: &[Vector3<f64>], value: Option<f64>) {
    let normal = if corners.len() == 4 {
        (corners[2] - corners[0]).cross(&(corners[3] - corners[1]))
    } else {
        (corners[1] - corners[0]).cross(&(corners[2] - corners[0]))
    };
    let normal = normal.try_normalize(0.0).unwrap_or_else(Vector3::zeros);
    if corners.len() == 4 {
        // Triangles (0, 1, 2) and (0, 2, 3): the diagonal 0–2 is opposite corner 1 in the
        // first and corner 2 in the second.
        facets.push(Facet {
            corners: [corners[0], corners[1], corners[2]],
            normal,
            outline: [true, false, true],
            value,
        });
        facets.push(Facet {
            corners: [corners[0], corners[2], corners[3]],
            normal,
            outline: [true, true, false],
            value,
        });
    } else {
        facets.push(Facet {
            corners: [corners[0], corners[1], corners[2]],
            normal,
            outline: [true; 3],
            value,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use musclefem_mesh::generate::{TetOrder, box_of_hexes, box_of_tets};

    fn positions(mesh: &Mesh) -> Vec<Vector3<f64>> {
        (0..mesh.node_count())
            .map(|i| mesh.nodes.position(i))
            .collect()
    }

    /// A tet10 box of 2 × 3 × 4 cubes, each cut into tetrahedra: every face of a cube on
    /// the boundary is two triangles, so the boundary has 2 × 2 (2·3 + 3·4 + 2·4) = 104
    /// facets, each drawn by its three corners, with outward normals.
    #[test]
    fn a_tet10_box_has_two_triangles_per_cube_face_on_its_boundary() {
        let mesh = box_of_tets([2.0, 3.0, 4.0], [2, 3, 4], TetOrder::Quadratic).unwrap();
        let x = positions(&mesh);
        let values: Vec<f64> = (0..mesh.element_count()).map(|e| e as f64).collect();
        let facets = boundary_facets(&mesh, &x, &values, None).unwrap();
        assert_eq!(facets.len(), 2 * 2 * (2 * 3 + 3 * 4 + 2 * 4));
        let centre = Vector3::new(1.0, 1.5, 2.0);
        for f in &facets {
            // Corners of the cubes only (integer coordinates), and on the box's surface.
            assert!(f.corners.iter().all(|c| c.iter().all(|v| v.fract() == 0.0)));
            let middle = (f.corners[0] + f.corners[1] + f.corners[2]) / 3.0;
            assert!(f.normal.dot(&(middle - centre)) > 0.0, "inward {f:?}");
            assert_eq!(f.outline, [true; 3]);
        }
        assert_eq!(
            boundary_facets(&mesh, &x, &values, Some(&[1])).unwrap_err(),
            "there is no block 1: the mesh has 1 (0 to 0)"
        );
    }

    /// Two hex8 blocks side by side: the face between them is hidden when both are drawn
    /// and on the boundary of either drawn alone; each facet has its own cell's value.
    #[test]
    fn the_face_between_two_blocks_shows_when_one_is_drawn() {
        let mut mesh = box_of_hexes([2.0, 1.0, 1.0], [2, 1, 1]).unwrap();
        let block = mesh.blocks.remove(0);
        let (left, right) = block.connectivity.split_at(8);
        mesh.blocks = vec![
            ElementBlock::new("left", block.shape, left.to_vec()).unwrap(),
            ElementBlock::new("right", block.shape, right.to_vec()).unwrap(),
        ];
        let x = positions(&mesh);
        let values = [10.0, 20.0];
        let both = boundary_facets(&mesh, &x, &values, None).unwrap();
        assert_eq!(both.len(), 2 * 10);
        let right = boundary_facets(&mesh, &x, &values, Some(&[1])).unwrap();
        assert_eq!(right.len(), 2 * 6);
        assert!(right.iter().all(|f| f.value == Some(20.0)));
        // The face at x = 1, now drawn, points towards −x (out of the right block).
        let inner: Vec<&Facet> = right
            .iter()
            .filter(|f| f.corners.iter().all(|c| c.x == 1.0))
            .collect();
        assert_eq!(inner.len(), 2);
        assert!(
            inner
                .iter()
                .all(|f| (f.normal + Vector3::x()).norm() < 1e-12)
        );
        // Each quadrilateral is two triangles sharing an unoutlined diagonal.
        let outlined: usize = right
            .iter()
            .map(|f| f.outline.iter().filter(|&&o| o).count())
            .sum();
        assert_eq!(outlined, 6 * 4);
    }

    #[test]
    fn rigid_triangles_are_grey_facets_and_bad_indices_are_named() {
        let v = [Vector3::zeros(), Vector3::x(), Vector3::y()];
        let facets = rigid_facets(&v, &[[0, 1, 2]]).unwrap();
        assert_eq!(facets[0].value, None);
        assert_eq!(facets[0].normal, Vector3::z());
        let error = rigid_facets(&v, &[[0, 1, 2], [0, 1, 3]]).unwrap_err();
        assert_eq!(error, "rigid triangle 1 refers to vertex 3 of 3");
    }
}
