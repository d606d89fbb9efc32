//! What `musclefem check` and `run` print about a scene: [`Model::describe`].

use super::Analysis;
use super::build::Model;
use super::locking::{locking_warning, small_strain_shear_modulus};

impl Model {
    /// A few lines on the model: its parts (with a locking warning where the element and
    /// the material lock), nodes and loads, interactions, and the analysis.
    pub fn describe(&self) -> String {
        let mut text = String::new();
        if !self.description.is_empty() {
            text += &format!("  {}\n", self.description);
        }
        for (name, part) in self.part_names.iter().zip(&self.parts) {
            let block = &self.mesh.blocks[part.block];
            text += &format!(
                "  part '{name}': {} {:?} elements, density {} kg/m3\n",
                block.len(),
                part.technology,
                part.density
            );
            if let Some(line) = self.activation_line(part.block) {
                text += &format!("  part '{name}': {line}\n");
            }
            if let Some(warning) = locking_warning(part.technology, part.material.as_ref()) {
                text += &format!("  warning: part '{name}': {warning}\n");
            }
            if let Some(warning) = size_warning(&self.mesh, part.block) {
                text += &format!("  warning: part '{name}': {warning}\n");
            }
            for note in self.part_notes.get(part.block).into_iter().flatten() {
                match note.strip_prefix("warning: ") {
                    Some(warning) => text += &format!("  warning: part '{name}': {warning}\n"),
                    None => text += &format!("  part '{name}': {note}\n"),
                }
            }
            let material = &self.material_names[part.block];
            if let Some(warning) = stiffness_warning(material, part.material.as_ref()) {
                text += &format!("  warning: part '{name}': {warning}\n");
            }
        }
        for body in &self.rigid_bodies {
            if let Some(warning) = extent_warning(body.vertices.iter().copied(), "surface") {
                text += &format!("  warning: rigid body '{}': {warning}\n", body.name);
            }
        }
        text += &format!(
            "  {} nodes; {} prescribed displacement components, {} nodal forces, {} rigid ties\n",
            self.mesh.nodes.len(),
            self.loads.displacements.len(),
            self.loads.forces.len(),
            self.loads.rigid_ties.len()
        );
        for interaction in &self.interactions {
            text += &format!("  interaction {}\n", interaction.describe());
        }
        text += &match &self.analysis {
            Analysis::Explicit(s) => format!(
                "  explicit, {} s, safety factor {}, history every {} s, frames every {} s\n",
                s.end_time, s.safety_factor, self.output_interval, self.frame_interval
            ),
            Analysis::Implicit(s) => format!(
                "  implicit{}, {} s in {} increments, history every converged increment, frames \
             every {} s\n",
                if s.dynamics.is_some() {
                    " (Newmark dynamics)"
                } else {
                    " (quasi-static)"
                },
                s.end_time,
                s.increments,
                self.frame_interval
            ),
        };
        if let Some(why) = &self.solver_rationale {
            text += &format!("  {why}\n");
        }
        text
    }
}

impl Model {
    /// "activation 0 … 0.5 over the step (from column 'VL' of emg.csv)" for a part whose
    /// material has an activation: its smallest and largest level at 1001 instants over
    /// the step.
    fn activation_line(&self, part: usize) -> Option<String> {
        let material = &self.parts[part].material;
        let end = self.analysis.end_time();
        let mut levels = (0..=1000).map(|i| material.activation(end * i as f64 / 1000.0));
        let first = levels.next()??;
        let (low, high) = levels
            .flatten()
            .fold((first, first), |(l, h), a| (l.min(a), h.max(a)));
        let source = match &self.activation_histories[part] {
            Some(history) => format!("recorded {}", history.source),
            None => format!("the material's own ({})", material.name()),
        };
        Some(format!(
            "activation {low:.3} … {high:.3} over the step, {source}"
        ))
    }
}

