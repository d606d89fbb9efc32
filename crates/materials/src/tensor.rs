//! Small tensor helpers shared by the built-in materials: Voigt storage, the deviatoric
//! projection, the isochoric/volumetric split of F, stress conversions, and the
//! assembly of the consistent tangent ∂P/∂F from directional derivatives of the
//! Kirchhoff stress.

use nalgebra::{Matrix3, Vector3, Vector6};

use crate::material::{Tangent, VoigtStress};

/// Voigt vector (xx, yy, zz, yz, xz, xy) of a symmetric matrix.
#[inline]
pub fn voigt_from_symmetric(m: &Matrix3<f64>) -> VoigtStress {
    Vector6::new(
        m[(0, 0)],
        m[(1, 1)],
        m[(2, 2)],
        m[(1, 2)],
        m[(0, 2)],
        m[(0, 1)],
    )
}

/// Symmetric matrix of a Voigt vector (xx, yy, zz, yz, xz, xy).
#[inline]
pub fn symmetric_from_voigt(v: &VoigtStress) -> Matrix3<f64> {
    Matrix3::new(v[0], v[5], v[4], v[5], v[1], v[3], v[4], v[3], v[2])
}

/// Deviatoric part dev(A) = A − (tr A / 3) I.
#[inline]
pub fn deviatoric(a: &Matrix3<f64>) -> Matrix3<f64> {
    a - Matrix3::from_diagonal_element(a.trace() / 3.0)
}

/// First Piola–Kirchhoff stress P = J σ F⁻ᵀ [Pa] from the Cauchy stress (Voigt).
pub fn first_piola_from_cauchy(f: &Matrix3<f64>, cauchy: &VoigtStress) -> Matrix3<f64> {
    let j = f.determinant();
    let f_inv = f.try_inverse().unwrap_or_else(Matrix3::zeros);
    j * symmetric_from_voigt(cauchy) * f_inv.transpose()
}

/// Von Mises equivalent stress √(3/2 s:s) of a Cauchy stress [Pa].
pub fn von_mises(cauchy: &VoigtStress) -> f64 {
    let s = deviatoric(&symmetric_from_voigt(cauchy));
    (1.5 * s.component_mul(&s).sum()).sqrt()
}

/// J^(-1/3) for J > 0, within a few ulp of `1 / J.cbrt()` but about three times faster
/// for the near-incompressible range |J − 1| ≤ 0.1 that tissue lives in: the Taylor series
/// (1 + e)^(-1/3) ≈ 1 − e/3 + 2e²/9 − 14e³/81 (relative error < 35e⁴/243 ≤ 1.5e-5), then
/// two Newton steps on 1/y³ = J, y ← y (4 − J y³)/3, each of which squares the error
/// (×2): 1.5e-5 → 4.5e-10 → 4e-19. Outside that range it calls `cbrt`.
#[inline]
pub fn inverse_cube_root(j: f64) -> f64 {
    let e = j - 1.0;
    if e.abs() <= 0.1 {
        let mut y = 1.0 + e * (-1.0 / 3.0 + e * (2.0 / 9.0 + e * (-14.0 / 81.0)));
        y *= (4.0 - j * y * y * y) * (1.0 / 3.0);
        y *= (4.0 - j * y * y * y) * (1.0 / 3.0);
        y
    } else {
        1.0 / j.cbrt()
    }
}

/// Pressure p = dW_V/dJ = 2 (J − 1)/D [Pa] of the volumetric energy W_V = (J − 1)²/D
/// shared by the built-in materials (D the compressibility [1/Pa]).
#[inline]
pub fn volumetric_pressure(jacobian: f64, compressibility: f64) -> f64 {
    2.0 * (jacobian - 1.0) / compressibility
}

/// d(J p)/dJ = 2 (2J − 1)/D [Pa], the slope of the volumetric Kirchhoff stress.
#[inline]
pub fn volumetric_kirchhoff_slope(jacobian: f64, compressibility: f64) -> f64 {
    2.0 * (2.0 * jacobian - 1.0) / compressibility
}

