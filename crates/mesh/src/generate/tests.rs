use std::collections::{BTreeSet, HashMap};

use super::*;
use crate::MeshError;

const SIZE: [f64; 3] = [0.03, 0.02, 0.05];
const DIVISIONS: [usize; 3] = [3, 2, 4];

/// The three kinds of generated box, with a label for messages.
fn boxes(size: [f64; 3], divisions: [usize; 3]) -> Vec<(&'static str, Mesh)> {
    vec![
        ("hex8", box_of_hexes(size, divisions).unwrap()),
        (
            "tet4",
            box_of_tets(size, divisions, TetOrder::Linear).unwrap(),
        ),
        (
            "tet10",
            box_of_tets(size, divisions, TetOrder::Quadratic).unwrap(),
        ),
    ]
}

fn box_volume(size: [f64; 3]) -> f64 {
    size.iter().product()
}

fn close(a: f64, b: f64, relative: f64) -> bool {
    (a - b).abs() <= relative * b.abs()
}

#[test]
fn generated_boxes_validate_and_fill_the_box() {
    for (size, divisions) in [
        (SIZE, DIVISIONS),
        ([1.0, 1.0, 1.0], [1, 1, 1]),
        ([2.0, 0.5, 1.5], [5, 1, 2]),
    ] {
        for (label, mesh) in boxes(size, divisions) {
            mesh.validate().unwrap_or_else(|e| panic!("{label}: {e}"));
            let cells: usize = divisions.iter().product();
            let per_cell = if label == "hex8" { 1 } else { 6 };
            assert_eq!(mesh.element_count(), cells * per_cell, "{label}");
            assert_eq!(mesh.element_set("all").unwrap().len(), mesh.element_count());
            let total = mesh.total_volume().unwrap();
            assert!(close(total, box_volume(size), 1e-12), "{label}: {total}");
            for &r in mesh.element_set("all").unwrap() {
                let v = mesh.element_volume(r).unwrap();
                assert!(v > 0.0, "{label} {r}: {v}");
            }
        }
    }
}

#[test]
fn outer_surface_is_closed_with_the_box_area() {
    let area = 2.0 * (SIZE[0] * SIZE[1] + SIZE[1] * SIZE[2] + SIZE[2] * SIZE[0]);
    for (label, mesh) in boxes(SIZE, DIVISIONS) {
        let mut sum = Vector3::zeros();
        let mut magnitude = 0.0;
        for &face in mesh.surface("outer").unwrap() {
            let a = mesh.face_area_vector(face).unwrap();
            sum += a;
            magnitude += a.norm();
        }
        assert!(sum.norm() < 1e-12 * area, "{label}: {sum}");
        assert!(
            close(magnitude, area, 1e-12),
            "{label}: {magnitude} vs {area}"
        );
        let named: usize = ["x0", "x1", "y0", "y1", "z0", "z1"]
            .iter()
            .map(|s| mesh.surface(s).unwrap().len())
            .sum();
        assert_eq!(named, mesh.surface("outer").unwrap().len(), "{label}");
    }
}

#[test]
fn named_surfaces_have_the_face_area_and_outward_normal() {
    for (label, mesh) in boxes(SIZE, DIVISIONS) {
        for (name, axis, upper) in BOX_FACES {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let area = SIZE[u] * SIZE[v];
            let mut normal = Vector3::zeros();
            normal[axis] = if upper { 1.0 } else { -1.0 };
            let mut sum = Vector3::zeros();
            for &face in mesh.surface(name).unwrap() {
                let a = mesh.face_area_vector(face).unwrap();
                // Every face of the surface points outward along the box normal.
                assert!(
                    close(a.dot(&normal), a.norm(), 1e-12),
                    "{label} {name} {face}: {a}"
                );
                sum += a;
            }
            assert!(
                (sum - area * normal).norm() < 1e-12 * area,
                "{label} {name}: {sum}"
            );
        }
    }
}