/// Largest extent of a part that is plausible for a muscle (or a bone beside it) [m].
pub const LARGEST_PLAUSIBLE_EXTENT: f64 = 2.0;
/// Smallest plausible extent of a part [m].
pub const SMALLEST_PLAUSIBLE_EXTENT: f64 = 1e-3;

/// A warning when the block's bounding box is larger than [`LARGEST_PLAUSIBLE_EXTENT`]
/// (a mesh in millimetres read as metres) or smaller than [`SMALLEST_PLAUSIBLE_EXTENT`]
/// (one in metres scaled down, or in micrometres) along its longest side.
pub fn size_warning(mesh: &musclefem_core::mesh::Mesh, block: usize) -> Option<String> {
    let points =
        (mesh.blocks[block].connectivity.iter()).map(|&id| mesh.nodes.position(id as usize));
    extent_warning(points, "mesh")
}

/// The warning of [`size_warning`] for a cloud of `points` [m], naming the key (`mesh` of
/// a part, `surface` of a rigid body) that takes `units = "mm"`.
fn extent_warning(
    points: impl Iterator<Item = nalgebra::Vector3<f64>>,
    key: &str,
) -> Option<String> {
    let mut low = nalgebra::Vector3::repeat(f64::INFINITY);
    let mut high = nalgebra::Vector3::repeat(f64::NEG_INFINITY);
    for x in points {
        low = low.inf(&x);
        high = high.sup(&x);
    }
    let extent = (high - low).max();
    if extent > LARGEST_PLAUSIBLE_EXTENT {
        Some(format!(
            "it is {extent:.3e} m across, more than any muscle or bone: is its file in \
             millimetres? ({key} = {{ file = ..., units = \"mm\" }})"
        ))
    } else if extent < SMALLEST_PLAUSIBLE_EXTENT {
        Some(format!(
            "it is {extent:.3e} m across, less than 1 mm: are its coordinates in the \
             right unit? (the scene's lengths are in m)"
        ))
    } else {
        None
    }
}

/// Largest small-strain shear modulus plausible for a deformable part (muscle, tendon,
/// or anything softer than bone, whose μ is about 3–5 GPa) [Pa].
pub const LARGEST_PLAUSIBLE_SHEAR_MODULUS: f64 = 1e10;
/// Smallest plausible small-strain shear modulus (passive muscle's is about 1 kPa) [Pa].
pub const SMALLEST_PLAUSIBLE_SHEAR_MODULUS: f64 = 10.0;

/// A warning when `material`'s (named `name`) small-strain shear modulus μ (from its
/// tangent at F = I, [`small_strain_shear_modulus`]) is outside
/// [[`SMALLEST_PLAUSIBLE_SHEAR_MODULUS`], [`LARGEST_PLAUSIBLE_SHEAR_MODULUS`]] Pa: a
/// value in kPa or MPa read as Pa (too soft), or one scaled twice, or a bone meant as a
/// rigid body (too stiff). None when the material gives no μ.
pub fn stiffness_warning(
    name: &str,
    material: &dyn musclefem_materials::Material,
) -> Option<String> {
    let mu = small_strain_shear_modulus(material)?;
    if mu > LARGEST_PLAUSIBLE_SHEAR_MODULUS {
        Some(format!(
            "material '{name}' has a small-strain shear modulus mu = {mu:.3e} Pa, more than \
             10 GPa, stiffer than bone (muscle ~1e3-1e5 Pa, tendon ~1e8 Pa): is a parameter \
             scaled twice, or is the part a bone better made a [[rigid_bodies]] surface? (the \
             scene's moduli are in Pa)"
        ))
    } else if mu < SMALLEST_PLAUSIBLE_SHEAR_MODULUS {
        Some(format!(
            "material '{name}' has a small-strain shear modulus mu = {mu:.3e} Pa, less than \
             10 Pa, softer than any tissue (passive muscle ~1e3 Pa): is a modulus given in \
             kPa or MPa? (the scene's moduli are in Pa: 10 kPa is 1e4)"
        ))
    } else {
        None
    }
}
