//! A chunk of one-point hex8 elements for the explicit solver: the batched kernel of
//! `element/hex8_one_point_batch.rs` with the material called once on the whole chunk.
//! The built-in neo-Hookean is called directly (`NeoHookean::accepted_block_stresses`:
//! the same stresses and errors without the generic block checks it does not need);
//! every other material through `<dyn Material>::update`.
//!
//! What an element keeps between steps (neo-Hookean, no state variables): its reference
//! data in the batch (B̄_1…7, V, k, H^α: 280 bytes) and F at the start and end of the
//! step (2 × 72 bytes), 424 bytes, plus 16 bytes per material state variable; its 8 nodal
//! forces (192 bytes) are held by the part for the node assembly. Stresses, hourglass
//! displacements and the F of the batches live on the stack during the update. The fiber
//! direction is the mesh block's (one point per element), not a copy.

use std::ops::Range;

use nalgebra::{Matrix3, Vector3};

use musclefem_materials::{
    Material, MaterialError, PointBlock, PointResponse, Tangent, VoigtStress,
};

use super::SolverError;
use super::checkpoint::{CheckpointReader, CheckpointWriter};
use super::chunk::{ELEMENTS_PER_CHUNK, largest_acoustic_modulus};
use super::element_fields::AcceptedPoints;
use crate::element::ElementError;
use crate::element::hex8_one_point::{OnePointReference, check_hourglass_modulus};
use crate::element::hex8_one_point_batch::{
    BatchDeformation, LANES, OnePointBatch, RelativePositions, lane_matrix,
};
use crate::mesh::{ElementBlock, Nodes};

/// Batches per chunk.
const BATCHES: usize = ELEMENTS_PER_CHUNK / LANES;
/// Points per material call with tangents (stable-step refresh): the tangents of a call
/// live on the stack (648 bytes each).
const TANGENT_POINTS: usize = 16;

#[derive(Debug)]
pub(crate) struct OnePointHexChunk {
    /// Elements of the block in this chunk.
    pub elements: Range<usize>,
    batches: Vec<OnePointBatch>,
    f_old: Vec<Matrix3<f64>>,
    f_new: Vec<Matrix3<f64>>,
    state_old: Vec<f64>,
    state_new: Vec<f64>,
    /// Largest acoustic modulus M of each element at the last refresh [Pa].
    wave_modulus: Vec<f64>,
}

impl OnePointHexChunk {
    /// Reference data of `elements` of `block` (reference positions `nodes`). Refuses an
    /// element inverted at a Gauss point and a negative or non-finite hourglass modulus.
    pub fn new(
        elements: Range<usize>,
        nodes: &Nodes,
        block: &ElementBlock,
        hourglass_modulus: f64,
        material: &dyn Material,
    ) -> Result<Self, ElementError> {
        check_hourglass_modulus(block, hourglass_modulus)?;
        let mut batches = Vec::with_capacity(elements.len().div_ceil(LANES));
        let mut references = Vec::with_capacity(LANES);
        let mut coords = [Vector3::zeros(); 8];
        for start in elements.clone().step_by(LANES) {
            references.clear();
            for element in start..(start + LANES).min(elements.end) {
                nodes.gather(block.element_nodes(element), &mut coords);
                let reference = OnePointReference::new(&coords).map_err(|(point, det_j)| {
                    ElementError::InvertedReference {
                        block: block.name.clone(),
                        element,
                        point,
                        det_j,
                    }
                })?;
                references.push(reference);
            }
            batches.push(OnePointBatch::new(&references, hourglass_modulus));
        }
        let points = elements.len();
        Ok(OnePointHexChunk {
            batches,
            f_old: vec![Matrix3::identity(); points],
            f_new: vec![Matrix3::identity(); points],
            state_old: material.initial_state(points),
            state_new: material.initial_state(points),
            wave_modulus: vec![0.0; points],
            elements,
        })
    }

