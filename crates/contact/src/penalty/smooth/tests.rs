//! Smooth penalty contact: its tangent against central differences (one pair with the
//! vertex normals held, a moving rigid main, a deformable main), and the helpers of
//! `sliding`: the closest-point contact on a flat surface (rim included), and the
//! continuity of the force when a pressed node slides over a convex fold, a concave fold
//! and a concave cone vertex, where the closest point's force direction jumps or sweeps
//! through the fold angle.

use std::collections::HashMap;

use musclefem_core::mesh::Mesh;
use musclefem_core::solver::{
    Interaction, InteractionReport, NodalField, RigidMotion, RigidRotation,
};
use musclefem_materials::Amplitude;
use nalgebra::{DMatrix, Point3, Unit};

use super::*;
use crate::normal_field::project_along_normals;
use crate::penalty::PenaltyContact;
use crate::rigid_surface::RigidSurface;
use crate::surface::DeformableSurface;
use crate::test_surfaces::{
    CORNERS, below, bowl, bumpy, folded, grid_triangles, jumps, line, mesh, point_over, tilted,
    turns,
};

/// Penalty ε [N/m³] of the tests.
const PENALTY: f64 = 1e3;

/// The forces (f_s, −φ_k f_s) of one active pair at `x` = (x_s, x₀, x₁, x₂) with fixed
/// vertex `normals` and k = ε A_s = `k`, and the pair.
fn pair(
    x: &[Vector3<f64>; 4],
    normals: &[Vector3<f64>; 3],
    k: f64,
) -> (DMatrix<f64>, SmoothContact) {
    let projection = project_along_normals(&x[0], &[x[1], x[2], x[3]], normals);
    let contact = SmoothContact {
        triangle: 0,
        gap: projection.gap(),
        active: true,
        weight: 1.0,
        projection,
    };
    let force = contact.force(k);
    let mut f = DMatrix::zeros(12, 1);
    f.fixed_view_mut::<3, 1>(0, 0).copy_from(&force);
    for c in 0..3 {
        let reaction = -projection.barycentric[c] * force;
        f.fixed_view_mut::<3, 1>(3 + 3 * c, 0).copy_from(&reaction);
    }
    (f, contact)
}

/// Adds `block` at nodes (`a`, `b`) of the dense matrix `k`.
fn add_block(k: &mut DMatrix<f64>, a: u32, b: u32, block: &Matrix3<f64>) {
    let mut view = k.fixed_view_mut::<3, 3>(3 * a as usize, 3 * b as usize);
    view += block;
}

#[test]
fn the_pair_tangent_matches_central_differences_with_the_normals_held() {
    let normals = tilted(&CORNERS);
    let k = 0.7 * PENALTY;
    let mut worst = 0.0f64;
    // Inside the face and near edge 0–1 (φ₂ = 0.01); penetrations up to a quarter of the
    // triangle's size.
    for phi in [[0.3, 0.45, 0.25], [0.5, 0.49, 0.01]] {
        for along in [-0.02, -0.1, -0.25] {
            let node = point_over(&CORNERS, &normals, phi, along);
            let x = [node, CORNERS[0], CORNERS[1], CORNERS[2]];
            let (_, contact) = pair(&x, &normals, k);
            assert!(contact.gap < 0.0);
            let mut stiffness = DMatrix::zeros(12, 12);
            contact.blocks(k, 0, Some([1, 2, 3]), &mut |a, b, block| {
                add_block(&mut stiffness, a, b, block);
            });
            let h = 1e-6;
            let mut error = 0.0f64;
            for column in 0..12 {
                let (mut plus, mut minus) = (x, x);
                plus[column / 3][column % 3] += h;
                minus[column / 3][column % 3] -= h;
                let fd = (pair(&plus, &normals, k).0 - pair(&minus, &normals, k).0) / (2.0 * h);
                for row in 0..12 {
                    error = error.max((fd[row] - stiffness[(row, column)]).abs());
                }
            }
            let error = error / stiffness.amax();
            eprintln!("smooth penalty pair, φ = {phi:?}, g = {along}: relative error {error:.1e}");
            assert!(error < 1e-6, "{error:e}");
            assert!(
                (stiffness.clone() - stiffness.transpose()).amax() > 1e-3 * stiffness.amax(),
                "tilted normals make it unsymmetric"
            );
            worst = worst.max(error);
        }
    }
    eprintln!("smooth penalty pair: worst relative tangent error {worst:.1e}");
}

/// The nodes of a secondary triangle with node 0 at `node` (the others 5 m above it, out
/// of reach).
fn triangle_at(node: Vector3<f64>) -> Vec<Vector3<f64>> {
    vec![
        node,
        node + Vector3::new(0.6, 0.0, 5.0),
        node + Vector3::new(0.0, 0.6, 5.0),
    ]
}

/// Smooth (or closest-point) contact of node 0 of the secondary triangle [0, 1, 2] of
/// `mesh` on `main`, searched within 0.5 m.
fn pressed(mesh: &Mesh, main: impl Into<ContactTarget>, smooth: bool) -> PenaltyContact {
    let skin = DeformableSurface::from_triangles(mesh, "skin", vec![[0, 1, 2]]).unwrap();
    let contact = PenaltyContact::new("press", skin, main, PENALTY)
        .unwrap()
        .with_search_distance(0.5)
        .unwrap();
    if smooth {
        contact.with_smooth_normals()
    } else {
        contact
    }
}

