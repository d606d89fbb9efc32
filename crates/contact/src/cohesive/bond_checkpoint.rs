//! The bonds of a cohesive interface in a checkpoint (`musclefem_core::solver::checkpoint`):
//! where each bond sits on the main surface and its damage history (changed by sliding
//! and by commits), and the state of the last force evaluation that the history rows and
//! frames read (force, traction, separation, damage, energy, foot). The derivatives in
//! [`BondState`] are not kept: every solver evaluates the forces again, with stiffness
//! where it needs it, before it reads them.

use musclefem_core::solver::{CheckpointReader, CheckpointWriter, SolverError};
use nalgebra::Vector3;

use super::bonds::{Bond, BondState};

/// Writes the bonds and their last evaluated states.
pub(super) fn save_bonds(bonds: &[Bond], states: &[BondState], out: &mut CheckpointWriter) {
    let column = |f: &dyn Fn(&Bond) -> Vector3<f64>| bonds.iter().map(f).collect::<Vec<_>>();
    out.u32s(&bonds.iter().map(|b| b.triangle).collect::<Vec<_>>());
    out.matrices(&column(&|b| b.coordinates));
    out.matrices(&column(&|b| b.normal));
    out.matrices(&column(&|b| b.reference_separation));
    out.f64s(&bonds.iter().map(|b| b.history).collect::<Vec<_>>());
    let column = |f: &dyn Fn(&BondState) -> Vector3<f64>| states.iter().map(f).collect::<Vec<_>>();
    out.u32s(&states.iter().map(|s| s.triangle).collect::<Vec<_>>());
    out.matrices(&column(&|s| s.coordinates));
    out.matrices(&column(&|s| s.force));
    out.matrices(&column(&|s| s.traction));
    out.matrices(&column(&|s| s.separation));
    for value in [
        |s: &BondState| s.history,
        |s: &BondState| s.damage,
        |s: &BondState| s.energy,
    ] {
        out.f64s(&states.iter().map(value).collect::<Vec<_>>());
    }
}

/// Reads what [`save_bonds`] wrote into the bonds of an interface built for the same
/// problem.
pub(super) fn restore_bonds(
    bonds: &mut [Bond],
    states: &mut [BondState],
    input: &mut CheckpointReader,
) -> Result<(), SolverError> {
    let mut triangles = vec![0u32; bonds.len()];
    let mut vectors = vec![Vector3::zeros(); bonds.len()];
    let mut values = vec![0.0; bonds.len()];
    input.u32s_into("bond triangles", &mut triangles)?;
    bonds
        .iter_mut()
        .zip(&triangles)
        .for_each(|(b, &t)| b.triangle = t);
    input.matrices_into("bond coordinates", &mut vectors)?;
    bonds
        .iter_mut()
        .zip(&vectors)
        .for_each(|(b, &x)| b.coordinates = x);
    input.matrices_into("bond normals", &mut vectors)?;
    bonds
        .iter_mut()
        .zip(&vectors)
        .for_each(|(b, &x)| b.normal = x);
    input.matrices_into("bond rest separations", &mut vectors)?;
    bonds
        .iter_mut()
        .zip(&vectors)
        .for_each(|(b, &x)| b.reference_separation = x);
    input.f64s_into("bond histories", &mut values)?;
    bonds
        .iter_mut()
        .zip(&values)
        .for_each(|(b, &x)| b.history = x);

    let mut triangles = vec![0u32; states.len()];
    let mut vectors = vec![Vector3::zeros(); states.len()];
    let mut values = vec![0.0; states.len()];
    input.u32s_into("bond triangles", &mut triangles)?;
    states
        .iter_mut()
        .zip(&triangles)
        .for_each(|(s, &t)| s.triangle = t);
    for set in [
        |s: &mut BondState, x: Vector3<f64>| s.coordinates = x,
        |s: &mut BondState, x: Vector3<f64>| s.force = x,
        |s: &mut BondState, x: Vector3<f64>| s.traction = x,
        |s: &mut BondState, x: Vector3<f64>| s.separation = x,
    ] {
        input.matrices_into("bond states", &mut vectors)?;
        states
            .iter_mut()
            .zip(&vectors)
            .for_each(|(s, &x)| set(s, x));
    }
    for set in [
        |s: &mut BondState, x: f64| s.history = x,
        |s: &mut BondState, x: f64| s.damage = x,
        |s: &mut BondState, x: f64| s.energy = x,
    ] {
        input.f64s_into("bond states", &mut values)?;
        states.iter_mut().zip(&values).for_each(|(s, &x)| set(s, x));
    }
    Ok(())
}
