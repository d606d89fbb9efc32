//! The tets of the specimen: every hex of the layered O-grid cut into six tets, through
//! two triangular prisms, conformingly (see [`super::fusiform_mesh`]).

use nalgebra::Vector3;

use super::o_grid::UnitSection;
use crate::Nodes;
use crate::geometry::tet4_volume;

/// Tet4 connectivity of the split described at [`super::fusiform_mesh`]: each section
/// quad into two triangles along its shorter diagonal, each triangular prism between two
/// layers into three tets ([`split_prism`]), each tet with a positive volume (two nodes
/// swapped where the split gives a negative one).
pub fn tets(section: &UnitSection, axial: usize, nodes: &Nodes) -> Vec<u32> {
    let per_layer = section.node_count() as u32;
    let triangles: Vec<[u32; 3]> = section
        .quads
        .iter()
        .flat_map(|&[a, b, c, d]| {
            let length =
                |p: u32, q: u32| (section.points[p as usize] - section.points[q as usize]).norm();
            if length(a, c) <= length(b, d) {
                [[a, b, c], [a, c, d]]
            } else {
                [[a, b, d], [b, c, d]]
            }
        })
        .collect();
    let mut connectivity = Vec::with_capacity(triangles.len() * axial * 12);
    let mut corners = [Vector3::zeros(); 4];
    for k in 0..axial as u32 {
        for triangle in &triangles {
            let bottom = triangle.map(|p| p + k * per_layer);
            let top = triangle.map(|p| p + (k + 1) * per_layer);
            for mut tet in split_prism(bottom, top) {
                nodes.gather(&tet, &mut corners);
                if tet4_volume(&corners) < 0.0 {
                    tet.swap(1, 2);
                }
                connectivity.extend_from_slice(&tet);
            }
        }
    }
    connectivity
}

/// The three tets of the triangular prism with corners `bottom` and `top` (top[i] above
/// bottom[i]) whose quad faces are cut along their diagonals through their smallest node
/// ids (orientation not fixed).
///
/// Relabel so that the smallest id is b0 (swap bottom and top if it is on top, rotate):
/// the two quad faces at b0 are then cut along b0–t1 and b0–t2, which cuts off the tet
/// (b0, t0, t1, t2); the rest is a pyramid with apex b0 over the quad (b1, b2, t2, t1),
/// cut into two tets along that quad's diagonal.
fn split_prism(bottom: [u32; 3], top: [u32; 3]) -> [[u32; 4]; 3] {
    let smallest = bottom
        .iter()
        .chain(&top)
        .min()
        .copied()
        .unwrap_or(bottom[0]);
    let (mut b, mut t) = if top.contains(&smallest) {
        (top, bottom)
    } else {
        (bottom, top)
    };
    let first = b.iter().position(|&id| id == smallest).unwrap_or(0);
    b.rotate_left(first);
    t.rotate_left(first);
    let cap = [b[0], t[0], t[1], t[2]];
    if b[1].min(t[2]) < b[2].min(t[1]) {
        // Diagonal b1–t2.
        [cap, [b[0], b[1], b[2], t[2]], [b[0], b[1], t[2], t[1]]]
    } else {
        // Diagonal b2–t1.
        [cap, [b[0], b[1], b[2], t[1]], [b[0], b[2], t[2], t[1]]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prism_split_cuts_each_quad_face_through_its_smallest_id() {
        // All 720 orderings of six ids on one prism.
        let mut ids = [0u32, 1, 2, 3, 4, 5];
        let mut checked = 0;
        permutations(&mut ids, 0, &mut |ids: &[u32; 6]| {
            let (bottom, top) = ([ids[0], ids[1], ids[2]], [ids[3], ids[4], ids[5]]);
            let tets = split_prism(bottom, top);
            for i in 0..3 {
                let j = (i + 1) % 3;
                let face = [bottom[i], bottom[j], top[j], top[i]];
                let smallest = *face.iter().min().unwrap();
                let k = face.iter().position(|&id| id == smallest).unwrap();
                let (diagonal_a, diagonal_b) = (face[k], face[(k + 2) % 4]);
                // Some tet has the edge along that diagonal; none the other diagonal.
                let has = |a: u32, b: u32| tets.iter().any(|t| t.contains(&a) && t.contains(&b));
                assert!(has(diagonal_a, diagonal_b), "{ids:?} face {i}");
                assert!(
                    !has(face[(k + 1) % 4], face[(k + 3) % 4]),
                    "{ids:?} face {i}"
                );
            }
            // The tets fill the right prism over the unit triangle, of volume 1/2.
            let position = |id: u32| {
                let k = ids.iter().position(|&i| i == id).unwrap();
                let corner = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]][k % 3];
                Vector3::new(corner[0], corner[1], (k / 3) as f64)
            };
            let volumes = tets.map(|t| tet4_volume(&t.map(position)).abs());
            assert!(volumes.iter().all(|&v| v > 0.1), "{ids:?}: {volumes:?}");
            assert!((volumes.iter().sum::<f64>() - 0.5).abs() < 1e-15, "{ids:?}");
            checked += 1;
        });
        assert_eq!(checked, 720);
    }

    fn permutations(ids: &mut [u32; 6], start: usize, f: &mut impl FnMut(&[u32; 6])) {
        if start == ids.len() {
            f(ids);
            return;
        }
        for i in start..ids.len() {
            ids.swap(start, i);
            permutations(ids, start + 1, f);
            ids.swap(start, i);
        }
    }
}