/// The forces of `contact` at `positions` after a search, stacked (3 per node).
fn stacked_forces(
    contact: &mut PenaltyContact,
    time: f64,
    positions: &[Vector3<f64>],
) -> DMatrix<f64> {
    let mut force = vec![Vector3::zeros(); positions.len()];
    contact.forces(time, positions, true, &mut force).unwrap();
    DMatrix::from_iterator(
        3 * positions.len(),
        1,
        force.iter().flat_map(|f| f.iter().copied()),
    )
}

/// The assembled stiffness of `contact`.
fn assembled(contact: &PenaltyContact, nodes: usize) -> DMatrix<f64> {
    let mut k = DMatrix::zeros(3 * nodes, 3 * nodes);
    contact.stiffness(&mut |a, b, block| add_block(&mut k, a, b, block));
    k
}

/// The assembled stiffness at `positions` (searched there) against central differences
/// of the forces (step 1e-7 m): the largest error relative to the largest entry, over
/// the columns of node 0 and over the others.
fn tangent_errors(
    contact: &mut PenaltyContact,
    time: f64,
    positions: &[Vector3<f64>],
) -> (f64, f64) {
    contact.search(time, positions).unwrap();
    stacked_forces(contact, time, positions);
    let n = positions.len();
    let k = assembled(contact, n);
    let h = 1e-7;
    let mut errors = [0.0f64; 2];
    for column in 0..3 * n {
        let (mut plus, mut minus) = (positions.to_vec(), positions.to_vec());
        plus[column / 3][column % 3] += h;
        minus[column / 3][column % 3] -= h;
        let fd = (stacked_forces(contact, time, &plus) - stacked_forces(contact, time, &minus))
            / (2.0 * h);
        let slot = usize::from(column >= 3);
        for row in 0..3 * n {
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
    let time = 0.6;
    let placement = main.placement(time);
    let mesh = mesh(&triangle_at(Vector3::zeros()));
    let mut contact = pressed(&mesh, surface, true);
    assert!(!contact.symmetric_stiffness());
    let mut worst = 0.0f64;
    // Inside faces and near edges (φ = 0.005), pressed in by 0.04 m and 0.15 m.
    for (t, phi) in [
        (10, [0.2, 0.5, 0.3]),
        (11, [0.6, 0.1, 0.3]),
        (10, [0.005, 0.6, 0.395]),
        (13, [0.4, 0.595, 0.005]),
    ] {
        for along in [-0.04, -0.15] {
            let corners = main.corners(t, &[], &placement);
            let normals = field.normals(t, &placement.rotation);
            let positions = triangle_at(point_over(&corners, &normals, phi, along));
            let (node, others) = tangent_errors(&mut contact, time, &positions);
            let state = contact.smooth.as_ref().unwrap().contacts[0];
            assert_eq!(state.triangle, t as u32);
            assert!(state.active && state.gap < 0.0);
            assert_eq!(contact.report().active_points, 1);
            assert_eq!(others, 0.0);
            eprintln!("rigid main, triangle {t}, φ = {phi:?}, g = {along}: {node:.1e}");
            assert!(node < 1e-6, "{node:e}");
            worst = worst.max(node);
        }
    }
    eprintln!("smooth penalty, rigid main: worst relative tangent error {worst:.1e}");
}

/// On a deformable main the tangent holds the vertex normals fixed: the columns of the
/// secondary node are exact, those of the main nodes miss the turn of the normals. Forces
/// and moments balance.
#[test]
fn on_a_deformable_main_the_node_columns_are_exact_and_forces_balance() {
    let bumps = bumpy();
    // Nodes 0–2: the secondary triangle; 3–27 the bumpy grid.
    let mut points = triangle_at(below(&bumps, 0.3, -0.4));
    points.extend(&bumps.vertices);
    let mesh = mesh(&points);
    let triangles = bumps.triangles.iter().map(|t| t.map(|v| v + 3)).collect();
    let main = DeformableSurface::from_triangles(&mesh, "bumps", triangles).unwrap();
    let mut contact = pressed(&mesh, main, true);
    assert!(!contact.symmetric_stiffness());
    let mut x = points.clone();
    x[0] += Vector3::new(0.05, 0.02, -0.06);
    x[3 + 12] += Vector3::new(0.02, -0.01, 0.03);
    let (node, others) = tangent_errors(&mut contact, 0.0, &x);
    let gap = contact.smooth.as_ref().unwrap().contacts[0].gap;
    eprintln!(
        "smooth penalty, deformable main (gap {gap:.3} m, triangles 1 m): relative tangent \
         error {node:.1e} (secondary node's columns), {others:.1e} (main nodes' columns, \
         normals held fixed)"
    );
    assert!(gap < -0.05);
    assert!(node < 1e-6, "{node:e}");
    assert!(others > 1e-4 && others < 0.1, "{others:e}");
    let mut force = vec![Vector3::zeros(); x.len()];
    contact.forces(0.0, &x, false, &mut force).unwrap();
    let total: Vector3<f64> = force.iter().sum();
    let moment: Vector3<f64> = x.iter().zip(&force).map(|(p, f)| p.cross(f)).sum();
    assert!(force[0].norm() > 1.0);
    assert!(
        total.norm() < 1e-12 * force[0].norm() && moment.norm() < 1e-12 * force[0].norm(),
        "{total} {moment}"
    );
    assert_eq!(contact.report().force, -force[0]);
}

mod sliding;
