//! The interface's forces, stiffness, commit and report on single bonds.

use musclefem_core::mesh::{Mesh, Nodes};
use musclefem_core::solver::{Interaction, RigidMotion, RigidRotation};
use musclefem_materials::Amplitude;
use nalgebra::{DMatrix, Matrix3, Unit, Vector3};

use super::*;
use crate::rigid_surface::RigidSurface;

fn settings(tangential: TangentialMode) -> CohesiveSettings {
    CohesiveSettings {
        normal_stiffness: 1e3,
        shear_stiffness: 1e3,
        tangential_stiffness: 1e3,
        initiation_separation: 0.01,
        failure_separation: 0.03,
        tangential,
        bond_tolerance: 1e-6,
    }
}

/// Main triangle nodes 0, 1, 2 on z = 0, secondary node 3 on it at (0.3, 0.2, 0), and
/// nodes 4, 5 of the secondary triangle [3, 4, 5], away from the main triangle (they do
/// not bond). Node 3's tributary area is a third of that triangle's 1.5 m², 0.5 m².
fn reference() -> Vec<Vector3<f64>> {
    vec![
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(0.3, 0.2, 0.0),
        Vector3::new(0.9, 0.2, 0.8),
        Vector3::new(0.3, 3.2, 0.0),
    ]
}

fn mesh(points: &[Vector3<f64>]) -> Mesh {
    let mut nodes = Nodes::new();
    for p in points {
        nodes.push(*p);
    }
    Mesh::new(nodes, vec![])
}

fn surfaces(mesh: &Mesh) -> (DeformableSurface, DeformableSurface) {
    let top = DeformableSurface::from_triangles(mesh, "top", vec![[3, 4, 5]]).unwrap();
    let bottom = DeformableSurface::from_triangles(mesh, "bottom", vec![[0, 1, 2]]).unwrap();
    (top, bottom)
}

fn deformable(settings: &CohesiveSettings) -> CohesiveInterface {
    let mesh = mesh(&reference());
    let (top, bottom) = surfaces(&mesh);
    let interface = CohesiveInterface::new("glue", &top, bottom, &mesh, settings).unwrap();
    assert_eq!(interface.bond_count(), 1);
    assert!((interface.bonded_reference_area() - 0.5).abs() < 1e-14);
    interface
}

fn all_forces(interface: &mut CohesiveInterface, time: f64, x: &[Vector3<f64>]) -> Vec<f64> {
    let mut force = vec![Vector3::zeros(); x.len()];
    interface.search(time, x).unwrap();
    interface.forces(time, x, true, &mut force).unwrap();
    force.iter().flat_map(|f| f.iter().copied()).collect()
}

/// The assembled stiffness against central differences of the forces.
/// Checks the stiffness against central differences of the forces (1e-6 of its largest
/// entry); returns its asymmetry max |K − Kᵀ| relative to that entry.
fn check_stiffness(interface: &mut CohesiveInterface, time: f64, x: &[Vector3<f64>]) -> f64 {
    let n = 3 * x.len();
    all_forces(interface, time, x);
    let mut k = DMatrix::<f64>::zeros(n, n);
    interface.stiffness(&mut |a, b, block: &Matrix3<f64>| {
        for i in 0..3 {
            for j in 0..3 {
                k[(3 * a as usize + i, 3 * b as usize + j)] += block[(i, j)];
            }
        }
    });
    let h = 1e-7;
    let scale = k.amax();
    for column in 0..n {
        let mut plus = x.to_vec();
        let mut minus = x.to_vec();
        plus[column / 3][column % 3] += h;
        minus[column / 3][column % 3] -= h;
        let fp = all_forces(interface, time, &plus);
        let fm = all_forces(interface, time, &minus);
        for row in 0..n {
            let fd = (fp[row] - fm[row]) / (2.0 * h);
            assert!(
                (fd - k[(row, column)]).abs() <= 1e-6 * scale,
                "K[{row}][{column}] = {} vs {fd}",
                k[(row, column)]
            );
        }
    }
    (&k - k.transpose()).amax() / scale
}

