//! Matching 2-D elements (Gmsh triangles and quadrangles on a physical surface, Abaqus
//! R3D3/S4/M3D3... elements) to faces of volume elements, by their corner nodes.

use std::collections::HashMap;

use super::build::RawBlock;

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

/// Every face of every volume element, by its corner labels.
pub(crate) struct FaceIndex {
    /// Sorted corners → (element label, 0-based face, outward corner cycle).
    faces: HashMap<Key, Vec<(i64, u8, Vec<i64>)>>,
}

impl FaceIndex {
    pub fn new(blocks: &[RawBlock]) -> Self {
        let mut faces: HashMap<Key, Vec<(i64, u8, Vec<i64>)>> = HashMap::new();
        for block in blocks {
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
        Self { faces }
    }

    /// The volume element (label) and face whose corners are `corners`: on an interface
    /// shared by two elements, the one whose outward normal agrees with the order of
    /// `corners`.
    pub fn find(&self, corners: &[i64]) -> Option<(i64, u8)> {
        let candidates = self.faces.get(&key(corners))?;
        candidates
            .iter()
            .find(|(_, _, outward)| same_cycle(outward, corners))
            .or(candidates.first())
            .map(|(label, face, _)| (*label, *face))
    }
}
