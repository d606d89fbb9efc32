//! A branched (Y-shaped) muscle: one inlet at the foot of the trunk, two outlets at the
//! ends of the bent arms (see `common::y_domain`). There is no closed-form potential; the checks
//! are what any correct flow must satisfy:
//!
//! - every element gets a unit direction;
//! - the flow is conserved: flux in = flux out to the solver tolerance, and the fluxes
//!   out of the two arms add up to the flux in;
//! - the direction field is continuous: away from the branch point (the re-entrant
//!   corners of the crotch, where ∇φ is singular, and the stagnation point between them,
//!   where ∇φ = 0), neighbouring elements differ by a few degrees;
//! - on the mirror-symmetric hex mesh the field is mirror-symmetric and the flow splits
//!   equally between the arms;
//! - the flow goes from the inlet to the outlets: up the trunk, out of the arm ends.

mod common;

use common::{Cells, Y_BRANCH_POINT, angle_degrees, element_centres, y_domain};
use musclefem_fibers::{
    BoundaryRegion, FiberField, FlowBoundary, FlowSettings, Side, compute_fibers,
};
use nalgebra::Vector3;

/// Radius around the branch point left out of the continuity check [m].
const EXCLUDED_RADIUS: f64 = 0.5;

/// Largest angle between neighbouring elements' directions away from the branch point
/// [°], at 8 divisions per metre.
const CONTINUITY: f64 = 8.0;

fn far_from_branch_point(x: Vector3<f64>) -> bool {
    let [bx, by] = Y_BRANCH_POINT;
    ((x.x - bx).powi(2) + (x.y - by).powi(2)).sqrt() > EXCLUDED_RADIUS
}

/// Largest angle between the directions of two elements that share a face, both far from
/// the singular points [°].
fn largest_neighbour_angle(mesh: &musclefem_mesh::Mesh, directions: &[Vector3<f64>]) -> f64 {
    let centres = element_centres(mesh);
    let block = &mesh.blocks[0];
    let shape = block.shape;
    let mut faces = std::collections::HashMap::new();
    let mut largest: f64 = 0.0;
    for (e, ids) in block.elements().enumerate() {
        for (f, local) in shape.faces().iter().enumerate() {
            let n = shape.face_shape(f).corner_count();
            let mut key: Vec<u32> = local[..n].iter().map(|&l| ids[l as usize]).collect();
            key.sort_unstable();
            if let Some(other) = faces.insert(key, e) {
                let (a, b): (usize, usize) = (other, e);
                if far_from_branch_point(centres[a]) && far_from_branch_point(centres[b]) {
                    largest = largest.max(angle_degrees(directions[a], directions[b]));
                }
            }
        }
    }
    largest
}

#[test]
fn one_inlet_two_outlets() {
    for cells in [Cells::Hex8, Cells::Tet4] {
        let mesh = y_domain(cells, 8);
        let boundary = FlowBoundary {
            inlet: vec![BoundaryRegion::node_set(&mesh, "y0").unwrap()],
            outlet: vec![
                BoundaryRegion::node_set(&mesh, "left_end").unwrap(),
                BoundaryRegion::node_set(&mesh, "right_end").unwrap(),
            ],
        };
        let field = compute_fibers(&mesh, &boundary, &FlowSettings::default()).unwrap();
        let balance = (field.inlet_flux - field.outlet_flux).abs() / field.inlet_flux;
        let neighbour_angle = largest_neighbour_angle(&mesh, &field.direction);
        println!(
            "{cells:?}: {} elements, flux in {:.12e} out {:.12e}, |in − out|/in = {balance:.1e}, largest neighbour angle away from the corners {neighbour_angle:.2}°, residual {:.1e}",
            mesh.element_count(),
            field.inlet_flux,
            field.outlet_flux,
            field.residual
        );
        assert_eq!(field.direction.len(), mesh.element_count());
        for d in &field.direction {
            assert!((d.norm() - 1.0).abs() < 1e-12);
        }
        assert!(balance < 1e-7, "{cells:?}: {balance:e}");
        assert!(
            neighbour_angle < CONTINUITY,
            "{cells:?}: {neighbour_angle}°"
        );

        // Up the trunk; in the arms, towards their ends.
        for (d, x) in field.direction.iter().zip(element_centres(&mesh)) {
            if x.y < 1.0 {
                assert!(d.y > 0.9, "{cells:?} trunk at {x}: {d}");
            }
            if x.y > 3.0 {
                let outward = if x.x < 1.0 { -d.x } else { d.x };
                assert!(outward > 0.3 && d.y > 0.0, "{cells:?} arm at {x}: {d}");
            }
        }
        if cells == Cells::Hex8 {
            assert_mirror_symmetric(&mesh, &field.direction);
        }
        assert_region_fluxes(cells, &field);
    }
}

