//! The sections of Gmsh 2.2 ASCII files: `$Nodes` (`node-number x y z`) and `$Elements`
//! (`elm-number elm-type number-of-tags <tags> node-number-list`; the first tag is the
//! physical group, 0 for none, the second the elementary entity).

use super::elements::{element_dim, node_count};
use super::{Reader, short};
use crate::mesh_import::ImportError;

impl Reader<'_> {
    pub(super) fn nodes_v2(&mut self) -> Result<(), ImportError> {
        let n = self.integers(1, "$Nodes: number-of-nodes")?[0];
        for _ in 0..self.count(n, "$Nodes")? {
            let line = self.line("$Nodes: 'node-number x y z'")?.to_string();
            let fields: Vec<&str> = line.split_whitespace().collect();
            let tag = fields.first().and_then(|f| f.parse::<i64>().ok());
            let x: Option<Vec<f64>> = fields
                .iter()
                .skip(1)
                .map(|f| f.parse::<f64>().ok().filter(|v| v.is_finite()))
                .collect();
            let (Some(tag), Some(x)) = (tag.filter(|&t| t > 0), x.filter(|x| x.len() == 3)) else {
                return Err(self.error(format!(
                    "$Nodes: expected 'node-number x y z' (a positive tag, 3 finite numbers), \
                     found '{}'",
                    short(&line)
                )));
            };
            let loc = self.loc();
            self.raw.node_labels.push(tag);
            self.raw.nodes.x.push(x[0]);
            self.raw.nodes.y.push(x[1]);
            self.raw.nodes.z.push(x[2]);
            self.raw.node_locs.push(loc);
        }
        Ok(())
    }

    pub(super) fn elements_v2(&mut self) -> Result<(), ImportError> {
        let n = self.integers(1, "$Elements: number-of-elements")?[0];
        for _ in 0..self.count(n, "$Elements")? {
            let fields = self.integers(
                3,
                "$Elements: elm-number elm-type number-of-tags <tags> node-number-list",
            )?;
            let loc = self.loc();
            let (tag, element_type) = (fields[0], fields[1]);
            let tags = self.count(fields[2], "$Elements: number-of-tags")?;
            let nodes = fields.get(3 + tags.min(fields.len())..).unwrap_or_default();
            let (Some(dim), Some(expected)) = (element_dim(element_type), node_count(element_type))
            else {
                return Err(self.error(format!(
                    "$Elements: element {tag}: element type {element_type} is not supported"
                )));
            };
            if 3 + tags > fields.len() || nodes.len() != expected {
                return Err(self.error(format!(
                    "$Elements: element {tag} (type {element_type}): expected {tags} tags and \
                     {expected} node numbers, found {} fields after the tag count",
                    fields.len() - 3
                )));
            }
            let physical = fields.get(3).copied().filter(|_| tags >= 1).unwrap_or(0);
            let entity = fields.get(4).copied().filter(|_| tags >= 2).unwrap_or(0);
            let groups: Vec<i64> = (physical != 0)
                .then_some(physical.abs())
                .into_iter()
                .collect();
            let nodes = nodes.to_vec();
            self.add_element(dim, entity, element_type, &groups, tag, &nodes, loc)?;
        }
        Ok(())
    }
}