#[test]
fn an_opened_bond_pulls_its_node_back_and_the_main_nodes_take_the_reaction() {
    let mut interface = deformable(&settings(TangentialMode::Elastic));
    let mut x = reference();
    x[3].z += 0.004;
    let f = all_forces(&mut interface, 0.0, &x);
    // f_s = A K δ n = 0.5 × 1e3 × 0.004 along +z (it enters like an internal force).
    assert!((f[11] - 2.0).abs() < 1e-12);
    // Reactions −ξ f_s, ξ = (0.5, 0.3, 0.2).
    assert!((f[2] + 1.0).abs() < 1e-12 && (f[5] + 0.6).abs() < 1e-12);
    assert!((f[8] + 0.4).abs() < 1e-12);
    let report = interface.report();
    assert!((report.force - Vector3::new(0.0, 0.0, -2.0)).norm() < 1e-12);
    assert_eq!(report.active_points, 1);
    assert!((report.active_area - 0.5).abs() < 1e-14);
    assert!((report.stored_energy - 0.5 * 0.5 * 1e3 * 0.004 * 0.004).abs() < 1e-15);
    let fields = interface.nodal_fields(4);
    assert_eq!(fields[0].name, "cohesive_traction");
    let traction = Vector3::from_column_slice(&fields[0].values[9..12]);
    assert!((traction - Vector3::new(0.0, 0.0, -4.0)).norm() < 1e-12);
    assert!(fields[0].values[..9].iter().all(|&v| v == 0.0));
}

#[test]
fn a_bond_formed_across_a_gap_rests_at_that_gap_in_both_modes() {
    for mode in [TangentialMode::FreeSlide, TangentialMode::Elastic] {
        // Node 3 starts 3 mm above the main triangle and bonds within 5 mm.
        let mut x = reference();
        x[3].z = 0.003;
        let mesh = mesh(&x);
        let (top, bottom) = surfaces(&mesh);
        let gap_settings = CohesiveSettings {
            bond_tolerance: 0.005,
            ..settings(mode)
        };
        let mut interface =
            CohesiveInterface::new("glue", &top, bottom, &mesh, &gap_settings).unwrap();
        assert_eq!(interface.bond_count(), 1);
        // Node 3's tributary area, a third of its (slightly tilted) triangle.
        let area = interface.bonded_reference_area();
        assert!((area - 0.5).abs() < 1e-2);
        let f = all_forces(&mut interface, 0.0, &x);
        // Zero to round-off (forces of the next checks are ~1 N).
        assert!(f.iter().all(|&v| v.abs() < 1e-13), "{mode:?}: {f:?}");
        assert!(interface.report().stored_energy < 1e-25);
        // Opening by 4 mm from the rest gap: f_s = A K δ with δ = 0.004 (not 0.007).
        x[3].z += 0.004;
        let f = all_forces(&mut interface, 0.0, &x);
        assert!((f[11] - area * 4.0).abs() < 1e-12, "{mode:?}: {}", f[11]);
        // Pressing 1 mm below the rest gap pushes back.
        x[3].z = 0.002;
        let f = all_forces(&mut interface, 0.0, &x);
        assert!((f[11] + area).abs() < 1e-12, "{mode:?}: {}", f[11]);
        check_stiffness(&mut interface, 0.0, &x);
    }
}

