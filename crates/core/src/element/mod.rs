//! Element technology: how a block of elements turns nodal positions into deformation
//! gradients at its integration points, and stresses there into nodal forces.
//!
//! Total Lagrangian throughout: shape-function gradients ∇_X N_a are taken in the
//! reference configuration once, when the kernel is built; F = Σ_a x_a ⊗ ∇_X N_a; the
//! internal force of node a is f_a = Σ_q P_q ∇_X N_a(q) w_q det J₀(q), with P = J σ F⁻ᵀ
//! the first Piola–Kirchhoff stress.
//!
//! Built so far, a file each:
//! - [`Technology::Hex8Full`] (`hex8_full.rs`): the fully integrated hex8 (2×2×2 Gauss),
//!   which locks for nearly incompressible tissue and is kept as the reference;
//! - [`Technology::Hex8FBar`] (`fbar.rs`): the same points with the F-bar modification
//!   F̄ = (J̄/J)^{1/3} F, J̄ the element's mean dilatation, which removes volumetric
//!   locking;
//! - [`Technology::Hex8OnePoint`] (`hex8_one_point.rs`): one point with the uniform
//!   (mean) gradient of Flanagan & Belytschko and a stiffness-type hourglass control
//!   whose energy [`BlockKernel::hourglass_energy`] reports;
//! - [`Technology::Tet4`] (`tet4.rs`): the constant-strain linear tet, one point (locks
//!   when nearly incompressible);
//! - [`Technology::Tet4NodalAverage`] (`tet4_nodal_average.rs`): the linear tet with
//!   nodally averaged F-bar (Bonet & Burton 1998): the element's volume change is the mean
//!   of its nodes' patch-averaged ones, which removes volumetric locking; its forces couple
//!   neighbouring elements, so the solvers evaluate it block by block;
//! - [`Technology::Tet10`] (`tet10.rs`): the quadratic tet with the 4-point rule of
//!   degree 2, exact for straight-sided elements (no treatment of incompressibility: it
//!   locks at muscle's K/μ ≈ 10⁴);
//! - [`Technology::Tet10FBar`] (`fbar.rs` on the tet10's points): the same points with
//!   the hex8's F-bar modification, J̄ the element's mean dilatation (no volumetric
//!   locking).
//!
//! Every technology passes the patch tests (linear fields, constant stress) on distorted
//! meshes. Not built: a mixed (u–p) tet10.

mod fbar;
mod hex8_full;
pub(crate) mod hex8_one_point;
pub(crate) mod hex8_one_point_batch;
mod isoparametric;
mod kind;
mod stiffness;
mod tet10;
mod tet4;
pub(crate) mod tet4_nodal_average;

pub use hex8_one_point::DEFAULT_HOURGLASS_FACTOR;
pub use kind::ElementKind;
pub use stiffness::{SYMMETRY_TOLERANCE, has_major_symmetry};

use nalgebra::{Matrix3, Vector3};
use thiserror::Error;

use crate::mesh::{ElementBlock, ElementShape, MAX_NODES_PER_ELEMENT, Nodes};

/// The element formulations a block can use. `PartialEq` only: a parameter is an `f64`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Technology {
    /// Trilinear hexahedron, 2×2×2 Gauss points (locks when nearly incompressible).
    Hex8Full,
    /// Trilinear hexahedron, 2×2×2 Gauss points, F-bar: the volume change of every point
    /// replaced by the element's mean dilatation.
    Hex8FBar,
    /// Trilinear hexahedron, one point with the mean gradient, and stiffness-type
    /// hourglass control of modulus `hourglass_modulus` G_hg [Pa] (≥ 0; see
    /// `hex8_one_point.rs` for the scaling, [`Technology::hex8_one_point`] for a default).
    Hex8OnePoint { hourglass_modulus: f64 },
    /// Linear tetrahedron, one point.
    Tet4,
    /// Linear tetrahedron, one point, nodally averaged F-bar: F̄ = (J̄/J)^{1/3} F with J̄
    /// the mean of the element's nodal Jacobians J_a = Σ v_e / Σ V_e over the tets of the
    /// block around node a (no volumetric locking).
    Tet4NodalAverage,
    /// Quadratic tetrahedron, 4 points (degree 2).
    Tet10,
    /// Quadratic tetrahedron, 4 points, F-bar: the volume change of every point replaced
    /// by the element's mean dilatation, as [`Technology::Hex8FBar`].
    Tet10FBar,
}

