//! The projection along the normal field on one triangle (flat and tilted normals) and the
//! walk across a strip and past its rim.

use super::*;
use crate::projection::project_on_triangle;
use crate::rigid_surface::RigidSurface;
use crate::test_surfaces::{CORNERS, face_normal, point_over, tilted};

#[test]
fn on_a_flat_triangle_the_projection_is_the_orthogonal_one() {
    let n = face_normal(&CORNERS);
    let [x0, x1, x2] = CORNERS;
    // Over the face, past an edge and past a corner (extrapolated), above and below.
    for (xi1, xi2, g) in [
        (0.3, 0.2, 0.15),
        (0.6, 0.7, -0.08),
        (-0.4, 1.6, 0.3),
        (0.25, 0.25, 0.0),
    ] {
        let x = x0 + xi1 * (x1 - x0) + xi2 * (x2 - x0) + g * n;
        let p = project_along_normals(&x, &CORNERS, &[n; 3]);
        let expected = Vector3::new(1.0 - xi1 - xi2, xi1, xi2);
        assert!(
            (p.barycentric - expected).norm() < 1e-14,
            "{:?}",
            p.barycentric
        );
        assert!((p.along - g).abs() < 1e-15 && (p.gap() - g).abs() < 1e-15);
        assert!((p.normal - n).norm() < 1e-15);
        if xi1 + xi2 <= 1.0 && xi1 >= 0.0 && xi2 >= 0.0 {
            // The closest point of the narrowphase.
            let closest = project_on_triangle(&x, &CORNERS);
            assert!((closest.gap - p.gap()).abs() < 1e-14);
            let phi: Vector3<f64> = closest.barycentric.into();
            assert!((phi - p.barycentric).norm() < 1e-14);
        }
    }
}

#[test]
fn with_tilted_vertex_normals_the_projection_solves_its_equation() {
    let normals = tilted(&CORNERS);
    let [x0, x1, x2] = CORNERS;
    let flat = face_normal(&CORNERS);
    for (phi, along) in [
        ([0.3, 0.45, 0.25], 0.2),
        ([0.5, 0.49, 0.01], -0.1),
        ([1.3, -0.2, -0.1], 0.35),
        ([0.1, 0.1, 0.8], 0.0),
    ] {
        let x = point_over(&CORNERS, &normals, phi, along);
        let p = project_along_normals(&x, &CORNERS, &normals);
        let [_, xi1, xi2] = p.barycentric.into();
        let normal = (1.0 - xi1 - xi2) * normals[0] + xi1 * normals[1] + xi2 * normals[2];
        let residual = x0 + xi1 * (x1 - x0) + xi2 * (x2 - x0) + p.along * normal - x;
        assert!(residual.norm() < 1e-12, "{residual}");
        assert!((p.normal - normal).norm() < 1e-15);
        assert!((p.barycentric - Vector3::from(phi)).norm() < 1e-12);
        assert!((p.along - along).abs() < 1e-12);
        assert_eq!(p.normals, normals);
        if along != 0.0 {
            // Not the orthogonal projection.
            let orthogonal = project_along_normals(&x, &CORNERS, &[flat; 3]);
            assert!((orthogonal.barycentric - p.barycentric).norm() > 1e-3);
        }
    }
    // Normals aimed at one point C, equally far from the corners: every foot reaches C
    // with g = |C − x_k| (J singular there). Projecting C gives the flat projection.
    let (a, b) = (x1 - x0, x2 - x0);
    let circumcentre = x0
        + (a.norm_squared() * b - b.norm_squared() * a).cross(&a.cross(&b))
            / (2.0 * a.cross(&b).norm_squared());
    let x = circumcentre + 0.5 * flat;
    let focus = CORNERS.map(|c| (x - c).normalize());
    assert!(((x - x0).norm() - (x - x1).norm()).abs() < 1e-14);
    let p = project_along_normals(&x, &CORNERS, &focus);
    let orthogonal = project_along_normals(&x, &CORNERS, &[flat; 3]);
    assert_eq!(p, orthogonal);
    assert_eq!(p.normals, [flat; 3]);
}

