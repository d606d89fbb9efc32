//! What a solver needs besides the mesh: each block's element technology, material and
//! density, and the prescribed motions.

use std::sync::Arc;

use musclefem_materials::{Amplitude, Material};

use crate::element::Technology;

/// One element block with its element technology, material and mass density.
#[derive(Debug, Clone)]
pub struct Part {
    /// Index of the block in the mesh.
    pub block: usize,
    pub technology: Technology,
    pub material: Arc<dyn Material>,
    /// Mass density in the reference configuration ρ₀ [kg/m³] (muscle ≈ 1060).
    pub density: f64,
}

/// Displacement component `dof` (0 = x, 1 = y, 2 = z) of `nodes` follows `amplitude`
/// (displacement [m] against time [s]).
#[derive(Debug, Clone)]
pub struct PrescribedDisplacement {
    pub nodes: Vec<u32>,
    pub dof: usize,
    pub amplitude: Amplitude,
}