    /// Reference volume of each element [m³], in order.
    pub fn volumes(&self) -> impl Iterator<Item = f64> + '_ {
        (0..self.elements.len()).map(|e| self.batches[e / LANES].volume(e % LANES))
    }

    /// F at the current `positions`, the material update over the step of `dt` ending at
    /// `time`, and the internal nodal forces into `forces` (8 per element) [N]. With
    /// `refresh`, the acoustic moduli M are refreshed from the material tangents of this
    /// update.
    /// On a material error, returns the element (of the block) and the error.
    pub fn update(
        &mut self,
        block: &ElementBlock,
        material: &dyn Material,
        positions: &[Vector3<f64>],
        time: f64,
        dt: f64,
        refresh: bool,
        forces: &mut [Vector3<f64>],
    ) -> Result<(), (usize, MaterialError)> {
        let count = self.elements.len();
        let mut deformations = [BatchDeformation::default(); BATCHES];
        #[cfg(target_arch = "x86_64")]
        let avx2 = std::is_x86_feature_detected!("avx2");
        #[cfg(not(target_arch = "x86_64"))]
        let avx2 = false;
        if avx2 {
            // SAFETY: the processor has AVX2 (checked above).
            unsafe { self.kinematics_avx2(block, positions, &mut deformations) };
        } else {
            self.kinematics(block, positions, &mut deformations);
        }
        let mut stress = [VoigtStress::zeros(); ELEMENTS_PER_CHUNK];
        let on_error = |offset| located_error(self.elements.start + offset);
        if let Some(neo_hookean) = material.as_neo_hookean() {
            // The fused path: the stresses and errors of `update` with fewer checks (see
            // `NeoHookean::accepted_block_stresses`).
            if refresh {
                let f_new = &self.f_new;
                refresh_in_groups(
                    &mut stress[..count],
                    &mut self.wave_modulus,
                    |points, stress, tangent| {
                        neo_hookean
                            .accepted_block_stresses(&f_new[points.clone()], stress, Some(tangent))
                            .map_err(on_error(points.start))
                    },
                )?;
            } else {
                neo_hookean
                    .accepted_block_stresses(&self.f_new, &mut stress[..count], None)
                    .map_err(on_error(0))?;
            }
        } else {
            let fiber = &block.fiber_direction[self.elements.clone()];
            self.material_update(material, time, dt, refresh, fiber, &mut stress[..count])?;
        }
        if avx2 {
            // SAFETY: as above.
            unsafe { self.nodal_forces_avx2(&deformations, &stress[..count], forces) };
        } else {
            self.nodal_forces(&deformations, &stress[..count], forces);
        }
        Ok(())
    }

    /// The Cauchy `stress` of every element through `<dyn Material>::update` at the
    /// step's F (`f_new`), and with `refresh` the acoustic moduli from its tangents.
    fn material_update(
        &mut self,
        material: &dyn Material,
        time: f64,
        dt: f64,
        refresh: bool,
        fiber: &[Vector3<f64>],
        stress: &mut [VoigtStress],
    ) -> Result<(), (usize, MaterialError)> {
        let count = self.elements.len();
        let nstate = self.state_old.len() / count.max(1);
        let on_error = |offset| located_error(self.elements.start + offset);
        if !refresh {
            let points = PointBlock {
                time,
                dt,
                deformation_gradient_old: &self.f_old,
                deformation_gradient_new: &self.f_new,
                fiber_direction: fiber,
                state_old: &self.state_old,
            };
            let mut response = PointResponse {
                cauchy_stress: stress,
                state_new: &mut self.state_new,
                tangent: None,
            };
            return material.update(&points, &mut response).map_err(on_error(0));
        }
        let (f_old, f_new) = (&self.f_old, &self.f_new);
        let (state_old, state_new) = (&self.state_old, &mut self.state_new);
        refresh_in_groups(stress, &mut self.wave_modulus, |points, stress, tangent| {
            let states = points.start * nstate..points.end * nstate;
            let block = PointBlock {
                time,
                dt,
                deformation_gradient_old: &f_old[points.clone()],
                deformation_gradient_new: &f_new[points.clone()],
                fiber_direction: &fiber[points.clone()],
                state_old: &state_old[states.clone()],
            };
            let mut response = PointResponse {
                cauchy_stress: stress,
                state_new: &mut state_new[states],
                tangent: Some(tangent),
            };
            material
                .update(&block, &mut response)
                .map_err(on_error(points.start))
        })
    }

    /// [`Self::kinematics`] compiled for 256-bit vectors. Rust does not contract a·b + c
    /// into fused multiply-adds, so it gives the bits of the baseline (SSE2) version.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn kinematics_avx2(
        &mut self,
        block: &ElementBlock,
        positions: &[Vector3<f64>],
        deformations: &mut [BatchDeformation; BATCHES],
    ) {
        self.kinematics(block, positions, deformations)
    }

    /// [`Self::nodal_forces`] compiled for 256-bit vectors (same bits).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn nodal_forces_avx2(
        &self,
        deformations: &[BatchDeformation; BATCHES],
        stress: &[VoigtStress],
        forces: &mut [Vector3<f64>],
    ) {
        self.nodal_forces(deformations, stress, forces)
    }

    /// F and q^α of every batch at the current `positions`; F into `f_new`.
    #[inline(always)]
    fn kinematics(
        &mut self,
        block: &ElementBlock,
        positions: &[Vector3<f64>],
        deformations: &mut [BatchDeformation; BATCHES],
    ) {
        for (b, (batch, deformation)) in self.batches.iter().zip(deformations).enumerate() {
            let first = self.elements.start + b * LANES;
            let lanes = LANES.min(self.elements.end - first);
            let relative = relative_positions(block, positions, first, lanes);
            *deformation = batch.deformation(&relative);
            for l in 0..lanes {
                self.f_new[b * LANES + l] = lane_matrix(&deformation.deformation_gradient, l);
            }
        }
    }

    /// The nodal forces of every element from its deformation and Cauchy `stress`.
    #[inline(always)]
    fn nodal_forces(
        &self,
        deformations: &[BatchDeformation; BATCHES],
        stress: &[VoigtStress],
        forces: &mut [Vector3<f64>],
    ) {
        for (b, (batch, deformation)) in self.batches.iter().zip(deformations).enumerate() {
            let first = b * LANES;
            let lanes = LANES.min(stress.len() - first);
            batch.forces(
                deformation,
                &stress[first..first + lanes],
                &mut forces[first * 8..(first + lanes) * 8],
            );
        }
    }

    /// Stable step L₀ √(ρ/M) of each element [s] with its element (block index), from the
    /// moduli of the last refresh, `density[e]` the density of element e of the block;
    /// L₀ = 2/√(8 Σ_a |B̄_a|²) (chunk.rs, `characteristic_length`).
    pub fn element_stable_steps<'s>(
        &'s self,
        density: &'s [f64],
    ) -> impl Iterator<Item = (f64, usize)> + 's {
        self.wave_modulus
            .iter()
            .enumerate()
            .map(move |(e, modulus)| {
                let sum = self.batches[e / LANES].gradient_sum_squares(e % LANES);
                let length = 2.0 / (8.0 * sum).sqrt();
                let element = self.elements.start + e;
                (length * (density[element] / modulus).sqrt(), element)
            })
    }

    /// Acoustic modulus M of each element of the chunk at the last refresh [Pa].
    pub fn wave_moduli(&self) -> &[f64] {
        &self.wave_modulus
    }

    /// Hourglass energy ½ k Σ_α |q^α|² of the chunk's elements at `positions` [J].
    pub fn hourglass_energy(&self, block: &ElementBlock, positions: &[Vector3<f64>]) -> f64 {
        let mut energy = 0.0;
        for (b, batch) in self.batches.iter().enumerate() {
            let first = self.elements.start + b * LANES;
            let lanes = LANES.min(self.elements.end - first);
            let relative = relative_positions(block, positions, first, lanes);
            let deformation = batch.deformation(&relative);
            energy += (0..lanes)
                .map(|l| batch.hourglass_energy(&deformation, l))
                .sum::<f64>();
        }
        energy
    }

    /// Accept the step: the new state and deformation become the old ones.
    pub fn commit(&mut self) {
        std::mem::swap(&mut self.state_old, &mut self.state_new);
        std::mem::swap(&mut self.f_old, &mut self.f_new);
    }

    /// Writes what evolves: F and the state variables (accepted and trial) and the
    /// acoustic moduli of the last refresh.
    pub fn save_state(&self, out: &mut CheckpointWriter) {
        out.matrices(&self.f_old);
        out.matrices(&self.f_new);
        out.f64s(&self.state_old);
        out.f64s(&self.state_new);
        out.f64s(&self.wave_modulus);
    }

    /// Reads what [`save_state`](Self::save_state) wrote.
    pub fn restore_state(&mut self, input: &mut CheckpointReader) -> Result<(), SolverError> {
        input.matrices_into("deformation gradients", &mut self.f_old)?;
        input.matrices_into("deformation gradients", &mut self.f_new)?;
        input.f64s_into("state variables", &mut self.state_old)?;
        input.f64s_into("state variables", &mut self.state_new)?;
        input.f64s_into("acoustic moduli", &mut self.wave_modulus)
    }

    /// The material points (one per element) of the last accepted step, for the output
    /// fields.
    pub fn accepted_points<'a>(&'a self, block: &'a ElementBlock) -> AcceptedPoints<'a> {
        AcceptedPoints {
            deformation_gradient: &self.f_old,
            fiber: &block.fiber_direction[self.elements.clone()],
            state: &self.state_old,
            first_element: self.elements.start,
            points_per_element: 1,
        }
    }
}

