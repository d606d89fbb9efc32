//! Smoothly sliding bonds: the tangent against finite differences, the continuity of the
//! force over convex and concave edges and a concave vertex, and a faceted cylinder (the
//! projection and the walk themselves: `normal_field/tests.rs`).

use musclefem_core::solver::{Interaction, RigidMotion, RigidRotation};
use musclefem_materials::Amplitude;
use nalgebra::{DMatrix, Unit};

use super::*;
use crate::cohesive::{CohesiveInterface, CohesiveSettings, TangentialMode};
use crate::main_side::MainSide;
use crate::normal_field::project_along_normals;
use crate::rigid_surface::RigidSurface;
use crate::surface::DeformableSurface;
use crate::test_surfaces::{
    CORNERS, below, bowl, bumpy, folded, jumps, line, mesh, point_over, tilted, turns,
};

/// K_nn = 1e3 N/m³, damage from 0.1 m to 0.3 m, bonds within 1 µm.
fn settings(tangential: TangentialMode) -> CohesiveSettings {
    CohesiveSettings {
        normal_stiffness: 1e3,
        shear_stiffness: 1e3,
        tangential_stiffness: 1e3,
        initiation_separation: 0.1,
        failure_separation: 0.3,
        tangential,
        bond_tolerance: 1e-6,
    }
}

fn law() -> CohesiveLaw {
    CohesiveLaw::new(&settings(TangentialMode::SmoothSlide), "test").unwrap()
}

/// A bond of 0.5 m² resting at a gap of 0.02 m.
fn bond() -> Bond {
    Bond {
        node: 0,
        area: 0.5,
        triangle: 0,
        coordinates: Vector3::repeat(1.0 / 3.0),
        normal: Vector3::z(),
        history: 0.0,
        reference_separation: Vector3::new(0.02, 0.0, 0.0),
    }
}

/// The forces on the secondary node and the corners (f_s, −φ_k f_s) at the nodal
/// positions `x` = (x_s, x₀, x₁, x₂) with fixed vertex `normals`, and the state.
fn bond_forces(x: &[Vector3<f64>; 4], normals: &[Vector3<f64>; 3]) -> (DMatrix<f64>, BondState) {
    let corners = [x[1], x[2], x[3]];
    let foot = Foot {
        triangle: 0,
        projection: project_along_normals(&x[0], &corners, normals),
    };
    let state = evaluate_smooth(&bond(), &law(), &foot, true);
    let mut f = DMatrix::zeros(12, 1);
    f.fixed_view_mut::<3, 1>(0, 0).copy_from(&state.force);
    for k in 0..3 {
        let reaction = -state.coordinates[k] * state.force;
        f.fixed_view_mut::<3, 1>(3 + 3 * k, 0).copy_from(&reaction);
    }
    (f, state)
}

/// The 12 × 12 stiffness of the state, assembled as the interface assembles it.
fn assembled(state: &BondState) -> DMatrix<f64> {
    let mut k = DMatrix::zeros(12, 12);
    for j in 0..4 {
        k.fixed_view_mut::<3, 3>(0, 3 * j)
            .copy_from(&state.coupling[j]);
        for c in 0..3 {
            let block = -state.force * state.coordinate_gradients[j].row(c)
                - state.coordinates[c] * state.coupling[j];
            k.fixed_view_mut::<3, 3>(3 + 3 * c, 3 * j).copy_from(&block);
        }
    }
    k
}

/// Largest |K − K_fd| over the largest |K| (central differences, step 1e-6 m), over the
/// secondary node's columns only (`node_only`: a rigid main) or all.
fn tangent_error(x: &[Vector3<f64>; 4], normals: &[Vector3<f64>; 3], node_only: bool) -> f64 {
    let (_, state) = bond_forces(x, normals);
    let k = assembled(&state);
    let h = 1e-6;
    let columns = if node_only { 3 } else { 12 };
    let mut error = 0.0f64;
    for column in 0..columns {
        let (mut plus, mut minus) = (*x, *x);
        plus[column / 3][column % 3] += h;
        minus[column / 3][column % 3] -= h;
        let fd = (bond_forces(&plus, normals).0 - bond_forces(&minus, normals).0) / (2.0 * h);
        let rows = if node_only { 3 } else { 12 };
        for row in 0..rows {
            error = error.max((fd[row] - k[(row, column)]).abs());
        }
    }
    error / k.amax()
}

