//! Internal forces of a [`Technology::Tet4NodalAverage`] block for the explicit solver, in
//! passes over the block (equations in `element/tet4_nodal_average.rs`):
//!
//! 1. per element (parallel chunks): F_e and the current volume v_e = V_e det F_e;
//! 2. per node (serial, element order): J_a = Σ_{e∋a} v_e / V_a;
//! 3. per element (parallel): J̄_e, F̄_e, the material update at F̄_e, the deviatoric
//!    forces and s_e = V_e tr σ̄_e / 12 (and, when asked, the acoustic modulus at F̄_e);
//! 4. per node (serial): S_a = Σ_{e∋a} s_e / V_a;
//! 5. per element (parallel): the coupling forces (Σ_{a∈e} S_a) v_e ∇_x N_b;
//! 6. the element forces gathered into the nodes serially in element order.
//!
//! Every sum runs in a fixed order, so the forces are the same, bit for bit, on any number
//! of threads; all storage is allocated once, when the part is prepared.
//!
//! [`Technology::Tet4NodalAverage`]: crate::element::Technology::Tet4NodalAverage

use std::ops::Range;

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use musclefem_materials::tensor::symmetric_from_voigt;
use musclefem_materials::{Material, MaterialError, PointBlock, PointResponse, VoigtStress};

use super::SolverError;
use super::checkpoint::{CheckpointReader, CheckpointWriter};
use super::chunk::{PointSlices, characteristic_length, chunk_ranges, point_acoustic_modulus};
use super::element_fields::AcceptedPoints;
use crate::element::BlockKernel;
use crate::element::tet4_nodal_average::{
    NodalAveraging, add_deviatoric_forces, add_pressure_forces, averaged_deformation_gradient,
    pressure_work,
};
use crate::mesh::ElementBlock;

/// A run of consecutive elements of the block with their material points and work arrays.
#[derive(Debug)]
struct AveragedChunk {
    elements: Range<usize>,
    /// Plain deformation gradient F_e.
    deformation: Vec<Matrix3<f64>>,
    /// F̄ of the last accepted step and of the current update (what the material sees).
    f_old: Vec<Matrix3<f64>>,
    f_new: Vec<Matrix3<f64>>,
    fiber: Vec<Vector3<f64>>,
    state_old: Vec<f64>,
    state_new: Vec<f64>,
    stress: Vec<VoigtStress>,
    /// v_e [m³].
    current_volume: Vec<f64>,
    /// s_e [J].
    pressure_work: Vec<f64>,
    /// Element forces, 4 per element [N].
    forces: Vec<Vector3<f64>>,
    /// Stable-step data, as for the plain tet4 [m], [Pa].
    reference_length: Vec<f64>,
    wave_modulus: Vec<f64>,
    positions: [Vector3<f64>; 4],
    /// One-point scratch for the acoustic modulus.
    scratch_state: Vec<f64>,
}

/// A nodally averaged tet4 block during an explicit run.
#[derive(Debug)]
pub(crate) struct NodalAveragePart {
    averaging: NodalAveraging,
    chunks: Vec<AveragedChunk>,
    /// v_e and s_e of all elements in block order (gathered from the chunks).
    current_volume: Vec<f64>,
    pressure_work: Vec<f64>,
    /// J_a and S_a [Pa] of every block-local node.
    nodal_jacobian: Vec<f64>,
    nodal_pressure: Vec<f64>,
}

impl NodalAveragePart {
    pub fn new(kernel: &BlockKernel, block: &ElementBlock, material: &dyn Material) -> Self {
        let averaging = NodalAveraging::new(kernel, block);
        let chunks = chunk_ranges(block.len())
            .map(|elements| {
                let n = elements.len();
                AveragedChunk {
                    deformation: vec![Matrix3::identity(); n],
                    f_old: vec![Matrix3::identity(); n],
                    f_new: vec![Matrix3::identity(); n],
                    fiber: elements.clone().map(|e| block.fiber_direction[e]).collect(),
                    state_old: material.initial_state(n),
                    state_new: material.initial_state(n),
                    stress: vec![VoigtStress::zeros(); n],
                    current_volume: vec![0.0; n],
                    pressure_work: vec![0.0; n],
                    forces: vec![Vector3::zeros(); 4 * n],
                    reference_length: elements
                        .clone()
                        .map(|e| characteristic_length(kernel, e))
                        .collect(),
                    wave_modulus: vec![0.0; n],
                    positions: [Vector3::zeros(); 4],
                    scratch_state: vec![0.0; material.state_count()],
                    elements,
                }
            })
            .collect();
        let nodes = averaging.node_count();
        NodalAveragePart {
            averaging,
            chunks,
            current_volume: vec![0.0; block.len()],
            pressure_work: vec![0.0; block.len()],
            nodal_jacobian: vec![0.0; nodes],
            nodal_pressure: vec![0.0; nodes],
        }
    }