#[test]
fn a_walk_crosses_the_surface_and_keeps_the_plane_of_the_rim_past_it() {
    // A strip of 20 unit squares on z = 0 along x (40 triangles).
    let vertices = (0..=20)
        .flat_map(|i| [0.0, 1.0].map(|y| Vector3::new(f64::from(i), y, 0.0)))
        .collect();
    let triangles = (0..20u32)
        .flat_map(|i| {
            let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
            [[a, b, c], [a, c, d]]
        })
        .collect();
    let main: ContactTarget = RigidSurface::new("strip", vertices, triangles)
        .unwrap()
        .into();
    let field = NormalField::new(&main, &[]);
    // Triangle 0 = [0, 2, 3]: edge 0 (0–2) on the rim, edge 1 (2–3) shared with triangle
    // 3 = [2, 5, 3], edge 2 (3–0) with triangle 1 = [0, 3, 1], whose other edges are rim.
    assert_eq!(field.across[0], [RIM, 3, 1]);
    assert_eq!(field.across[1], [0, RIM, RIM]);
    assert_eq!(field.across[3], [2, RIM, 0]);
    assert!(field.normals.iter().all(|n| *n == Vector3::z()));
    let at = (&[][..], &Isometry3::identity());
    let x = Vector3::new(13.7, 0.6, 0.5);
    let foot = walk(&field, &main, at, 99, 0, &x);
    assert_eq!(foot.triangle / 2, 13);
    let [a, b, c] = main.corners(foot.triangle as usize, &[], at.1);
    let phi = foot.projection.barycentric;
    let point = phi.x * a + phi.y * b + phi.z * c;
    assert!((point - Vector3::new(13.7, 0.6, 0.0)).norm() < 1e-14);
    assert!((foot.projection.gap() - 0.5).abs() < 1e-15);
    // Past the end of the strip (x = 20) the foot extrapolates the rim triangle's plane.
    let x = Vector3::new(21.5, 0.3, -0.2);
    let foot = walk(&field, &main, at, 99, foot.triangle, &x);
    assert_eq!(foot.triangle / 2, 19);
    assert!(foot.projection.barycentric.min() < -1.0);
    assert!((foot.projection.gap() + 0.2).abs() < 1e-14);
    // Past a side rim (y > 1), beside square 5: walks along the rim to it.
    let x = Vector3::new(5.5, 1.4, 0.1);
    let foot = walk(&field, &main, at, 99, 0, &x);
    assert_eq!(foot.triangle / 2, 5);
    assert!((foot.projection.gap() - 0.1).abs() < 1e-14);
}

#[test]
fn normals_updated_around_some_triangles_are_the_full_updates_bits() {
    use crate::surface::DeformableSurface;
    use musclefem_core::mesh::generate::box_of_hexes;
    // The outer surface of a box of 4 × 3 × 2 hexahedra, its nodes moved off the box.
    let mesh = box_of_hexes([1.0, 0.8, 0.5], [4, 3, 2]).unwrap();
    let block = mesh.blocks[0].name.clone();
    let surface = DeformableSurface::outer_surface(&mesh, &[&block]).unwrap();
    let positions: Vec<Vector3<f64>> = (0..mesh.node_count())
        .map(|n| {
            let x = mesh.nodes.position(n);
            let s = n as f64;
            x + 0.03 * Vector3::new((1.3 * s).sin(), (0.7 * s).cos(), (2.1 * s).sin())
        })
        .collect();
    let main = ContactTarget::Deformable(surface.clone());
    let mut full = NormalField::new(&main, &[]);
    full.update(&main, &positions);
    let mut some = NormalField::new(&main, &[]);
    let chosen = [3u32, 3, 17, 40, 41];
    some.update_around(&main, &positions, chosen.iter().copied());
    let identity = UnitQuaternion::identity();
    for t in 0..surface.triangles.len() {
        // Bit for bit, whether the corners were updated or are computed on demand.
        assert_eq!(
            some.normals_at(t, &main, &positions, &identity),
            full.normals(t, &identity),
            "triangle {t}"
        );
    }
    // Only the chosen triangles' corners were updated; the others were computed on demand.
    let updated = some.current.iter().filter(|c| **c).count();
    assert!((3..=3 * 4).contains(&updated), "{updated} updated");
    assert!(updated < surface.nodes.len());
}
