//! A run of consecutive elements of one block with everything their update needs, owned,
//! so that chunks update in parallel without sharing and without allocating: deformation
//! gradients, material states, stresses, element forces, and the explicit solver's
//! stable-step data. The implicit solver wraps it to compute element stiffness matrices
//! (`implicit_chunk.rs`), from tangents it asks for when it needs them
//! ([`ElementChunk::tangents_of_last_update`]), so that none are kept for the whole mesh.

use std::ops::Range;

use nalgebra::{Matrix3, Vector3};

use musclefem_materials::{
    Material, MaterialError, PointBlock, PointResponse, Tangent, VoigtStress,
};

use super::SolverError;
use super::checkpoint::{CheckpointReader, CheckpointWriter};
use super::element_fields::AcceptedPoints;
use crate::element::BlockKernel;
use crate::mesh::{ElementBlock, MAX_NODES_PER_ELEMENT};

/// Elements per chunk: 64 hex8 = 512 material points per material call.
pub(crate) const ELEMENTS_PER_CHUNK: usize = 64;

/// The element ranges of a block of `elements` elements, [`ELEMENTS_PER_CHUNK`] each.
pub(crate) fn chunk_ranges(elements: usize) -> impl Iterator<Item = Range<usize>> {
    (0..elements)
        .step_by(ELEMENTS_PER_CHUNK)
        .map(move |start| start..(start + ELEMENTS_PER_CHUNK).min(elements))
}

/// Room for the stresses and states a repeated material update writes
/// ([`ElementChunk::tangents_of_last_update`]).
#[derive(Debug, Default)]
pub(crate) struct PointScratch {
    stress: Vec<VoigtStress>,
    state: Vec<f64>,
}

#[derive(Debug)]
pub(crate) struct ElementChunk {
    /// Elements of the block in this chunk.
    pub elements: Range<usize>,
    f_old: Vec<Matrix3<f64>>,
    f_new: Vec<Matrix3<f64>>,
    fiber: Vec<Vector3<f64>>,
    state_old: Vec<f64>,
    state_new: Vec<f64>,
    stress: Vec<VoigtStress>,
    /// End time and length [s] of the step of the last update.
    last_step: (f64, f64),
    /// Internal nodal forces, `nodes_per_element` per element [N].
    pub forces: Vec<Vector3<f64>>,
    /// Reference characteristic length of each element for the stable step [m]
    /// ([`characteristic_length`]).
    reference_length: Vec<f64>,
    /// Largest acoustic modulus of each element at its first integration point, from the
    /// material tangent, refreshed by `refresh_wave_moduli` [Pa].
    wave_modulus: Vec<f64>,
    /// Current volume v of each element at the last update [m³] and its gradient
    /// ∂v/∂x_a, `nodes_per_element` per element [m²], kept for the explicit solver's
    /// viscosities ([`Self::keep_volume_gradients`]; empty otherwise).
    volume: Vec<f64>,
    volume_gradient: Vec<Vector3<f64>>,
    positions: Vec<Vector3<f64>>,
}

impl ElementChunk {
    pub fn new(
        elements: Range<usize>,
        kernel: &BlockKernel,
        block: &ElementBlock,
        material: &dyn Material,
    ) -> Self {
        let points = elements.len() * kernel.points_per_element();
        let fiber = elements
            .clone()
            .flat_map(|e| {
                std::iter::repeat_n(block.fiber_direction[e], kernel.points_per_element())
            })
            .collect();
        let npe = kernel.nodes_per_element();
        let reference_length = elements
            .clone()
            .map(|e| characteristic_length(kernel, e))
            .collect();
        ElementChunk {
            f_old: vec![Matrix3::identity(); points],
            f_new: vec![Matrix3::identity(); points],
            fiber,
            state_old: material.initial_state(points),
            state_new: material.initial_state(points),
            stress: vec![VoigtStress::zeros(); points],
            last_step: (0.0, 0.0),
            forces: vec![Vector3::zeros(); elements.len() * npe],
            reference_length,
            wave_modulus: vec![0.0; elements.len()],
            volume: Vec::new(),
            volume_gradient: Vec::new(),
            positions: vec![Vector3::zeros(); npe],
            elements,
        }
    }