/// A node that bonds past the main triangle's edge (rest state with in-plane parts) keeps
/// a consistent, symmetric stiffness while the main triangle moves, tilts and stretches:
/// its rest offset turns with the triangle's frame, in-plane parts included, and the
/// forces are the gradient of the bond's energy, so they balance forces and moments.
#[test]
fn an_edge_bond_across_a_gap_is_a_spring_whose_rest_offset_turns_with_the_main() {
    let mut x = reference();
    // Beyond the hypotenuse x + y = 1, 2 mm above the plane: the closest point is on it.
    x[3] = Vector3::new(0.6, 0.5, 0.002);
    let mesh = mesh(&x);
    let (top, bottom) = surfaces(&mesh);
    // Elastic range throughout (as in the knee, where damage starts at 30 mm): the law
    // is K δ, and the force A K (δ − R δ_ref) depends on the frame only through R δ_ref.
    let edge_settings = CohesiveSettings {
        bond_tolerance: 0.1,
        initiation_separation: 1.0,
        failure_separation: 3.0,
        ..settings(TangentialMode::Elastic)
    };
    let mut interface =
        CohesiveInterface::new("glue", &top, bottom, &mesh, &edge_settings).unwrap();
    assert_eq!(interface.bond_count(), 1);
    assert!(
        all_forces(&mut interface, 0.0, &x)
            .iter()
            .all(|&v| v.abs() < 1e-12)
    );
    // Turning the whole pair rigidly leaves the bond at rest.
    let turn = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), 0.4)
        * nalgebra::Rotation3::from_axis_angle(&Vector3::x_axis(), 0.3);
    let turned: Vec<Vector3<f64>> = x.iter().map(|p| turn * p).collect();
    let f = all_forces(&mut interface, 0.0, &turned);
    assert!(f.iter().all(|&v| v.abs() < 1e-12), "{f:?}");
    x[0] += Vector3::new(0.01, -0.02, 0.005);
    x[1] += Vector3::new(0.03, 0.01, 0.1);
    x[2] += Vector3::new(-0.02, 0.04, -0.05);
    x[3] += Vector3::new(0.008, -0.006, 0.012);
    let asymmetry = check_stiffness(&mut interface, 0.0, &x);
    assert!(asymmetry < 1e-9, "{asymmetry:e}");
    assert!(interface.symmetric_stiffness());
    // Σ f = 0 and Σ x × f = 0: the bond pulls the main triangle where it should.
    let f = all_forces(&mut interface, 0.0, &x);
    let forces: Vec<Vector3<f64>> = f.chunks(3).map(Vector3::from_column_slice).collect();
    let total: Vector3<f64> = forces.iter().sum();
    let moment: Vector3<f64> = x.iter().zip(&forces).map(|(p, f)| p.cross(f)).sum();
    let scale = forces.iter().map(|f| f.norm()).fold(0.0, f64::max);
    assert!(scale > 1.0, "{scale}");
    assert!(total.norm() < 1e-12 * scale, "{total}");
    assert!(moment.norm() < 1e-12 * scale, "{moment}");
    // f = ∂E/∂x, E the stored energy (central differences).
    let energy = |interface: &mut CohesiveInterface, at: &[Vector3<f64>]| {
        all_forces(interface, 0.0, at);
        interface.report().stored_energy
    };
    let h = 1e-7;
    for (i, fi) in f.iter().enumerate() {
        let (mut plus, mut minus) = (x.clone(), x.clone());
        plus[i / 3][i % 3] += h;
        minus[i / 3][i % 3] -= h;
        let gradient = (energy(&mut interface, &plus) - energy(&mut interface, &minus)) / (2.0 * h);
        assert!(
            (gradient - fi).abs() < 1e-6 * scale,
            "{i}: {gradient} vs {fi}"
        );
    }
}

#[test]
fn damage_waits_for_commit_and_never_heals() {
    let mut interface = deformable(&settings(TangentialMode::Elastic));
    let mut x = reference();
    x[3].z += 0.02;
    all_forces(&mut interface, 0.0, &x);
    // D(0.02) = 0.03 × 0.01 / (0.02 × 0.02) = 0.75; a trial is not committed.
    assert!((interface.bond_states().next().unwrap().2 - 0.75).abs() < 1e-14);
    x[3].z = 0.005;
    all_forces(&mut interface, 0.0, &x);
    assert_eq!(interface.bond_states().next().unwrap().2, 0.0);
    x[3].z = 0.02;
    all_forces(&mut interface, 0.0, &x);
    interface.commit();
    x[3].z = 0.005;
    let f = all_forces(&mut interface, 0.0, &x);
    assert!((f[11] - 0.25 * 0.5 * 1e3 * 0.005).abs() < 1e-12);
    assert!((interface.report().bonded_area - 0.5).abs() < 1e-15);
    x[3].z = 0.04;
    all_forces(&mut interface, 0.0, &x);
    interface.commit();
    assert_eq!(interface.report().bonded_area, 0.0);
    // Failed, pressed: the normal stiffness still resists.
    x[3].z = -0.001;
    let f = all_forces(&mut interface, 0.0, &x);
    assert!((f[11] + 0.5 * 1e3 * 0.001).abs() < 1e-12);
}