#[test]
fn node_sets_hold_the_nodes_on_each_box_face() {
    let n = DIVISIONS;
    for (label, mesh) in boxes(SIZE, DIVISIONS) {
        for (name, axis, upper) in BOX_FACES {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let expected = if label == "tet10" {
                (2 * n[u] + 1) * (2 * n[v] + 1)
            } else {
                (n[u] + 1) * (n[v] + 1)
            };
            let set = mesh.node_set(name).unwrap();
            assert_eq!(set.len(), expected, "{label} {name}");
            let plane = if upper { SIZE[axis] } else { 0.0 };
            for &id in set {
                assert_eq!(
                    mesh.nodes.position(id as usize)[axis],
                    plane,
                    "{label} {name}"
                );
            }
            // And no other node lies on that plane.
            let on_plane = (0..mesh.node_count())
                .filter(|&i| mesh.nodes.position(i)[axis] == plane)
                .count();
            assert_eq!(on_plane, expected, "{label} {name}");
        }
    }
}

#[test]
fn tet10_has_one_node_per_edge_and_no_duplicates() {
    let [nx, ny, nz] = DIVISIONS;
    let mesh = box_of_tets(SIZE, DIVISIONS, TetOrder::Quadratic).unwrap();
    let corners = (nx + 1) * (ny + 1) * (nz + 1);
    // Lattice edges along x, y, z; one diagonal per lattice face; one per cell.
    let edges = nx * (ny + 1) * (nz + 1)
        + (nx + 1) * ny * (nz + 1)
        + (nx + 1) * (ny + 1) * nz
        + nx * ny * (nz + 1)
        + nx * (ny + 1) * nz
        + (nx + 1) * ny * nz
        + nx * ny * nz;
    assert_eq!(mesh.node_count(), corners + edges);
    // The same count from the tet4 mesh's distinct edges.
    let linear = box_of_tets(SIZE, DIVISIONS, TetOrder::Linear).unwrap();
    let mut distinct = BTreeSet::new();
    for tet in linear.blocks[0].elements() {
        for &[a, b] in ElementShape::Tet4.edges() {
            let (a, b) = (tet[a as usize], tet[b as usize]);
            distinct.insert((a.min(b), a.max(b)));
        }
    }
    assert_eq!(distinct.len(), edges);
    let scale = SIZE.iter().fold(f64::INFINITY, |m, &s| m.min(s));
    for i in 0..mesh.node_count() {
        for j in i + 1..mesh.node_count() {
            let d = (mesh.nodes.position(i) - mesh.nodes.position(j)).norm();
            assert!(d > 1e-6 * scale, "nodes {i} and {j} coincide");
        }
    }
    // Every mid-edge node is at the midpoint of its edge in every element.
    let block = &mesh.blocks[0];
    for ids in block.elements() {
        for (e, &[a, b]) in block.shape.edges().iter().enumerate() {
            let m = ids[block.shape.mid_edge_node(e).unwrap() as usize] as usize;
            let mid = 0.5
                * (mesh.nodes.position(ids[a as usize] as usize)
                    + mesh.nodes.position(ids[b as usize] as usize));
            assert!((mesh.nodes.position(m) - mid).norm() < 1e-15);
        }
    }
}

#[test]
fn tet_split_is_conforming() {
    let [nx, ny, nz] = DIVISIONS;
    let mesh = box_of_tets(SIZE, DIVISIONS, TetOrder::Linear).unwrap();
    let mut count: HashMap<[u32; 3], usize> = HashMap::new();
    for tet in mesh.blocks[0].elements() {
        for skip in 0..4 {
            let mut key: Vec<u32> = (0..4).filter(|&i| i != skip).map(|i| tet[i]).collect();
            key.sort_unstable();
            *count.entry([key[0], key[1], key[2]]).or_insert(0) += 1;
        }
    }
    let mut boundary = 0;
    for (key, n) in &count {
        let points: Vec<_> = key
            .iter()
            .map(|&i| mesh.nodes.position(i as usize))
            .collect();
        let on_box = (0..3)
            .any(|d| points.iter().all(|p| p[d] == 0.0) || points.iter().all(|p| p[d] == SIZE[d]));
        let expected = if on_box { 1 } else { 2 };
        assert_eq!(*n, expected, "face {key:?}");
        boundary += usize::from(on_box);
    }
    assert_eq!(boundary, 4 * (nx * ny + ny * nz + nz * nx));
}

