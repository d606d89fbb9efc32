//! A run of consecutive elements of one block for the implicit solver: deformation
//! gradients, material states, stresses, tangents, element forces and element stiffness
//! matrices, owned, so that chunks update in parallel without sharing.

use std::ops::Range;

use nalgebra::{Matrix3, Vector3};

use musclefem_materials::{
    Material, MaterialError, PointBlock, PointResponse, Tangent, VoigtStress,
};

use crate::element::BlockKernel;
use crate::mesh::ElementBlock;

/// Elements per chunk: 64 hex8 = 512 material points per material call.
pub(crate) const ELEMENTS_PER_CHUNK: usize = 64;

/// Largest |𝔸 − 𝔸ᵀ| relative to the largest |𝔸| for a tangent to count as symmetric.
const SYMMETRY_TOLERANCE: f64 = 1e-9;

#[derive(Debug)]
pub(crate) struct ImplicitChunk {
    pub elements: Range<usize>,
    f_old: Vec<Matrix3<f64>>,
    f_new: Vec<Matrix3<f64>>,
    fiber: Vec<Vector3<f64>>,
    state_old: Vec<f64>,
    state_new: Vec<f64>,
    stress: Vec<VoigtStress>,
    tangent: Vec<Tangent>,
    /// Internal nodal forces, `nodes_per_element` per element [N].
    pub forces: Vec<Vector3<f64>>,
    /// Element stiffness matrices, `element_dofs()²` per element, row-major [N/m].
    pub stiffness: Vec<f64>,
    /// Whether every tangent of the last update with stiffness had major symmetry.
    pub symmetric: bool,
    positions: Vec<Vector3<f64>>,
}

impl ImplicitChunk {
    pub fn new(
        elements: Range<usize>,
        kernel: &BlockKernel,
        block: &ElementBlock,
        material: &dyn Material,
    ) -> Self {
        let ppe = kernel.points_per_element();
        let points = elements.len() * ppe;
        let fiber = elements
            .clone()
            .flat_map(|e| std::iter::repeat_n(block.fiber_direction[e], ppe))
            .collect();
        let npe = kernel.nodes_per_element();
        let dofs = kernel.element_dofs();
        ImplicitChunk {
            f_old: vec![Matrix3::identity(); points],
            f_new: vec![Matrix3::identity(); points],
            fiber,
            state_old: material.initial_state(points),
            state_new: material.initial_state(points),
            stress: vec![VoigtStress::zeros(); points],
            tangent: Vec::new(),
            forces: vec![Vector3::zeros(); elements.len() * npe],
            stiffness: vec![0.0; elements.len() * dofs * dofs],
            symmetric: true,
            positions: vec![Vector3::zeros(); npe],
            elements,
        }
    }

    /// Material update at the current `positions` over the step of `dt` ending at `time`
    /// (state at the start of the step from the last `commit`), the internal nodal forces
    /// and, with `with_stiffness`, the element stiffness matrices. On a material error,
    /// returns the element (of the block) and the error.
    pub fn update(
        &mut self,
        kernel: &BlockKernel,
        block: &ElementBlock,
        material: &dyn Material,
        positions: &[Vector3<f64>],
        time: f64,
        dt: f64,
        with_stiffness: bool,
    ) -> Result<(), (usize, MaterialError)> {
        let ppe = kernel.points_per_element();
        let npe = kernel.nodes_per_element();
        for (local, element) in self.elements.clone().enumerate() {
            gather(&mut self.positions, block.element_nodes(element), positions);
            kernel.element_deformation_gradients(
                element,
                &self.positions,
                &mut self.f_new[local * ppe..(local + 1) * ppe],
            );
        }
        if with_stiffness && self.tangent.len() != self.f_new.len() {
            self.tangent = vec![Tangent::zeros(); self.f_new.len()];
        }
        let points = PointBlock {
            time,
            dt,
            deformation_gradient_old: &self.f_old,
            deformation_gradient_new: &self.f_new,
            fiber_direction: &self.fiber,
            state_old: &self.state_old,
        };
        let mut response = PointResponse {
            cauchy_stress: &mut self.stress,
            state_new: &mut self.state_new,
            tangent: with_stiffness.then_some(self.tangent.as_mut_slice()),
        };
        material.update(&points, &mut response).map_err(|error| {
            let element = match &error {
                MaterialError::InvalidPoint { point, .. }
                | MaterialError::NonFiniteResult { point, .. } => self.elements.start + point / ppe,
                _ => self.elements.start,
            };
            (element, error)
        })?;
        self.forces.fill(Vector3::zeros());
        for (local, element) in self.elements.clone().enumerate() {
            gather(&mut self.positions, block.element_nodes(element), positions);
            let points = local * ppe..(local + 1) * ppe;
            kernel.add_element_forces(
                element,
                &self.positions,
                &self.f_new[points.clone()],
                &self.stress[points],
                &mut self.forces[local * npe..(local + 1) * npe],
            );
        }
        if with_stiffness {
            let size = kernel.element_dofs().pow(2);
            self.stiffness.fill(0.0);
            for (local, element) in self.elements.clone().enumerate() {
                let added = kernel.add_element_stiffness(
                    element,
                    &self.tangent[local * ppe..(local + 1) * ppe],
                    &mut self.stiffness[local * size..(local + 1) * size],
                );
                debug_assert!(added, "checked when the part was prepared");
            }
            self.symmetric = self.tangent.iter().all(|t| {
                let scale = t.amax();
                (t - t.transpose()).amax() <= SYMMETRY_TOLERANCE * scale
            });
        }
        Ok(())
    }

    /// Accept the step: the new state and deformation become the old ones.
    pub fn commit(&mut self) {
        std::mem::swap(&mut self.state_old, &mut self.state_new);
        std::mem::swap(&mut self.f_old, &mut self.f_new);
    }
}

/// The element's node positions out of all nodes' `positions`.
#[inline]
fn gather(out: &mut [Vector3<f64>], ids: &[u32], positions: &[Vector3<f64>]) {
    for (x, &id) in out.iter_mut().zip(ids) {
        *x = positions[id as usize];
    }
}