#[test]
fn the_stiffness_is_consistent_with_a_deformable_main_in_elastic_opening() {
    let mut interface = deformable(&settings(TangentialMode::Elastic));
    let mut x = reference();
    // The main triangle moved, tilted and stretched; the node opened into softening.
    x[0] += Vector3::new(0.01, -0.02, 0.005);
    x[1] += Vector3::new(0.03, 0.01, 0.1);
    x[2] += Vector3::new(-0.02, 0.04, -0.05);
    x[3] += Vector3::new(0.008, -0.006, 0.012);
    check_stiffness(&mut interface, 0.0, &x);
    // Unloading after damage (secant).
    all_forces(&mut interface, 0.0, &x);
    interface.commit();
    x[3] -= Vector3::new(0.002, 0.0, 0.006);
    check_stiffness(&mut interface, 0.0, &x);
}

fn rigid(tangential: TangentialMode, stiffness: [f64; 3]) -> CohesiveInterface {
    let ramp = |v| Some(Amplitude::ramp(1.0, v).unwrap());
    let motion = RigidMotion {
        translation: [ramp(0.01), None, ramp(-0.02)],
        rotation: Some(RigidRotation {
            center: Vector3::new(0.2, 0.1, 0.0),
            axis: Unit::new_normalize(Vector3::new(1.0, 1.0, 0.3)),
            angle: Amplitude::ramp(1.0, 0.4).unwrap(),
        }),
        follower: None,
    };
    let femur = RigidSurface::new("femur", reference()[..3].to_vec(), vec![[0, 1, 2]])
        .unwrap()
        .with_motion(motion);
    let [kn, ks, kt] = stiffness;
    let s = CohesiveSettings {
        normal_stiffness: kn,
        shear_stiffness: ks,
        tangential_stiffness: kt,
        ..settings(tangential)
    };
    // The secondary node 0 at (0.3, 0.2, 0) with 0.7 m² (a third of 2.1 m²); nodes 1 and
    // 2 away from the main triangle.
    let mut points = interface_mesh_positions();
    points[0] = Vector3::new(0.3, 0.2, 0.0);
    let mesh = mesh(&points);
    let muscle = DeformableSurface::from_triangles(&mesh, "muscle", vec![[0, 1, 2]]).unwrap();
    let interface = CohesiveInterface::new("bone", &muscle, femur, &mesh, &s).unwrap();
    assert!((interface.bonded_reference_area() - 0.7).abs() < 1e-14);
    interface
}

#[test]
fn the_stiffness_is_consistent_with_a_rigid_main_in_every_mode() {
    for (mode, k) in [
        (TangentialMode::Elastic, [1e3, 1e3, 1e3]),
        (TangentialMode::Elastic, [1e3, 4e2, 7e2]),
        (TangentialMode::FreeSlide, [1e3, 4e2, 7e2]),
    ] {
        let mut interface = rigid(mode, k);
        assert_eq!(
            interface.symmetric_stiffness(),
            mode == TangentialMode::FreeSlide || k[0] == k[1]
        );
        // Where the bonded point goes at t = 0.6, plus a separation in softening.
        let placement = interface.main.placement(0.6);
        let point = placement * nalgebra::Point3::new(0.3, 0.2, 0.0);
        let mut x = interface_mesh_positions();
        x[0] = point.coords + Vector3::new(0.006, 0.009, 0.011);
        check_stiffness(&mut interface, 0.6, &x);
    }
}

#[test]
fn a_rigid_main_follows_its_motion() {
    let mut interface = rigid(TangentialMode::Elastic, [1e3; 3]);
    let placement = interface.main.placement(1.0);
    let point = placement * nalgebra::Point3::new(0.3, 0.2, 0.0);
    let normal = placement * Vector3::z();
    let mut x = interface_mesh_positions();
    x[0] = point.coords + 0.004 * normal;
    let f = all_forces(&mut interface, 1.0, &x);
    let expected = 0.7 * 1e3 * 0.004 * normal;
    assert!((Vector3::from_column_slice(&f[..3]) - expected).norm() < 1e-12);
    assert!(f[3..].iter().all(|&v| v == 0.0));
    let (_, separation, _) = interface.bond_states().next().unwrap();
    assert!((separation - Vector3::new(0.004, 0.0, 0.0)).norm() < 1e-15);
}

/// The positions of the rigid cases' mesh (3 nodes).
fn interface_mesh_positions() -> Vec<Vector3<f64>> {
    vec![
        Vector3::zeros(),
        Vector3::new(0.9, 0.2, 0.8),
        Vector3::new(0.3, 4.4, 0.0),
    ]
}

