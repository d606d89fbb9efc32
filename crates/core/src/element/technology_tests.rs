//! Patch tests of every technology on distorted meshes: linear fields give F = A exactly,
//! a constant stress gives forces that cancel at interior nodes, the reference volumes
//! add up to the box.

use std::collections::BTreeSet;

use nalgebra::{Matrix3, Vector3};

use super::*;
use crate::Mesh;
use crate::mesh::generate::{TetOrder, box_of_hexes, box_of_tets, distort};

const SIZE: [f64; 3] = [0.02, 0.01, 0.015];

pub(super) const ALL: [Technology; 6] = [
    Technology::Hex8Full,
    Technology::Hex8FBar,
    Technology::Hex8OnePoint {
        hourglass_modulus: 1e3,
    },
    Technology::Tet4,
    Technology::Tet10,
    Technology::Tet10FBar,
];

/// A box of the technology's shape with its interior nodes moved at random.
pub(super) fn distorted_mesh(technology: Technology) -> Mesh {
    let mut mesh = match technology.shape() {
        ElementShape::Hex8 => box_of_hexes(SIZE, [4, 3, 3]),
        ElementShape::Tet4 => box_of_tets(SIZE, [4, 3, 3], TetOrder::Linear),
        ElementShape::Tet10 => box_of_tets(SIZE, [3, 2, 2], TetOrder::Quadratic),
    }
    .unwrap();
    let moved = distort(&mut mesh, 0.3, 11).unwrap();
    assert!(moved > 0, "{technology:?}: the mesh must be distorted");
    mesh
}

/// The element's node positions under x = A X + b.
fn mapped(mesh: &Mesh, ids: &[u32], a: &Matrix3<f64>, b: &Vector3<f64>) -> Vec<Vector3<f64>> {
    ids.iter()
        .map(|&id| a * mesh.nodes.position(id as usize) + b)
        .collect()
}

fn boundary_nodes(mesh: &Mesh) -> BTreeSet<u32> {
    ["x0", "x1", "y0", "y1", "z0", "z1"]
        .iter()
        .flat_map(|s| mesh.node_set(s).unwrap().iter().copied())
        .collect()
}

pub(super) fn neo_hookean(
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

/// Internal forces of `element` at `positions` through the solver's path:
/// `element_deformation_gradients`, the material, `add_element_forces`.
pub(super) fn element_forces(
    kernel: &BlockKernel,
    material: &dyn musclefem_materials::Material,
    element: usize,
    positions: &[Vector3<f64>],
) -> Vec<Vector3<f64>> {
    use musclefem_materials::{PointBlock, PointResponse, VoigtStress};
    let ppe = kernel.points_per_element();
    let mut f = vec![Matrix3::identity(); ppe];
    kernel.element_deformation_gradients(element, positions, &mut f);
    let identity = vec![Matrix3::identity(); ppe];
    let fibers = vec![Vector3::x(); ppe];
    let block = PointBlock {
        time: 0.0,
        dt: 1e-3,
        deformation_gradient_old: &identity,
        deformation_gradient_new: &f,
        fiber_direction: &fibers,
        state_old: &[],
    };
    let mut stress = vec![VoigtStress::zeros(); ppe];
    let mut response = PointResponse {
        cauchy_stress: &mut stress,
        state_new: &mut [],
        tangent: None,
    };
    material.update(&block, &mut response).unwrap();
    let mut forces = vec![Vector3::zeros(); kernel.nodes_per_element()];
    kernel.add_element_forces(element, positions, &f, &stress, &mut forces, None);
    forces
}

#[test]
fn every_technology_reproduces_a_linear_field_exactly() {
    let a = Matrix3::new(1.1, 0.2, -0.05, 0.03, 0.95, 0.1, -0.02, 0.04, 1.2);
    let b = Vector3::new(0.001, -0.002, 0.003);
    for technology in ALL {
        let mesh = distorted_mesh(technology);
        let block = &mesh.blocks[0];
        let kernel = BlockKernel::new(&mesh.nodes, block, technology).unwrap();
        assert_eq!(kernel.len(), block.len());
        assert_eq!(kernel.points_per_element(), technology.points_per_element());
        assert_eq!(kernel.nodes_per_element(), block.shape.nodes_per_element());
        let mut f = vec![Matrix3::zeros(); kernel.points_per_element()];
        let mut worst: f64 = 0.0;
        for (element, ids) in block.elements().enumerate() {
            let positions = mapped(&mesh, ids, &a, &b);
            kernel.element_deformation_gradients(element, &positions, &mut f);
            for fq in &f {
                worst = worst.max((fq - a).amax());
            }
            // No hourglass force or energy under a linear field.
            let mut hourglass = vec![Vector3::zeros(); kernel.nodes_per_element()];
            kernel.add_hourglass_forces(element, &positions, &mut hourglass);
            let largest = hourglass.iter().map(|h| h.amax()).fold(0.0, f64::max);
            assert!(
                largest < 1e-15,
                "{technology:?} element {element}: {largest}"
            );
            assert!(kernel.hourglass_energy(element, &positions).abs() < 1e-30);
        }
        println!("{technology:?}: largest |F − A| = {worst:.2e}");
        assert!(worst < 1e-10, "{technology:?}: {worst}");
    }
}

#[test]
fn every_technology_has_the_box_volume() {
    let exact = SIZE.iter().product::<f64>();
    for technology in ALL {
        let mesh = distorted_mesh(technology);
        let kernel = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], technology).unwrap();
        let total: f64 = (0..kernel.len()).map(|e| kernel.reference_volume(e)).sum();
        assert!(
            (total - exact).abs() < 1e-12 * exact,
            "{technology:?}: {total} vs {exact}"
        );
        // And element by element the mesh's own volume (exact rules).
        for e in 0..kernel.len() {
            let v = mesh
                .element_volume(crate::ElementRef {
                    block: 0,
                    element: e as u32,
                })
                .unwrap();
            assert!((kernel.reference_volume(e) - v).abs() < 1e-12 * v);
        }
    }
}

