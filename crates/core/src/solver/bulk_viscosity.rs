//! Linear and quadratic bulk viscosity of the explicit solver (the artificial viscosity of
//! von Neumann–Richtmyer and Landshoff, as in Abaqus/Explicit and LS-DYNA): a pressure
//!
//! q = ρ₀ L₀ (−b₁ c ε̇_v + b₂² L₀ ε̇_v² [ε̇_v < 0])   [Pa],
//!
//! with ε̇_v = v̇/v the volumetric strain rate of the element, c = √(M/ρ₀) its dilatational
//! wave speed, L₀ its characteristic length (total Lagrangian: reference length and
//! density). The linear term damps ringing at the highest frequencies; the quadratic one,
//! active in compression only, smears a shock over a few elements. The pressure acts as a
//! Cauchy stress −q I, so its nodal forces are f_a = −q ∂v/∂x_a with
//! ∂v/∂x_a = Σ_p w_p J_p F_p⁻ᵀ ∇_X N_a(p) (v = Σ_p w_p J_p). The power −q v̇ ≥ 0 is
//! dissipated: the solver reports its work as the viscous energy.
//!
//! The linear term lowers the stable step to Δt = (2/ω)(√(1 + b₁²) − b₁); the solver applies
//! that factor. The quadratic term's further reduction in fast compression is not; it is
//! small at the defaults and the energy balance would catch an instability.
//!
//! **Shear viscosity** (a project addition, off by default): a deviatoric Cauchy stress
//!
//! σ_v = 2η dev D̄,  D̄ = sym L̄,  L̄ = (1/v) Σ_a v_a ⊗ ∂v/∂x_a   [Pa],
//!
//! with η [Pa s] and L̄ the element's volume-averaged velocity gradient ((1/v) ∫ ∇v dv, from
//! the half-step velocities of the step just taken). Its nodal forces are f_a = σ_v ∂v/∂x_a
//! and its power Σ_a f_a·v_a = 2η v |dev D̄|² ≥ 0 is dissipated (viscous energy). A rigid
//! motion gives D̄ = 0 and no force. It damps a mode of frequency ω in proportion to
//! ηω/μ: strongly the ringing of single elements, hardly the slow loading of a
//! quasi-static run. It adds (4/3)η/(ρ c L₀) to the damping ratio of an element's highest
//! mode, so the step factor becomes √(1 + ζ²) − ζ with ζ = b₁ + that ratio at its largest
//! (with the densities after mass scaling: a mass-scaled element's ratio is
//! (4/3) η/(Δt M), tiny for a soft tissue's 10⁻⁵ s steps and η of 10³ Pa s).
//!
//! Not available for `Tet4NodalAverage` blocks yet (the solver refuses the combination).

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use super::checkpoint::{CheckpointReader, CheckpointWriter};
use super::chunk::{ELEMENTS_PER_CHUNK, ElementChunk};
use crate::element::BlockKernel;
use crate::mesh::{ElementBlock, MAX_NODES_PER_ELEMENT};

/// Coefficients b₁ (linear) and b₂ (quadratic), dimensionless.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BulkViscosity {
    pub linear: f64,
    pub quadratic: f64,
}

impl Default for BulkViscosity {
    /// b₁ = 0.06, b₂ = 1.2 (the Abaqus/Explicit defaults).
    fn default() -> Self {
        BulkViscosity {
            linear: 0.06,
            quadratic: 1.2,
        }
    }
}

impl BulkViscosity {
    /// Factor on the stable step from the linear term: √(1 + b₁²) − b₁.
    pub fn stable_step_factor(&self) -> f64 {
        damped_step_factor(self.linear)
    }
}

/// Factor on the undamped stable step 2/ω of central differences with a damping ratio ζ
/// at the highest frequency: √(1 + ζ²) − ζ.
pub fn damped_step_factor(damping_ratio: f64) -> f64 {
    (1.0 + damping_ratio * damping_ratio).sqrt() - damping_ratio
}

/// The artificial viscosities of one run: bulk (b₁, b₂) and shear η [Pa s].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Viscosities {
    pub bulk: Option<BulkViscosity>,
    /// η [Pa s], 0 for none.
    pub shear: f64,
}