#[test]
fn nothing_within_the_tolerance_is_an_error_naming_the_interface_and_surfaces() {
    let mut x = reference();
    x[3].z = 0.01;
    let mesh = mesh(&x);
    let (top, bottom) = surfaces(&mesh);
    let error = CohesiveInterface::new(
        "glue",
        &top,
        bottom,
        &mesh,
        &settings(TangentialMode::Elastic),
    )
    .unwrap_err()
    .to_string();
    for part in ["'glue'", "'top'", "'bottom'", "1.000e-6 m", "1.000e-2 m"] {
        assert!(error.contains(part), "{error}");
    }
}

/// A fixed rigid pyramid: apex (0, 0, 0.3) over the square (±1, ±1, 0), four faces
/// facing up and out; its apex and the edges to it are interior.
fn pyramid() -> RigidSurface {
    let vertices = vec![
        Vector3::new(-1.0, -1.0, 0.0),
        Vector3::new(1.0, -1.0, 0.0),
        Vector3::new(1.0, 1.0, 0.0),
        Vector3::new(-1.0, 1.0, 0.0),
        Vector3::new(0.0, 0.0, 0.3),
    ];
    let triangles = (0..4u32).map(|i| [i, (i + 1) % 4, 4]).collect();
    RigidSurface::new("pyramid", vertices, triangles).unwrap()
}

#[test]
fn sliding_bonds_have_a_consistent_stiffness_over_faces_edges_and_vertices() {
    let apex = Vector3::new(0.0, 0.0, 0.3);
    let mut points = interface_mesh_positions();
    points[0] = apex;
    let mesh = mesh(&points);
    let muscle = DeformableSurface::from_triangles(&mesh, "muscle", vec![[0, 1, 2]]).unwrap();
    let mut interface = CohesiveInterface::new(
        "slide",
        &muscle,
        pyramid(),
        &mesh,
        &settings(TangentialMode::FreeSlide),
    )
    .unwrap();
    let face_normal = |i: usize| {
        let p = pyramid();
        let [a, b, c] = p.triangles[i].map(|v| p.vertices[v as usize]);
        (b - a).cross(&(c - a)).normalize()
    };
    let edge_midpoint = 0.5 * (apex + Vector3::new(1.0, -1.0, 0.0));
    let bisector = (face_normal(0) + face_normal(1)).normalize();
    let centroid = (Vector3::new(-1.0, -1.0, 0.0) + Vector3::new(1.0, -1.0, 0.0) + apex) / 3.0;
    // Gaps of 15 mm (softening), and 5 mm (elastic), over the three features.
    for gap in [0.015, 0.005] {
        for (feature, x) in [
            ("face", centroid + gap * face_normal(0)),
            ("edge", edge_midpoint + gap * bisector),
            (
                "vertex",
                apex + gap * Vector3::new(0.05, 0.1, 1.0).normalize(),
            ),
        ] {
            let mut positions = interface_mesh_positions();
            positions[0] = x;
            let f = all_forces(&mut interface, 0.0, &positions);
            let (_, separation, _) = interface.bond_states().next().unwrap();
            assert!(
                (separation.x - gap).abs() < 1e-12,
                "{feature}: {separation:?}"
            );
            let corners = pyramid().triangles[interface.bonds[0].triangle as usize]
                .map(|v| pyramid().vertices[v as usize]);
            let found = match crate::projection::project_on_triangle(&x, &corners).feature {
                crate::projection::Feature::Face => "face",
                crate::projection::Feature::Edge(_) => "edge",
                crate::projection::Feature::Vertex(_) => "vertex",
            };
            assert_eq!(found, feature);
            // The force pulls the node straight back towards the closest point.
            let expected = mode_one(gap) * interface.bonded_reference_area();
            assert!((Vector3::from_column_slice(&f[..3]).norm() - expected).abs() < 1e-9);
            check_stiffness(&mut interface, 0.0, &positions);
        }
    }
}

/// The normal traction of [`settings`] in monotonic opening [Pa].
fn mode_one(opening: f64) -> f64 {
    let s = settings(TangentialMode::FreeSlide);
    if opening <= s.initiation_separation {
        s.normal_stiffness * opening
    } else {
        s.normal_stiffness * s.initiation_separation * (s.failure_separation - opening)
            / (s.failure_separation - s.initiation_separation)
    }
}

