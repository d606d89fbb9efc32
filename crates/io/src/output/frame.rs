//! [`Frame`]: what one output frame holds, independent of the solver that produced it.
//!
//! A frame borrows the mesh and plain slices, so a solver (or its output callback) fills
//! it from whatever arrays it keeps. Per-element values ("cell data") come one per element
//! over all blocks, **in block order** (every element of `mesh.blocks[0]`, then of
//! `mesh.blocks[1]`, ...): the order of the cells in the VTU file. Per-node values
//! ("point data") come one per node, in node-id order. A value per element is whatever
//! the solver reports for the element (its one integration point, or an average over its
//! points); the frame does not know.

use std::path::Path;

use musclefem_core::mesh::Mesh;
use musclefem_materials::VoigtStress;
use nalgebra::Vector3;

use crate::OutputError;

/// Array names the writer uses itself; a named field cannot take one of them (nor start
/// with `set_`).
pub const RESERVED_NAMES: [&str; 8] = [
    "displacement",
    "velocity",
    "cauchy_stress",
    "von_mises",
    "fiber_direction_reference",
    "fiber_direction_current",
    "block_id",
    "element_in_block",
];

/// Values of a named field: one item per element (cell field) or per node (point field).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FieldValues<'a> {
    /// One number per item.
    Scalar(&'a [f64]),
    /// One 3-vector per item.
    Vector(&'a [Vector3<f64>]),
    /// `components` numbers per item, item-major (`values.len()` = items × components).
    Components {
        components: usize,
        values: &'a [f64],
    },
}

impl FieldValues<'_> {
    /// Numbers per item.
    pub fn components(&self) -> usize {
        match self {
            FieldValues::Scalar(_) => 1,
            FieldValues::Vector(_) => 3,
            FieldValues::Components { components, .. } => *components,
        }
    }

    /// Number of items (elements or nodes) the values cover; `None` if a
    /// [`FieldValues::Components`] slice is not a whole number of items.
    pub fn items(&self) -> Option<usize> {
        match self {
            FieldValues::Scalar(v) => Some(v.len()),
            FieldValues::Vector(v) => Some(v.len()),
            FieldValues::Components { components, values } => {
                if *components == 0 || !values.len().is_multiple_of(*components) {
                    None
                } else {
                    Some(values.len() / components)
                }
            }
        }
    }

    /// The numbers, item-major.
    pub fn flatten(&self) -> Vec<f64> {
        match self {
            FieldValues::Scalar(v) => v.to_vec(),
            FieldValues::Vector(v) => v.iter().flat_map(|x| [x.x, x.y, x.z]).collect(),
            FieldValues::Components { values, .. } => values.to_vec(),
        }
    }
}

/// A named field (a material state variable such as `activation` or `ce_stretch`, or any
/// other quantity) with its unit, which is not written to the VTU file (VTK arrays carry
/// no unit) but belongs in the array name if it matters, e.g. `ce_length_m`.
#[derive(Clone, Debug, PartialEq)]
pub struct Field<'a> {
    /// Array name in the VTU file: non-empty, letters, digits, `_`, `-`, `.` only.
    pub name: String,
    pub values: FieldValues<'a>,
}

/// One output frame: the mesh in its reference configuration plus nodal and element
/// fields at `time`. See the module documentation for the orders.
#[derive(Clone, Debug)]
pub struct Frame<'a> {
    /// Time [s].
    pub time: f64,
    /// The mesh; its node positions are the reference configuration.
    pub mesh: &'a Mesh,
    /// Displacement of each node from its reference position [m].
    pub displacement: &'a [Vector3<f64>],
    /// Velocity of each node [m/s], if the solver has one.
    pub velocity: Option<&'a [Vector3<f64>]>,
    /// Cauchy stress of each element [Pa] in the solvers' Voigt order
    /// (σxx, σyy, σzz, σyz, σxz, σxy).
    pub cauchy_stress: Option<&'a [VoigtStress]>,
    /// Fiber direction of each element in the current configuration (F a₀ / |F a₀|),
    /// if the solver computes it. The reference direction is always written, from the
    /// mesh.
    pub current_fiber_direction: Option<&'a [Vector3<f64>]>,
    /// Named per-element fields (state variables, activation, ...).
    pub cell_fields: Vec<Field<'a>>,
    /// Named per-node fields.
    pub point_fields: Vec<Field<'a>>,
}

