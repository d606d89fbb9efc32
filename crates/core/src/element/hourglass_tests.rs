//! The one-point hex8's hourglass control: what it resists and what it must not.

use nalgebra::{Matrix3, Rotation3, Vector3};

use super::hex8_one_point::hourglass_base;
use super::technology_tests::{distorted_mesh, element_forces, neo_hookean};
use super::*;
use crate::Mesh;
use crate::mesh::generate::box_of_hexes;

const MODULUS: f64 = 1e3;

fn one_point() -> Technology {
    Technology::Hex8OnePoint {
        hourglass_modulus: MODULUS,
    }
}

fn reference(mesh: &Mesh, element: usize) -> Vec<Vector3<f64>> {
    mesh.blocks[0]
        .element_nodes(element)
        .iter()
        .map(|&id| mesh.nodes.position(id as usize))
        .collect()
}

/// The displacement modes the centre point does not see:
/// Γ^α_a = h^α_a − Σ_i (h^α · B̄_i) X_ia (X from the centroid).
fn hourglass_modes(kernel: &BlockKernel, element: usize, x: &[Vector3<f64>]) -> [[f64; 8]; 4] {
    let mean = kernel.gradients(element);
    let centroid = x.iter().sum::<Vector3<f64>>() / 8.0;
    let mut modes = [[0.0; 8]; 4];
    for (mode, h) in modes.iter_mut().zip(hourglass_base()) {
        let hb: Vector3<f64> = h.iter().zip(mean).map(|(ha, b)| b * *ha).sum();
        for a in 0..8 {
            mode[a] = h[a] - hb.dot(&(x[a] - centroid));
        }
    }
    modes
}

fn hourglass_forces(kernel: &BlockKernel, element: usize, x: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    let mut f = vec![Vector3::zeros(); 8];
    kernel.add_hourglass_forces(element, x, &mut f);
    f
}

fn largest(f: &[Vector3<f64>]) -> f64 {
    f.iter().map(|v| v.amax()).fold(0.0, f64::max)
}

/// Each of the 4 modes, in each direction, on every element of a distorted mesh: F = I
/// at the centre, yet hourglass forces resist it, with E_hg = ½ Σ f·u (linear forces).
#[test]
fn hourglass_modes_leave_the_centre_unstrained_and_are_resisted() {
    let mesh = distorted_mesh(one_point());
    let kernel = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], one_point()).unwrap();
    let amplitude = 1e-4;
    let mut smallest_energy = f64::INFINITY;
    for element in 0..kernel.len() {
        let x = reference(&mesh, element);
        let (_, k) = kernel.hourglass_vectors(element).unwrap();
        assert!(k > 0.0);
        for (alpha, mode) in hourglass_modes(&kernel, element, &x).iter().enumerate() {
            for direction in 0..3 {
                let u: Vec<Vector3<f64>> = mode
                    .iter()
                    .map(|m| Vector3::ith(direction, amplitude * m))
                    .collect();
                let positions: Vec<Vector3<f64>> = x.iter().zip(&u).map(|(x, u)| x + u).collect();
                let mut f = [Matrix3::zeros()];
                kernel.element_deformation_gradients(element, &positions, &mut f);
                assert!(
                    (f[0] - Matrix3::identity()).amax() < 1e-12,
                    "element {element}, mode {alpha}: {}",
                    f[0]
                );
                let forces = hourglass_forces(&kernel, element, &positions);
                let energy = kernel.hourglass_energy(element, &positions);
                let work: f64 = forces.iter().zip(&u).map(|(f, u)| f.dot(u)).sum();
                assert!(energy > 0.0 && largest(&forces) > 0.0);
                assert!(
                    (energy - 0.5 * work).abs() < 1e-10 * energy,
                    "{energy} vs {}",
                    0.5 * work
                );
                // Relative to the value 32 k s² on an undistorted element (q = 8 s).
                let relative = energy / (32.0 * k * amplitude * amplitude);
                smallest_energy = smallest_energy.min(relative);
            }
        }
    }
    println!("smallest E_hg / (32 k s²) over modes and elements: {smallest_energy:.3}");
    assert!(smallest_energy > 0.5, "{smallest_energy}");
}

/// A finite rotation with a translation, and a general linear field: no hourglass force
/// and no hourglass energy; a rotation superposed on an hourglass mode keeps its energy.
#[test]
fn rigid_motions_and_linear_fields_give_no_hourglass_force() {
    let mesh = distorted_mesh(one_point());
    let kernel = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], one_point()).unwrap();
    let rotation = Rotation3::from_axis_angle(
        &nalgebra::Unit::new_normalize(Vector3::new(1.0, 2.0, -0.5)),
        0.7,
    );
    let shift = Vector3::new(0.3, -0.1, 0.05);
    let a = Matrix3::new(1.1, 0.2, -0.05, 0.03, 0.95, 0.1, -0.02, 0.04, 1.2);
    for element in 0..kernel.len() {
        let x = reference(&mesh, element);
        let (_, k) = kernel.hourglass_vectors(element).unwrap();
        // Force scale of a unit hourglass mode of amplitude 1 µm: k × 8 × 1e-6.
        let scale = k * 8e-6;
        for map in [rotation.matrix(), &a] {
            let positions: Vec<Vector3<f64>> = x.iter().map(|x| map * x + shift).collect();
            let f = hourglass_forces(&kernel, element, &positions);
            assert!(
                largest(&f) < 1e-9 * scale,
                "element {element}: {}",
                largest(&f)
            );
        }
        let mode = hourglass_modes(&kernel, element, &x)[2];
        let bent: Vec<Vector3<f64>> = x
            .iter()
            .zip(&mode)
            .map(|(x, m)| x + Vector3::new(1e-4 * m, -2e-4 * m, 0.5e-4 * m))
            .collect();
        let turned: Vec<Vector3<f64>> = bent.iter().map(|x| rotation * x + shift).collect();
        let (e0, e1) = (
            kernel.hourglass_energy(element, &bent),
            kernel.hourglass_energy(element, &turned),
        );
        assert!((e0 - e1).abs() < 1e-10 * e0, "{e0} vs {e1}");
    }
}

