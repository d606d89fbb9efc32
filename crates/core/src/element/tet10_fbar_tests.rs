//! The F-bar tet10 on curved elements (mid-edge nodes off their edges' midpoints): a
//! homogeneous deformation x = A X + b gives F̄ = A and so the material's stress at A at
//! every point, and the same forces as the plain tet10 (for an isochoric A too, where
//! J̄ = 1); the mean dilatation's gradient, which the implicit solver's mixed pressure
//! linearizes, is the derivative of J̄.

use nalgebra::{Matrix3, Vector3};

use super::technology_tests::{distorted_mesh, element_forces, neo_hookean};
use super::*;
use crate::Mesh;

/// Largest distance [m] the mid-edge nodes are moved off their edges (the cells are about
/// 7 mm).
const CURVATURE: f64 = 7e-4;

/// Shear and bulk modulus [Pa] of the neo-Hookean solid: muscle's K/μ = 10⁴.
const SHEAR: f64 = 1e4;
const BULK: f64 = 1e8;

/// Round-off bound on forces compared relative to their largest: the pressure K (J − 1)
/// carries K × 1e-16 of J's round-off against stresses of order μ, so 1e-12 K/μ.
const ROUND_OFF: f64 = 1e-12 * BULK / SHEAR;

/// The distorted tet10 box with every mid-edge node moved by up to [`CURVATURE`] in a
/// direction that varies from node to node, so the edges are curved and det J₀ varies
/// within the elements.
fn curved_mesh() -> Mesh {
    let mut mesh = distorted_mesh(Technology::Tet10FBar);
    let block = mesh.blocks[0].clone();
    let mut moved = vec![false; mesh.nodes.len()];
    for ids in block.elements() {
        for &id in &ids[4..] {
            moved[id as usize] = true;
        }
    }
    for (id, _) in moved.iter().enumerate().filter(|(_, m)| **m) {
        let s = id as f64;
        let offset = Vector3::new((1.3 * s).sin(), (2.1 * s).cos(), (0.7 * s + 1.0).sin());
        let x = mesh.nodes.position(id) + offset * (CURVATURE / 3f64.sqrt());
        mesh.nodes.set_position(id, x);
    }
    // The edges are curved: a mid-edge node is off the midpoint of its corners.
    let edges = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)];
    let largest = block
        .elements()
        .flat_map(|ids| {
            edges.iter().enumerate().map(|(m, &(a, b))| {
                let corners = (mesh.nodes.position(ids[a] as usize)
                    + mesh.nodes.position(ids[b] as usize))
                    / 2.0;
                (mesh.nodes.position(ids[4 + m] as usize) - corners).norm()
            })
        })
        .fold(0.0, f64::max);
    assert!(largest > 0.5 * CURVATURE, "{largest}");
    mesh
}

/// Nodes of `element` of the first block under x = A X + b.
fn mapped(mesh: &Mesh, element: usize, a: &Matrix3<f64>, b: &Vector3<f64>) -> Vec<Vector3<f64>> {
    mesh.blocks[0]
        .element_nodes(element)
        .iter()
        .map(|&id| a * mesh.nodes.position(id as usize) + b)
        .collect()
}