#[test]
fn generators_reject_unusable_arguments() {
    for (size, divisions) in [
        ([0.0, 1.0, 1.0], [1, 1, 1]),
        ([1.0, f64::NAN, 1.0], [1, 1, 1]),
        ([1.0; 3], [1, 0, 1]),
    ] {
        let e = box_of_hexes(size, divisions).unwrap_err();
        assert!(
            matches!(
                e,
                MeshError::InvalidArgument {
                    generator: "box_of_hexes",
                    ..
                }
            ),
            "{e}"
        );
        let e = box_of_tets(size, divisions, TetOrder::Linear).unwrap_err();
        assert!(
            matches!(
                e,
                MeshError::InvalidArgument {
                    generator: "box_of_tets",
                    ..
                }
            ),
            "{e}"
        );
    }
    let e = box_of_hexes([1.0; 3], [2000, 2000, 2000]).unwrap_err();
    assert!(e.to_string().contains("2^32"), "{e}");
}

#[test]
fn distortion_is_valid_reproducible_and_keeps_the_boundary() {
    for (label, original) in boxes(SIZE, [4, 3, 4]) {
        let mut mesh = original.clone();
        let moved = distort(&mut mesh, 0.3, 7).unwrap();
        let interior_corners = 3 * 2 * 3;
        assert_eq!(
            moved, interior_corners,
            "{label}: every interior corner moves"
        );
        mesh.validate().unwrap_or_else(|e| panic!("{label}: {e}"));
        let total = mesh.total_volume().unwrap();
        assert!(close(total, box_volume(SIZE), 1e-12), "{label}: {total}");
        let outer: BTreeSet<u32> = mesh
            .surface("outer")
            .unwrap()
            .iter()
            .flat_map(|f| f.nodes(&mesh).unwrap().to_vec())
            .collect();
        let mut changed = 0;
        for i in 0..mesh.node_count() {
            let d = (mesh.nodes.position(i) - original.nodes.position(i)).norm();
            if outer.contains(&(i as u32)) {
                assert_eq!(d, 0.0, "{label}: boundary node {i} moved");
            } else if d > 0.0 {
                changed += 1;
                assert!(d <= 0.3 * 0.01, "{label}: node {i} moved {d} m");
            }
        }
        assert!(changed >= interior_corners, "{label}: {changed}");
        let mut again = original.clone();
        distort(&mut again, 0.3, 7).unwrap();
        assert_eq!(again.nodes, mesh.nodes, "{label}: same seed, same mesh");
        let mut other = original.clone();
        distort(&mut other, 0.3, 8).unwrap();
        assert_ne!(
            other.nodes, mesh.nodes,
            "{label}: another seed, another mesh"
        );
    }
    let mut mesh = box_of_hexes(SIZE, DIVISIONS).unwrap();
    assert!(distort(&mut mesh, -0.1, 1).is_err());
    assert!(distort(&mut mesh, f64::INFINITY, 1).is_err());
}

#[test]
fn large_distortion_stays_valid() {
    for (label, mut mesh) in boxes(SIZE, DIVISIONS) {
        distort(&mut mesh, 0.9, 3).unwrap();
        mesh.validate().unwrap_or_else(|e| panic!("{label}: {e}"));
        assert!(
            close(mesh.total_volume().unwrap(), box_volume(SIZE), 1e-12),
            "{label}"
        );
    }
}