/// Relative difference between the fluxes out of the two arms allowed on the
/// mirror-symmetric hex mesh (dimensionless): the solver tolerance (relative residual
/// 1e-10) bounds it; measured 7.6e-11 at 8 divisions per metre.
const HEX_SPLIT: f64 = 1e-8;

/// The same on the tet mesh, whose diagonals are not mirror-symmetric: a discretisation
/// error, measured 3.2e-5 at 8 divisions per metre.
const TET_SPLIT: f64 = 1e-4;

/// One region per end piece, named as given: the inlet carries the whole inlet flux, the
/// arms' fluxes add up to it (to the solver tolerance, as the totals) and split equally.
fn assert_region_fluxes(cells: Cells, field: &FiberField) {
    let regions = &field.region_fluxes;
    let summary: Vec<_> = regions
        .iter()
        .map(|r| (r.name.as_str(), r.side, r.faces))
        .collect();
    assert_eq!(
        summary,
        [
            ("y0", Side::Inlet, field.inlet_faces),
            ("left_end", Side::Outlet, field.outlet_faces / 2),
            ("right_end", Side::Outlet, field.outlet_faces / 2),
        ],
        "{cells:?}"
    );
    let (inlet, left, right) = (regions[0].flux, regions[1].flux, regions[2].flux);
    assert_eq!(inlet, field.inlet_flux, "{cells:?}");
    let sum_error = (left + right - inlet).abs() / inlet;
    let split = (left - right).abs() / inlet;
    println!(
        "{cells:?}: inlet 'y0' {inlet:.9e}, outlet 'left_end' {left:.9e} ({:.4} %), 'right_end' {right:.9e} ({:.4} %); |left + right − in|/in = {sum_error:.1e}, |left − right|/in = {split:.1e}",
        100.0 * left / (left + right),
        100.0 * right / (left + right),
    );
    assert!(left > 0.0 && right > 0.0, "{cells:?}: {left}, {right}");
    assert!(sum_error < 1e-7, "{cells:?}: {sum_error:e}");
    let allowed = if cells == Cells::Hex8 {
        HEX_SPLIT
    } else {
        TET_SPLIT
    };
    assert!(split < allowed, "{cells:?}: {split:e}");
}

/// The hex mesh is symmetric about x = 1: the direction at the mirror image of an element
/// centre is the mirror image of its direction.
fn assert_mirror_symmetric(mesh: &musclefem_mesh::Mesh, directions: &[Vector3<f64>]) {
    let key = |x: Vector3<f64>| {
        (
            (x.x * 1e6).round() as i64,
            (x.y * 1e6).round() as i64,
            (x.z * 1e6).round() as i64,
        )
    };
    let centres = element_centres(mesh);
    let by_centre: std::collections::HashMap<_, usize> = centres
        .iter()
        .enumerate()
        .map(|(e, x)| (key(*x), e))
        .collect();
    for (e, x) in centres.iter().enumerate() {
        let mirror = Vector3::new(2.0 - x.x, x.y, x.z);
        let m = by_centre[&key(mirror)];
        let d = directions[e];
        let expected = Vector3::new(-d.x, d.y, d.z);
        assert!(
            (directions[m] - expected).norm() < 1e-7,
            "{x}: {d} vs {}",
            directions[m]
        );
    }
}

#[test]
fn two_inlets_one_outlet_reverse_the_flow() {
    let mesh = y_domain(Cells::Tet4, 4);
    let forward = FlowBoundary::from_names(&mesh, &["y0"], &["left_end", "right_end"]).unwrap();
    let backward = FlowBoundary::from_names(&mesh, &["left_end", "right_end"], &["y0"]).unwrap();
    let settings = FlowSettings::default();
    let forward = compute_fibers(&mesh, &forward, &settings).unwrap();
    let backward = compute_fibers(&mesh, &backward, &settings).unwrap();
    // φ ↦ 1 − φ: the same flow backwards.
    for (f, b) in forward.direction.iter().zip(&backward.direction) {
        assert!((f + b).norm() < 1e-6, "{f} vs {b}");
    }
    assert!((forward.inlet_flux - backward.outlet_flux).abs() < 1e-8 * forward.inlet_flux);
    assert!((backward.inlet_flux - backward.outlet_flux).abs() < 1e-7 * backward.inlet_flux);
}
