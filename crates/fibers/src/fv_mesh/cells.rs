//! Cell geometry: the volume and the volume centroid of every cell, and the check that
//! no element is inverted.
//!
//! A tet4 or tet10 cell is the tetrahedron of its four corner nodes (the mid-edge nodes of
//! a tet10 are ignored: the finite-volume cells are straight-sided). A hex8 cell is the
//! trilinear hexahedron of its eight nodes.

use musclefem_mesh::geometry::{hex8_gradients, jacobian, tet4_volume};
use musclefem_mesh::{ElementShape, Mesh};
use nalgebra::Vector3;
use rayon::prelude::*;

use crate::error::FiberError;

/// 1/√3, the abscissa of 2-point Gauss–Legendre quadrature on [−1, 1].
const GAUSS_2: f64 = 0.577_350_269_189_625_8;

/// Elements per parallel task.
const CHUNK: usize = 4096;

/// Centroid [m] and volume [m³] of every cell, block after block. Errors on the first
/// element (by block, then element) whose volume is not positive.
pub(crate) fn cell_geometry(mesh: &Mesh) -> Result<(Vec<Vector3<f64>>, Vec<f64>), FiberError> {
    let mut centres = Vec::with_capacity(mesh.element_count());
    let mut volumes = Vec::with_capacity(mesh.element_count());
    for block in &mesh.blocks {
        let shape = block.shape;
        let n = shape.nodes_per_element();
        let corners = shape.corner_count();
        let geometry: Vec<(Vector3<f64>, f64)> = block
            .connectivity
            .par_chunks_exact(n)
            .with_min_len(CHUNK)
            .map(|ids| {
                let mut coords = [Vector3::zeros(); 8];
                mesh.nodes.gather(&ids[..corners], &mut coords);
                match shape {
                    ElementShape::Hex8 => hex_centroid_and_volume(&coords),
                    ElementShape::Tet4 | ElementShape::Tet10 => {
                        tet_centroid_and_volume(&coords[..4])
                    }
                }
            })
            .collect();
        if let Some(element) = geometry
            .iter()
            .position(|&(_, volume)| !(volume > 0.0 && volume.is_finite()))
        {
            return Err(FiberError::InvertedElement {
                block: block.name.clone(),
                element,
                shape,
                volume: geometry[element].1,
            });
        }
        for (centre, volume) in geometry {
            centres.push(centre);
            volumes.push(volume);
        }
    }
    Ok((centres, volumes))
}

/// Centroid (the mean of the corners) and volume (p₂ − p₁)·((p₃ − p₁) × (p₄ − p₁))/6 of
/// the tetrahedron `p[0..4]`.
fn tet_centroid_and_volume(p: &[Vector3<f64>]) -> (Vector3<f64>, f64) {
    let centre = (p[0] + p[1] + p[2] + p[3]) / 4.0;
    (centre, tet4_volume(p))
}

/// Volume V = ∫ det J dξ and centroid x̄ = ∫ x det J dξ / V of the trilinear hexahedron
/// with nodes `p` (Abaqus C3D8 order), by 2×2×2 Gauss quadrature: exact, as x det J is at
/// most cubic in each reference coordinate.
fn hex_centroid_and_volume(p: &[Vector3<f64>; 8]) -> (Vector3<f64>, f64) {
    let reference = ElementShape::Hex8.reference_nodes();
    let mut volume = 0.0;
    let mut moment = Vector3::zeros();
    for g in reference {
        let xi = [GAUSS_2 * g[0], GAUSS_2 * g[1], GAUSS_2 * g[2]];
        let det = jacobian(p, &hex8_gradients(xi)).determinant();
        let mut x = Vector3::zeros();
        for (node, r) in p.iter().zip(reference) {
            let shape_function =
                (1.0 + r[0] * xi[0]) * (1.0 + r[1] * xi[1]) * (1.0 + r[2] * xi[2]) / 8.0;
            x += shape_function * node;
        }
        volume += det;
        moment += det * x;
    }
    (moment / volume, volume)
}

#[cfg(test)]
mod tests {
    use musclefem_mesh::generate::{TetOrder, box_of_hexes, box_of_tets};

    use super::*;

    #[test]
    fn frustum_hex_has_its_exact_centroid_and_volume() {
        // Bottom square [0,1]² at z = 0, top square [0,a]² at z = h: a frustum of a
        // pyramid (planar faces), volume h/3 (A₁ + A₂ + √(A₁A₂)); its centroid height is
        // h (A₁ + 2√(A₁A₂) + 3A₂) / (4 (A₁ + √(A₁A₂) + A₂)).
        let (a, h) = (0.4, 0.7);
        let v = |x, y, z| Vector3::new(x, y, z);
        let p = [
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(1.0, 1.0, 0.0),
            v(0.0, 1.0, 0.0),
            v(0.0, 0.0, h),
            v(a, 0.0, h),
            v(a, a, h),
            v(0.0, a, h),
        ];
        let (centre, volume) = hex_centroid_and_volume(&p);
        let (a1, a2) = (1.0, a * a);
        let exact_volume = h / 3.0 * (a1 + a2 + (a1 * a2).sqrt());
        let exact_z =
            h * (a1 + 2.0 * (a1 * a2).sqrt() + 3.0 * a2) / (4.0 * (a1 + (a1 * a2).sqrt() + a2));
        assert!((volume - exact_volume).abs() < 1e-15);
        assert!(
            (centre.z - exact_z).abs() < 1e-15,
            "{} vs {exact_z}",
            centre.z
        );
    }

    #[test]
    fn box_cells_fill_the_box() {
        for mesh in [
            box_of_hexes([1.0, 2.0, 3.0], [2, 3, 1]).unwrap(),
            box_of_tets([1.0, 2.0, 3.0], [2, 1, 2], TetOrder::Quadratic).unwrap(),
        ] {
            let (centres, volumes) = cell_geometry(&mesh).unwrap();
            let total: f64 = volumes.iter().sum();
            let moment: Vector3<f64> = centres.iter().zip(&volumes).map(|(c, v)| c * *v).sum();
            assert!((total - 6.0).abs() < 1e-13);
            assert!((moment / total - Vector3::new(0.5, 1.0, 1.5)).norm() < 1e-13);
        }
    }

    #[test]
    fn inverted_element_is_named() {
        let mut mesh = box_of_tets([1.0; 3], [2, 1, 1], TetOrder::Linear).unwrap();
        mesh.blocks[0].connectivity.swap(4 * 7 + 1, 4 * 7 + 2);
        let err = cell_geometry(&mesh).unwrap_err();
        assert!(
            matches!(&err, FiberError::InvertedElement { block, element: 7, shape: ElementShape::Tet4, volume } if block == "tets" && *volume < 0.0),
            "{err}"
        );
    }
}