/// The Cauchy stress of `material` at `f` (Voigt).
fn stress_at(
    material: &dyn musclefem_materials::Material,
    f: &Matrix3<f64>,
) -> musclefem_materials::VoigtStress {
    use musclefem_materials::{PointBlock, PointResponse, VoigtStress};
    let mut stress = [VoigtStress::zeros()];
    material
        .update(
            &PointBlock {
                time: 0.0,
                dt: 1e-3,
                deformation_gradient_old: &[Matrix3::identity()],
                deformation_gradient_new: &[*f],
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
    stress[0]
}

/// On every curved element under x = A X + b: F̄ = A at every point, so the material's
/// stress is its stress at A, and the forces are the plain tet10's (they add up to zero).
/// Returns the largest |forces − plain tet10's| relative to the element's largest force.
fn homogeneous_deformation_is_reproduced(a: &Matrix3<f64>) -> f64 {
    let mesh = curved_mesh();
    let block = &mesh.blocks[0];
    let fbar = BlockKernel::new(&mesh.nodes, block, Technology::Tet10FBar).unwrap();
    let plain = BlockKernel::new(&mesh.nodes, block, Technology::Tet10).unwrap();
    let material = neo_hookean(SHEAR, BULK);
    let expected = stress_at(material.as_ref(), a);
    let b = Vector3::new(0.001, -0.002, 0.003);
    let mut f = [Matrix3::zeros(); 4];
    let mut worst: f64 = 0.0;
    for element in 0..block.len() {
        let positions = mapped(&mesh, element, a, &b);
        fbar.element_deformation_gradients(element, &positions, &mut f);
        for (q, fq) in f.iter().enumerate() {
            assert!(
                (fq - a).amax() < 1e-12,
                "element {element}, point {q}: {fq}"
            );
            let stress = stress_at(material.as_ref(), fq);
            assert!(
                (stress - expected).amax() < 1e-9 * expected.amax(),
                "element {element}, point {q}: {stress} vs {expected}"
            );
        }
        let with_fbar = element_forces(&fbar, material.as_ref(), element, &positions);
        let with_plain = element_forces(&plain, material.as_ref(), element, &positions);
        let scale = with_plain.iter().map(|v| v.amax()).fold(0.0, f64::max);
        let sum: Vector3<f64> = with_fbar.iter().sum();
        assert!(sum.amax() < 1e-12 * scale, "element {element}: {sum}");
        for (x, y) in with_fbar.iter().zip(&with_plain) {
            worst = worst.max((x - y).amax() / scale);
        }
    }
    worst
}

#[test]
fn a_homogeneous_deformation_gives_the_materials_stress_on_curved_tet10() {
    let a = Matrix3::new(1.1, 0.2, -0.05, 0.03, 0.95, 0.1, -0.02, 0.04, 1.2);
    let worst = homogeneous_deformation_is_reproduced(&a);
    println!(
        "det A = {:.4}: largest |f − f_tet10| / |f| = {worst:.2e}",
        a.determinant()
    );
    assert!(worst < ROUND_OFF, "{worst}");
}

#[test]
fn an_isochoric_deformation_gives_the_plain_tet10_forces() {
    let stretch = 1.2_f64;
    let shear = Matrix3::new(1.0, 0.3, 0.0, 0.0, 1.0, -0.1, 0.0, 0.0, 1.0);
    let a = shear * Matrix3::from_diagonal(&Vector3::new(stretch, 1.0, 1.0 / stretch));
    assert!((a.determinant() - 1.0).abs() < 1e-15);
    let worst = homogeneous_deformation_is_reproduced(&a);
    println!("isochoric: largest |f − f_tet10| / |f| = {worst:.2e}");
    assert!(worst < ROUND_OFF, "{worst}");
}

/// ∂J̄/∂x_a against central differences of J̄ = v/V on a curved element under a
/// non-affine deformation (relative 1e-7).
#[test]
fn the_mean_dilatation_gradient_is_its_derivative() {
    let mesh = curved_mesh();
    let block = &mesh.blocks[0];
    let kernel = BlockKernel::new(&mesh.nodes, block, Technology::Tet10FBar).unwrap();
    let element = block.len() / 2;
    let mut x: Vec<Vector3<f64>> = block
        .element_nodes(element)
        .iter()
        .map(|&id| mesh.nodes.position(id as usize))
        .collect();
    for p in &mut x {
        *p += Vector3::new(3.0 * p.y * p.z, -2.0 * p.x * p.x, 0.1 * p.y);
    }
    let (mean, gradient) = kernel.mean_dilatation_gradient(element, &x);
    assert!(
        (mean - 1.0).abs() > 1e-4,
        "the deformation changes the volume: {mean}"
    );
    let h = 1e-8;
    let largest = gradient.iter().map(|g| g.amax()).fold(0.0, f64::max);
    for a in 0..x.len() {
        for k in 0..3 {
            let mut plus = x.clone();
            let mut minus = x.clone();
            plus[a][k] += h;
            minus[a][k] -= h;
            let numeric = (kernel.mean_dilatation_gradient(element, &plus).0
                - kernel.mean_dilatation_gradient(element, &minus).0)
                / (2.0 * h);
            assert!(
                (numeric - gradient[a][k]).abs() < 1e-7 * largest,
                "node {a}, {k}: {numeric} vs {}",
                gradient[a][k]
            );
        }
    }
    assert!(gradient[x.len()..].iter().all(|g| g.amax() == 0.0));
}