#[test]
fn the_tangent_matches_central_differences_with_the_normals_held() {
    let normals = tilted(&CORNERS);
    let mut worst = 0.0f64;
    // Inside the face and near edge 0–1 (φ₂ = 0.01); elastic opening, softening,
    // compression; gaps up to a quarter of the triangle's size.
    for phi in [[0.3, 0.45, 0.25], [0.5, 0.49, 0.01]] {
        for along in [0.06, 0.25, -0.05] {
            let node = point_over(&CORNERS, &normals, phi, along);
            let x = [node, CORNERS[0], CORNERS[1], CORNERS[2]];
            let (_, state) = bond_forces(&x, &normals);
            assert!(state.force.norm() > 1.0, "{}", state.force.norm());
            let all = tangent_error(&x, &normals, false);
            let node_only = tangent_error(&x, &normals, true);
            eprintln!(
                "smooth tangent φ = {phi:?}, g = {along}: relative error {all:.1e} (all \
                 nodes), {node_only:.1e} (secondary node)"
            );
            assert!(all < 1e-6 && node_only < 1e-6);
            worst = worst.max(all);
        }
    }
    // Softening is a loading branch: the tangent is the consistent one, not the secant.
    let node = point_over(&CORNERS, &normals, [0.3, 0.45, 0.25], 0.25);
    let x = [node, CORNERS[0], CORNERS[1], CORNERS[2]];
    let (_, state) = bond_forces(&x, &normals);
    assert!(state.damage > 0.0 && state.damage < 1.0);
    eprintln!("smooth tangent: worst relative error {worst:.1e}");
}

/// An interface bonding node 0 of a secondary triangle, at `reference` on the rigid
/// `main` surface, to it (the triangle's other nodes are 5 m away and do not bond).
fn bonded_to(
    main: RigidSurface,
    reference: Vector3<f64>,
    mode: TangentialMode,
) -> CohesiveInterface {
    let points = secondary(reference);
    let mesh = mesh(&points);
    let skin = DeformableSurface::from_triangles(&mesh, "skin", vec![[0, 1, 2]]).unwrap();
    let interface = CohesiveInterface::new("glide", &skin, main, &mesh, &settings(mode)).unwrap();
    assert_eq!(interface.bond_count(), 1);
    interface
}

/// The secondary triangle's nodes with node 0 at `node`.
fn secondary(node: Vector3<f64>) -> Vec<Vector3<f64>> {
    vec![
        node,
        node + Vector3::new(0.6, 0.0, 5.0),
        node + Vector3::new(0.0, 0.6, 5.0),
    ]
}

/// The force on node 0 at `x` (forces only: the walk starts from the committed triangle).
fn node_force(interface: &mut CohesiveInterface, time: f64, x: Vector3<f64>) -> Vector3<f64> {
    let positions = secondary(x);
    let mut force = vec![Vector3::zeros(); positions.len()];
    interface
        .forces(time, &positions, true, &mut force)
        .unwrap();
    force[0]
}

/// The assembled stiffness at `positions` against central differences of the forces
/// (step 1e-7 m): the largest error relative to the largest entry, over the columns of
/// node 0 and over the others.
fn interface_tangent_errors(
    interface: &mut CohesiveInterface,
    time: f64,
    positions: &[Vector3<f64>],
) -> (f64, f64) {
    let n = 3 * positions.len();
    let forces = |interface: &mut CohesiveInterface, at: &[Vector3<f64>]| {
        let mut force = vec![Vector3::zeros(); at.len()];
        interface.forces(time, at, true, &mut force).unwrap();
        DMatrix::from_iterator(n, 1, force.iter().flat_map(|f| f.iter().copied()))
    };
    forces(interface, positions);
    let mut k = DMatrix::<f64>::zeros(n, n);
    interface.stiffness(&mut |a, b, block: &Matrix3<f64>| {
        let (a, b) = (3 * a as usize, 3 * b as usize);
        let mut view = k.fixed_view_mut::<3, 3>(a, b);
        view += block;
    });
    let h = 1e-7;
    let mut errors = [0.0f64; 2];
    for column in 0..n {
        let (mut plus, mut minus) = (positions.to_vec(), positions.to_vec());
        plus[column / 3][column % 3] += h;
        minus[column / 3][column % 3] -= h;
        let fd = (forces(interface, &plus) - forces(interface, &minus)) / (2.0 * h);
        let slot = usize::from(column >= 3);
        for row in 0..n {
            errors[slot] = errors[slot].max((fd[row] - k[(row, column)]).abs());
        }
    }
    (errors[0] / k.amax(), errors[1] / k.amax())
}

