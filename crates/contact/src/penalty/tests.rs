//! The closest-point search against a brute-force search over all triangles.

use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::{Interaction, RigidMotion, RigidRotation};
use musclefem_materials::Amplitude;
use nalgebra::Unit;

use super::*;
use crate::rigid_surface::RigidSurface;

/// The closest point over all triangles by brute force: (squared distance, triangle).
fn brute_force(x: &Vector3<f64>, corners: &[[Vector3<f64>; 3]]) -> (f64, usize) {
    let mut best = (f64::INFINITY, usize::MAX);
    for (t, c) in corners.iter().enumerate() {
        let (w, _) = closest_feature(x, c);
        let d = (x - (c[0] * w[0] + c[1] * w[1] + c[2] * w[2])).norm_squared();
        if d < best.0 {
            best = (d, t);
        }
    }
    best
}

/// With the candidate lists reused (nodes and a turning sphere moved since the query,
/// within the Verlet margin) and the last winners measured first, every node within
/// the search distance finds the same closest triangle and gap as a search over all
/// triangles.
#[test]
fn reused_candidates_give_the_brute_force_closest_point_on_a_moving_sphere() {
    let mesh = box_of_hexes([1.0, 1.0, 1.0], [5, 5, 5]).unwrap();
    let secondary = DeformableSurface::from_mesh_surface(&mesh, "outer").unwrap();
    let motion = RigidMotion {
        translation: [Some(Amplitude::ramp(1.0, 0.3).unwrap()), None, None],
        rotation: Some(RigidRotation {
            center: Vector3::new(0.0, 0.1, 0.0),
            axis: Unit::new_normalize(Vector3::new(1.0, 2.0, 0.5)),
            angle: Amplitude::ramp(1.0, 0.5).unwrap(),
        }),
        follower: None,
    };
    let sphere = RigidSurface::sphere("ball", Vector3::zeros(), 1.0, 3)
        .unwrap()
        .with_motion(motion.clone());
    let search_distance = 0.1;
    let mut contact = PenaltyContact::new("test", secondary.clone(), sphere.clone(), 1e6)
        .unwrap()
        .with_search_distance(search_distance)
        .unwrap();
    // Each surface node at a reproducible point near the sphere (radius 0.92–1.08),
    // placed in the sphere's frame at time `t`, then moved by `shift`.
    let place = |t: f64, shift: f64| {
        let iso = motion.isometry_at(t);
        let mut positions = vec![Vector3::zeros(); mesh.node_count()];
        for (i, &n) in secondary.nodes.iter().enumerate() {
            let f = |a: f64| ((i as f64 + 1.0) * a).fract();
            let direction = Vector3::new(
                f(0.754877666) - 0.5,
                f(0.569840291) - 0.5,
                f(0.362345) - 0.5,
            )
            .normalize();
            let body = direction * (0.92 + 0.16 * f(0.2718281));
            positions[n as usize] =
                iso.transform_point(&Point3::from(body)).coords + Vector3::repeat(shift);
        }
        positions
    };
    let (start, later) = (0.5, 0.52);
    let mut force = vec![Vector3::zeros(); mesh.node_count()];
    // The first evaluation leaves each node's winner, measured first by the second.
    let positions = place(start, 0.0);
    contact.search(start, &positions).unwrap();
    contact
        .forces(start, &positions, false, &mut force)
        .unwrap();
    let positions = place(later, 0.01);
    contact.search(later, &positions).unwrap();
    let statistics = contact.broadphase().statistics();
    assert_eq!(
        (statistics.searches, statistics.queries),
        (2, 1),
        "the second search must reuse the lists"
    );
    contact
        .forces(later, &positions, false, &mut force)
        .unwrap();

    let iso = motion.isometry_at(later);
    let corners: Vec<[Vector3<f64>; 3]> = sphere
        .triangles
        .iter()
        .map(|t| t.map(|v| sphere.vertices[v as usize]))
        .collect();
    let mut compared = 0;
    for (i, &n) in secondary.nodes.iter().enumerate() {
        let body = iso
            .inverse_transform_point(&Point3::from(positions[n as usize]))
            .coords;
        let (distance2, triangle) = brute_force(&body, &corners);
        if distance2.sqrt() > search_distance {
            continue;
        }
        let found = &contact.contacts[i];
        assert_eq!(found.triangle as usize, triangle, "node {n}");
        let gap = project_on_triangle(&body, &corners[triangle]).gap;
        assert_eq!(found.gap, gap, "node {n}");
        compared += 1;
    }
    assert!(compared > 50, "the test must compare nodes: {compared}");
}

/// Per-node penalties: a node pressed into a plane carries ε_i A_i g, its own ε, in both
/// the closest-point and the smooth contact; a wrong count or value is refused.
#[test]
fn each_node_carries_its_own_penalty() {
    let mesh = box_of_hexes([1.0, 1.0, 1.0], [2, 2, 2]).unwrap();
    let secondary = DeformableSurface::from_mesh_surface(&mesh, "z0").unwrap();
    let plane =
        RigidSurface::plane("floor", Vector3::new(0.5, 0.5, 0.0), Vector3::z(), 2.0, 4).unwrap();
    let count = secondary.nodes.len();
    let penalties: Vec<f64> = (0..count).map(|i| 1e6 * (1.0 + i as f64)).collect();
    // Every node of the bottom face 1 mm into the floor.
    let positions: Vec<Vector3<f64>> = (0..mesh.node_count())
        .map(|n| mesh.nodes.position(n) - Vector3::new(0.0, 0.0, 1e-3))
        .collect();
    for smooth in [false, true] {
        let mut contact = PenaltyContact::new("test", secondary.clone(), plane.clone(), 1e6)
            .unwrap()
            .with_node_penalties(penalties.clone())
            .unwrap();
        if smooth {
            contact = contact.with_smooth_normals();
        }
        let mut force = vec![Vector3::zeros(); mesh.node_count()];
        contact.search(0.0, &positions).unwrap();
        contact.forces(0.0, &positions, true, &mut force).unwrap();
        for (i, &node) in secondary.nodes.iter().enumerate() {
            // f_c = ε A g ν (it enters like an internal force): g = −1 mm along +z.
            let expected = -penalties[i] * secondary.node_area[i] * 1e-3;
            let f = force[node as usize];
            assert!(
                (f.z - expected).abs() < 1e-9 * expected.abs() && f.xy().norm() < 1e-12,
                "smooth {smooth}, node {node}: {f:?} against {expected}"
            );
        }
    }
    let contact = PenaltyContact::new("test", secondary.clone(), plane, 1e6).unwrap();
    assert!(
        contact
            .clone()
            .with_node_penalties(vec![1e6; count - 1])
            .is_err()
    );
    let mut bad = vec![1e6; count];
    bad[0] = f64::NAN;
    assert!(contact.with_node_penalties(bad).is_err());
}