/// Kirchhoff pressure J p = J dU/dJ = k ln J [Pa] of the logarithmic volumetric energy
/// U = k/2 (ln J)² (FEBio's default for its uncoupled materials; k the bulk modulus [Pa]).
#[inline]
pub fn logarithmic_volumetric_kirchhoff(jacobian: f64, bulk_modulus: f64) -> f64 {
    bulk_modulus * jacobian.ln()
}

/// d(J p)/dJ = k / J [Pa] of U = k/2 (ln J)², the slope of its Kirchhoff pressure.
#[inline]
pub fn logarithmic_volumetric_kirchhoff_slope(jacobian: f64, bulk_modulus: f64) -> f64 {
    bulk_modulus / jacobian
}

/// Deviatoric part of a symmetric tensor in Voigt order.
#[inline]
pub fn deviatoric_voigt(a: &Vector6<f64>) -> Vector6<f64> {
    let mean = (a[0] + a[1] + a[2]) * (1.0 / 3.0);
    Vector6::new(a[0] - mean, a[1] - mean, a[2] - mean, a[3], a[4], a[5])
}

/// v ⊗ v in Voigt order.
#[inline]
pub fn outer_voigt(v: &Vector3<f64>) -> Vector6<f64> {
    Vector6::new(
        v[0] * v[0],
        v[1] * v[1],
        v[2] * v[2],
        v[1] * v[2],
        v[0] * v[2],
        v[0] * v[1],
    )
}

/// Left Cauchy–Green tensor B = F Fᵀ in Voigt order (only its 6 distinct entries).
#[inline]
pub fn left_cauchy_green_voigt(f: &Matrix3<f64>) -> Vector6<f64> {
    let row = |i: usize| Vector3::new(f[(i, 0)], f[(i, 1)], f[(i, 2)]);
    let (r0, r1, r2) = (row(0), row(1), row(2));
    Vector6::new(
        r0.dot(&r0),
        r1.dot(&r1),
        r2.dot(&r2),
        r1.dot(&r2),
        r0.dot(&r2),
        r0.dot(&r1),
    )
}

/// The isochoric/volumetric split of a deformation gradient:
/// J = det F, F̄ = J^(-1/3) F, B̄ = F̄ F̄ᵀ (Voigt order), Ī₁ = tr B̄.
#[derive(Debug, Clone, Copy)]
pub struct IsochoricSplit {
    pub f: Matrix3<f64>,
    pub jacobian: f64,
    /// J^(-1/3)
    pub j_minus_third: f64,
    /// B̄ in Voigt order (xx, yy, zz, yz, xz, xy).
    pub b_bar: Vector6<f64>,
    pub i1_bar: f64,
}

impl IsochoricSplit {
    #[inline]
    pub fn new(f: &Matrix3<f64>) -> Self {
        let jacobian = f.determinant();
        let j_minus_third = inverse_cube_root(jacobian);
        let b_bar = left_cauchy_green_voigt(f) * (j_minus_third * j_minus_third);
        IsochoricSplit {
            f: *f,
            jacobian,
            j_minus_third,
            b_bar,
            i1_bar: b_bar[0] + b_bar[1] + b_bar[2],
        }
    }

    /// F̄ = J^(-1/3) F.
    #[inline]
    pub fn f_bar(&self) -> Matrix3<f64> {
        self.f * self.j_minus_third
    }
}