#[test]
fn on_a_moving_rigid_main_the_tangent_is_exact() {
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
    let surface = bumpy().with_motion(motion);
    let main = ContactTarget::Rigid(surface.clone());
    let field = NormalField::new(&main, &[]);
    // Bonded at the reference over the face of triangle 10 (square (1, 1)), on it.
    let on_face = |t: usize, phi: [f64; 3]| {
        let [a, b, c] = main.corners(t, &[], &Isometry3::identity());
        phi[0] * a + phi[1] * b + phi[2] * c
    };
    let mut interface = bonded_to(
        surface,
        on_face(10, [0.2, 0.5, 0.3]),
        TangentialMode::SmoothSlide,
    );
    assert!(!interface.symmetric_stiffness());
    let time = 0.6;
    let placement = main.placement(time);
    let mut worst = 0.0f64;
    // Inside faces and near edges (φ = 0.005), elastic and softening (gap 0.15 m).
    for (t, phi) in [
        (10, [0.2, 0.5, 0.3]),
        (11, [0.6, 0.1, 0.3]),
        (10, [0.005, 0.6, 0.395]),
        (13, [0.4, 0.595, 0.005]),
    ] {
        for along in [0.04, 0.15] {
            let corners = main.corners(t, &[], &placement);
            let normals = field.normals(t, &placement.rotation);
            let node = point_over(&corners, &normals, phi, along);
            let positions = secondary(node);
            let f = node_force(&mut interface, time, node);
            let (_, separation, _) = interface.bond_states().next().unwrap();
            let gap = along * point_over(&[Vector3::zeros(); 3], &normals, phi, 1.0).norm();
            assert!(
                (separation.x - gap).abs() < 1e-12,
                "{separation:?} vs {gap}"
            );
            assert!(f.norm() > 1.0);
            let (node, others) = interface_tangent_errors(&mut interface, time, &positions);
            assert_eq!(others, 0.0);
            let error = node;
            eprintln!("rigid main, triangle {t}, φ = {phi:?}, g = {along}: {error:.1e}");
            assert!(error < 1e-6, "{error:e}");
            worst = worst.max(error);
        }
    }
    eprintln!("rigid main: worst relative tangent error {worst:.1e}");
}

/// The forces on a node bonded at `reference` on `main` and then moved along `path`, with
/// a search before every force evaluation (as the solvers do at every iteration) or
/// without (the bond's committed triangle stays where it formed).
fn along_path(
    main: &RigidSurface,
    mode: TangentialMode,
    reference: Vector3<f64>,
    path: &[Vector3<f64>],
    search: bool,
) -> Vec<Vector3<f64>> {
    let mut interface = bonded_to(main.clone(), reference, mode);
    path.iter()
        .map(|&x| {
            if search {
                interface.search(0.0, &secondary(x)).unwrap();
            }
            node_force(&mut interface, 0.0, x)
        })
        .collect()
}

/// Continuity along a path crossing an edge or a vertex at a fixed height (1 m in 200 and
/// 400 steps): the largest change of the SmoothSlide force between consecutive samples,
/// and the largest turn of its direction, are within 10 times their medians and halve
/// with the step; the forces do not depend on searches (the walk runs in every force
/// evaluation). Returns the largest turn [rad] at the finer step.
fn assert_continuous(main: &RigidSurface, reference: Vector3<f64>, ends: [Vector3<f64>; 2]) -> f64 {
    let path = |samples| line(ends[0], ends[1], samples);
    let smooth = TangentialMode::SmoothSlide;
    let coarse = along_path(main, smooth, reference, &path(200), false);
    let fine = along_path(main, smooth, reference, &path(400), false);
    assert!(coarse.iter().all(|f| f.norm() > 1.0));
    let searched = along_path(main, smooth, reference, &path(400), true);
    for (f, g) in fine.iter().zip(&searched) {
        assert!((f - g).norm() <= 1e-12 * f.norm(), "{f} vs {g}");
    }
    for (what, unit, measure) in [
        (
            "force change",
            "N",
            jumps as fn(&[Vector3<f64>]) -> (f64, f64),
        ),
        ("turn", "rad", turns),
    ] {
        let (largest, median) = measure(&coarse);
        let (finer, finer_median) = measure(&fine);
        eprintln!(
            "  smooth slide, {what}: largest {largest:.3e} {unit}, median {median:.3e} (step \
             5 mm); {finer:.3e}, {finer_median:.3e} (2.5 mm)"
        );
        assert!(largest < 10.0 * median, "{what}: {largest:e} vs {median:e}");
        assert!(finer < 0.6 * largest, "{what}: {finer:e} vs {largest:e}");
    }
    turns(&fine).0
}

