//! The bulk and shear viscosity (`crate::solver::bulk_viscosity`) over all the explicit
//! parts: the damping it adds to the stable step, and its nodal forces.

use nalgebra::Vector3;

use super::{PartElements, PartRun};
use crate::mesh::Mesh;

/// Smallest L₀ √(ρ M) over the elements with viscous forces [Pa s]: the shear viscosity
/// η adds (4/3) η / (L₀ √(ρ M)) to the damping ratio of an element's highest mode.
pub(in crate::solver) fn smallest_impedance_length(runs: &[PartRun]) -> f64 {
    let mut smallest = f64::INFINITY;
    for run in runs {
        if let (Some(_), PartElements::General { chunks, .. }) = (&run.viscous, &run.elements) {
            for chunk in chunks {
                for (element, (length, modulus)) in (chunk.elements.clone())
                    .zip(chunk.reference_lengths().iter().zip(chunk.wave_moduli()))
                {
                    let rho = run.element_density[element];
                    smallest = smallest.min(length * (rho * modulus).sqrt());
                }
            }
        }
    }
    smallest
}

/// The bulk- and shear-viscosity forces of the last [`internal_forces`] (which evaluates
/// them with the element forces when given the viscosities and the velocities) into
/// `viscous_force`, gathered serially in element order; volumes committed.
pub(in crate::solver) fn viscous_forces(
    mesh: &Mesh,
    runs: &mut [PartRun],
    viscous_force: &mut [Vector3<f64>],
) {
    viscous_force.fill(Vector3::zeros());
    for run in runs.iter_mut() {
        if let Some(viscous) = &mut run.viscous {
            viscous.scatter(&mesh.blocks[run.block], viscous_force);
            viscous.commit();
        }
    }
}
