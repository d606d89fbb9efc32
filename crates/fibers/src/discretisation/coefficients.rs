//! Geometric coefficients of the face fluxes: the orthogonal coefficient, the correction
//! vector and the interpolation weight of every face.

use musclefem_mesh::Mesh;
use nalgebra::Vector3;
use rayon::prelude::*;

use crate::error::FiberError;
use crate::fv_mesh::FvMesh;

/// Faces per parallel task.
const CHUNK: usize = 4096;

/// The geometric coefficients of the flux ∫ ∇φ·dS through one face, from the split
/// S = Δ + k of its area vector S along d, the vector from the cell centroid to the
/// neighbour centroid (interior face) or to the face centre (boundary face).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FaceCoefficients {
    /// a = |S|²/(S·d) [m]: the flux is a (φ_other − φ_P) + k·(∇φ)_f. Over-relaxed: |Δ| =
    /// |S|/cos θ, θ the angle between S and d.
    pub orthogonal: f64,
    /// k = S − a d [m²], orthogonal to S: the part of the area vector whose flux
    /// k·(∇φ)_f is the explicit non-orthogonal correction.
    pub correction_vector: Vector3<f64>,
    /// w in (∇φ)_f = w ∇φ_P + (1 − w) ∇φ_N, w = S·(x_N − x_f) / S·(x_N − x_P), clamped to
    /// [0, 1] (interior faces; 1 on boundary faces, where (∇φ)_f = ∇φ_P).
    pub owner_weight: f64,
}

/// The coefficients of every face, in the order of [`FvMesh::interior`] and
/// [`FvMesh::boundary`].
#[derive(Clone, Debug)]
pub(crate) struct Coefficients {
    pub interior: Vec<FaceCoefficients>,
    pub boundary: Vec<FaceCoefficients>,
}

impl Coefficients {
    /// Errors if a face is not crossed by its d (S·d ≤ 0: a cell whose centroid lies
    /// outside one of its faces), naming the owner element.
    pub fn new(mesh: &Mesh, fv: &FvMesh) -> Result<Self, FiberError> {
        let interior = fv
            .interior
            .par_iter()
            .with_min_len(CHUNK)
            .map(|face| {
                let owner = fv.cell_centre[face.owner as usize];
                let neighbour = fv.cell_centre[face.neighbour as usize];
                let d = neighbour - owner;
                let owner_weight = (face.area_vector.dot(&(neighbour - face.centre))
                    / face.area_vector.dot(&d))
                .clamp(0.0, 1.0);
                split(face.area_vector, d, owner_weight).ok_or_else(|| {
                    degenerate(
                        mesh,
                        fv,
                        face.owner as usize,
                        face.owner_face,
                        "its neighbour's centroid",
                    )
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let boundary = fv
            .boundary
            .par_iter()
            .with_min_len(CHUNK)
            .map(|face| {
                let d = face.centre - fv.cell_centre[face.cell as usize];
                split(face.area_vector, d, 1.0).ok_or_else(|| {
                    degenerate(
                        mesh,
                        fv,
                        face.cell as usize,
                        face.local_face,
                        "the face centre",
                    )
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self { interior, boundary })
    }
}

/// The over-relaxed split of `area_vector` S along `d`; `None` unless S·d > 0.
fn split(
    area_vector: Vector3<f64>,
    d: Vector3<f64>,
    owner_weight: f64,
) -> Option<FaceCoefficients> {
    let s_dot_d = area_vector.dot(&d);
    let orthogonal = area_vector.norm_squared() / s_dot_d;
    if !(s_dot_d > 0.0 && orthogonal.is_finite()) {
        return None;
    }
    Some(FaceCoefficients {
        orthogonal,
        correction_vector: area_vector - orthogonal * d,
        owner_weight: if owner_weight.is_finite() {
            owner_weight
        } else {
            0.5
        },
    })
}

fn degenerate(mesh: &Mesh, fv: &FvMesh, cell: usize, local_face: u8, towards: &str) -> FiberError {
    let (block, element) = fv.name_of(mesh, cell);
    FiberError::DegenerateCell {
        block,
        element,
        reason: format!(
            "the line from its centroid to {towards} does not cross its face S{} outward (a cell too distorted for the finite-volume scheme)",
            local_face + 1
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_is_over_relaxed() {
        let s = Vector3::new(2.0, 0.0, 0.0);
        let d = Vector3::new(1.0, 1.0, 0.0);
        let c = split(s, d, 0.3).unwrap();
        // |S|²/(S·d) = 4/2; k = S − 2 d = (0, −2, 0) is orthogonal to S.
        assert_eq!(c.orthogonal, 2.0);
        assert_eq!(c.correction_vector, Vector3::new(0.0, -2.0, 0.0));
        assert_eq!(c.owner_weight, 0.3);
        // Exact for a linear field: a (g·d) + k·g = g·S.
        let g = Vector3::new(0.7, -1.3, 0.4);
        assert!((c.orthogonal * g.dot(&d) + c.correction_vector.dot(&g) - g.dot(&s)).abs() < 1e-15);
        assert!(split(s, Vector3::new(-1.0, 3.0, 0.0), 0.5).is_none());
        assert!(split(s, Vector3::new(0.0, 3.0, 0.0), 0.5).is_none());
    }
}
