//! The explicit non-orthogonal correction and the boundary fluxes.

use nalgebra::Vector3;
use rayon::prelude::*;

use super::coefficients::Coefficients;
use crate::boundary::BoundaryKind;
use crate::fv_mesh::{FaceRef, FvMesh};

/// Cells per parallel task.
const CHUNK: usize = 2048;

/// Writes into `correction` the net correction flux out of every cell [m]:
///
/// c_P = Σ_interior ± k_f·(w ∇φ_owner + (1 − w) ∇φ_neighbour) + Σ_fixed k_b·∇φ_P,
///
/// (+ for the owner, − for the neighbour: the area vector points out of the owner), the
/// explicit part of the flux ∫ ∇φ·dS. Each interior face's term is evaluated by the same
/// expression from both sides, so the corrections cancel exactly in the sum over cells.
pub(crate) fn non_orthogonal_correction(
    fv: &FvMesh,
    coefficients: &Coefficients,
    kinds: &[BoundaryKind],
    gradient: &[Vector3<f64>],
    correction: &mut [f64],
) {
    correction
        .par_iter_mut()
        .enumerate()
        .with_min_len(CHUNK)
        .for_each(|(cell, c)| {
            let mut sum = 0.0;
            for &face in fv.faces_of(cell) {
                match face {
                    FaceRef::Interior(f) => {
                        let face = &fv.interior[f as usize];
                        let coefficient = &coefficients.interior[f as usize];
                        let w = coefficient.owner_weight;
                        let face_gradient = w * gradient[face.owner as usize]
                            + (1.0 - w) * gradient[face.neighbour as usize];
                        let flux = coefficient.correction_vector.dot(&face_gradient);
                        sum += if face.owner as usize == cell {
                            flux
                        } else {
                            -flux
                        };
                    }
                    FaceRef::Boundary(b) => {
                        if kinds[b as usize].potential().is_some() {
                            sum += coefficients.boundary[b as usize]
                                .correction_vector
                                .dot(&gradient[cell]);
                        }
                    }
                }
            }
            *c = sum;
        });
}

/// The flux of ∇φ out of the mesh through boundary face `b` [m]:
/// a_b (φ_b − φ_P) + k_b·∇φ_P on inlet and outlet faces, 0 on walls.
pub(crate) fn boundary_flux(
    fv: &FvMesh,
    coefficients: &Coefficients,
    kinds: &[BoundaryKind],
    potential: &[f64],
    gradient: &[Vector3<f64>],
    b: usize,
) -> f64 {
    let Some(fixed) = kinds[b].potential() else {
        return 0.0;
    };
    let cell = fv.boundary[b].cell as usize;
    let coefficient = &coefficients.boundary[b];
    coefficient.orthogonal * (fixed - potential[cell])
        + coefficient.correction_vector.dot(&gradient[cell])
}
