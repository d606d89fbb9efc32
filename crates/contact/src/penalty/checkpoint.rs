//! A penalty contact in a checkpoint (`musclefem_core::solver::checkpoint`): frictionless
//! contact keeps no history, but each node's last closest feature is the next search's
//! first guess and the history rows and frames read the last evaluation, so both are
//! kept; the broadphase is rebuilt from scratch after a checkpoint, in the run that took
//! it as in the resumed one ([`super::super::broadphase::Broadphase::forget`]).

use musclefem_core::solver::{CheckpointReader, CheckpointWriter, SolverError};
use nalgebra::Vector3;

use super::NodeContact;
use super::smooth::SmoothContact;

/// Writes the closest features of the last evaluation.
pub(super) fn save_contacts(contacts: &[NodeContact], out: &mut CheckpointWriter) {
    out.u32s(&contacts.iter().map(|c| c.triangle).collect::<Vec<_>>());
    let numbers = |f: &dyn Fn(&NodeContact) -> f64| contacts.iter().map(f).collect::<Vec<_>>();
    out.f64s(&numbers(&|c| c.gap));
    out.f64s(&numbers(&|c| c.active as u8 as f64));
    out.f64s(&numbers(&|c| c.weight));
    out.f64s(&numbers(&|c| c.geometry.count as f64));
    out.f64s(&numbers(&|c| c.geometry.tangent_count as f64));
    let vectors =
        |f: &dyn Fn(&NodeContact) -> Vector3<f64>| contacts.iter().map(f).collect::<Vec<_>>();
    out.matrices(&vectors(&|c| c.offset));
    out.matrices(&vectors(&|c| Vector3::from(c.geometry.weights)));
    out.matrices(&vectors(&|c| c.geometry.vertices.map(f64::from).into()));
    out.matrices(&vectors(&|c| c.geometry.tangents[0]));
    out.matrices(&vectors(&|c| c.geometry.tangents[1]));
}

/// Reads what [`save_contacts`] wrote.
pub(super) fn restore_contacts(
    contacts: &mut [NodeContact],
    input: &mut CheckpointReader,
) -> Result<(), SolverError> {
    let n = contacts.len();
    let mut triangles = vec![0u32; n];
    input.u32s_into("contact triangles", &mut triangles)?;
    let mut numbers = vec![vec![0.0; n]; 5];
    for values in &mut numbers {
        input.f64s_into("contacts", values)?;
    }
    let mut vectors = vec![vec![Vector3::zeros(); n]; 5];
    for values in &mut vectors {
        input.matrices_into("contacts", values)?;
    }
    for (i, c) in contacts.iter_mut().enumerate() {
        c.triangle = triangles[i];
        c.gap = numbers[0][i];
        c.active = numbers[1][i] != 0.0;
        c.weight = numbers[2][i];
        c.geometry.count = numbers[3][i] as usize;
        c.geometry.tangent_count = numbers[4][i] as usize;
        c.offset = vectors[0][i];
        c.geometry.weights = vectors[1][i].into();
        c.geometry.vertices = [0, 1, 2].map(|k| vectors[2][i][k] as u8);
        c.geometry.tangents = [vectors[3][i], vectors[4][i]];
    }
    Ok(())
}

/// Writes the projections along the smooth normals of the last evaluation (their
/// inverse Jacobians, which only the stiffness reads, are recomputed with it).
pub(super) fn save_smooth_contacts(contacts: &[SmoothContact], out: &mut CheckpointWriter) {
    out.u32s(&contacts.iter().map(|c| c.triangle).collect::<Vec<_>>());
    let numbers = |f: &dyn Fn(&SmoothContact) -> f64| contacts.iter().map(f).collect::<Vec<_>>();
    out.f64s(&numbers(&|c| c.gap));
    out.f64s(&numbers(&|c| c.active as u8 as f64));
    out.f64s(&numbers(&|c| c.weight));
    out.f64s(&numbers(&|c| c.projection.along));
    let vectors =
        |f: &dyn Fn(&SmoothContact) -> Vector3<f64>| contacts.iter().map(f).collect::<Vec<_>>();
    out.matrices(&vectors(&|c| c.projection.barycentric));
    out.matrices(&vectors(&|c| c.projection.normal));
    for k in 0..3 {
        out.matrices(&vectors(&|c| c.projection.normals[k]));
    }
}

/// Reads what [`save_smooth_contacts`] wrote.
pub(super) fn restore_smooth_contacts(
    contacts: &mut [SmoothContact],
    input: &mut CheckpointReader,
) -> Result<(), SolverError> {
    let n = contacts.len();
    let mut triangles = vec![0u32; n];
    input.u32s_into("contact triangles", &mut triangles)?;
    let mut numbers = vec![vec![0.0; n]; 4];
    for values in &mut numbers {
        input.f64s_into("contacts", values)?;
    }
    let mut vectors = vec![vec![Vector3::zeros(); n]; 5];
    for values in &mut vectors {
        input.matrices_into("contacts", values)?;
    }
    for (i, c) in contacts.iter_mut().enumerate() {
        c.triangle = triangles[i];
        c.gap = numbers[0][i];
        c.active = numbers[1][i] != 0.0;
        c.weight = numbers[2][i];
        c.projection.along = numbers[3][i];
        c.projection.barycentric = vectors[0][i];
        c.projection.normal = vectors[1][i];
        c.projection.normals = [vectors[2][i], vectors[3][i], vectors[4][i]];
        c.projection.inverse = None;
    }
    Ok(())
}
