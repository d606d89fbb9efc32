//! Driving a material point by hand: one step of `update` from a kept state, and the
//! deformation gradients and rotations the tests use.

// Each test binary uses a part of this file.
#![allow(dead_code)]

use musclefem_materials::{Material, MaterialError, PointBlock, PointResponse, VoigtStress};
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};

/// One material point carried through steps: F and the state at the last accepted step.
pub struct Point<'m> {
    pub material: &'m dyn Material,
    pub fiber: Vector3<f64>,
    pub f: Matrix3<f64>,
    pub state: Vec<f64>,
    pub time: f64,
}

impl<'m> Point<'m> {
    pub fn new(material: &'m dyn Material, fiber: Vector3<f64>) -> Self {
        Point {
            material,
            fiber,
            f: Matrix3::identity(),
            state: material.initial_state(1),
            time: 0.0,
        }
    }

    /// A step of `dt` to `f_new`; accepted (F and state kept) when it succeeds.
    pub fn step(&mut self, f_new: Matrix3<f64>, dt: f64) -> Result<VoigtStress, MaterialError> {
        let (stress, state) = self.trial(f_new, dt)?;
        self.f = f_new;
        self.state = state;
        self.time += dt;
        Ok(stress)
    }

    /// A step of `dt` to `f_new` without accepting it: the stress and the new state.
    pub fn trial(
        &self,
        f_new: Matrix3<f64>,
        dt: f64,
    ) -> Result<(VoigtStress, Vec<f64>), MaterialError> {
        let f_old = [self.f];
        let f_new = [f_new];
        let block = PointBlock {
            time: self.time + dt,
            dt,
            deformation_gradient_old: &f_old,
            deformation_gradient_new: &f_new,
            fiber_direction: &[self.fiber],
            state_old: &self.state,
        };
        let mut stress = [VoigtStress::zeros()];
        let mut state = vec![0.0; self.state.len()];
        let mut response = PointResponse {
            cauchy_stress: &mut stress,
            state_new: &mut state,
            tangent: None,
        };
        self.material.update(&block, &mut response)?;
        Ok((stress[0], state))
    }

    /// The value of the state variable `name`.
    pub fn state_named(&self, name: &str) -> f64 {
        let index = self
            .material
            .state_variables()
            .iter()
            .position(|s| s.name == name)
            .unwrap_or_else(|| panic!("no state variable {name}"));
        self.state[index]
    }
}

/// The rotation by `angle` [rad] about `axis`.
pub fn rotation(axis: [f64; 3], angle: f64) -> Matrix3<f64> {
    let axis = Unit::new_normalize(Vector3::from(axis));
    *Rotation3::from_axis_angle(&axis, angle).matrix()
}

/// The symmetric matrix of a Voigt vector (xx, yy, zz, yz, xz, xy).
pub fn matrix(v: &VoigtStress) -> Matrix3<f64> {
    Matrix3::new(v[0], v[5], v[4], v[5], v[1], v[3], v[4], v[3], v[2])
}

/// |a - b| / |b| (the Frobenius norm of the symmetric tensors).
pub fn relative_difference(a: &VoigtStress, b: &VoigtStress) -> f64 {
    (matrix(a) - matrix(b)).norm() / matrix(b).norm()
}

/// Deformation gradients away from the identity: stretches, shears, general ones with
/// J from about 0.7 to 1.4 (a fixed pseudo-random sequence).
pub fn deformation_gradients() -> Vec<Matrix3<f64>> {
    let mut fs = vec![
        Matrix3::from_diagonal(&Vector3::new(1.3, 0.9, 0.95)),
        Matrix3::new(1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        Matrix3::identity() * 1.1,
    ];
    let mut seed: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = move || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    while fs.len() < 24 {
        let f = Matrix3::identity() + Matrix3::from_fn(|_, _| 0.3 * next());
        let j = f.determinant();
        if (0.7..1.4).contains(&j) {
            fs.push(f);
        }
    }
    fs
}

/// The polar decomposition F = R U from the eigenvectors of C = Fᵀ F: (R, U).
pub fn polar(f: &Matrix3<f64>) -> (Matrix3<f64>, Matrix3<f64>) {
    let eigen = (f.transpose() * f).symmetric_eigen();
    let root = eigen.eigenvalues.map(f64::sqrt);
    let u = eigen.eigenvectors * Matrix3::from_diagonal(&root) * eigen.eigenvectors.transpose();
    let r = f * u.try_inverse().unwrap();
    (r, u)
}