/// A homogeneous deformation gives the same stress at every point; the assembled forces
/// then cancel at every interior node and each element's forces add up to zero.
#[test]
fn every_technology_passes_the_constant_stress_patch_test() {
    let a = Matrix3::new(1.1, 0.2, -0.05, 0.03, 0.95, 0.1, -0.02, 0.04, 1.2);
    let material = neo_hookean(1e4, 1e6);
    for technology in ALL {
        let mesh = distorted_mesh(technology);
        let block = &mesh.blocks[0];
        let kernel = BlockKernel::new(&mesh.nodes, block, technology).unwrap();
        let mut nodal = vec![Vector3::zeros(); mesh.nodes.len()];
        for (element, ids) in block.elements().enumerate() {
            let positions = mapped(&mesh, ids, &a, &Vector3::zeros());
            let forces = element_forces(&kernel, material.as_ref(), element, &positions);
            let sum: Vector3<f64> = forces.iter().sum();
            let scale = forces.iter().map(|f| f.amax()).fold(0.0, f64::max);
            assert!(
                sum.amax() < 1e-12 * scale,
                "{technology:?} {element}: {sum}"
            );
            for (&id, f) in ids.iter().zip(&forces) {
                nodal[id as usize] += f;
            }
        }
        let scale = nodal.iter().map(|f| f.amax()).fold(0.0, f64::max);
        let boundary = boundary_nodes(&mesh);
        let worst = nodal
            .iter()
            .enumerate()
            .filter(|(n, _)| !boundary.contains(&(*n as u32)))
            .map(|(_, f)| f.amax())
            .fold(0.0, f64::max);
        println!(
            "{technology:?}: largest interior force / largest force = {:.2e}",
            worst / scale
        );
        assert!(worst < 1e-9 * scale, "{technology:?}: {worst} vs {scale}");
        // The x1 face carries the traction P e_x over its area 0.01 × 0.015.
        let one = [a];
        let piola = {
            use musclefem_materials::{PointBlock, PointResponse, VoigtStress};
            let mut stress = [VoigtStress::zeros()];
            material
                .update(
                    &PointBlock {
                        time: 0.0,
                        dt: 1e-3,
                        deformation_gradient_old: &[Matrix3::identity()],
                        deformation_gradient_new: &one,
                        fiber_direction: &[Vector3::x()],
                        state_old: &[],
                    },
                    &mut PointResponse {
                        cauchy_stress: &mut stress,
                        state_new: &mut [],
                        tangent: None,
                    },
                )
                .unwrap();
            musclefem_materials::tensor::first_piola_from_cauchy(&a, &stress[0])
        };
        let on_face: Vector3<f64> = mesh
            .node_set("x1")
            .unwrap()
            .iter()
            .map(|&n| nodal[n as usize])
            .sum();
        let expected = piola * Vector3::x() * (SIZE[1] * SIZE[2]);
        assert!(
            (on_face - expected).amax() < 1e-9 * expected.amax(),
            "{technology:?}: {on_face} vs {expected}"
        );
    }
}

#[test]
fn a_block_of_another_shape_is_refused() {
    let hexes = box_of_hexes([1.0; 3], [1, 1, 1]).unwrap();
    let tets = box_of_tets([1.0; 3], [1, 1, 1], TetOrder::Linear).unwrap();
    for (mesh, technology) in [
        (&hexes, Technology::Tet4),
        (&hexes, Technology::Tet10),
        (&tets, Technology::Tet10),
        (&tets, Technology::hex8_one_point(1e4)),
    ] {
        let err = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], technology).unwrap_err();
        assert!(
            matches!(err, ElementError::WrongShape { .. }),
            "{technology:?}: {err}"
        );
        assert!(err.to_string().contains(technology.shape().name()), "{err}");
    }
}

#[test]
fn an_inverted_tet_is_refused() {
    for order in [TetOrder::Linear, TetOrder::Quadratic] {
        let mut mesh = box_of_tets([1.0; 3], [1, 1, 1], order).unwrap();
        let technology = match order {
            TetOrder::Linear => Technology::Tet4,
            TetOrder::Quadratic => Technology::Tet10,
        };
        // Mirror the mesh through x = 0: every element turns inside out.
        for x in &mut mesh.nodes.x {
            *x = -*x;
        }
        let err = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], technology).unwrap_err();
        assert!(
            matches!(err, ElementError::InvertedReference { element: 0, .. }),
            "{err}"
        );
    }
}