/// The stable-step refresh's material update: `update(points, stress, tangents)` fills
/// the stresses and tangents of the chunk's points, [`TANGENT_POINTS`] at a time (their
/// tangents live on the stack), and each point's acoustic modulus M goes into
/// `wave_modulus`.
fn refresh_in_groups(
    stress: &mut [VoigtStress],
    wave_modulus: &mut [f64],
    mut update: impl FnMut(
        Range<usize>,
        &mut [VoigtStress],
        &mut [Tangent],
    ) -> Result<(), (usize, MaterialError)>,
) -> Result<(), (usize, MaterialError)> {
    let mut tangent = [Tangent::zeros(); TANGENT_POINTS];
    for first in (0..stress.len()).step_by(TANGENT_POINTS) {
        let points = first..(first + TANGENT_POINTS).min(stress.len());
        let n = points.len();
        update(
            points.clone(),
            &mut stress[points.clone()],
            &mut tangent[..n],
        )?;
        for (e, t) in points.zip(&tangent) {
            wave_modulus[e] = largest_acoustic_modulus(t);
        }
    }
    Ok(())
}

/// A material error of the points from element `first` of the block on, as the element
/// (of the block) it names and the error.
fn located_error(first: usize) -> impl Fn(MaterialError) -> (usize, MaterialError) {
    move |error: MaterialError| {
        let element = match &error {
            MaterialError::InvalidPoint { point, .. }
            | MaterialError::NonFiniteResult { point, .. } => first + point,
            _ => first,
        };
        (element, error)
    }
}

/// Positions of nodes 1…7 relative to node 0 of the `lanes` elements of `block` from
/// `first` on (unused lanes zero) [m].
#[inline(always)]
fn relative_positions(
    block: &ElementBlock,
    positions: &[Vector3<f64>],
    first: usize,
    lanes: usize,
) -> RelativePositions {
    let mut relative: RelativePositions = [[[0.0; LANES]; 3]; 7];
    for l in 0..lanes {
        let ids = block.element_nodes(first + l);
        let origin = positions[ids[0] as usize];
        for a in 1..8 {
            let x = positions[ids[a] as usize];
            for i in 0..3 {
                relative[a - 1][i][l] = x[i] - origin[i];
            }
        }
    }
    relative
}
