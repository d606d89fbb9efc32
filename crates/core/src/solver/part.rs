//! What a solver needs of each element block besides the mesh: its element technology,
//! material and density.

use std::sync::Arc;

use musclefem_materials::Material;

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