/// One element chunk's new volumes [m³] and viscous element forces [N].
pub(super) type ChunkSlices<'a> = (&'a mut [f64], &'a mut [Vector3<f64>]);

/// Per-element state of one block: current volumes at the last two steps and the viscous
/// element forces of the last evaluation.
pub(super) struct ViscousBlock {
    volume_old: Vec<f64>,
    volume_new: Vec<f64>,
    /// `nodes_per_element` forces per element [N].
    forces: Vec<Vector3<f64>>,
}

impl ViscousBlock {
    /// Writes the element volumes of the last two evaluations.
    pub fn save_state(&self, out: &mut CheckpointWriter) {
        out.f64s(&self.volume_old);
        out.f64s(&self.volume_new);
    }

    /// Reads what [`save_state`](Self::save_state) wrote.
    pub fn restore_state(
        &mut self,
        input: &mut CheckpointReader,
    ) -> Result<(), super::SolverError> {
        input.f64s_into("element volumes", &mut self.volume_old)?;
        input.f64s_into("element volumes", &mut self.volume_new)
    }

    pub fn new(kernel: &BlockKernel) -> Self {
        let volumes: Vec<f64> = (0..kernel.len())
            .map(|e| kernel.reference_volume(e))
            .collect();
        ViscousBlock {
            volume_old: volumes.clone(),
            volume_new: volumes,
            forces: vec![Vector3::zeros(); kernel.len() * kernel.nodes_per_element()],
        }
    }

    /// The accepted volumes (block-wide), and this block's new volumes and element
    /// forces cut into the explicit element chunks' ranges, for [`chunk_forces`] in
    /// parallel.
    pub fn chunk_slices(
        &mut self,
        nodes_per_element: usize,
    ) -> (&[f64], impl IndexedParallelIterator<Item = ChunkSlices<'_>>) {
        let volumes = self.volume_new.par_chunks_mut(ELEMENTS_PER_CHUNK);
        let forces = self
            .forces
            .par_chunks_mut(ELEMENTS_PER_CHUNK * nodes_per_element);
        (&self.volume_old, volumes.zip(forces))
    }

    /// Add the element forces of the last evaluation into the nodal `force`, serially in
    /// element order (the same sum on any number of threads).
    pub fn scatter(&self, block: &ElementBlock, force: &mut [Vector3<f64>]) {
        let npe = block.shape.nodes_per_element();
        for (element, ids) in block.elements().enumerate() {
            for (&id, f) in ids
                .iter()
                .zip(&self.forces[element * npe..(element + 1) * npe])
            {
                force[id as usize] += f;
            }
        }
    }

    /// Accept the step: the new volumes become the old ones.
    pub fn commit(&mut self) {
        std::mem::swap(&mut self.volume_old, &mut self.volume_new);
    }
}

/// The viscous element forces of `chunk` after a step of `dt` [s] taken with the nodal
/// `velocities` [m/s], from the current volumes and volume gradients of its last update
/// ([`ElementChunk::keep_volume_gradients`]), its reference lengths and acoustic moduli,
/// `density[e]` the (possibly mass-scaled) density of element e of the block [kg/m³]
/// and `volume_old` the block's accepted volumes; into the chunk's `volume_new` and
/// `forces` (`nodes_per_element` per element).
#[allow(clippy::too_many_arguments)]
pub(super) fn chunk_forces(
    viscosities: &Viscosities,
    chunk: &ElementChunk,
    block: &ElementBlock,
    density: &[f64],
    velocities: &[Vector3<f64>],
    dt: f64,
    volume_old: &[f64],
    (volume_new, forces): ChunkSlices<'_>,
) {
    let npe = block.shape.nodes_per_element();
    let mut local_velocity = [Vector3::zeros(); MAX_NODES_PER_ELEMENT];
    let (lengths, moduli) = (chunk.reference_lengths(), chunk.wave_moduli());
    let gradients = chunk.volume_gradients();
    for (i, (element, &volume)) in chunk.elements.clone().zip(chunk.volumes()).enumerate() {
        let gradient = &gradients[i * npe..(i + 1) * npe];
        for (v, &id) in local_velocity.iter_mut().zip(block.element_nodes(element)) {
            *v = velocities[id as usize];
        }
        volume_new[i] = volume;
        // Cauchy stress of the viscosities: −q I + σ_v.
        let mut stress = Matrix3::zeros();
        if let Some(bulk) = &viscosities.bulk {
            let old = volume_old[element];
            let rate = (volume - old) / (0.5 * (volume + old) * dt);
            let rho = density[element];
            let length = lengths[i];
            let speed = (moduli[i] / rho).sqrt();
            let mut q = -bulk.linear * rho * speed * length * rate;
            if rate < 0.0 {
                q += rho * (bulk.quadratic * length * rate).powi(2);
            }
            stress -= Matrix3::identity() * q;
        }
        if viscosities.shear > 0.0 && volume > 0.0 {
            stress += shear_stress(viscosities.shear, volume, &local_velocity[..npe], gradient);
        }
        for (f, g) in forces[i * npe..(i + 1) * npe].iter_mut().zip(gradient) {
            *f = stress * g;
        }
    }
}