impl<'a> Frame<'a> {
    /// A frame of `mesh` at `time` [s] with nodal `displacement` [m] and nothing else.
    pub fn new(time: f64, mesh: &'a Mesh, displacement: &'a [Vector3<f64>]) -> Self {
        Self {
            time,
            mesh,
            displacement,
            velocity: None,
            cauchy_stress: None,
            current_fiber_direction: None,
            cell_fields: Vec::new(),
            point_fields: Vec::new(),
        }
    }

    /// With nodal velocities [m/s].
    pub fn with_velocity(mut self, velocity: &'a [Vector3<f64>]) -> Self {
        self.velocity = Some(velocity);
        self
    }

    /// With the Cauchy stress of each element [Pa], Voigt order (xx, yy, zz, yz, xz, xy).
    pub fn with_cauchy_stress(mut self, stress: &'a [VoigtStress]) -> Self {
        self.cauchy_stress = Some(stress);
        self
    }

    /// With the current fiber direction of each element (unit vectors).
    pub fn with_current_fiber_direction(mut self, direction: &'a [Vector3<f64>]) -> Self {
        self.current_fiber_direction = Some(direction);
        self
    }

    /// With a named scalar per element.
    pub fn with_cell_scalar(mut self, name: &str, values: &'a [f64]) -> Self {
        self.cell_fields
            .push(field(name, FieldValues::Scalar(values)));
        self
    }

    /// With a named 3-vector per element.
    pub fn with_cell_vector(mut self, name: &str, values: &'a [Vector3<f64>]) -> Self {
        self.cell_fields
            .push(field(name, FieldValues::Vector(values)));
        self
    }

    /// With a named field of `components` numbers per element (item-major).
    pub fn with_cell_components(
        mut self,
        name: &str,
        components: usize,
        values: &'a [f64],
    ) -> Self {
        let values = FieldValues::Components { components, values };
        self.cell_fields.push(field(name, values));
        self
    }

    /// With a named scalar per node.
    pub fn with_point_scalar(mut self, name: &str, values: &'a [f64]) -> Self {
        self.point_fields
            .push(field(name, FieldValues::Scalar(values)));
        self
    }

    /// With a named 3-vector per node.
    pub fn with_point_vector(mut self, name: &str, values: &'a [Vector3<f64>]) -> Self {
        self.point_fields
            .push(field(name, FieldValues::Vector(values)));
        self
    }

    /// With `components` values per node, node after node.
    pub fn with_point_components(
        mut self,
        name: &str,
        components: usize,
        values: &'a [f64],
    ) -> Self {
        let values = FieldValues::Components { components, values };
        self.point_fields.push(field(name, values));
        self
    }

