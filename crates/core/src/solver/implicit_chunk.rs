//! A chunk of elements for the implicit solver: the shared [`ElementChunk`] (states,
//! stresses, forces) and the element stiffness matrices computed from its tangents (for
//! F-bar hex8 and tet10, with the mixed element pressure of `mixed_pressure.rs`) into a
//! [`StiffnessWork`] that the solver adds into the sparse matrix and reuses for the next
//! chunk: neither the tangents nor the element matrices are kept for the whole mesh
//! (`docs/implicit-speed.md`, "Memory").

use std::ops::Range;

use nalgebra::Vector3;

use musclefem_materials::{Material, MaterialError, Tangent, VoigtStress};

use super::SolverError;
use super::checkpoint::{CheckpointReader, CheckpointWriter};
use super::chunk::{ElementChunk, PointScratch};
use super::element_fields::AcceptedPoints;
use super::mixed_pressure::MixedPressure;
use crate::element::{BlockKernel, has_major_symmetry};
use crate::mesh::{ElementBlock, MAX_NODES_PER_ELEMENT};

/// Most integration points of an element (the 2×2×2 hex8).
const MAX_POINTS_PER_ELEMENT: usize = 8;

/// Room for one chunk's element stiffness matrices and what computing them needs.
#[derive(Debug, Default)]
pub(crate) struct StiffnessWork {
    /// Element stiffness matrices of the chunk, `element_dofs()²` per element, row-major
    /// [N/m].
    pub matrices: Vec<f64>,
    /// The material tangents ∂P/∂F of the chunk's points [Pa].
    tangents: Vec<Tangent>,
    scratch: PointScratch,
}

#[derive(Debug)]
pub(crate) struct ImplicitChunk {
    chunk: ElementChunk,
    /// Whether every tangent of the last stiffness computed had major symmetry.
    pub symmetric: bool,
    /// The mixed pressure's linearization points (F-bar hex8 and tet10 with
    /// [`super::implicit::ImplicitSettings::mixed_pressure_tangent`]).
    mixed: Option<MixedPressure>,
}

impl ImplicitChunk {
    pub fn new(
        elements: Range<usize>,
        kernel: &BlockKernel,
        block: &ElementBlock,
        material: &dyn Material,
        mixed_pressure_tangent: bool,
    ) -> Self {
        let mixed = (mixed_pressure_tangent && kernel.technology().uses_mean_dilatation())
            .then(|| MixedPressure::new(elements.len()));
        ImplicitChunk {
            mixed,
            chunk: ElementChunk::new(elements, kernel, block, material),
            symmetric: true,
        }
    }

    /// Elements of the block in this chunk.
    pub fn elements(&self) -> Range<usize> {
        self.chunk.elements.clone()
    }

    /// End time [s] of the step of the last update.
    pub fn last_time(&self) -> f64 {
        self.chunk.last_time()
    }

    /// Internal nodal forces, `nodes_per_element` per element [N].
    pub fn forces(&self) -> &[Vector3<f64>] {
        &self.chunk.forces
    }

    /// Material update at the current `positions` over the step of `dt` ending at `time`
    /// (state at the start of the step from the last `commit`) and the internal nodal
    /// forces. On a material error, returns the element (of the block) and the error.
    pub fn update(
        &mut self,
        kernel: &BlockKernel,
        block: &ElementBlock,
        material: &dyn Material,
        positions: &[Vector3<f64>],
        time: f64,
        dt: f64,
    ) -> Result<(), (usize, MaterialError)> {
        self.chunk
            .update(kernel, block, material, positions, time, dt)
    }

    /// The element stiffness matrices at `positions` into `work.matrices`, from the
    /// stresses of the last [`Self::update`] (which must have been at these positions)
    /// and the material tangents of that update, computed again here
    /// ([`ElementChunk::tangents_of_last_update`]). On a material error, returns the
    /// element (of the block) and the error.
    pub fn compute_stiffness(
        &mut self,
        kernel: &BlockKernel,
        block: &ElementBlock,
        material: &dyn Material,
        positions: &[Vector3<f64>],
        work: &mut StiffnessWork,
    ) -> Result<(), (usize, MaterialError)> {
        let ppe = kernel.points_per_element();
        let size = kernel.element_dofs().pow(2);
        let elements = self.chunk.elements.len();
        work.tangents.resize(elements * ppe, Tangent::zeros());
        self.chunk
            .tangents_of_last_update(material, ppe, &mut work.scratch, &mut work.tangents)?;
        let tangents = &work.tangents;
        let stresses = self.chunk.stresses();
        let deformation_gradients = self.chunk.deformation_gradients();
        work.matrices.clear();
        work.matrices.resize(elements * size, 0.0);
        let mut element_positions = [Vector3::zeros(); MAX_NODES_PER_ELEMENT];
        let npe = kernel.nodes_per_element();
        // The stresses and tangents of an element shifted to its mixed pressure.
        let mut shifted_stress = [VoigtStress::zeros(); MAX_POINTS_PER_ELEMENT];
        let mut shifted = [Tangent::zeros(); MAX_POINTS_PER_ELEMENT];
        self.symmetric = true;
        for (local, element) in self.chunk.elements.clone().enumerate() {
            for (x, &id) in element_positions
                .iter_mut()
                .zip(block.element_nodes(element))
            {
                *x = positions[id as usize];
            }
            let points = local * ppe..(local + 1) * ppe;
            let symmetric = tangents[points.clone()].iter().all(has_major_symmetry);
            self.symmetric &= symmetric;
            let (stress, tangent) = match &mut self.mixed {
                Some(mixed) => {
                    let (stress, tangent) = (&mut shifted_stress[..ppe], &mut shifted[..ppe]);
                    stress.copy_from_slice(&stresses[points.clone()]);
                    tangent.copy_from_slice(&tangents[points.clone()]);
                    mixed.shift_to_mixed_pressure(
                        local,
                        kernel,
                        element,
                        &element_positions[..npe],
                        &deformation_gradients[points],
                        stress,
                        tangent,
                    );
                    (&*stress, &*tangent)
                }
                None => (&stresses[points.clone()], &tangents[points]),
            };
            let added = kernel.add_element_stiffness_with(
                element,
                &element_positions[..npe],
                stress,
                tangent,
                &mut work.matrices[local * size..(local + 1) * size],
                symmetric,
            );
            debug_assert!(added, "checked when the part was prepared");
        }
        Ok(())
    }

    /// The last stiffness computed is being solved with (see [`MixedPressure::promote`]).
    pub fn stiffness_solved(&mut self) {
        if let Some(mixed) = &mut self.mixed {
            mixed.promote();
        }
    }

    /// A step starts (or restarts) from a converged state.
    pub fn start_step(&mut self) {
        if let Some(mixed) = &mut self.mixed {
            mixed.restart();
        }
    }

    /// Accept the step: the new state and deformation become the old ones.
    pub fn commit(&mut self) {
        self.chunk.commit();
    }

    /// Writes the material points' state (the stiffness and the mixed pressure's
    /// linearization are rebuilt by the next step's first evaluation).
    pub fn save_state(&self, out: &mut CheckpointWriter) {
        self.chunk.save_state(out);
    }

    /// Reads what [`save_state`](Self::save_state) wrote.
    pub fn restore_state(&mut self, input: &mut CheckpointReader) -> Result<(), SolverError> {
        self.chunk.restore_state(input)
    }

    /// The material points of the last accepted step, for the output fields.
    pub fn accepted_points(&self) -> AcceptedPoints<'_> {
        self.chunk.accepted_points()
    }
}
