//! Element technology: how a block of elements turns nodal positions into deformation
//! gradients at its integration points, and stresses there into nodal forces.
//!
//! Total Lagrangian throughout: shape-function gradients ∇_X N_a are taken in the
//! reference configuration once, when the kernel is built; F = Σ_a x_a ⊗ ∇_X N_a; the
//! internal force of node a is f_a = Σ_q P_q ∇_X N_a(q) w_q det J₀(q), with P = J σ F⁻ᵀ
//! the first Piola–Kirchhoff stress.
//!
//! Built so far:
//! - [`Technology::Hex8Full`]: the fully integrated hex8, which locks for nearly
//!   incompressible tissue and is kept as the reference;
//! - [`Technology::Hex8FBar`]: the same points with the F-bar modification
//!   F̄ = (J̄/J)^{1/3} F, J̄ the element's mean dilatation (see `fbar.rs`), which removes
//!   volumetric locking.
//!
//! One-point hourglass-controlled hex8, tet4 and tet10 are still to come
//! (elements-and-solvers issue).

mod fbar;
mod hex8_full;

use nalgebra::{Matrix3, Vector3};
use thiserror::Error;

use crate::mesh::{ElementBlock, ElementShape, Nodes};

/// The element formulations a block can use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Technology {
    /// Trilinear hexahedron, 2×2×2 Gauss points (locks when nearly incompressible).
    Hex8Full,
    /// Trilinear hexahedron, 2×2×2 Gauss points, F-bar: the volume change of every point
    /// replaced by the element's mean dilatation.
    Hex8FBar,
}

impl Technology {
    /// The element shape this technology works on.
    pub fn shape(self) -> ElementShape {
        match self {
            Technology::Hex8Full | Technology::Hex8FBar => ElementShape::Hex8,
        }
    }

    /// Integration points per element.
    pub fn points_per_element(self) -> usize {
        match self {
            Technology::Hex8Full | Technology::Hex8FBar => 8,
        }
    }
}

/// Why a kernel cannot be built for a block.
#[derive(Debug, Error, PartialEq)]
pub enum ElementError {
    #[error(
        "block '{block}': technology {technology:?} needs {expected} elements, the block has {found}"
    )]
    WrongShape {
        block: String,
        technology: Technology,
        expected: &'static str,
        found: &'static str,
    },
    #[error(
        "block '{block}', element {element}: det J = {det_j:e} <= 0 at integration point {point} of the reference configuration"
    )]
    InvertedReference {
        block: String,
        element: usize,
        point: usize,
        det_j: f64,
    },
}

/// Reference data of one block for its technology, computed once: per integration point,
/// the reference gradients ∇_X N_a of every node and the weight w det J₀ [m³].
/// Stored point after point, element after element (structure of arrays per quantity).
#[derive(Debug, Clone)]
pub struct BlockKernel {
    technology: Technology,
    nodes_per_element: usize,
    points_per_element: usize,
    /// ∇_X N_a [1/m], `nodes_per_element` per point.
    gradients: Vec<Vector3<f64>>,
    /// w det J₀ [m³], one per point.
    weights: Vec<f64>,
}

impl BlockKernel {
    /// Build the reference data of `block` (positions from `nodes`) for `technology`.
    pub fn new(
        nodes: &Nodes,
        block: &ElementBlock,
        technology: Technology,
    ) -> Result<Self, ElementError> {
        if block.shape != technology.shape() {
            return Err(ElementError::WrongShape {
                block: block.name.clone(),
                technology,
                expected: technology.shape().name(),
                found: block.shape.name(),
            });
        }
        let mut kernel = hex8_full::reference_data(nodes, block)?;
        kernel.technology = technology;
        Ok(kernel)
    }

    pub fn technology(&self) -> Technology {
        self.technology
    }

    pub fn nodes_per_element(&self) -> usize {
        self.nodes_per_element
    }

    pub fn points_per_element(&self) -> usize {
        self.points_per_element
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.weights.len() / self.points_per_element
    }

    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }

    /// ∇_X N_a of every node at integration point `point` (global point index
    /// element × points_per_element + local point).
    #[inline]
    pub fn gradients(&self, point: usize) -> &[Vector3<f64>] {
        let n = self.nodes_per_element;
        &self.gradients[point * n..(point + 1) * n]
    }

    /// w det J₀ of a point [m³].
    #[inline]
    pub fn weight(&self, point: usize) -> f64 {
        self.weights[point]
    }

    /// Reference volume of element `element` [m³].
    pub fn reference_volume(&self, element: usize) -> f64 {
        let p = self.points_per_element;
        self.weights[element * p..(element + 1) * p].iter().sum()
    }

    /// F = Σ_a x_a ⊗ ∇_X N_a at `point`, from the element's current nodal positions.
    #[inline]
    pub fn deformation_gradient(&self, point: usize, positions: &[Vector3<f64>]) -> Matrix3<f64> {
        let mut f = Matrix3::zeros();
        for (x, g) in positions.iter().zip(self.gradients(point)) {
            f += x * g.transpose();
        }
        f
    }

    /// The deformation gradients the material sees at every point of `element`, from its
    /// current nodal `positions`: F itself, or F̄ for F-bar.
    pub fn element_deformation_gradients(
        &self,
        element: usize,
        positions: &[Vector3<f64>],
        out: &mut [Matrix3<f64>],
    ) {
        let ppe = self.points_per_element;
        for (q, f) in out.iter_mut().enumerate() {
            *f = self.deformation_gradient(element * ppe + q, positions);
        }
        if self.technology == Technology::Hex8FBar {
            fbar::modify(self, element, out);
        }
    }

    /// Add the internal nodal forces of `element` [N] from the Cauchy stresses `stress`
    /// the material returned at the deformation gradients `material_f` (those of
    /// [`Self::element_deformation_gradients`]) at its current `positions`.
    pub fn add_element_forces(
        &self,
        element: usize,
        positions: &[Vector3<f64>],
        material_f: &[Matrix3<f64>],
        stress: &[musclefem_materials::VoigtStress],
        forces: &mut [Vector3<f64>],
    ) {
        let ppe = self.points_per_element;
        match self.technology {
            Technology::Hex8Full => {
                for q in 0..ppe {
                    let piola = musclefem_materials::tensor::first_piola_from_cauchy(
                        &material_f[q],
                        &stress[q],
                    );
                    self.add_internal_forces(element * ppe + q, &piola, forces);
                }
            }
            Technology::Hex8FBar => {
                fbar::add_element_forces(self, element, positions, stress, forces);
            }
        }
    }

    /// Add the point's contribution P ∇_X N_a w det J₀ to the element's nodal forces [N].
    #[inline]
    pub fn add_internal_forces(
        &self,
        point: usize,
        first_piola: &Matrix3<f64>,
        forces: &mut [Vector3<f64>],
    ) {
        let w = self.weight(point);
        for (f, g) in forces.iter_mut().zip(self.gradients(point)) {
            *f += first_piola * g * w;
        }
    }
}

#[cfg(test)]
mod tests;
