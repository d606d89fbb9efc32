//! Checks of the nodally averaged tet4 block passes: the patch tests on a distorted mesh,
//! and the forces against central differences of the total strain energy.

use std::collections::BTreeSet;

use nalgebra::{Matrix3, Vector3};

use super::NodalAveragePart;
use crate::element::{BlockKernel, Technology};
use crate::mesh::Mesh;
use crate::mesh::generate::{TetOrder, box_of_tets, distort};

const SIZE: [f64; 3] = [0.02, 0.01, 0.015];

pub(crate) fn neo_hookean(
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

/// A tet box of `divisions` cells with its interior nodes moved at random.
fn distorted_tets(divisions: [usize; 3]) -> Mesh {
    let mut mesh = box_of_tets(SIZE, divisions, TetOrder::Linear).unwrap();
    assert!(distort(&mut mesh, 0.3, 7).unwrap() > 0);
    mesh
}

fn boundary_nodes(mesh: &Mesh) -> BTreeSet<u32> {
    ["x0", "x1", "y0", "y1", "z0", "z1"]
        .iter()
        .flat_map(|s| mesh.node_set(s).unwrap().iter().copied())
        .collect()
}

/// Internal forces of the block at `positions` through the solver's passes.
fn forces(
    mesh: &Mesh,
    kernel: &BlockKernel,
    part: &mut NodalAveragePart,
    material: &dyn musclefem_materials::Material,
    positions: &[Vector3<f64>],
) -> Vec<Vector3<f64>> {
    let mut force = vec![Vector3::zeros(); positions.len()];
    part.add_internal_forces(
        kernel,
        &mesh.blocks[0],
        material,
        positions,
        0.0,
        1e-3,
        false,
        &mut force,
    )
    .unwrap();
    force
}

/// x = A X + b on a distorted mesh (216 tets, 4 chunks): every nodal Jacobian is det A,
/// the material sees F̄ = A (1e-10), interior nodal forces cancel and the x1 face carries
/// P(A) e_x times its area.
#[test]
fn linear_field_patch_test() {
    let a = Matrix3::new(1.1, 0.2, -0.05, 0.03, 0.95, 0.1, -0.02, 0.04, 1.2);
    let b = Vector3::new(0.001, -0.002, 0.003);
    let mesh = distorted_tets([4, 3, 3]);
    let block = &mesh.blocks[0];
    let kernel = BlockKernel::new(&mesh.nodes, block, Technology::Tet4NodalAverage).unwrap();
    let material = neo_hookean(1e4, 1e6);
    let mut part = NodalAveragePart::new(&kernel, block, material.as_ref());
    assert!(part.chunks.len() > 1);
    let positions: Vec<_> = (0..mesh.nodes.len())
        .map(|i| a * mesh.nodes.position(i) + b)
        .collect();
    let nodal = forces(&mesh, &kernel, &mut part, material.as_ref(), &positions);
    let worst_f = part
        .chunks
        .iter()
        .flat_map(|c| c.f_new.iter())
        .map(|f| (f - a).amax())
        .fold(0.0, f64::max);
    let worst_j = part
        .nodal_jacobian
        .iter()
        .map(|j| (j - a.determinant()).abs())
        .fold(0.0, f64::max);
    println!("largest |F̄ − A| = {worst_f:.2e}, |J_a − det A| = {worst_j:.2e}");
    assert!(worst_f < 1e-10, "{worst_f}");
    assert!(worst_j < 1e-10, "{worst_j}");

    let scale = nodal.iter().map(|f| f.amax()).fold(0.0, f64::max);
    let boundary = boundary_nodes(&mesh);
    let interior = nodal
        .iter()
        .enumerate()
        .filter(|(n, _)| !boundary.contains(&(*n as u32)))
        .map(|(_, f)| f.amax())
        .fold(0.0, f64::max);
    println!(
        "largest interior force / largest force = {:.2e}",
        interior / scale
    );
    assert!(interior < 1e-10 * scale, "{interior} vs {scale}");

    // P(A) e_x A₀ on x1 from the material at A (an independent path: no averaging).
    let piola = {
        use musclefem_materials::{PointBlock, PointResponse, VoigtStress};
        let mut stress = [VoigtStress::zeros()];
        material
            .update(
                &PointBlock {
                    time: 0.0,
                    dt: 1e-3,
                    deformation_gradient_old: &[Matrix3::identity()],
                    deformation_gradient_new: &[a],
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
        (on_face - expected).amax() < 1e-10 * expected.amax(),
        "{on_face} vs {expected}"
    );
}

/// Ψ(F) = μ/2 (J^{-2/3} tr(F Fᵀ) − 3) + (J − 1)²/D [Pa], the neo-Hookean energy written
/// out here independently of the material library.
fn neo_hookean_energy(f: &Matrix3<f64>, shear_modulus: f64, bulk_modulus: f64) -> f64 {
    let j = f.determinant();
    let i1_bar = j.powf(-2.0 / 3.0) * (f * f.transpose()).trace();
    0.5 * shear_modulus * (i1_bar - 3.0) + 0.5 * bulk_modulus * (j - 1.0).powi(2)
}

/// W = Σ_e V_e Ψ(F̄_e) [J] with F̄ built here from the definitions (nodal volume sums by
/// node id, J̄ the mean over the corners) rather than with the solver's passes; with
/// `averaged` false, the plain tet4 energy Σ_e V_e Ψ(F_e).
fn total_energy(
    mesh: &Mesh,
    kernel: &BlockKernel,
    positions: &[Vector3<f64>],
    shear_modulus: f64,
    bulk_modulus: f64,
    averaged: bool,
) -> f64 {
    let block = &mesh.blocks[0];
    let mut current = vec![0.0; mesh.nodes.len()];
    let mut reference = vec![0.0; mesh.nodes.len()];
    let mut f = Vec::with_capacity(block.len());
    for (e, ids) in block.elements().enumerate() {
        let x: Vec<_> = ids.iter().map(|&i| positions[i as usize]).collect();
        let fe = kernel.deformation_gradient(e, &x);
        for &i in ids {
            current[i as usize] += kernel.reference_volume(e) * fe.determinant();
            reference[i as usize] += kernel.reference_volume(e);
        }
        f.push(fe);
    }
    block
        .elements()
        .enumerate()
        .map(|(e, ids)| {
            let mean = ids
                .iter()
                .map(|&i| current[i as usize] / reference[i as usize])
                .sum::<f64>()
                / 4.0;
            let f_bar = if averaged {
                f[e] * (mean / f[e].determinant()).cbrt()
            } else {
                f[e]
            };
            kernel.reference_volume(e) * neo_hookean_energy(&f_bar, shear_modulus, bulk_modulus)
        })
        .sum()
}

/// Small SplitMix64-based generator in [−1, 1).
fn uniform(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    2.0 * (z >> 11) as f64 / (1u64 << 53) as f64 - 1.0
}

/// f_int = ∂W/∂x (the internal force of the code's convention, the negative of the
/// restoring force −∂W/∂x) against central differences of W on a distorted 2×2×2 tet
/// box (48 tets, every interior node coupled) under a random inhomogeneous deformation
/// with a large volume change: every component within 1e-6 of the largest force.
#[test]
fn forces_are_the_gradient_of_the_strain_energy() {
    let (mu, kappa) = (1e4, 2e5);
    let mesh = distorted_tets([2, 2, 2]);
    let block = &mesh.blocks[0];
    let kernel = BlockKernel::new(&mesh.nodes, block, Technology::Tet4NodalAverage).unwrap();
    let material = neo_hookean(mu, kappa);
    let mut part = NodalAveragePart::new(&kernel, block, material.as_ref());
    let stretch = Matrix3::new(1.15, 0.1, 0.0, -0.05, 0.9, 0.08, 0.02, 0.0, 1.1);
    let mut seed = 3;
    let mut positions: Vec<_> = (0..mesh.nodes.len())
        .map(|i| stretch * mesh.nodes.position(i))
        .collect();
    for x in &mut positions {
        for k in 0..3 {
            x[k] += 0.08 * 0.005 * uniform(&mut seed);
        }
    }
    let analytic = forces(&mesh, &kernel, &mut part, material.as_ref(), &positions);
    let scale = analytic.iter().map(|f| f.amax()).fold(0.0, f64::max);
    let h = 1e-8;
    let mut worst: f64 = 0.0;
    let mut moved = positions.clone();
    for node in 0..positions.len() {
        for k in 0..3 {
            moved[node][k] = positions[node][k] + h;
            let plus = total_energy(&mesh, &kernel, &moved, mu, kappa, true);
            moved[node][k] = positions[node][k] - h;
            let minus = total_energy(&mesh, &kernel, &moved, mu, kappa, true);
            moved[node][k] = positions[node][k];
            let numeric = (plus - minus) / (2.0 * h);
            worst = worst.max((numeric - analytic[node][k]).abs());
        }
    }
    println!(
        "largest |f − ∂W/∂x| / max|f| = {:.2e} (max|f| = {scale:.3e} N)",
        worst / scale
    );
    assert!(worst < 1e-6 * scale, "{worst} vs {scale}");
    // The averaging matters here: the gradient of the plain tet4 energy Σ V_e Ψ(F_e)
    // differs by much more than the tolerance.
    let mut difference: f64 = 0.0;
    for node in 0..positions.len() {
        for k in 0..3 {
            moved[node][k] = positions[node][k] + h;
            let plus = total_energy(&mesh, &kernel, &moved, mu, kappa, false);
            moved[node][k] = positions[node][k] - h;
            let minus = total_energy(&mesh, &kernel, &moved, mu, kappa, false);
            moved[node][k] = positions[node][k];
            difference = difference.max(((plus - minus) / (2.0 * h) - analytic[node][k]).abs());
        }
    }
    println!(
        "plain tet4 energy gradient: largest difference / max|f| = {:.2e}",
        difference / scale
    );
    assert!(difference > 1e-2 * scale, "{difference}");
}

/// An inverted tet is reported with its element (the averaged J̄ of its nodes could still be
/// positive, so the material alone would not notice).
#[test]
fn an_inverted_element_is_reported() {
    let mesh = box_of_tets(SIZE, [2, 2, 2], TetOrder::Linear).unwrap();
    let block = &mesh.blocks[0];
    let kernel = BlockKernel::new(&mesh.nodes, block, Technology::Tet4NodalAverage).unwrap();
    let material = neo_hookean(1e4, 1e5);
    let mut part = NodalAveragePart::new(&kernel, block, material.as_ref());
    let mut positions: Vec<_> = (0..mesh.nodes.len())
        .map(|i| mesh.nodes.position(i))
        .collect();
    // The centre node (1, 1, 1) of the lattice pushed along the diagonal of cell
    // (1, 1, 1) past its far corner: the 6 tets of that cell turn inside out.
    let centre = 1 + 3 * (1 + 3);
    let far = Vector3::new(SIZE[0], SIZE[1], SIZE[2]);
    let start = positions[centre];
    positions[centre] = start + (far - start) * 1.2;
    let mut force = vec![Vector3::zeros(); positions.len()];
    let (element, error) = part
        .add_internal_forces(
            &kernel,
            block,
            material.as_ref(),
            &positions,
            0.0,
            1e-3,
            false,
            &mut force,
        )
        .unwrap_err();
    let ids = block.element_nodes(element);
    assert!(ids.contains(&(centre as u32)), "{element}: {ids:?}");
    let x: Vec<_> = ids.iter().map(|&i| positions[i as usize]).collect();
    assert!(kernel.deformation_gradient(element, &x).determinant() <= 0.0);
    assert!(error.to_string().contains("inverted"), "{error}");
}

#[test]
fn a_hex_block_is_refused() {
    let hexes = crate::mesh::generate::box_of_hexes(SIZE, [1, 1, 1]).unwrap();
    let err =
        BlockKernel::new(&hexes.nodes, &hexes.blocks[0], Technology::Tet4NodalAverage).unwrap_err();
    assert!(
        matches!(err, crate::element::ElementError::WrongShape { .. }),
        "{err}"
    );
}
