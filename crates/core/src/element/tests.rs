//! Kernel tests against exact references: linear fields, volumes, equilibrium.

use nalgebra::{Matrix3, Vector3};

use super::*;
use crate::mesh::generate::{box_of_hexes, distort};

fn distorted_box() -> crate::Mesh {
    let mut mesh = box_of_hexes([0.02, 0.01, 0.015], [4, 3, 3]).unwrap();
    let moved = distort(&mut mesh, 0.3, 7).unwrap();
    assert!(moved > 0);
    mesh
}

/// Patch test: the positions of a linear field x = A X + b give F = A at every
/// integration point of every element of a distorted mesh (1e-10).
#[test]
fn linear_field_is_reproduced_exactly_on_a_distorted_mesh() {
    let mesh = distorted_box();
    let block = &mesh.blocks[0];
    let kernel = BlockKernel::new(&mesh.nodes, block, Technology::Hex8Full).unwrap();
    let a = Matrix3::new(1.1, 0.2, -0.05, 0.03, 0.95, 0.1, -0.02, 0.04, 1.2);
    let b = Vector3::new(0.001, -0.002, 0.003);
    let mut positions = [Vector3::zeros(); 8];
    for (element, ids) in block.elements().enumerate() {
        for (x, &id) in positions.iter_mut().zip(ids) {
            *x = a * mesh.nodes.position(id as usize) + b;
        }
        for q in 0..8 {
            let f = kernel.deformation_gradient(element * 8 + q, &positions);
            assert!((f - a).amax() < 1e-10, "element {element}, point {q}: {f}");
        }
    }
}

#[test]
fn reference_volumes_add_up_to_the_box() {
    let mesh = distorted_box();
    let kernel = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], Technology::Hex8Full).unwrap();
    let total: f64 = (0..kernel.len()).map(|e| kernel.reference_volume(e)).sum();
    assert!(
        (total - 0.02 * 0.01 * 0.015).abs() < 1e-12 * 3e-6,
        "{total}"
    );
}

/// A constant stress gives nodal forces that sum to zero on every element and cancel at
/// every interior node; on the boundary they are the traction P N times the face area.
#[test]
fn constant_stress_is_in_equilibrium() {
    let mesh = distorted_box();
    let block = &mesh.blocks[0];
    let kernel = BlockKernel::new(&mesh.nodes, block, Technology::Hex8Full).unwrap();
    let piola = Matrix3::new(3.0, 1.0, 0.5, 1.0, -2.0, 0.25, 0.5, 0.25, 1.5);
    let mut nodal = vec![Vector3::zeros(); mesh.nodes.len()];
    for (element, ids) in block.elements().enumerate() {
        let mut forces = [Vector3::zeros(); 8];
        for q in 0..8 {
            kernel.add_internal_forces(element * 8 + q, &piola, &mut forces);
        }
        let sum: Vector3<f64> = forces.iter().sum();
        assert!(
            sum.amax() < 1e-12 * piola.amax() * 1e-4,
            "element {element}: {sum}"
        );
        for (&id, f) in ids.iter().zip(&forces) {
            nodal[id as usize] += f;
        }
    }
    // On face x1 (normal +x, area 0.01 × 0.015) the forces add up to P e_x × area.
    let on_face: Vector3<f64> = mesh
        .node_set("x1")
        .unwrap()
        .iter()
        .map(|&n| nodal[n as usize])
        .sum();
    let expected = piola * Vector3::x() * (0.01 * 0.015);
    assert!(
        (on_face - expected).amax() < 1e-12,
        "{on_face} vs {expected}"
    );
    let boundary: std::collections::BTreeSet<u32> = ["x0", "x1", "y0", "y1", "z0", "z1"]
        .iter()
        .flat_map(|s| mesh.node_set(s).unwrap().iter().copied())
        .collect();
    for (n, f) in nodal.iter().enumerate() {
        if !boundary.contains(&(n as u32)) {
            assert!(
                f.amax() < 1e-12 * piola.amax() * 1e-4,
                "interior node {n}: {f}"
            );
        }
    }
}

#[test]
fn a_tet_block_is_refused() {
    let mesh = crate::mesh::generate::box_of_tets(
        [1.0, 1.0, 1.0],
        [1, 1, 1],
        crate::mesh::generate::TetOrder::Linear,
    )
    .unwrap();
    let err = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], Technology::Hex8Full).unwrap_err();
    assert!(err.to_string().contains("hex8"), "{err}");
}