/// The shear viscosity's Cauchy stress 2η dev D̄ [Pa] of an element of current `volume`
/// whose nodes move at `velocities`, with `gradient` = ∂v/∂x_a (module documentation).
fn shear_stress(
    eta: f64,
    volume: f64,
    velocities: &[Vector3<f64>],
    gradient: &[Vector3<f64>],
) -> Matrix3<f64> {
    let mut velocity_gradient = Matrix3::zeros();
    for (v, g) in velocities.iter().zip(gradient) {
        velocity_gradient += v * g.transpose();
    }
    let rate = (velocity_gradient + velocity_gradient.transpose()) * (0.5 / volume);
    let deviator = rate - Matrix3::identity() * (rate.trace() / 3.0);
    deviator * (2.0 * eta)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::Technology;
    use crate::mesh::generate::{TetOrder, box_of_hexes, box_of_tets, distort};

    /// The first element of a distorted hex8 and a distorted tet10 block, each with its
    /// kernel and its nodes moved by a non-affine deformation.
    fn deformed_elements() -> Vec<(Technology, BlockKernel, Vec<Vector3<f64>>)> {
        [
            (
                box_of_hexes([1.0; 3], [2; 3]).unwrap(),
                Technology::Hex8Full,
            ),
            (
                box_of_tets([1.0; 3], [1; 3], TetOrder::Quadratic).unwrap(),
                Technology::Tet10,
            ),
        ]
        .into_iter()
        .map(|(mut mesh, technology)| {
            distort(&mut mesh, 0.15, 7).unwrap();
            let block = &mesh.blocks[0];
            let kernel = BlockKernel::new(&mesh.nodes, block, technology).unwrap();
            let x = (block.element_nodes(0).iter())
                .map(|&id| mesh.nodes.position(id as usize))
                .map(|p| p + Vector3::new(0.1 * p.y * p.z, -0.05 * p.x * p.x, 0.08 * p.y))
                .collect();
            (technology, kernel, x)
        })
        .collect()
    }

    /// On a distorted, deformed tet10 and hex8: a rigid motion (translation and spin
    /// v = w × x) gives no shear-viscosity stress; a simple shear v = (γ̇ y, 0, 0) plus a
    /// dilatation gives 2η dev D exactly (the velocity field is linear, so its mean
    /// gradient is its gradient), and the nodal forces' power is 2η v |dev D|².
    #[test]
    fn the_shear_viscosity_is_2_eta_dev_d_and_ignores_rigid_motion() {
        let eta = 3.0;
        for (technology, kernel, x) in deformed_elements() {
            let npe = kernel.nodes_per_element();
            let mut gradient = vec![Vector3::zeros(); npe];
            let volume = kernel.volume_and_gradient(0, &x, &mut gradient);
            let spin = Vector3::new(0.3, -1.2, 0.7);
            let rigid: Vec<_> = x
                .iter()
                .map(|p| Vector3::new(0.4, 0.1, -2.0) + spin.cross(p))
                .collect();
            let stress = shear_stress(eta, volume, &rigid, &gradient);
            assert!(stress.amax() < 1e-12, "{technology:?}: {stress}");

            let (shear_rate, dilatation_rate) = (0.8, 0.3);
            let velocity_gradient = Matrix3::new(
                dilatation_rate,
                shear_rate,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
            );
            let moving: Vec<_> = x.iter().map(|p| velocity_gradient * p).collect();
            let stress = shear_stress(eta, volume, &moving, &gradient);
            let rate = (velocity_gradient + velocity_gradient.transpose()) * 0.5;
            let deviator = rate - Matrix3::identity() * (rate.trace() / 3.0);
            let expected = deviator * (2.0 * eta);
            assert!(
                (stress - expected).amax() < 1e-12,
                "{technology:?}: {stress} vs {expected}"
            );
            let power: f64 = (moving.iter())
                .zip(&gradient)
                .map(|(v, g)| (stress * g).dot(v))
                .sum();
            let dissipation = 2.0 * eta * volume * deviator.norm_squared();
            assert!(
                (power - dissipation).abs() < 1e-12 * dissipation,
                "{technology:?}: power {power} vs {dissipation}"
            );
        }
    }

    /// The F-bar kernels hand out v and ∂v/∂x_a with their forces (F⁻ᵀ J rather than the
    /// cofactor): the same to round-off, and the same forces as without them.
    #[test]
    fn the_fbar_forces_carry_the_volume_gradient() {
        for (technology, kernel, x) in deformed_elements() {
            let fbar = match technology {
                Technology::Hex8Full => Technology::Hex8FBar,
                _ => Technology::Tet10FBar,
            };
            // The mesh of `deformed_elements`, again.
            let mut mesh = match technology {
                Technology::Hex8Full => box_of_hexes([1.0; 3], [2; 3]),
                _ => box_of_tets([1.0; 3], [1; 3], TetOrder::Quadratic),
            }
            .unwrap();
            distort(&mut mesh, 0.15, 7).unwrap();
            let kernel_fbar = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], fbar).unwrap();
            let (npe, ppe) = (kernel.nodes_per_element(), kernel.points_per_element());
            let mut expected = vec![Vector3::zeros(); npe];
            let volume = kernel.volume_and_gradient(0, &x, &mut expected);
            let stress =
                vec![musclefem_materials::VoigtStress::new(3.0, -1.0, 2.0, 0.5, -0.7, 0.2); ppe];
            let f = vec![Matrix3::identity(); ppe];
            let (mut forces, mut plain_forces) =
                (vec![Vector3::zeros(); npe], vec![Vector3::zeros(); npe]);
            let mut gradient = vec![Vector3::zeros(); npe];
            let fbar_volume = kernel_fbar
                .add_element_forces(0, &x, &f, &stress, &mut forces, Some(&mut gradient))
                .unwrap();
            let no_volume =
                kernel_fbar.add_element_forces(0, &x, &f, &stress, &mut plain_forces, None);
            assert_eq!(no_volume, None);
            assert_eq!(forces, plain_forces, "{fbar:?}");
            assert!((fbar_volume - volume).abs() < 1e-14 * volume, "{fbar:?}");
            let scale = expected.iter().map(|g| g.norm()).fold(0.0, f64::max);
            for (a, (g, e)) in gradient.iter().zip(&expected).enumerate() {
                assert!(
                    (g - e).norm() < 1e-13 * scale,
                    "{fbar:?} node {a}: {g} vs {e}"
                );
            }
        }
    }

    /// ∂v/∂x_a against central differences of v on distorted, deformed elements.
    #[test]
    fn the_volume_gradient_is_the_derivative_of_the_volume() {
        for (technology, kernel, x) in deformed_elements() {
            let npe = kernel.nodes_per_element();
            let mut gradient = vec![Vector3::zeros(); npe];
            kernel.volume_and_gradient(0, &x, &mut gradient);
            let h = 1e-6;
            let mut scratch = vec![Vector3::zeros(); npe];
            for a in 0..npe {
                for k in 0..3 {
                    let mut plus = x.clone();
                    plus[a][k] += h;
                    let mut minus = x.clone();
                    minus[a][k] -= h;
                    let difference = (kernel.volume_and_gradient(0, &plus, &mut scratch)
                        - kernel.volume_and_gradient(0, &minus, &mut scratch))
                        / (2.0 * h);
                    assert!(
                        (difference - gradient[a][k]).abs() < 1e-8,
                        "{technology:?} node {a} component {k}: {difference} vs {}",
                        gradient[a][k]
                    );
                }
            }
        }
    }
}