    /// Deformation gradients at the current `positions`, the material update over the
    /// step of `dt` ending at `time`, and the internal nodal forces. On a material error,
    /// returns the element (of the block) and the error.
    pub fn update(
        &mut self,
        kernel: &BlockKernel,
        block: &ElementBlock,
        material: &dyn Material,
        positions: &[Vector3<f64>],
        time: f64,
        dt: f64,
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
        self.last_step = (time, dt);
        // The stresses and states are moved out while the points' inputs are borrowed.
        let (mut stress, mut state_new) = (
            std::mem::take(&mut self.stress),
            std::mem::take(&mut self.state_new),
        );
        let updated = material.update(
            &self.points_of_last_update(),
            &mut PointResponse {
                cauchy_stress: &mut stress,
                state_new: &mut state_new,
                tangent: None,
            },
        );
        (self.stress, self.state_new) = (stress, state_new);
        updated.map_err(|error| self.element_of(ppe, error))?;
        self.forces.fill(Vector3::zeros());
        let keep_volumes = !self.volume.is_empty();
        for (local, element) in self.elements.clone().enumerate() {
            gather(&mut self.positions, block.element_nodes(element), positions);
            let points = local * ppe..(local + 1) * ppe;
            let nodes = local * npe..(local + 1) * npe;
            let volume = kernel.add_element_forces(
                element,
                &self.positions,
                &self.f_new[points.clone()],
                &self.stress[points],
                &mut self.forces[nodes.clone()],
                keep_volumes.then(|| &mut self.volume_gradient[nodes]),
            );
            if let Some(volume) = volume {
                self.volume[local] = volume;
            }
        }
        Ok(())
    }

    /// End time [s] of the step of the last update.
    pub fn last_time(&self) -> f64 {
        self.last_step.0
    }

    /// The material points' inputs of the last update: its deformation gradients, the
    /// state at the start of its step, and its step's end time and length.
    fn points_of_last_update(&self) -> PointBlock<'_> {
        let (time, dt) = self.last_step;
        PointBlock {
            time,
            dt,
            deformation_gradient_old: &self.f_old,
            deformation_gradient_new: &self.f_new,
            fiber_direction: &self.fiber,
            state_old: &self.state_old,
        }
    }

    /// The block element of a material error of this chunk's points, with the error.
    fn element_of(
        &self,
        points_per_element: usize,
        error: MaterialError,
    ) -> (usize, MaterialError) {
        let element = match &error {
            MaterialError::InvalidPoint { point, .. }
            | MaterialError::NonFiniteResult { point, .. } => {
                self.elements.start + point / points_per_element
            }
            _ => self.elements.start,
        };
        (element, error)
    }

    /// The consistent tangents ∂P/∂F of the last update's points into `tangents` (one per
    /// point): the material update of [`Self::update`] is repeated from the same inputs
    /// (deformation gradients, state at the start of the step, time and step), so the
    /// tangents are those that update would have computed, bit for bit; the stresses and
    /// states it writes again go to `scratch` (resized as needed) and are dropped.
    pub fn tangents_of_last_update(
        &self,
        material: &dyn Material,
        points_per_element: usize,
        scratch: &mut PointScratch,
        tangents: &mut [Tangent],
    ) -> Result<(), (usize, MaterialError)> {
        scratch
            .stress
            .resize(self.stress.len(), VoigtStress::zeros());
        scratch.state.resize(self.state_new.len(), 0.0);
        let mut response = PointResponse {
            cauchy_stress: &mut scratch.stress,
            state_new: &mut scratch.state,
            tangent: Some(tangents),
        };
        material
            .update(&self.points_of_last_update(), &mut response)
            .map_err(|error| self.element_of(points_per_element, error))
    }

    /// From now on, every update also keeps each element's current volume and its
    /// gradient ([`Self::volumes`], [`Self::volume_gradients`]), which the element forces
    /// of the F-bar kernels compute anyway: the explicit solver's viscosities act through
    /// them.
    pub fn keep_volume_gradients(&mut self, nodes_per_element: usize) {
        self.volume = vec![0.0; self.elements.len()];
        self.volume_gradient = vec![Vector3::zeros(); self.elements.len() * nodes_per_element];
    }

    /// Current volume of each element at the last update [m³] (empty unless
    /// [`Self::keep_volume_gradients`]).
    pub fn volumes(&self) -> &[f64] {
        &self.volume
    }

    /// ∂v/∂x_a of each element at the last update, `nodes_per_element` per element [m²]
    /// (empty unless [`Self::keep_volume_gradients`]).
    pub fn volume_gradients(&self) -> &[Vector3<f64>] {
        &self.volume_gradient
    }

    /// Refresh each element's acoustic modulus from the material tangent ∂P/∂F at its
    /// first integration point after the last `update` (one point at a time: no storage
    /// for tangents). For a direction n the acoustic tensor is Q_ik = ∂P_iJ/∂F_kL n_J n_L;
    /// the modulus is the largest eigenvalue of Q over n = e_x, e_y, e_z.
    pub fn refresh_wave_moduli(
        &mut self,
        kernel: &BlockKernel,
        material: &dyn Material,
        time: f64,
        dt: f64,
    ) -> Result<(), (usize, MaterialError)> {
        let ppe = kernel.points_per_element();
        let nstate = material.state_count();
        let mut scratch_state = vec![0.0; nstate];
        for (local, element) in self.elements.clone().enumerate() {
            let point = local * ppe;
            self.wave_modulus[local] = point_acoustic_modulus(
                material,
                time,
                dt,
                PointSlices {
                    f_old: &self.f_old[point..point + 1],
                    f_new: &self.f_new[point..point + 1],
                    fiber: &self.fiber[point..point + 1],
                    state_old: &self.state_old[point * nstate..(point + 1) * nstate],
                },
                &mut scratch_state,
            )
            .map_err(|error| (element, error))?;
        }
        Ok(())
    }

    /// Stable step L₀ √(ρ₀ / M) of each element of the chunk with its element index
    /// (total Lagrangian: reference length and density, current acoustic modulus), with
    /// `density[e]` the density of element e of the block.
    pub fn element_stable_steps<'s>(
        &'s self,
        density: &'s [f64],
    ) -> impl Iterator<Item = (f64, usize)> + 's {
        self.elements
            .clone()
            .zip(self.reference_length.iter().zip(&self.wave_modulus))
            .map(|(element, (length, modulus))| {
                (length * (density[element] / modulus).sqrt(), element)
            })
    }

    /// Reference characteristic length L₀ of each element of the chunk [m].
    pub fn reference_lengths(&self) -> &[f64] {
        &self.reference_length
    }

    /// Acoustic modulus M of each element of the chunk at the last refresh [Pa].
    pub fn wave_moduli(&self) -> &[f64] {
        &self.wave_modulus
    }

    /// Cauchy stresses of the last update, `points_per_element` per element [Pa].
    pub fn stresses(&self) -> &[VoigtStress] {
        &self.stress
    }

    /// The deformation gradients of the last update, as the material saw them (F̄ for
    /// F-bar), `points_per_element` per element.
    pub fn deformation_gradients(&self) -> &[Matrix3<f64>] {
        &self.f_new
    }

    /// Accept the step: the new state and deformation become the old ones.
    pub fn commit(&mut self) {
        std::mem::swap(&mut self.state_old, &mut self.state_new);
        std::mem::swap(&mut self.f_old, &mut self.f_new);
    }

    /// Writes what evolves: F and the state variables (accepted and trial), the stresses
    /// and the acoustic moduli of the last refresh (the tangents and forces are
    /// recomputed before they are read).
    pub fn save_state(&self, out: &mut CheckpointWriter) {
        out.matrices(&self.f_old);
        out.matrices(&self.f_new);
        out.f64s(&self.state_old);
        out.f64s(&self.state_new);
        out.matrices(&self.stress);
        out.f64s(&self.wave_modulus);
    }

    /// Reads what [`save_state`](Self::save_state) wrote.
    pub fn restore_state(&mut self, input: &mut CheckpointReader) -> Result<(), SolverError> {
        input.matrices_into("deformation gradients", &mut self.f_old)?;
        input.matrices_into("deformation gradients", &mut self.f_new)?;
        input.f64s_into("state variables", &mut self.state_old)?;
        input.f64s_into("state variables", &mut self.state_new)?;
        input.matrices_into("stresses", &mut self.stress)?;
        input.f64s_into("acoustic moduli", &mut self.wave_modulus)
    }

    /// The material points of the last accepted step, for the output fields.
    pub fn accepted_points(&self) -> AcceptedPoints<'_> {
        AcceptedPoints {
            deformation_gradient: &self.f_old,
            fiber: &self.fiber,
            state: &self.state_old,
            first_element: self.elements.start,
            points_per_element: self.f_old.len() / self.elements.len().max(1),
        }
    }
}

