//! Matching the 2-D elements of physical surfaces to faces of volume elements.

use std::collections::{BTreeMap, HashMap};

use super::super::build::{Entry, Member};
use super::{Reader, SurfaceElement};
use crate::mesh_import::ImportError;

/// A surface as the raw mesh holds it: name and (element entry, face) pairs.
type RawSurface = (String, Vec<(Entry, u8)>);

/// Sorted corner labels of a face (a triangle's fourth entry is 0, never a label).
type Key = [i64; 4];

fn key(corners: &[i64]) -> Key {
    let mut k = [0; 4];
    for (slot, &c) in k.iter_mut().zip(corners) {
        *slot = c;
    }
    let n = corners.len().min(4);
    k[..n].sort_unstable();
    k
}

/// True if `b` is a rotation of the cycle `a` (same orientation).
fn same_cycle(a: &[i64], b: &[i64]) -> bool {
    a.len() == b.len() && (0..a.len()).any(|r| (0..a.len()).all(|i| a[i] == b[(i + r) % b.len()]))
}

/// One surface per physical surface group, in group order.
pub(super) fn surfaces(reader: &Reader) -> Result<Vec<RawSurface>, ImportError> {
    if reader.surface_elements.is_empty() {
        return Ok(Vec::new());
    }
    // Every face of every volume element: (element label, face, outward corners).
    let mut faces: HashMap<Key, Vec<(i64, u8, Vec<i64>)>> = HashMap::new();
    for block in &reader.raw.blocks {
        let shape = block.shape;
        let n = shape.nodes_per_element();
        let corners = shape.face_shape(0).corner_count();
        for (e, &label) in block.labels.iter().enumerate() {
            let Some(nodes) = block.nodes.get(e * n..(e + 1) * n) else {
                continue;
            };
            for (f, local) in shape.faces().iter().enumerate() {
                let outward: Vec<i64> = local[..corners]
                    .iter()
                    .filter_map(|&l| nodes.get(l as usize).copied())
                    .collect();
                faces
                    .entry(key(&outward))
                    .or_default()
                    .push((label, f as u8, outward));
            }
        }
    }
    let mut surfaces: BTreeMap<(i64, i64), Vec<(Entry, u8)>> = BTreeMap::new();
    for element in &reader.surface_elements {
        let SurfaceElement {
            tag,
            entity,
            corners,
            loc,
        } = element;
        let candidates = faces
            .get(&key(corners))
            .map(Vec::as_slice)
            .unwrap_or_default();
        let chosen = candidates
            .iter()
            .find(|(_, _, outward)| same_cycle(outward, corners))
            .or(candidates.first())
            .ok_or_else(|| {
                reader.raw.error(
                    *loc,
                    format!(
                        "$Elements: surface element {tag} on surface {entity} (nodes {corners:?}) \
                         is not a face of any volume element"
                    ),
                )
            })?;
        let groups = reader
            .entity_groups
            .get(&(2, *entity))
            .map(Vec::as_slice)
            .unwrap_or_default();
        for &g in groups {
            surfaces.entry((2, g)).or_default().push((
                Entry {
                    member: Member::Label(chosen.0),
                    loc: *loc,
                },
                chosen.1,
            ));
        }
    }
    Ok(surfaces
        .into_iter()
        .map(|((dim, tag), faces)| (reader.group_name(dim, tag), faces))
        .collect())
}