    /// Add the block's internal nodal forces [N] at `positions` (all mesh nodes) to
    /// `force`, materials updated (not committed) over the step of `dt` ending at `time`;
    /// with `refresh`, recompute the acoustic moduli. On a material error (det F ≤ 0
    /// included), returns the element of the block and the error.
    #[allow(clippy::too_many_arguments)]
    pub fn add_internal_forces(
        &mut self,
        kernel: &BlockKernel,
        block: &ElementBlock,
        material: &dyn Material,
        positions: &[Vector3<f64>],
        time: f64,
        dt: f64,
        refresh: bool,
        force: &mut [Vector3<f64>],
    ) -> Result<(), (usize, MaterialError)> {
        // 1. F_e and v_e.
        self.chunks
            .par_iter_mut()
            .for_each(|chunk| chunk.volumes(kernel, block, positions));
        for chunk in &self.chunks {
            self.current_volume[chunk.elements.clone()].copy_from_slice(&chunk.current_volume);
        }
        // 2. J_a.
        self.averaging
            .nodal_jacobians(&self.current_volume, &mut self.nodal_jacobian);
        // 3. Material at F̄, deviatoric forces, s_e.
        let (averaging, nodal_jacobian) = (&self.averaging, &self.nodal_jacobian);
        self.chunks.par_iter_mut().try_for_each(|chunk| {
            chunk.material_update(kernel, averaging, nodal_jacobian, material, time, dt)?;
            if refresh {
                chunk.refresh_wave_moduli(material, time, dt)?;
            }
            Ok(())
        })?;
        for chunk in &self.chunks {
            self.pressure_work[chunk.elements.clone()].copy_from_slice(&chunk.pressure_work);
        }
        // 4. S_a.
        self.averaging
            .nodal_pressures(&self.pressure_work, &mut self.nodal_pressure);
        // 5. Coupling forces.
        let nodal_pressure = &self.nodal_pressure;
        self.chunks
            .par_iter_mut()
            .for_each(|chunk| chunk.pressure_forces(kernel, averaging, nodal_pressure));
        // 6. Gather.
        for chunk in &self.chunks {
            self.averaging
                .scatter(chunk.elements.start, &chunk.forces, force);
        }
        Ok(())
    }

    /// Stable step L₀ √(ρ₀/M) of each element with its index, `density[e]` the density of
    /// element e (the plain tet4 bound, see `element/tet4_nodal_average.rs`).
    pub fn element_stable_steps<'s>(
        &'s self,
        density: &'s [f64],
    ) -> impl Iterator<Item = (f64, usize)> + 's {
        self.chunks.iter().flat_map(move |chunk| {
            chunk
                .elements
                .clone()
                .zip(chunk.reference_length.iter().zip(&chunk.wave_modulus))
                .map(move |(element, (length, modulus))| {
                    (length * (density[element] / modulus).sqrt(), element)
                })
        })
    }

    /// Acoustic modulus M of each element at the last refresh [Pa], in element order.
    pub fn wave_moduli(&self) -> impl Iterator<Item = f64> + '_ {
        self.chunks
            .iter()
            .flat_map(|chunk| chunk.wave_modulus.iter().copied())
    }

    /// Accept the step: the new states and deformations become the old ones.
    pub fn commit(&mut self) {
        for chunk in &mut self.chunks {
            std::mem::swap(&mut chunk.state_old, &mut chunk.state_new);
            std::mem::swap(&mut chunk.f_old, &mut chunk.f_new);
        }
    }

    /// Writes what evolves: per element F, F̄ (accepted and trial), the state variables,
    /// stresses, volumes, pressure work and acoustic moduli; per node J_a and S_a.
    pub fn save_state(&self, out: &mut CheckpointWriter) {
        for chunk in &self.chunks {
            out.matrices(&chunk.deformation);
            out.matrices(&chunk.f_old);
            out.matrices(&chunk.f_new);
            out.f64s(&chunk.state_old);
            out.f64s(&chunk.state_new);
            out.matrices(&chunk.stress);
            out.f64s(&chunk.current_volume);
            out.f64s(&chunk.pressure_work);
            out.f64s(&chunk.wave_modulus);
        }
        out.f64s(&self.current_volume);
        out.f64s(&self.pressure_work);
        out.f64s(&self.nodal_jacobian);
        out.f64s(&self.nodal_pressure);
    }

    /// Reads what [`save_state`](Self::save_state) wrote.
    pub fn restore_state(&mut self, input: &mut CheckpointReader) -> Result<(), SolverError> {
        for chunk in &mut self.chunks {
            input.matrices_into("deformation gradients", &mut chunk.deformation)?;
            input.matrices_into("deformation gradients", &mut chunk.f_old)?;
            input.matrices_into("deformation gradients", &mut chunk.f_new)?;
            input.f64s_into("state variables", &mut chunk.state_old)?;
            input.f64s_into("state variables", &mut chunk.state_new)?;
            input.matrices_into("stresses", &mut chunk.stress)?;
            input.f64s_into("element volumes", &mut chunk.current_volume)?;
            input.f64s_into("pressure work", &mut chunk.pressure_work)?;
            input.f64s_into("acoustic moduli", &mut chunk.wave_modulus)?;
        }
        input.f64s_into("element volumes", &mut self.current_volume)?;
        input.f64s_into("pressure work", &mut self.pressure_work)?;
        input.f64s_into("nodal volume ratios", &mut self.nodal_jacobian)?;
        input.f64s_into("nodal pressures", &mut self.nodal_pressure)
    }

    /// The material points (one per element, at F̄) of the last accepted step, chunk by
    /// chunk, for the output fields.
    pub fn accepted_points(&self) -> Vec<AcceptedPoints<'_>> {
        self.chunks
            .iter()
            .map(|chunk| AcceptedPoints {
                deformation_gradient: &chunk.f_old,
                fiber: &chunk.fiber,
                state: &chunk.state_old,
                first_element: chunk.elements.start,
                points_per_element: 1,
            })
            .collect()
    }
}