/// The hourglass forces are the gradient of the hourglass energy (central differences).
#[test]
fn hourglass_forces_are_the_energy_gradient() {
    let mesh = distorted_mesh(one_point());
    let kernel = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], one_point()).unwrap();
    let element = 5;
    let x = reference(&mesh, element);
    // An arbitrary nodal motion (it includes hourglass components).
    let positions: Vec<Vector3<f64>> = x
        .iter()
        .enumerate()
        .map(|(a, x)| {
            let t = a as f64;
            x + 1e-4 * Vector3::new((1.3 * t).sin(), (0.7 * t + 1.0).cos(), (2.1 * t).sin())
        })
        .collect();
    let forces = hourglass_forces(&kernel, element, &positions);
    let h = 1e-7;
    for a in 0..8 {
        for d in 0..3 {
            let mut plus = positions.clone();
            let mut minus = positions.clone();
            plus[a][d] += h;
            minus[a][d] -= h;
            let derivative = (kernel.hourglass_energy(element, &plus)
                - kernel.hourglass_energy(element, &minus))
                / (2.0 * h);
            assert!(
                (derivative - forces[a][d]).abs() < 1e-6 * largest(&forces),
                "node {a}, component {d}: {derivative} vs {}",
                forces[a][d]
            );
        }
    }
}

/// The documented scaling: on a cube of side h the mode u_x = s ξη has
/// E_hg = 2 G_hg h s², and F = I at the centre.
#[test]
fn cube_hourglass_energy_has_the_documented_scaling() {
    let side = 0.004;
    let mesh = box_of_hexes([side; 3], [1, 1, 1]).unwrap();
    let kernel = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], one_point()).unwrap();
    let x = reference(&mesh, 0);
    let s = 1e-5;
    let positions: Vec<Vector3<f64>> = x
        .iter()
        .map(|p| {
            let (xi, eta) = (2.0 * p[0] / side - 1.0, 2.0 * p[1] / side - 1.0);
            p + Vector3::new(s * xi * eta, 0.0, 0.0)
        })
        .collect();
    let energy = kernel.hourglass_energy(0, &positions);
    let expected = 2.0 * MODULUS * side * s * s;
    assert!(
        (energy - expected).abs() < 1e-12 * expected,
        "{energy} vs {expected}"
    );
    let mut f = [Matrix3::zeros()];
    kernel.element_deformation_gradients(0, &positions, &mut f);
    assert!((f[0] - Matrix3::identity()).amax() < 1e-14);
    // With no hourglass control the mode costs nothing: the element's forces vanish.
    let free = Technology::Hex8OnePoint {
        hourglass_modulus: 0.0,
    };
    let kernel = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], free).unwrap();
    let forces = element_forces(&kernel, neo_hookean(1e4, 1e6).as_ref(), 0, &positions);
    assert!(largest(&forces) < 1e-12, "{}", largest(&forces));
}

/// Bending a unit cube: the one-point element's energy does not grow with the bulk
/// modulus (its centre sees no volume change), unlike full integration's.
#[test]
fn one_point_hex8_does_not_lock_in_bending() {
    let mesh = box_of_hexes([1.0; 3], [1, 1, 1]).unwrap();
    let x = reference(&mesh, 0);
    let u: Vec<Vector3<f64>> = x
        .iter()
        .map(|p| Vector3::new(1e-4 * (p[0] - 0.5) * (p[1] - 0.5), 0.0, 0.0))
        .collect();
    let positions: Vec<Vector3<f64>> = x.iter().zip(&u).map(|(x, u)| x + u).collect();
    let energy = |technology: Technology, bulk: f64| {
        let kernel = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], technology).unwrap();
        let forces = element_forces(&kernel, neo_hookean(1.0, bulk).as_ref(), 0, &positions);
        0.5 * forces.iter().zip(&u).map(|(f, u)| f.dot(u)).sum::<f64>()
    };
    let one = Technology::hex8_one_point(1.0);
    let growth = energy(one, 1e4) / energy(one, 10.0);
    let full = energy(Technology::Hex8Full, 1e4) / energy(Technology::Hex8Full, 10.0);
    println!("bending energy K = 1e4 over K = 10: one point {growth:.4}, full {full:.1}");
    assert!((growth - 1.0).abs() < 1e-6, "{growth}");
    assert!(full > 100.0);
}

#[test]
fn a_negative_or_nan_hourglass_modulus_is_refused() {
    let mesh = box_of_hexes([1.0; 3], [1, 1, 1]).unwrap();
    for modulus in [-1.0, f64::NAN, f64::INFINITY] {
        let technology = Technology::Hex8OnePoint {
            hourglass_modulus: modulus,
        };
        let err = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], technology).unwrap_err();
        assert!(
            matches!(err, ElementError::InvalidParameter { .. }),
            "{err}"
        );
        assert!(err.to_string().contains("hourglass modulus"), "{err}");
    }
    assert_eq!(
        Technology::hex8_one_point(2e4),
        Technology::Hex8OnePoint {
            hourglass_modulus: DEFAULT_HOURGLASS_FACTOR * 2e4
        }
    );
}
