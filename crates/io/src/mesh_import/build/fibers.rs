//! The fibers a file gives its elements (Abaqus `*ORIENTATION` through `*SOLID
//! SECTION`), written into the blocks' fiber directions.

use std::collections::HashMap;

use musclefem_mesh::{ElementRef, Mesh};
use nalgebra::Vector3;

use super::{FiberRule, Loc, RawMesh};
use crate::mesh_import::ImportError;

impl RawMesh {
    /// Sets the fiber of every element a section orients; returns the source of each
    /// block's fibers (`None`: no element of the block is oriented, its fibers are e_x).
    pub(super) fn apply_fibers(
        &self,
        mesh: &mut Mesh,
        element_ids: &HashMap<i64, ElementRef>,
        warnings: &mut Vec<(Loc, String, String)>,
    ) -> Result<Vec<Option<String>>, ImportError> {
        // (assignment, section line) that oriented each element, per block.
        let mut by: Vec<Vec<Option<usize>>> =
            mesh.blocks.iter().map(|b| vec![None; b.len()]).collect();
        for (a, assignment) in self.fiber_assignments.iter().enumerate() {
            let what = format!("*SOLID SECTION with {}", assignment.source);
            let refs = self.resolve(
                &assignment.elements,
                element_ids,
                "element set of the",
                &what,
                "element",
            )?;
            let (per_element, default, distribution) = match &assignment.rule {
                FiberRule::Uniform(d) => (HashMap::new(), Some(*d), ""),
                FiberRule::PerElement {
                    distribution,
                    default,
                    per_element,
                } => {
                    let mut map = HashMap::new();
                    for (entry, d) in per_element {
                        for r in self.resolve(
                            std::slice::from_ref(entry),
                            element_ids,
                            "*DISTRIBUTION",
                            distribution,
                            "element",
                        )? {
                            map.insert(r, *d);
                        }
                    }
                    (map, *default, distribution.as_str())
                }
            };
            for r in refs {
                let label = self.blocks[r.block as usize].labels[r.element as usize];
                let direction = per_element.get(&r).copied().or(default).ok_or_else(|| {
                    self.error(
                        assignment.section,
                        format!(
                            "element {label}: *DISTRIBUTION {distribution} gives it no vectors \
                             and has no default line (empty first field)"
                        ),
                    )
                })?;
                let slot = &mut by[r.block as usize][r.element as usize];
                if let Some(other) = slot.filter(|&o| o != a) {
                    let first = self.fiber_assignments[other].section;
                    return Err(self.error(
                        assignment.section,
                        format!(
                            "element {label} is oriented twice (also by the *SOLID SECTION at \
                             line {})",
                            first.line
                        ),
                    ));
                }
                *slot = Some(a);
                mesh.blocks[r.block as usize].fiber_direction[r.element as usize] =
                    Vector3::from(direction);
            }
        }
        let mut sources = Vec::with_capacity(by.len());
        for (b, oriented) in by.iter().enumerate() {
            let mut used: Vec<usize> = oriented.iter().flatten().copied().collect();
            used.sort_unstable();
            used.dedup();
            let Some(&first) = used.first() else {
                sources.push(None);
                continue;
            };
            let mut source = used
                .iter()
                .map(|&a| self.fiber_assignments[a].source.as_str())
                .collect::<Vec<_>>()
                .join(", ");
            let count = oriented.iter().flatten().count();
            if count < oriented.len() {
                let block = &mesh.blocks[b].name;
                let message = format!(
                    "{count} of the {} elements of block '{block}' are oriented: the others \
                     keep the fiber e_x",
                    oriented.len()
                );
                warnings.push((
                    self.fiber_assignments[first].section,
                    "SOLID SECTION".into(),
                    message.clone(),
                ));
                source += &format!(" ({message})");
            }
            sources.push(Some(source));
        }
        Ok(sources)
    }
}