impl Technology {
    /// [`Technology::Hex8OnePoint`] with the default hourglass modulus
    /// G_hg = [`DEFAULT_HOURGLASS_FACTOR`] × `shear_modulus` [Pa] (the material's shear
    /// modulus at rest, e.g. μ of a neo-Hookean solid, or 2c·b of the Hill matrix term).
    pub fn hex8_one_point(shear_modulus: f64) -> Self {
        Technology::Hex8OnePoint {
            hourglass_modulus: DEFAULT_HOURGLASS_FACTOR * shear_modulus,
        }
    }

    /// The element shape this technology works on.
    pub fn shape(self) -> ElementShape {
        match self {
            Technology::Hex8Full | Technology::Hex8FBar | Technology::Hex8OnePoint { .. } => {
                ElementShape::Hex8
            }
            Technology::Tet4 | Technology::Tet4NodalAverage => ElementShape::Tet4,
            Technology::Tet10 | Technology::Tet10FBar => ElementShape::Tet10,
        }
    }

    /// Integration points per element.
    pub fn points_per_element(self) -> usize {
        match self {
            Technology::Hex8Full | Technology::Hex8FBar => 8,
            Technology::Hex8OnePoint { .. } | Technology::Tet4 | Technology::Tet4NodalAverage => 1,
            Technology::Tet10 | Technology::Tet10FBar => 4,
        }
    }

