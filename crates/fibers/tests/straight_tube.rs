//! A straight tube (a box) with the inlet and outlet at its two ends: the exact potential
//! is linear, φ = 1 − x/L, and every fiber is axial. The scheme is exact for this field
//! on any mesh, so every direction must be e_x to round-off and solver tolerance.

mod common;

use common::{Cells, angle_degrees, box_mesh};
use musclefem_fibers::{BoundaryRegion, FlowBoundary, FlowSettings, Side, compute_fibers};
use musclefem_mesh::ElementBlock;
use musclefem_mesh::Face;
use musclefem_mesh::generate::distort;
use nalgebra::Vector3;

/// Largest angle between a fiber and e_x allowed [rad].
const AXIAL: f64 = 1e-8;

fn max_angle_from_axis(field: &musclefem_fibers::FiberField) -> f64 {
    field
        .direction
        .iter()
        .map(|d| angle_degrees(*d, Vector3::x()).to_radians())
        .fold(0.0, f64::max)
}

#[test]
fn every_fiber_is_axial_on_regular_and_distorted_meshes() {
    for cells in Cells::ALL {
        for distorted in [false, true] {
            let mut mesh = box_mesh(cells, [0.1, 0.03, 0.02], [10, 4, 3]);
            if distorted {
                distort(&mut mesh, 0.3, 11).unwrap();
            }
            let boundary = FlowBoundary::from_names(&mesh, &["x0"], &["x1"]).unwrap();
            let field = compute_fibers(&mesh, &boundary, &FlowSettings::default()).unwrap();
            let angle = max_angle_from_axis(&field);
            println!(
                "{cells:?} distorted {distorted}: max angle {angle:.2e} rad, {} solves, {} CG iterations, residual {:.1e}, flux in {:.6e} out {:.6e}",
                field.linear_solves,
                field.linear_iterations,
                field.residual,
                field.inlet_flux,
                field.outlet_flux
            );
            assert!(
                angle < AXIAL,
                "{cells:?} distorted {distorted}: {angle:e} rad"
            );
            // Flux = area / length for φ dropping by 1 over L: 0.03 · 0.02 / 0.1 m.
            let exact_flux = 0.03 * 0.02 / 0.1;
            assert!((field.inlet_flux - exact_flux).abs() < 1e-8 * exact_flux);
            assert!((field.outlet_flux - exact_flux).abs() < 1e-8 * exact_flux);
            // φ = 1 − x/L at the centroids.
            assert_eq!(field.potential.len(), mesh.element_count());
        }
    }
}

#[test]
fn blocks_of_different_shapes_form_one_tube() {
    // A hex box and a tet box are not conforming (quads against triangles), so two tet
    // blocks and one hex tube: split the tet box's elements into two blocks by x.
    let mut mesh = box_mesh(Cells::Tet4, [0.1, 0.03, 0.02], [10, 4, 3]);
    let block = mesh.blocks.remove(0);
    let (mut left, mut right) = (Vec::new(), Vec::new());
    for ids in block.elements() {
        let x: f64 = ids.iter().map(|&i| mesh.nodes.x[i as usize]).sum::<f64>() / 4.0;
        if x < 0.05 { &mut left } else { &mut right }.extend_from_slice(ids);
    }
    mesh.blocks = vec![
        ElementBlock::new("right", block.shape, right).unwrap(),
        ElementBlock::new("left", block.shape, left).unwrap(),
    ];
    mesh.surfaces.clear();
    let boundary = FlowBoundary::from_names(&mesh, &["x0"], &["x1"]).unwrap();
    let field = compute_fibers(&mesh, &boundary, &FlowSettings::default()).unwrap();
    assert!(max_angle_from_axis(&field) < AXIAL);
    assert_eq!(
        field.block_offsets,
        vec![0, mesh.blocks[0].len(), mesh.element_count()]
    );
    field.assign_to(&mut mesh).unwrap();
    for block in &mesh.blocks {
        for d in &block.fiber_direction {
            assert!((d - Vector3::x()).norm() < 1e-8);
        }
    }
}

/// The inlet given as its two halves (y below and above the middle), then once more as a
/// whole: each half carries half the exact flux, and the whole, whose faces the halves
/// already claimed, none. The outlet is one region with the whole outlet flux.
#[test]
fn region_fluxes_split_the_inlet_by_area() {
    let mesh = box_mesh(Cells::Hex8, [0.1, 0.03, 0.02], [10, 4, 3]);
    let inlet = mesh.surface("x0").unwrap();
    let (low, high): (Vec<Face>, Vec<Face>) = inlet.iter().partition(|&&face| {
        let nodes = mesh.face_nodes(face).unwrap();
        let y: f64 = nodes.iter().map(|&n| mesh.nodes.y[n as usize]).sum::<f64>();
        y / (nodes.len() as f64) < 0.015
    });
    let halves = |name: &str, faces: Vec<Face>| BoundaryRegion::Faces {
        name: name.to_string(),
        faces,
    };
    let boundary = FlowBoundary {
        inlet: vec![
            halves("low", low),
            halves("high", high),
            BoundaryRegion::surface(&mesh, "x0").unwrap(),
        ],
        outlet: vec![BoundaryRegion::node_set(&mesh, "x1").unwrap()],
    };
    let field = compute_fibers(&mesh, &boundary, &FlowSettings::default()).unwrap();
    let exact_flux = 0.03 * 0.02 / 0.1;
    let expected = [
        ("low", Side::Inlet, 6, exact_flux / 2.0),
        ("high", Side::Inlet, 6, exact_flux / 2.0),
        ("x0", Side::Inlet, 0, 0.0),
        ("x1", Side::Outlet, 12, exact_flux),
    ];
    assert_eq!(field.region_fluxes.len(), expected.len());
    for (region, (name, side, faces, flux)) in field.region_fluxes.iter().zip(expected) {
        assert_eq!(
            (region.name.as_str(), region.side, region.faces),
            (name, side, faces)
        );
        assert!(
            (region.flux - flux).abs() < 1e-8 * exact_flux,
            "{name}: {} vs {flux}",
            region.flux
        );
    }
    let inlet_sum: f64 = field.region_fluxes[..3].iter().map(|r| r.flux).sum();
    assert!((inlet_sum - field.inlet_flux).abs() < 1e-14 * exact_flux);
}
