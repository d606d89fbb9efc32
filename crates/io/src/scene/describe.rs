//! What `musclefem check` and `run` print about a scene: [`Model::describe`].

use super::Analysis;
use super::build::Model;
use super::locking::locking_warning;

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
            if let Some(warning) = locking_warning(part.technology, part.material.as_ref()) {
                text += &format!("  warning: part '{name}': {warning}\n");
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