#[test]
fn sliding_bonds_over_the_face_and_past_the_rim_have_the_full_consistent_stiffness() {
    let mut interface = deformable(&settings(TangentialMode::FreeSlide));
    let mut x = reference();
    // The main triangle moved, tilted and stretched.
    x[0] += Vector3::new(0.01, -0.02, 0.005);
    x[1] += Vector3::new(0.03, 0.01, 0.1);
    x[2] += Vector3::new(-0.02, 0.04, -0.05);
    let [a, b, c] = [x[0], x[1], x[2]];
    let n = (b - a).cross(&(c - a)).normalize();
    let centroid = (a + b + c) / 3.0;
    let in_plane = |v: Vector3<f64>| v - v.dot(&n) * n;
    let over_face = centroid + in_plane(Vector3::new(0.05, -0.03, 0.0));
    let past_edge = 0.5 * (a + b) + 0.05 * (b - a).cross(&n).normalize();
    let past_corner = b + 0.05 * in_plane(b - centroid).normalize();
    // Openings far beyond the triangle's size matter most: the lever arm g/h.
    let mut asymmetry: f64 = 0.0;
    for gap in [0.005, 0.015] {
        for (place, foot) in [
            ("face", over_face),
            ("edge", past_edge),
            ("corner", past_corner),
        ] {
            x[3] = foot + gap * n;
            let f = all_forces(&mut interface, 0.0, &x);
            let (_, separation, _) = interface.bond_states().next().unwrap();
            assert!((separation.x - gap).abs() < 1e-12, "{place}");
            // The forces balance.
            let total: Vector3<f64> = (0..4)
                .map(|i| Vector3::from_column_slice(&f[3 * i..3 * i + 3]))
                .sum();
            assert!(total.norm() < 1e-12, "{place}");
            let k_asymmetry = check_stiffness(&mut interface, 0.0, &x);
            if place == "face" {
                // The Hessian of A Φ(g): symmetric.
                assert!(k_asymmetry < 1e-9, "{place}: {k_asymmetry:e}");
            }
            asymmetry = asymmetry.max(k_asymmetry);
        }
    }
    // Past the rim the force along the triangle's normal is not the gradient of a
    // potential: the stiffness is unsymmetric, and the interface says so (the implicit
    // solver then factorizes with LU instead of reading one triangle).
    assert!(asymmetry > 1e-3, "{asymmetry:e}");
    assert!(!interface.symmetric_stiffness());
}

#[test]
fn sliding_bonds_over_interior_edges_and_corners_of_a_deformable_main_are_consistent() {
    // The pyramid's corners as mesh nodes 0–4 (then moved a little), the secondary
    // triangle [5, 6, 7] with node 5 bonded at the apex.
    let p = pyramid();
    let mut points = p.vertices.clone();
    points.extend([
        Vector3::new(0.0, 0.0, 0.3),
        Vector3::new(0.6, 0.2, 1.1),
        Vector3::new(0.0, 3.2, 0.3),
    ]);
    let mesh = mesh(&points);
    let main = DeformableSurface::from_triangles(&mesh, "pyramid", p.triangles.clone()).unwrap();
    let skin = DeformableSurface::from_triangles(&mesh, "skin", vec![[5, 6, 7]]).unwrap();
    let s = settings(TangentialMode::FreeSlide);
    let mut interface = CohesiveInterface::new("slide", &skin, main, &mesh, &s).unwrap();
    let mut x = points.clone();
    x[1] += Vector3::new(0.02, -0.01, 0.03);
    x[4] += Vector3::new(-0.01, 0.02, 0.01);
    let apex = x[4];
    let normal = |t: usize| {
        let [a, b, c] = p.triangles[t].map(|v| x[v as usize]);
        (b - a).cross(&(c - a)).normalize()
    };
    let middle = 0.5 * (apex + x[1]);
    let bisector = (normal(0) + normal(1)).normalize();
    let up = (normal(0) + normal(1) + normal(2) + normal(3)).normalize();
    for gap in [0.005, 0.015] {
        for (place, node) in [
            ("edge", middle + gap * bisector),
            ("vertex", apex + gap * up),
        ] {
            x[5] = node;
            all_forces(&mut interface, 0.0, &x);
            let (_, separation, _) = interface.bond_states().next().unwrap();
            assert!((separation.x - gap).abs() < 1e-12, "{place}");
            check_stiffness(&mut interface, 0.0, &x);
        }
    }
}