#[test]
fn the_force_is_continuous_over_a_convex_edge() {
    let ridge = folded(-(15f64.to_radians().tan()));
    eprintln!("convex edge (30° fold):");
    let turn = assert_continuous(
        &ridge,
        below(&ridge, -0.5, 0.3),
        [Vector3::new(-0.5, 0.3, 0.05), Vector3::new(0.5, 0.3, 0.05)],
    );
    assert!(turn < 0.01, "{turn}");
}

#[test]
fn the_force_is_continuous_over_a_concave_edge_where_the_closest_point_jumps() {
    let slope = 15f64.to_radians().tan();
    let valley = folded(slope);
    let reference = below(&valley, -0.5, 0.3);
    let ends = [Vector3::new(-0.5, 0.3, 0.2), Vector3::new(0.5, 0.3, 0.2)];
    eprintln!("concave edge (30° fold):");
    let turn = assert_continuous(&valley, reference, ends);
    assert!(turn < 0.01, "{turn}");
    // FreeSlide's force turns by the fold angle between two samples 2.5 mm apart.
    let closest = along_path(
        &valley,
        TangentialMode::FreeSlide,
        reference,
        &line(ends[0], ends[1], 400),
        true,
    );
    let jump = turns(&closest).0;
    eprintln!("  free slide: the force turns by {jump:.4} rad between two samples");
    assert!((jump - 30f64.to_radians()).abs() < 1e-3, "{jump}");
}

#[test]
fn the_force_is_continuous_around_a_concave_vertex() {
    let slope = 15f64.to_radians().tan();
    let cone = bowl(slope);
    // A path passing 0.05 m beside the apex at 0.2 m above it, over four of the six faces.
    let ends = [Vector3::new(-0.5, 0.05, 0.2), Vector3::new(0.5, 0.05, 0.2)];
    let under = below(&cone, -0.5, 0.05);
    eprintln!("concave vertex (cone rising 15°):");
    let turn = assert_continuous(&cone, under, ends);
    assert!(turn < 0.01, "{turn}");
    let path = line(ends[0], ends[1], 400);
    let closest = along_path(&cone, TangentialMode::FreeSlide, under, &path, true);
    let jump = turns(&closest).0;
    eprintln!("  free slide: the force turns by {jump:.4} rad between two samples");
    assert!(jump > 0.2, "{jump}");
}