/// One material point's inputs: deformation gradients at the start and end of the step,
/// fiber direction and state at the start (one-element slices).
pub(crate) struct PointSlices<'a> {
    pub f_old: &'a [Matrix3<f64>],
    pub f_new: &'a [Matrix3<f64>],
    pub fiber: &'a [Vector3<f64>],
    pub state_old: &'a [f64],
}

/// The largest acoustic modulus [Pa] of one material point over the step of `dt` ending at
/// `time` ([`largest_acoustic_modulus`] of its tangent); the point's new state goes to
/// `scratch_state` and is not kept.
pub(crate) fn point_acoustic_modulus(
    material: &dyn Material,
    time: f64,
    dt: f64,
    point: PointSlices,
    scratch_state: &mut [f64],
) -> Result<f64, MaterialError> {
    let mut stress = [VoigtStress::zeros()];
    let mut tangent = [Tangent::zeros()];
    let block = PointBlock {
        time,
        dt,
        deformation_gradient_old: point.f_old,
        deformation_gradient_new: point.f_new,
        fiber_direction: point.fiber,
        state_old: point.state_old,
    };
    let mut response = PointResponse {
        cauchy_stress: &mut stress,
        state_new: scratch_state,
        tangent: Some(&mut tangent),
    };
    material.update(&block, &mut response)?;
    Ok(largest_acoustic_modulus(&tangent[0]))
}

