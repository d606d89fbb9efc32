//! The sections of Gmsh 4.1 ASCII files: `$Entities`, `$Nodes`, `$Elements`.

use super::elements::unsupported_type;
use super::{Reader, short};
use crate::mesh_import::ImportError;

impl Reader<'_> {
    pub(super) fn entities(&mut self) -> Result<(), ImportError> {
        let counts = self.integers(4, "$Entities: numPoints numCurves numSurfaces numVolumes")?;
        for dim in 0..4 {
            let n = self.count(counts[dim], "$Entities")?;
            // Points: tag x y z numPhysical ...; others: tag and a bounding box first.
            let physical_at = if dim == 0 { 4 } else { 7 };
            for _ in 0..n {
                let line = self.line("an entity line")?.to_string();
                let fields: Vec<&str> = line.split_whitespace().collect();
                let bad = || {
                    self.error(format!(
                        "$Entities: malformed entity of dimension {dim}: '{}'",
                        short(&line)
                    ))
                };
                let tag = fields
                    .first()
                    .and_then(|f| f.parse::<i64>().ok())
                    .ok_or_else(bad)?;
                let n_physical = fields
                    .get(physical_at)
                    .and_then(|f| f.parse::<usize>().ok())
                    .ok_or_else(bad)?;
                let groups: Option<Vec<i64>> = fields
                    .get(physical_at + 1..(physical_at + 1).saturating_add(n_physical))
                    .and_then(|g| {
                        g.iter()
                            .map(|f| f.parse::<i64>().ok().map(i64::abs))
                            .collect()
                    });
                self.entity_groups
                    .insert((dim as i64, tag), groups.ok_or_else(bad)?);
            }
        }
        Ok(())
    }

    pub(super) fn nodes(&mut self) -> Result<(), ImportError> {
        let header = self.integers(4, "$Nodes: numEntityBlocks numNodes minNodeTag maxNodeTag")?;
        let header_loc = self.loc();
        let (blocks, total) = (
            self.count(header[0], "$Nodes")?,
            self.count(header[1], "$Nodes")?,
        );
        let first_node = self.raw.node_labels.len();
        for _ in 0..blocks {
            let block =
                self.integers(4, "$Nodes: entityDim entityTag parametric numNodesInBlock")?;
            if !(0..=3).contains(&block[0]) {
                return Err(
                    self.error(format!("$Nodes: entity dimension {} is not 0..3", block[0]))
                );
            }
            let extra = if block[2] != 0 { block[0] as usize } else { 0 };
            let n = self.count(block[3], "$Nodes: numNodesInBlock")?;
            let mut tags = Vec::new();
            for _ in 0..n {
                let tag = self.integers(1, "$Nodes: a node tag")?[0];
                if tag <= 0 {
                    return Err(self.error(format!("$Nodes: node tag {tag} is not positive")));
                }
                tags.push((tag, self.loc()));
            }
            for &(tag, loc) in &tags {
                let line = self.line("$Nodes: node coordinates")?.to_string();
                let values: Option<Vec<f64>> =
                    line.split_whitespace().map(|f| f.parse().ok()).collect();
                let x = match values {
                    Some(v) if v.len() == 3 + extra => v,
                    _ => {
                        return Err(self.error(format!(
                            "$Nodes: node {tag}: expected {} numbers, found '{}'",
                            3 + extra,
                            short(&line)
                        )));
                    }
                };
                if x.iter().any(|c| !c.is_finite()) {
                    return Err(self.error(format!(
                        "$Nodes: node {tag}: coordinates '{}' are not finite",
                        short(&line)
                    )));
                }
                self.raw.node_labels.push(tag);
                self.raw.nodes.x.push(x[0]);
                self.raw.nodes.y.push(x[1]);
                self.raw.nodes.z.push(x[2]);
                self.raw.node_locs.push(loc);
            }
        }
        let read = self.raw.node_labels.len() - first_node;
        if read != total {
            return Err(self.raw.error(
                header_loc,
                format!("$Nodes: the header announces {total} nodes, the blocks hold {read}"),
            ));
        }
        Ok(())
    }

    pub(super) fn elements(&mut self) -> Result<(), ImportError> {
        let header = self.integers(4, "$Elements: numEntityBlocks numElements minTag maxTag")?;
        let header_loc = self.loc();
        let (blocks, total) = (
            self.count(header[0], "$Elements")?,
            self.count(header[1], "$Elements")?,
        );
        let mut read = 0usize;
        for _ in 0..blocks {
            let block = self.integers(
                4,
                "$Elements: entityDim entityTag elementType numElementsInBlock",
            )?;
            let (dim, entity, element_type) = (block[0], block[1], block[2]);
            let n = self.count(block[3], "$Elements: numElementsInBlock")?;
            let groups = self
                .entity_groups
                .get(&(dim, entity))
                .cloned()
                .unwrap_or_default();
            if let Some(m) = unsupported_type(dim, entity, element_type, !groups.is_empty()) {
                return Err(self.error(m));
            }
            for _ in 0..n {
                let tags = self.integers(2, "$Elements: elementTag nodeTag ...")?;
                let loc = self.loc();
                self.add_element(dim, entity, element_type, &groups, tags[0], &tags[1..], loc)?;
            }
            read += n;
        }
        if read != total {
            return Err(self.raw.error(
                header_loc,
                format!("$Elements: the header announces {total} elements, the blocks hold {read}"),
            ));
        }
        Ok(())
    }
}
