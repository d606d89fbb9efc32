//! The elements of a Gmsh file, whatever its version or encoding: volume elements into
//! blocks named after their physical group, 2-D elements of physical surfaces kept to be
//! matched to volume faces, every element's nodes into its groups' node sets.

use musclefem_mesh::ElementShape;

use super::super::build::{Entry, Loc, Member, RawBlock};
use super::{Reader, SurfaceElement};
use crate::mesh_import::ImportError;

/// Node entries over all physical groups (an entity in many groups multiplies them).
pub(super) const MAX_GROUP_ENTRIES: usize = 1 << 26;

/// Gmsh types of 2-D elements and their number of nodes (corners first).
pub(super) fn surface_type(element_type: i64) -> Option<(usize, usize)> {
    match element_type {
        2 => Some((3, 3)),
        9 => Some((6, 3)),
        20 => Some((9, 3)),
        21 => Some((10, 3)),
        3 => Some((4, 4)),
        16 => Some((8, 4)),
        10 => Some((9, 4)),
        _ => None,
    }
}

/// Why an element type cannot be read in an entity of dimension `dim` (`grouped`: the
/// entity is in a physical group), if it cannot.
pub(super) fn unsupported_type(
    dim: i64,
    entity: i64,
    element_type: i64,
    grouped: bool,
) -> Option<String> {
    if dim == 3 && volume_type(element_type).is_none() {
        return Some(format!(
            "$Elements: element type {element_type} in volume {entity} is not supported \
             (supported: 4 tet4, 5 hex8, 11 tet10)"
        ));
    }
    if dim == 2 && grouped && surface_type(element_type).is_none() {
        return Some(format!(
            "$Elements: element type {element_type} on physical surface {entity} is not \
             supported (supported: 2, 3, 9, 10, 16, 20, 21)"
        ));
    }
    None
}

pub(super) fn volume_type(element_type: i64) -> Option<ElementShape> {
    match element_type {
        4 => Some(ElementShape::Tet4),
        5 => Some(ElementShape::Hex8),
        11 => Some(ElementShape::Tet10),
        _ => None,
    }
}

/// The dimension of a Gmsh element type, for the types [`node_count`] knows.
pub(super) fn element_dim(element_type: i64) -> Option<i64> {
    Some(match element_type {
        15 => 0,
        1 | 8 | 26 => 1,
        2 | 3 | 9 | 10 | 16 | 20 | 21 => 2,
        4..=7 | 11..=14 | 17..=19 => 3,
        _ => return None,
    })
}

/// The number of nodes of a Gmsh element type (binary files do not say it per element),
/// for the types a mesh of solids carries; `None` for others.
pub(super) fn node_count(element_type: i64) -> Option<usize> {
    Some(match element_type {
        15 => 1,
        1 => 2,
        8 => 3,
        26 => 4,
        2 => 3,
        3 | 4 => 4,
        9 | 7 => 6,
        5 | 16 => 8,
        6 => 6,
        10 | 20 => 9,
        11 | 21 => 10,
        12 => 27,
        13 => 18,
        14 => 14,
        17 => 20,
        18 => 15,
        19 => 13,
        _ => return None,
    })
}

impl Reader<'_> {
    /// One element of entity (`dim`, `entity`) in the physical `groups`: a volume element
    /// goes to its block and element sets, a 2-D element of a physical surface is kept to
    /// be matched to a volume face, and every element's nodes go to its groups' node sets.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn add_element(
        &mut self,
        dim: i64,
        entity: i64,
        element_type: i64,
        groups: &[i64],
        tag: i64,
        nodes: &[i64],
        loc: Loc,
    ) -> Result<(), ImportError> {
        let error = |m: String| self.raw.error(loc, m);
        if tag <= 0 || nodes.iter().any(|&t| t <= 0) {
            return Err(error(format!(
                "$Elements: element {tag}: tags must be positive"
            )));
        }
        self.group_entries = self
            .group_entries
            .saturating_add(groups.len() * nodes.len());
        if self.group_entries > MAX_GROUP_ENTRIES {
            return Err(error(format!(
                "$Elements: physical groups hold more than {MAX_GROUP_ENTRIES} node entries"
            )));
        }
        for &g in groups {
            let set = self.group_nodes.entry((dim, g)).or_default();
            set.extend(nodes.iter().map(|&l| Entry {
                member: Member::Label(l),
                loc,
            }));
        }
        if let Some(m) = unsupported_type(dim, entity, element_type, !groups.is_empty()) {
            return Err(error(m));
        }
        match dim {
            3 => {
                let Some(shape) = volume_type(element_type) else {
                    return Ok(());
                };
                let expected = shape.nodes_per_element();
                if nodes.len() != expected {
                    return Err(error(format!(
                        "$Elements: element {tag} ({shape}): expected {expected} node tags, found {}",
                        nodes.len()
                    )));
                }
                let b = self.block(entity, groups, shape);
                let block = &mut self.raw.blocks[b];
                block.labels.push(tag);
                let start = block.nodes.len();
                block.nodes.extend_from_slice(nodes);
                if shape == ElementShape::Tet10 {
                    block.nodes.swap(start + 8, start + 9);
                }
                block.locs.push(loc);
                for &g in groups {
                    let set = self.group_elements.entry((3, g)).or_default();
                    set.push(Entry {
                        member: Member::Label(tag),
                        loc,
                    });
                }
            }
            2 if !groups.is_empty() => {
                let Some((count, corners)) = surface_type(element_type) else {
                    return Ok(());
                };
                if nodes.len() != count {
                    return Err(error(format!(
                        "$Elements: surface element {tag} (type {element_type}): expected {count} node tags, found {}",
                        nodes.len()
                    )));
                }
                self.surface_elements.push(SurfaceElement {
                    tag,
                    entity,
                    groups: groups.to_vec(),
                    corners: nodes[..corners].to_vec(),
                    loc,
                });
            }
            _ => {}
        }
        Ok(())
    }

    /// The name of physical group (dim, tag).
    pub(super) fn group_name(&self, dim: i64, tag: i64) -> String {
        self.physical_names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| format!("physical_{dim}_{tag}"))
    }

    /// The block of a volume entity's elements of one shape.
    pub(super) fn block(&mut self, entity: i64, groups: &[i64], shape: ElementShape) -> usize {
        let cached = (entity, groups.first().copied(), shape);
        if let Some(&b) = self.entity_blocks.get(&cached) {
            return b;
        }
        let b = self.named_block(entity, groups, shape);
        self.entity_blocks.insert(cached, b);
        b
    }

    fn named_block(&mut self, entity: i64, groups: &[i64], shape: ElementShape) -> usize {
        let name = match groups.first() {
            Some(&g) => self.group_name(3, g),
            None => format!("volume_{entity}"),
        };
        let key = (name.clone(), shape);
        if let Some(&b) = self.blocks.get(&key) {
            return b;
        }
        let mut unique = name.clone();
        if self.raw.blocks.iter().any(|b| b.name == unique) {
            unique = format!("{name}_{shape}");
        }
        self.raw.blocks.push(RawBlock {
            name: unique,
            type_name: shape.name().to_string(),
            shape,
            labels: Vec::new(),
            nodes: Vec::new(),
            locs: Vec::new(),
        });
        self.blocks.insert(key, self.raw.blocks.len() - 1);
        self.raw.blocks.len() - 1
    }
}