/// The largest acoustic modulus [Pa] of a material point with tangent ∂P/∂F: the largest
/// eigenvalue of the acoustic tensor Q_ik = ∂P_iJ/∂F_kL n_J n_L over n = e_x, e_y, e_z
/// (tangent entry (i + 3J, k + 3L), column-major F).
pub(crate) fn largest_acoustic_modulus(tangent: &Tangent) -> f64 {
    (0..3)
        .map(|j| {
            let acoustic = Matrix3::from_fn(|i, k| tangent[(i + 3 * j, k + 3 * j)]);
            largest_symmetric_eigenvalue(&acoustic)
        })
        .fold(0.0, f64::max)
}

/// Largest eigenvalue of the symmetric part of a 3×3 matrix, in closed form (Smith 1961):
/// with q = tr A/3, p² = |A − qI|²/6 and B = (A − qI)/p, λ_max = q + 2p cos(φ),
/// φ = acos(det B / 2)/3. Relative error ~1e-15 of the spread of the eigenvalues; several
/// times faster than the iterative symmetric eigen-solver.
pub(crate) fn largest_symmetric_eigenvalue(a: &Matrix3<f64>) -> f64 {
    let a = (a + a.transpose()) * 0.5;
    let q = a.trace() / 3.0;
    let shifted = a - Matrix3::from_diagonal_element(q);
    let p = (shifted.norm_squared() / 6.0).sqrt();
    if p <= f64::EPSILON * q.abs() || p == 0.0 {
        return q;
    }
    let half_det = (shifted / p).determinant() / 2.0;
    let phi = half_det.clamp(-1.0, 1.0).acos() / 3.0;
    q + 2.0 * p * phi.cos()
}

/// The element's node positions out of all nodes' `positions`.
#[inline]
fn gather(out: &mut [Vector3<f64>], ids: &[u32], positions: &[Vector3<f64>]) {
    for (x, &id) in out.iter_mut().zip(ids) {
        *x = positions[id as usize];
    }
}

/// Characteristic length of an element for the central-difference stability limit [m]:
/// with lumped masses ρV/n on its n nodes and b_a = (1/V) Σ_q w_q ∇_X N_a(q) the mean
/// gradients, the largest eigenfrequency is bounded by ω² ≤ n (M/ρ) Σ_a b_a·b_a
/// (Flanagan & Belytschko 1981), so Δt = 2/ω ≥ L/c with L = 2/√(n Σ_a b_a·b_a).
/// A cube of side h gives h/√3, the exact limit of its one-point hexahedron (volume over
/// largest face area, h, is not conservative for the hourglass-like modes).
pub(crate) fn characteristic_length(kernel: &BlockKernel, element: usize) -> f64 {
    let ppe = kernel.points_per_element();
    let npe = kernel.nodes_per_element();
    let mut mean = [Vector3::zeros(); MAX_NODES_PER_ELEMENT];
    let mut volume = 0.0;
    for q in 0..ppe {
        let point = element * ppe + q;
        let w = kernel.weight(point);
        for (b, g) in mean.iter_mut().zip(kernel.gradients(point)) {
            *b += g * w;
        }
        volume += w;
    }
    let sum: f64 = mean[..npe].iter().map(|b| b.norm_squared()).sum::<f64>() / (volume * volume);
    2.0 / (npe as f64 * sum).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed form agrees with the iterative solver on random, repeated-eigenvalue,
    /// diagonal and scalar matrices.
    #[test]
    fn largest_eigenvalue_in_closed_form() {
        let mut seed = 12345u64;
        let mut random = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let rotation = nalgebra::Rotation3::from_euler_angles(0.3, -1.1, 2.0).into_inner();
        let mut cases: Vec<Matrix3<f64>> = (0..200)
            .map(|_| {
                let m = Matrix3::from_fn(|_, _| random()) * 1e6;
                m + m.transpose()
            })
            .collect();
        cases.push(Matrix3::from_diagonal(&Vector3::new(3e9, 1e4, 1e4)));
        cases.push(
            rotation * Matrix3::from_diagonal(&Vector3::new(1e4, 1e4, 3e9)) * rotation.transpose(),
        );
        cases.push(
            rotation * Matrix3::from_diagonal(&Vector3::new(2e4, 2e4, 1e4)) * rotation.transpose(),
        );
        cases.push(Matrix3::from_diagonal_element(7.0));
        for m in cases {
            let expected = m.symmetric_eigenvalues().max();
            let spread = m.symmetric_eigenvalues().amax();
            let got = largest_symmetric_eigenvalue(&m);
            assert!(
                (got - expected).abs() <= 1e-12 * spread,
                "{got} vs {expected} for {m}"
            );
        }
    }
}