    /// Check that every array fits the mesh and every name is valid and unique; `path`
    /// is the file the frame is for (errors name it).
    pub fn check(&self, path: &Path) -> Result<(), OutputError> {
        let bad = |message: String| OutputError::Data {
            path: path.to_path_buf(),
            message,
        };
        if !self.time.is_finite() {
            return Err(bad(format!("frame time {} is not finite", self.time)));
        }
        let mesh = self.mesh;
        let nodes = mesh.node_count();
        if mesh.nodes.y.len() != nodes || mesh.nodes.z.len() != nodes {
            return Err(bad(
                "the mesh's node coordinate arrays differ in length".into()
            ));
        }
        let elements = mesh.element_count();
        for block in &mesh.blocks {
            if let Some(&id) = block.connectivity.iter().find(|&&id| id as usize >= nodes) {
                return Err(bad(format!(
                    "block '{}' refers to node {id}, the mesh has {nodes} nodes",
                    block.name
                )));
            }
            if block.fiber_direction.len() != block.len() {
                return Err(bad(format!(
                    "block '{}' has {} fiber directions for {} elements",
                    block.name,
                    block.fiber_direction.len(),
                    block.len()
                )));
            }
        }
        for (name, set) in &mesh.element_sets {
            for e in set {
                let fits = mesh
                    .blocks
                    .get(e.block as usize)
                    .is_some_and(|b| (e.element as usize) < b.len());
                if !fits {
                    return Err(bad(format!(
                        "element set '{name}' holds a missing element {e}"
                    )));
                }
            }
        }
        let count = |what: &str, len: usize, expected: usize, per: &str| {
            if len == expected {
                Ok(())
            } else {
                Err(bad(format!(
                    "{what} has {len} values, expected one per {per} ({expected})"
                )))
            }
        };
        count("displacement", self.displacement.len(), nodes, "node")?;
        if let Some(v) = self.velocity {
            count("velocity", v.len(), nodes, "node")?;
        }
        if let Some(s) = self.cauchy_stress {
            count("cauchy_stress", s.len(), elements, "element")?;
        }
        if let Some(f) = self.current_fiber_direction {
            count("fiber_direction_current", f.len(), elements, "element")?;
        }
        let mut names: Vec<&str> = Vec::new();
        let fields = self.cell_fields.iter().map(|f| (f, elements, "element"));
        let fields = fields.chain(self.point_fields.iter().map(|f| (f, nodes, "node")));
        for (f, expected, per) in fields {
            check_name(&f.name).map_err(|m| bad(format!("field '{}': {m}", f.name)))?;
            if names.contains(&f.name.as_str()) {
                return Err(bad(format!("two fields are named '{}'", f.name)));
            }
            names.push(&f.name);
            let items = f.values.items().ok_or_else(|| {
                bad(format!(
                    "field '{}' is not a whole number of {}-component items",
                    f.name,
                    f.values.components()
                ))
            })?;
            count(&format!("field '{}'", f.name), items, expected, per)?;
        }
        Ok(())
    }
}

fn field<'a>(name: &str, values: FieldValues<'a>) -> Field<'a> {
    Field {
        name: name.to_string(),
        values,
    }
}

/// Why `name` cannot name a field, if it cannot.
fn check_name(name: &str) -> Result<(), String> {
    if name.is_empty() {
        return Err("empty name".into());
    }
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')))
    {
        return Err(format!(
            "character {c:?} (use letters, digits, '_', '-', '.')"
        ));
    }
    if RESERVED_NAMES.contains(&name) || name.starts_with("set_") {
        return Err("the writer uses this name itself".into());
    }
    Ok(())
}

pub use musclefem_materials::tensor::von_mises;

/// A Voigt stress (xx, yy, zz, yz, xz, xy) in the order ParaView and VTK give 6-component
/// symmetric tensors (`vtkMath::TensorFromSymmetricTensor`): (XX, YY, ZZ, XY, YZ, XZ).
pub fn voigt_to_vtk_symmetric(stress: &VoigtStress) -> [f64; 6] {
    [
        stress[0], stress[1], stress[2], stress[5], stress[3], stress[4],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn von_mises_of_known_states() {
        // Uniaxial σ: σ_vm = |σ|; pure shear τ: √3 τ; hydrostatic p: 0.
        let uniaxial = VoigtStress::new(0.0, -7.0, 0.0, 0.0, 0.0, 0.0);
        assert!((von_mises(&uniaxial) - 7.0).abs() < 1e-14);
        let shear = VoigtStress::new(0.0, 0.0, 0.0, 0.0, 2.0, 0.0);
        assert!((von_mises(&shear) - 2.0 * 3f64.sqrt()).abs() < 1e-14);
        let hydrostatic = VoigtStress::new(5.0, 5.0, 5.0, 0.0, 0.0, 0.0);
        assert!(von_mises(&hydrostatic).abs() < 1e-14);
    }

    #[test]
    fn vtk_order_moves_the_shears() {
        let s = VoigtStress::new(1.0, 2.0, 3.0, 23.0, 13.0, 12.0);
        assert_eq!(
            voigt_to_vtk_symmetric(&s),
            [1.0, 2.0, 3.0, 12.0, 23.0, 13.0]
        );
    }

    #[test]
    fn names_are_checked() {
        assert!(check_name("activation").is_ok());
        assert!(check_name("ce_stretch-1.0").is_ok());
        assert!(check_name("").is_err());
        assert!(check_name("a b").is_err());
        assert!(check_name("x\"y").is_err());
        assert!(check_name("von_mises").is_err());
        assert!(check_name("set_all").is_err());
    }
}
