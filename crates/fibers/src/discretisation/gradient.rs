//! Cell gradients by weighted least squares.
//!
//! For cell P, every interior face gives a neighbour centroid and every inlet or outlet
//! face its centre, at offset dᵢ = xᵢ − x_P with the potential difference φᵢ − φ_P. The
//! gradient g minimises
//!
//! Σᵢ wᵢ (dᵢ·g − (φᵢ − φ_P))² + Σ_walls (n̂·g)²,   wᵢ = 1/|dᵢ|²,
//!
//! the wall rows asking for the zero normal derivative of an impermeable wall (each row
//! is then a directional derivative of weight 1). The normal equations give
//! g = M⁻¹ Σᵢ wᵢ dᵢ (φᵢ − φ_P), M = Σᵢ wᵢ dᵢ dᵢᵀ + Σ_walls n̂ n̂ᵀ; M depends on the geometry
//! only, so its inverse is computed once per cell. Exact for a linear potential whose
//! gradient is parallel to the walls.

use musclefem_mesh::Mesh;
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use crate::boundary::BoundaryKind;
use crate::error::FiberError;
use crate::fv_mesh::{FaceRef, FvMesh};

/// Cells per parallel task.
const CHUNK: usize = 2048;

/// A cell whose least-squares matrix has det M below this fraction of (tr M / 3)³ has a
/// stencil too flat to give a gradient.
const DEGENERATE: f64 = 1e-12;

/// The inverse least-squares matrix M⁻¹ of every cell (dimensionless: every row of the
/// least-squares problem is a unit direction).
#[derive(Clone, Debug)]
pub(crate) struct LeastSquaresGradient {
    inverse: Vec<Matrix3<f64>>,
}

impl LeastSquaresGradient {
    /// The matrices M⁻¹ of every cell. Errors if a cell's stencil does not span space.
    pub fn new(mesh: &Mesh, fv: &FvMesh, kinds: &[BoundaryKind]) -> Result<Self, FiberError> {
        let inverse = (0..fv.cell_count())
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|cell| {
                let mut m = Matrix3::zeros();
                for &face in fv.faces_of(cell) {
                    let row = match stencil_point(fv, kinds, cell, face) {
                        StencilPoint::Point { offset, .. } => offset.normalize(),
                        StencilPoint::Wall { unit_normal } => unit_normal,
                    };
                    m += row * row.transpose();
                }
                let scale = (m.trace() / 3.0).powi(3);
                match m.try_inverse() {
                    Some(inverse) if m.determinant() > DEGENERATE * scale => Ok(inverse),
                    _ => {
                        let (block, element) = fv.name_of(mesh, cell);
                        Err(FiberError::DegenerateCell {
                            block,
                            element,
                            reason: "its neighbours and faces do not span space, so it has no least-squares gradient".to_string(),
                        })
                    }
                }
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self { inverse })
    }

    /// Writes ∇φ [1/m] of every cell into `gradient`, from the cell potentials `potential`
    /// and the fixed potentials of the inlet and outlet faces.
    pub fn compute(
        &self,
        fv: &FvMesh,
        kinds: &[BoundaryKind],
        potential: &[f64],
        gradient: &mut [Vector3<f64>],
    ) {
        gradient
            .par_iter_mut()
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(cell, g)| {
                let phi = potential[cell];
                let mut sum = Vector3::zeros();
                for &face in fv.faces_of(cell) {
                    if let StencilPoint::Point { offset, value } =
                        stencil_point(fv, kinds, cell, face)
                    {
                        let other = match value {
                            PointValue::Cell(c) => potential[c],
                            PointValue::Fixed(v) => v,
                        };
                        sum += offset * ((other - phi) / offset.norm_squared());
                    }
                }
                *g = self.inverse[cell] * sum;
            });
    }
}

/// What a face of a cell contributes to the cell's least-squares stencil.
enum StencilPoint {
    /// A point at `offset` = x − x_P [m] from the centroid with a known potential.
    Point {
        offset: Vector3<f64>,
        value: PointValue,
    },
    /// A wall: the row n̂·g = 0.
    Wall { unit_normal: Vector3<f64> },
}

/// Where the potential of a stencil point comes from.
enum PointValue {
    /// The potential of this cell.
    Cell(usize),
    /// A fixed boundary potential.
    Fixed(f64),
}

#[inline]
fn stencil_point(fv: &FvMesh, kinds: &[BoundaryKind], cell: usize, face: FaceRef) -> StencilPoint {
    let centre = fv.cell_centre[cell];
    match face {
        FaceRef::Interior(f) => {
            let f = &fv.interior[f as usize];
            let other = if f.owner as usize == cell {
                f.neighbour
            } else {
                f.owner
            } as usize;
            StencilPoint::Point {
                offset: fv.cell_centre[other] - centre,
                value: PointValue::Cell(other),
            }
        }
        FaceRef::Boundary(b) => {
            let face = &fv.boundary[b as usize];
            match kinds[b as usize].potential() {
                Some(value) => StencilPoint::Point {
                    offset: face.centre - centre,
                    value: PointValue::Fixed(value),
                },
                None => StencilPoint::Wall {
                    unit_normal: face.area_vector / face.area_vector.norm(),
                },
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use musclefem_mesh::generate::{TetOrder, box_of_tets, distort};

    use super::*;

    #[test]
    fn linear_fields_along_the_walls_are_exact_on_a_distorted_mesh() {
        // A box whose only walls are y = 0, 1 and z = 0, 1 (x = 0 and x = 1 fixed): a
        // potential linear in x has a gradient parallel to the walls.
        let mut mesh = box_of_tets([1.0, 1.0, 1.0], [4, 3, 3], TetOrder::Linear).unwrap();
        distort(&mut mesh, 0.3, 7).unwrap();
        let fv = FvMesh::new(&mesh).unwrap();
        let kinds: Vec<BoundaryKind> = fv
            .boundary
            .iter()
            .map(|f| {
                let n = f.area_vector / f.area_vector.norm();
                if n.x < -0.99 {
                    BoundaryKind::Inlet
                } else if n.x > 0.99 {
                    BoundaryKind::Outlet
                } else {
                    BoundaryKind::Wall
                }
            })
            .collect();
        let lsq = LeastSquaresGradient::new(&mesh, &fv, &kinds).unwrap();
        // φ = 1 − x is the inlet (x = 0) and outlet (x = 1) potential.
        let potential: Vec<f64> = fv.cell_centre.iter().map(|c| 1.0 - c.x).collect();
        let mut gradient = vec![Vector3::zeros(); fv.cell_count()];
        lsq.compute(&fv, &kinds, &potential, &mut gradient);
        for g in &gradient {
            assert!((g - Vector3::new(-1.0, 0.0, 0.0)).norm() < 1e-12, "{g}");
        }
    }
}
