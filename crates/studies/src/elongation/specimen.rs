//! The specimen of the test: the paper's fusiform muscle or a cylinder of its mid-belly
//! radius, meshed by `musclefem_core::mesh::generate::fusiform_mesh` (radius profile
//! r(z) = r_end + (r_mid − r_end) sin²(π z / L), L = 50 mm, r_end = 4.5 mm,
//! r_mid = 8.75 mm), with its reference length and mid-belly cross-section area.

use anyhow::{Context, Result};

use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::{
    PAPER_MID_RADIUS, SpecimenShape, SpecimenSpec, fusiform_mesh,
};

use super::ElementChoice;

/// Which solid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Shape {
    /// The paper's fusiform muscle.
    Fusiform,
    /// A cylinder of the mid-belly radius 8.75 mm, 50 mm long.
    Cylinder,
}

/// A meshed specimen: one block `muscle`, node sets `origin` (z = 0, held) and
/// `insertion` (z = L, pulled), fibers along the axis z.
pub struct SpecimenMesh {
    pub mesh: Mesh,
    /// Reference length L [m].
    pub length: f64,
    /// The engineering stress's denominator [m²]: for the fusiform muscle the paper's
    /// nominal mid-belly area π r_mid²; for the cylinder, a prism of the mesh's polygon,
    /// its own cross-section [`SpecimenMesh::mesh_area`], so that its curve is the
    /// material's uniaxial response. (With π r_mid² there, a coarse cylinder's smaller
    /// faceted section biased fits through it: 10 % too stiff with 8.75 mm elements,
    /// whose section is an octagon, against a material-point curve.)
    pub reference_area: f64,
    /// Area of the mesh's mid-belly cross-section [m²]: a polygon, smaller than π r_mid²
    /// (by 2.5 % with 16 edges around, 0.6 % with 32).
    pub mesh_area: f64,
}

impl SpecimenMesh {
    /// What turns the rows of a test of `mode` on this specimen into its curve.
    pub fn curve_scale(&self, mode: super::Activation) -> super::curve::CurveScale {
        super::curve::CurveScale {
            pulled: mode.pulled_end(),
            length: self.length,
            area: self.reference_area,
        }
    }
}

/// Mesh `shape` with `element`s of target size `mesh_size` [m].
pub fn specimen_mesh(shape: Shape, element: ElementChoice, mesh_size: f64) -> Result<SpecimenMesh> {
    let solid = match shape {
        Shape::Fusiform => SpecimenShape::paper_fusiform(),
        Shape::Cylinder => SpecimenShape::cylinder(PAPER_MID_RADIUS),
    };
    let element_shape = element.kind().shape();
    let spec = SpecimenSpec {
        shape: solid,
        element: element_shape,
        mesh_size,
    };
    let mesh = fusiform_mesh(&spec).with_context(|| {
        format!(
            "meshing the {} with {} mm elements",
            shape.name(),
            musclefem_io::csv::format_number(1e3 * mesh_size)
        )
    })?;
    let mesh_area = spec.mesh_mid_belly_area()?;
    Ok(SpecimenMesh {
        mesh,
        length: solid.length(),
        reference_area: match shape {
            Shape::Fusiform => solid.mid_belly_area(),
            Shape::Cylinder => mesh_area,
        },
        mesh_area,
    })
}