/// A rigid cylinder of radius R = 1 m (24 facets around, 6 rows along z from −1.5 m to
/// 1.5 m) and a node at radial distance R + h, h = 0.01 m, sliding 0.9 m along and a
/// quarter turn around it: the smooth gap stays within R (1 − cos(Δ/2)) = s²/(8R) (s the
/// facet width, Δ = 15° its angle) above h, and the force points exactly along the radius;
/// the closest-point force of FreeSlide turns with the facets, by up to Δ/2 off the radius.
#[test]
fn on_a_faceted_cylinder_the_force_follows_the_radius() {
    let (radius, around, h) = (1.0, 24usize, 0.01);
    let cylinder = RigidSurface::cylinder(
        "shaft",
        Vector3::zeros(),
        Vector3::z(),
        radius,
        3.0,
        [around, 6],
    )
    .unwrap();
    let delta = 2.0 * std::f64::consts::PI / around as f64;
    // The directions of the vertices at angles 0 and Δ.
    let e1 = cylinder.vertices[0].xy().push(0.0).normalize();
    let e2 = (cylinder.vertices[1].xy().push(0.0).normalize() - e1 * delta.cos()) / delta.sin();
    let radial = |angle: f64| e1 * angle.cos() + e2 * angle.sin();
    // Bonded on the middle of a facet (rest gap 0).
    let reference = radial(0.5 * delta) * radius * (0.5 * delta).cos() + 0.25 * Vector3::z();
    let bound = radius * (1.0 - (0.5 * delta).cos());
    let samples = 600;
    let path: Vec<(Vector3<f64>, Vector3<f64>)> = (0..=samples)
        .map(|i| {
            let s = i as f64 / samples as f64;
            let angle = 0.5 * delta + s * 0.5 * std::f64::consts::PI;
            let x = radial(angle) * (radius + h) + (0.25 - 0.9 * s) * Vector3::z();
            (x, radial(angle))
        })
        .collect();
    let mut measured = Vec::new();
    for mode in [TangentialMode::SmoothSlide, TangentialMode::FreeSlide] {
        let mut interface = bonded_to(cylinder.clone(), reference, mode);
        let (mut lowest, mut highest, mut off_radius) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
        for (x, r) in &path {
            let positions = secondary(*x);
            let mut force = vec![Vector3::zeros(); 3];
            interface.search(0.0, &positions).unwrap();
            interface
                .forces(0.0, &positions, false, &mut force)
                .unwrap();
            let (_, separation, _) = interface.bond_states().next().unwrap();
            let error = separation.x - h;
            lowest = lowest.min(error);
            highest = highest.max(error);
            off_radius = off_radius.max(force[0].normalize().cross(r).norm().asin());
        }
        eprintln!(
            "cylinder, {mode:?}: gap − h in [{lowest:.3e}, {highest:.3e}] m \
             (s²/8R = {bound:.3e} m), force off the radius by up to {off_radius:.2e} rad \
             (Δ/2 = {:.3e})",
            0.5 * delta
        );
        measured.push((lowest, highest, off_radius));
    }
    let (lowest, highest, off_radius) = measured[0];
    assert!(
        lowest > -1e-12 && highest < bound + 1e-12,
        "{lowest:e} {highest:e}"
    );
    // The whole range is used: the node passes over vertices and facet middles.
    assert!(highest > 0.95 * bound, "{highest:e}");
    assert!(off_radius < 1e-12, "{off_radius:e}");
    let (_, _, closest_off_radius) = measured[1];
    assert!(
        closest_off_radius > 0.9 * 0.5 * delta,
        "{closest_off_radius}"
    );
}

/// On a deformable main the tangent holds the vertex normals fixed: its columns for the
/// secondary node are exact, those of the main nodes miss the turn of the normals.
#[test]
fn on_a_deformable_main_the_node_columns_are_exact() {
    let bumps = bumpy();
    // Nodes 0–2: the secondary triangle; 3–27 the bumpy grid.
    let reference = below(&bumps, 0.3, -0.4);
    let mut points = secondary(reference);
    points.extend(&bumps.vertices);
    let mesh = mesh(&points);
    let triangles = bumps.triangles.iter().map(|t| t.map(|v| v + 3)).collect();
    let main = DeformableSurface::from_triangles(&mesh, "bumps", triangles).unwrap();
    let skin = DeformableSurface::from_triangles(&mesh, "skin", vec![[0, 1, 2]]).unwrap();
    let s = settings(TangentialMode::SmoothSlide);
    let mut interface = CohesiveInterface::new("glide", &skin, main, &mesh, &s).unwrap();
    assert_eq!(interface.bond_count(), 1);
    assert!(!interface.symmetric_stiffness());
    let mut x = points.clone();
    x[0] += Vector3::new(0.05, 0.02, 0.06);
    x[3 + 12] += Vector3::new(0.02, -0.01, 0.03);
    let (node, others) = interface_tangent_errors(&mut interface, 0.0, &x);
    eprintln!(
        "deformable main: relative tangent error {node:.1e} (secondary node's columns), \
         {others:.1e} (main nodes' columns, normals held fixed)"
    );
    assert!(node < 1e-6, "{node:e}");
    assert!(others > 1e-4, "{others:e}");
    // Forces balance on a deformable main.
    let mut force = vec![Vector3::zeros(); x.len()];
    interface.forces(0.0, &x, false, &mut force).unwrap();
    let total: Vector3<f64> = force.iter().sum();
    let moment: Vector3<f64> = x.iter().zip(&force).map(|(p, f)| p.cross(f)).sum();
    assert!(force[0].norm() > 1.0);
    assert!(
        total.norm() < 1e-12 && moment.norm() < 1e-12,
        "{total} {moment}"
    );
}
