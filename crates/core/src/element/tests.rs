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

fn neo_hookean(
    shear_modulus: f64,
    bulk_modulus: f64,
) -> std::sync::Arc<dyn musclefem_materials::Material> {
    let params = std::collections::BTreeMap::from([
        ("mu".to_string(), shear_modulus),
        ("D".to_string(), 2.0 / bulk_modulus),
    ]);
    musclefem_materials::MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap()
}

/// Internal forces of element `element` of `kernel` at `positions` (material at rest
/// before the step, a hyperelastic material so the state does not matter).
fn element_forces(
    kernel: &BlockKernel,
    material: &dyn musclefem_materials::Material,
    element: usize,
    positions: &[Vector3<f64>],
) -> Vec<Vector3<f64>> {
    use musclefem_materials::{PointBlock, PointResponse, VoigtStress};
    let mut f = [Matrix3::identity(); 8];
    kernel.element_deformation_gradients(element, positions, &mut f);
    let identity = [Matrix3::identity(); 8];
    let block = PointBlock {
        time: 0.0,
        dt: 1e-3,
        deformation_gradient_old: &identity,
        deformation_gradient_new: &f,
        fiber_direction: &[Vector3::x(); 8],
        state_old: &[],
    };
    let mut stress = [VoigtStress::zeros(); 8];
    let mut response = PointResponse {
        cauchy_stress: &mut stress,
        state_new: &mut [],
        tangent: None,
    };
    material.update(&block, &mut response).unwrap();
    let mut forces = vec![Vector3::zeros(); 8];
    kernel.add_element_forces(element, positions, &f, &stress, &mut forces, None);
    forces
}

#[test]
fn fbar_reproduces_linear_fields_and_constant_stress() {
    let mesh = distorted_box();
    let block = &mesh.blocks[0];
    let full = BlockKernel::new(&mesh.nodes, block, Technology::Hex8Full).unwrap();
    let fbar = BlockKernel::new(&mesh.nodes, block, Technology::Hex8FBar).unwrap();
    let a = Matrix3::new(1.1, 0.2, -0.05, 0.03, 0.95, 0.1, -0.02, 0.04, 1.2);
    let material = neo_hookean(1e4, 1e6);
    let mut nodal = vec![Vector3::zeros(); mesh.nodes.len()];
    let mut positions = [Vector3::zeros(); 8];
    for (element, ids) in block.elements().enumerate() {
        for (x, &id) in positions.iter_mut().zip(ids) {
            *x = a * mesh.nodes.position(id as usize);
        }
        let mut f = [Matrix3::zeros(); 8];
        fbar.element_deformation_gradients(element, &positions, &mut f);
        for (q, fq) in f.iter().enumerate() {
            assert!(
                (fq - a).amax() < 1e-10,
                "element {element}, point {q}: {fq}"
            );
        }
        // Under a homogeneous deformation F-bar and full integration give the same forces.
        let with_fbar = element_forces(&fbar, material.as_ref(), element, &positions);
        let with_full = element_forces(&full, material.as_ref(), element, &positions);
        for (x, y) in with_fbar.iter().zip(&with_full) {
            assert!((x - y).amax() < 1e-9 * y.amax().max(1e-12), "{x} vs {y}");
        }
        for (&id, force) in ids.iter().zip(&with_fbar) {
            nodal[id as usize] += force;
        }
    }
    // Constant stress: the assembled forces vanish at interior nodes.
    let boundary: std::collections::BTreeSet<u32> = ["x0", "x1", "y0", "y1", "z0", "z1"]
        .iter()
        .flat_map(|s| mesh.node_set(s).unwrap().iter().copied())
        .collect();
    let scale = nodal.iter().map(|f| f.amax()).fold(0.0, f64::max);
    for (n, f) in nodal.iter().enumerate() {
        if !boundary.contains(&(n as u32)) {
            assert!(f.amax() < 1e-9 * scale, "interior node {n}: {f}");
        }
    }
}

/// Volumetric locking, measured: the energy ½ u·f of a small bending mode
/// u_x = ε (x − ½)(y − ½) of a unit cube element grows with the bulk modulus for the fully
/// integrated hex8 (its Gauss points see a volume change), and not with F-bar (the
/// element's mean dilatation is zero in bending).
#[test]
fn fbar_does_not_lock_in_bending_and_full_integration_does() {
    let mesh = box_of_hexes([1.0; 3], [1, 1, 1]).unwrap();
    let block = &mesh.blocks[0];
    let epsilon = 1e-4;
    let reference: Vec<Vector3<f64>> = block
        .element_nodes(0)
        .iter()
        .map(|&id| mesh.nodes.position(id as usize))
        .collect();
    let displacement: Vec<Vector3<f64>> = reference
        .iter()
        .map(|x| Vector3::new(epsilon * (x[0] - 0.5) * (x[1] - 0.5), 0.0, 0.0))
        .collect();
    let positions: Vec<Vector3<f64>> = reference
        .iter()
        .zip(&displacement)
        .map(|(x, u)| x + u)
        .collect();
    let energy = |technology: Technology, bulk_modulus: f64| {
        let kernel = BlockKernel::new(&mesh.nodes, block, technology).unwrap();
        let material = neo_hookean(1.0, bulk_modulus);
        let forces = element_forces(&kernel, material.as_ref(), 0, &positions);
        0.5 * forces
            .iter()
            .zip(&displacement)
            .map(|(f, u)| f.dot(u))
            .sum::<f64>()
    };
    let full_growth = energy(Technology::Hex8Full, 1e4) / energy(Technology::Hex8Full, 10.0);
    let fbar_growth = energy(Technology::Hex8FBar, 1e4) / energy(Technology::Hex8FBar, 10.0);
    println!("bending energy, K = 1e4 over K = 10: full {full_growth:.1}, F-bar {fbar_growth:.4}");
    assert!(full_growth > 100.0, "full integration: {full_growth}");
    assert!((fbar_growth - 1.0).abs() < 0.01, "F-bar: {fbar_growth}");
}