/// Consistent tangent 𝔸 = ∂P/∂F of a decoupled material whose Kirchhoff stress is
/// τ = dev(M(F̄)) + J p(J) I, given
/// - `tau`: τ at F [Pa];
/// - `d_jp_dj`: d(J p)/dJ [Pa];
/// - `d_m`: the directional derivative dM[dF̄] of the isochoric "stress-like" tensor M.
///
/// For each unit direction E = e_k ⊗ e_L of F:
/// dJ = J F⁻¹_Lk, dF̄ = J^(-1/3) (E − ⅓ F⁻¹_Lk F), dτ = dev(dM[dF̄]) + d(Jp)/dJ dJ I,
/// and since P = τ F⁻ᵀ: dP = dτ F⁻ᵀ − τ F⁻ᵀ Eᵀ F⁻ᵀ, which fills column k + 3L.
pub fn decoupled_tangent(
    split: &IsochoricSplit,
    tau: &Matrix3<f64>,
    d_jp_dj: f64,
    mut d_m: impl FnMut(&Matrix3<f64>) -> Matrix3<f64>,
) -> Tangent {
    let f_inv = split.f.try_inverse().unwrap_or_else(Matrix3::zeros);
    let f_inv_t = f_inv.transpose();
    let tau_f_inv_t = tau * f_inv_t;
    let mut tangent = Tangent::zeros();
    for l in 0..3 {
        for k in 0..3 {
            let trace_finv_e = f_inv[(l, k)];
            let mut e = Matrix3::zeros();
            e[(k, l)] = 1.0;
            let d_jacobian = split.jacobian * trace_finv_e;
            let d_f_bar = (e - split.f * (trace_finv_e / 3.0)) * split.j_minus_third;
            let d_tau =
                deviatoric(&d_m(&d_f_bar)) + Matrix3::from_diagonal_element(d_jp_dj * d_jacobian);
            // τ F⁻ᵀ Eᵀ F⁻ᵀ = (column l of τ F⁻ᵀ) ⊗ (row k of F⁻ᵀ), with no products by
            // the zeros of E.
            let d_p = d_tau * f_inv_t - tau_f_inv_t.column(l) * f_inv_t.row(k);
            let column = k + 3 * l;
            for row in 0..9 {
                tangent[(row, column)] = d_p[row];
            }
        }
    }
    tangent
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tangents_outer_product_is_the_product_through_the_unit_direction() {
        // A Eᵀ B with E = e_k ⊗ e_l, as decoupled_tangent forms it, and as the full
        // products gave it before: the same bits (no entry of A or B is zero here).
        let a = Matrix3::new(1.3, -0.2, 0.7, 0.05, 2.1, -1.1, 0.4, 0.9, -3.3);
        let b = Matrix3::new(0.8, 0.15, -0.6, -0.35, 1.7, 0.25, 0.45, -0.55, 1.05);
        for l in 0..3 {
            for k in 0..3 {
                let mut e = Matrix3::zeros();
                e[(k, l)] = 1.0;
                let product = a * e.transpose() * b;
                let outer = a.column(l) * b.row(k);
                assert_eq!(
                    product.map(f64::to_bits),
                    outer.map(f64::to_bits),
                    "{k}, {l}"
                );
            }
        }
    }

    #[test]
    fn voigt_round_trip() {
        let v = Vector6::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0);
        let m = symmetric_from_voigt(&v);
        assert_eq!(m, m.transpose());
        assert_eq!(m[(1, 2)], 4.0);
        assert_eq!(m[(0, 2)], 5.0);
        assert_eq!(m[(0, 1)], 6.0);
        assert_eq!(voigt_from_symmetric(&m), v);
    }

    #[test]
    fn von_mises_of_uniaxial_stress_is_its_magnitude() {
        let v = Vector6::new(-7.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        assert!((von_mises(&v) - 7.0).abs() < 1e-12);
        let shear = Vector6::new(0.0, 0.0, 0.0, 0.0, 0.0, 2.0);
        assert!((von_mises(&shear) - 2.0 * 3f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn inverse_cube_root_matches_cbrt_to_round_off() {
        for i in 0..=20_000 {
            let j = 0.5 + i as f64 * 5e-5;
            let y = inverse_cube_root(j);
            let reference = 1.0 / j.cbrt();
            assert!(
                (y - reference).abs() <= 4.0 * f64::EPSILON * reference,
                "J = {j}"
            );
        }
        for j in [1e-6, 0.2, 3.0, 1e6] {
            assert_eq!(inverse_cube_root(j), 1.0 / f64::cbrt(j));
        }
    }

    #[test]
    fn split_is_volume_preserving() {
        let f = Matrix3::new(1.2, 0.1, 0.0, 0.05, 0.9, 0.2, 0.0, -0.1, 1.1);
        let s = IsochoricSplit::new(&f);
        assert!((s.f_bar().determinant() - 1.0).abs() < 1e-14);
        let b_bar = s.f_bar() * s.f_bar().transpose();
        assert!((symmetric_from_voigt(&s.b_bar) - b_bar).amax() < 1e-15);
        assert!((s.jacobian - f.determinant()).abs() < 1e-15);
    }
}