impl AveragedChunk {
    fn volumes(&mut self, kernel: &BlockKernel, block: &ElementBlock, positions: &[Vector3<f64>]) {
        for (local, element) in self.elements.clone().enumerate() {
            for (x, &id) in self.positions.iter_mut().zip(block.element_nodes(element)) {
                *x = positions[id as usize];
            }
            let f = kernel.deformation_gradient(element, &self.positions);
            self.deformation[local] = f;
            self.current_volume[local] = kernel.weight(element) * f.determinant();
        }
    }

    fn material_update(
        &mut self,
        kernel: &BlockKernel,
        averaging: &NodalAveraging,
        nodal_jacobian: &[f64],
        material: &dyn Material,
        time: f64,
        dt: f64,
    ) -> Result<(), (usize, MaterialError)> {
        for (local, element) in self.elements.clone().enumerate() {
            let f = &self.deformation[local];
            let jacobian = f.determinant();
            if jacobian.is_nan() || jacobian <= 0.0 {
                return Err((
                    element,
                    MaterialError::InvalidPoint {
                        point: local,
                        reason: format!("det F = {jacobian:e} <= 0: the tet is inverted"),
                    },
                ));
            }
            let averaged = averaging.element_mean(element, nodal_jacobian);
            self.f_new[local] = averaged_deformation_gradient(f, averaged);
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
            tangent: None,
        };
        material.update(&points, &mut response).map_err(|error| {
            let element = match &error {
                MaterialError::InvalidPoint { point, .. }
                | MaterialError::NonFiniteResult { point, .. } => self.elements.start + point,
                _ => self.elements.start,
            };
            (element, error)
        })?;
        self.forces.fill(Vector3::zeros());
        for (local, element) in self.elements.clone().enumerate() {
            let sigma = symmetric_from_voigt(&self.stress[local]);
            let averaged = averaging.element_mean(element, nodal_jacobian);
            add_deviatoric_forces(
                kernel,
                element,
                &self.deformation[local],
                averaged,
                &sigma,
                &mut self.forces[4 * local..4 * local + 4],
            );
            self.pressure_work[local] = pressure_work(kernel, element, &sigma);
        }
        Ok(())
    }

    fn pressure_forces(
        &mut self,
        kernel: &BlockKernel,
        averaging: &NodalAveraging,
        nodal_pressure: &[f64],
    ) {
        for (local, element) in self.elements.clone().enumerate() {
            let pressure = 4.0 * averaging.element_mean(element, nodal_pressure);
            add_pressure_forces(
                kernel,
                element,
                &self.deformation[local],
                pressure,
                &mut self.forces[4 * local..4 * local + 4],
            );
        }
    }

    /// Largest eigenvalue of the acoustic tensor Q_ik = ∂P_iJ/∂F_kL n_J n_L at F̄ over
    /// n = e_x, e_y, e_z, one point at a time (as `ElementChunk::refresh_wave_moduli`).
    fn refresh_wave_moduli(
        &mut self,
        material: &dyn Material,
        time: f64,
        dt: f64,
    ) -> Result<(), (usize, MaterialError)> {
        let nstate = self.scratch_state.len();
        for (local, element) in self.elements.clone().enumerate() {
            self.wave_modulus[local] = point_acoustic_modulus(
                material,
                time,
                dt,
                PointSlices {
                    f_old: &self.f_old[local..local + 1],
                    f_new: &self.f_new[local..local + 1],
                    fiber: &self.fiber[local..local + 1],
                    state_old: &self.state_old[local * nstate..(local + 1) * nstate],
                },
                &mut self.scratch_state,
            )
            .map_err(|error| (element, error))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod locking_tests;
#[cfg(test)]
mod tests;
