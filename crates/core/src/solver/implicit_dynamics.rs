//! Implicit dynamics by Newmark's method with the lumped mass of the explicit solver
//! (ρ₀ V_e of every element shared equally by its nodes).
//!
//! With Δt the step, u, v, a the nodal displacement [m], velocity [m/s] and acceleration
//! [m/s²] at the start of the step, the end-of-step values follow
//! u⁺ = u + Δt v + Δt² [(½ − β) a + β a⁺] and v⁺ = v + Δt [(1 − γ) a + γ a⁺], so
//! a⁺ = (u⁺ − ũ) / (β Δt²) with the predictor ũ = u + Δt v + (½ − β) Δt² a. Equilibrium
//! at the end of the step, M a⁺ + f_int(u⁺) = f_ext, has the tangent K + M / (β Δt²).
//! β = ¼, γ = ½ is the trapezoidal rule (average acceleration): unconditionally stable,
//! second-order, no numerical damping; for it
//! ΔT + ½ (f_int + f_int⁺)·Δu − ½ (f_ext + f_ext⁺)·Δu = 0 holds at every converged step
//! (ΔT the change of the kinetic energy ½ vᵀ M v), which [`EnergyBalance`] tracks.

use nalgebra::Vector3;

use super::{Part, SolverError};
use crate::element::BlockKernel;
use crate::mesh::Mesh;

/// Newmark's parameters (default: the trapezoidal rule β = ¼, γ = ½).
#[derive(Debug, Clone, PartialEq)]
pub struct Newmark {
    pub beta: f64,
    pub gamma: f64,
}

impl Default for Newmark {
    fn default() -> Self {
        Newmark {
            beta: 0.25,
            gamma: 0.5,
        }
    }
}

/// The inertia of the model during a dynamic run.
pub(super) struct Inertia {
    /// Lumped mass of every node [kg].
    pub mass: Vec<f64>,
    /// 1 / (β Δt²) of the current step [1/s²].
    pub coefficient: f64,
    /// Predictor ũ of every node [m].
    pub predicted: Vec<Vector3<f64>>,
    /// Velocity and acceleration at the start of the step.
    pub velocity: Vec<Vector3<f64>>,
    pub acceleration: Vec<Vector3<f64>>,
}

/// Lumped nodal masses [kg]: ρ₀ V_e of every element shared equally by its nodes.
pub(super) fn lumped_mass(mesh: &Mesh, parts: &[Part]) -> Result<Vec<f64>, SolverError> {
    let mut mass = vec![0.0; mesh.nodes.len()];
    for part in parts {
        if !(part.density.is_finite() && part.density > 0.0) {
            return Err(SolverError::InvalidPart {
                block: part.block,
                reason: format!("density {} kg/m3 must be positive", part.density),
            });
        }
        let block = &mesh.blocks[part.block];
        let kernel = BlockKernel::new(&mesh.nodes, block, part.technology).map_err(|source| {
            SolverError::Element {
                block: part.block,
                cause: source,
            }
        })?;
        for (element, ids) in block.elements().enumerate() {
            let share = part.density * kernel.reference_volume(element) / ids.len() as f64;
            for &id in ids {
                mass[id as usize] += share;
            }
        }
    }
    Ok(mass)
}

impl Inertia {
    pub fn new(mass: Vec<f64>) -> Self {
        let n = mass.len();
        Inertia {
            mass,
            coefficient: 0.0,
            predicted: vec![Vector3::zeros(); n],
            velocity: vec![Vector3::zeros(); n],
            acceleration: vec![Vector3::zeros(); n],
        }
    }

    /// Set the predictor and coefficient for a step of `dt` from `displacement`.
    pub fn start_step(&mut self, newmark: &Newmark, displacement: &[Vector3<f64>], dt: f64) {
        self.coefficient = 1.0 / (newmark.beta * dt * dt);
        for (((p, u), v), a) in self
            .predicted
            .iter_mut()
            .zip(displacement)
            .zip(&self.velocity)
            .zip(&self.acceleration)
        {
            *p = u + v * dt + a * ((0.5 - newmark.beta) * dt * dt);
        }
    }

    /// The inertial force M a⁺ of `node` at displacement `u` [N].
    pub fn force(&self, node: usize, u: &Vector3<f64>) -> Vector3<f64> {
        (u - self.predicted[node]) * (self.mass[node] * self.coefficient)
    }

    /// Accept the converged `displacement` of a step of `dt`: new velocity and
    /// acceleration.
    pub fn commit(&mut self, newmark: &Newmark, displacement: &[Vector3<f64>], dt: f64) {
        for (((u, p), v), a) in displacement
            .iter()
            .zip(&self.predicted)
            .zip(self.velocity.iter_mut())
            .zip(self.acceleration.iter_mut())
        {
            let next = (u - p) * self.coefficient;
            *v += (*a * (1.0 - newmark.gamma) + next * newmark.gamma) * dt;
            *a = next;
        }
    }

    /// Kinetic energy ½ vᵀ M v [J].
    pub fn kinetic_energy(&self) -> f64 {
        0.5 * self
            .velocity
            .iter()
            .zip(&self.mass)
            .map(|(v, m)| m * v.norm_squared())
            .sum::<f64>()
    }
}

/// Energy bookkeeping of a dynamic run [J]: the work of the internal forces W_int and of
/// the external ones (nodal loads and reactions of the prescribed motions) W_ext, both by
/// the trapezoidal rule over each step, and the kinetic energy T. For the trapezoidal
/// Newmark rule T + W_int − W_ext stays at its initial value (0) to the Newton tolerance.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EnergyBalance {
    pub kinetic: f64,
    pub internal_work: f64,
    pub external_work: f64,
}

impl EnergyBalance {
    /// T + W_int − W_ext [J].
    pub fn total(&self) -> f64 {
        self.kinetic + self.internal_work - self.external_work
    }
}