    /// Whether the material sees F̄ = (J̄/J)^{1/3} F with the element's mean dilatation J̄
    /// (`fbar.rs`): [`Technology::Hex8FBar`] and [`Technology::Tet10FBar`].
    pub fn uses_mean_dilatation(self) -> bool {
        matches!(self, Technology::Hex8FBar | Technology::Tet10FBar)
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
    #[error("block '{block}': technology {technology:?}: {reason}")]
    InvalidParameter {
        block: String,
        technology: Technology,
        reason: String,
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
    /// Hourglass vectors and stiffnesses ([`Technology::Hex8OnePoint`] only).
    hourglass: Option<hex8_one_point::Hourglass>,
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
        match technology {
            Technology::Hex8Full | Technology::Hex8FBar => {
                hex8_full::reference_data(nodes, block, technology)
            }
            Technology::Hex8OnePoint { hourglass_modulus } => {
                hex8_one_point::reference_data(nodes, block, hourglass_modulus)
            }
            Technology::Tet4 => tet4::reference_data(nodes, block),
            Technology::Tet4NodalAverage => tet4_nodal_average::reference_data(nodes, block),
            Technology::Tet10 | Technology::Tet10FBar => {
                tet10::reference_data(nodes, block, technology)
            }
        }
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

    /// F-bar only: the element's mean dilatation J̄ = v/V at its current `positions` and
    /// ∂J̄/∂x_a per node [1/m] (`fbar.rs`; zero past the element's nodes).
    pub(crate) fn mean_dilatation_gradient(
        &self,
        element: usize,
        positions: &[Vector3<f64>],
    ) -> (f64, [Vector3<f64>; MAX_NODES_PER_ELEMENT]) {
        fbar::mean_dilatation_gradient(self, element, positions)
    }

    /// The deformation gradients the material sees at every point of `element`, from its
    /// current nodal `positions`: F itself (with the mean gradient for the one-point hex8),
    /// or F̄ for F-bar.
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
        if self.technology.uses_mean_dilatation() {
            fbar::modify(self, element, out);
        }
    }

    /// Add the internal nodal forces of `element` [N] from the Cauchy stresses `stress`
    /// the material returned at the deformation gradients `material_f` (those of
    /// [`Self::element_deformation_gradients`]) at its current `positions`.
    /// [`Technology::Tet4NodalAverage`] couples neighbours and is evaluated block by block
    /// by the solvers (`tet4_nodal_average.rs`); element by element it gives the plain tet4
    /// forces, which are its forces under a homogeneous deformation.
    ///
    /// Given a `volume_gradient`, also returns the element's current volume
    /// v = Σ_q w_q J_q [m³] and writes its gradient ∂v/∂x_a [m²] there
    /// ([`Self::volume_and_gradient`]): the explicit solver's bulk and shear viscosity act
    /// through it. The F-bar kernels have both at hand; the others compute them
    /// afterwards.
    pub fn add_element_forces(
        &self,
        element: usize,
        positions: &[Vector3<f64>],
        material_f: &[Matrix3<f64>],
        stress: &[musclefem_materials::VoigtStress],
        forces: &mut [Vector3<f64>],
        volume_gradient: Option<&mut [Vector3<f64>]>,
    ) -> Option<f64> {
        let ppe = self.points_per_element;
        match self.technology {
            Technology::Hex8FBar | Technology::Tet10FBar => {
                let wanted = volume_gradient.is_some();
                let volume = fbar::add_element_forces(
                    self,
                    element,
                    positions,
                    stress,
                    forces,
                    volume_gradient,
                );
                wanted.then_some(volume)
            }
            Technology::Hex8Full
            | Technology::Hex8OnePoint { .. }
            | Technology::Tet4
            | Technology::Tet4NodalAverage
            | Technology::Tet10 => {
                for q in 0..ppe {
                    let piola = musclefem_materials::tensor::first_piola_from_cauchy(
                        &material_f[q],
                        &stress[q],
                    );
                    self.add_internal_forces(element * ppe + q, &piola, forces);
                }
                self.add_hourglass_forces(element, positions, forces);
                volume_gradient
                    .map(|gradient| self.volume_and_gradient(element, positions, gradient))
            }
        }
    }

    /// Current volume v = Σ_q w_q J_q [m³] of `element` at its current `positions`, and
    /// its gradient ∂v/∂x_a = Σ_q w_q J_q F_q⁻ᵀ ∇_X N_a(q) [m²] into `gradient` (one per
    /// node).
    pub fn volume_and_gradient(
        &self,
        element: usize,
        positions: &[Vector3<f64>],
        gradient: &mut [Vector3<f64>],
    ) -> f64 {
        gradient.iter_mut().for_each(|g| *g = Vector3::zeros());
        let mut volume = 0.0;
        for q in 0..self.points_per_element {
            let point = element * self.points_per_element + q;
            let f: Matrix3<f64> = self.deformation_gradient(point, positions);
            let w = self.weight(point);
            volume += w * f.determinant();
            // J F⁻ᵀ is the cofactor of F, well defined even at J → 0.
            let cofactor = Matrix3::from_columns(&[
                f.column(1).cross(&f.column(2)),
                f.column(2).cross(&f.column(0)),
                f.column(0).cross(&f.column(1)),
            ]);
            for (g, grad_n) in gradient.iter_mut().zip(self.gradients(point)) {
                *g += cofactor * grad_n * w;
            }
        }
        volume
    }

    /// Add the hourglass forces f_a = k Σ_α q^α γ^α_a [N] of `element` at its current
    /// `positions` ([`Technology::Hex8OnePoint`]; nothing for the other technologies).
    /// [`Self::add_element_forces`] includes them.
    pub fn add_hourglass_forces(
        &self,
        element: usize,
        positions: &[Vector3<f64>],
        forces: &mut [Vector3<f64>],
    ) {
        if let Some(hourglass) = &self.hourglass {
            hourglass.add_forces(element, positions, forces);
        }
    }

    /// Hourglass energy E_hg = ½ k Σ_α |q^α|² [J] of `element` at its current
    /// `positions` (zero for technologies without hourglass control). It is part of the
    /// internal energy the forces of [`Self::add_element_forces`] do work against.
    pub fn hourglass_energy(&self, element: usize, positions: &[Vector3<f64>]) -> f64 {
        self.hourglass
            .as_ref()
            .map_or(0.0, |h| h.energy(element, positions))
    }

    /// The hourglass vectors γ^α_a (4 modes × 8 nodes, dimensionless) and stiffness k
    /// [N/m] of `element`, for a stiffness matrix K_ab = k Σ_α γ^α_a γ^α_b I
    /// ([`Technology::Hex8OnePoint`] only).
    pub fn hourglass_vectors(&self, element: usize) -> Option<(&[[f64; 8]; 4], f64)> {
        self.hourglass.as_ref().map(|h| h.of(element))
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
mod hourglass_tests;
#[cfg(test)]
mod technology_tests;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tet10_fbar_tests;
