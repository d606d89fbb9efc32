//! The full linearization of a sliding bond over the face of its triangle: the force
//! f_s = T(g) n on the secondary node and f_k = −ξ_k f_s on corner k, with T = A t_n(g)
//! [N], g = (x_s − x_m)·n the gap [m], n the unit normal of the current triangle and ξ
//! the barycentric coordinates of the closest point x_m = Σ ξ_k x_k (d = x_s − x_m = g n).
//!
//! With a₁ = x₁ − x₀, a₂ = x₂ − x₀, a = a₁ × a₂, P = I − n⊗n and T' = A dt_n/dg:
//! - ∂g/∂x_s = n, ∂g/∂x_k = −ξ_k n (the turning of n does not change g at the closest
//!   point, since d ∥ n);
//! - ∂n/∂x₁ = −P [a₂]× / |a|, ∂n/∂x₂ = P [a₁]× / |a|, ∂n/∂x₀ = P ([a₂]× − [a₁]×) / |a|;
//! - the closest point keeps d·a_α = 0, so M δξ = (a_α·(δx_s − Σ ξ_k δx_k) + g n·δa_α)_α
//!   with the metric M_αβ = a_α·a_β, for (ξ₁, ξ₂), and δξ₀ = −δξ₁ − δξ₂;
//! - ∂f_s/∂x_j = T' n ⊗ ∂g/∂x_j + T ∂n/∂x_j, and the interface adds
//!   ∂f_k/∂x_j = −f_s ⊗ ∂ξ_k/∂x_j − ξ_k ∂f_s/∂x_j.
//!
//! This is the Hessian of A Φ(g) with Φ' = t_n: symmetric, and consistent while the law
//! holds its branch. For a rigid main only ∂f_s/∂x_s = T' n⊗n enters.

use nalgebra::{Matrix2, Matrix2x3, Matrix3, RowVector3, Vector3};

/// ∂f_s/∂x_j and ∂ξ/∂x_j (row k = ∂ξ_k/∂x_j) for j = the secondary node and corners 0,
/// 1, 2, of a bond at gap `gap` [m] over the face of the triangle `corners` [m] with unit
/// normal `normal`, at the closest point of barycentric coordinates `xi`; `force` = T [N]
/// and `slope` = T' [N/m].
pub fn face_tangent(
    corners: &[Vector3<f64>; 3],
    xi: &Vector3<f64>,
    normal: &Vector3<f64>,
    gap: f64,
    force: f64,
    slope: f64,
) -> ([Matrix3<f64>; 4], [Matrix3<f64>; 4]) {
    let n = normal;
    let a1 = corners[1] - corners[0];
    let a2 = corners[2] - corners[0];
    let length = a1.cross(&a2).norm();
    let metric = Matrix2::new(a1.dot(&a1), a1.dot(&a2), a1.dot(&a2), a2.dot(&a2));
    let (Some(inverse), true) = (metric.try_inverse(), length > 0.0) else {
        // A collapsed triangle: the node–point stiffness alone.
        let k = slope * n * n.transpose();
        return ([k, -xi.x * k, -xi.y * k, -xi.z * k], [Matrix3::zeros(); 4]);
    };
    let p = (Matrix3::identity() - n * n.transpose()) / length;
    let turning = [
        Matrix3::zeros(),
        p * (a2.cross_matrix() - a1.cross_matrix()),
        -p * a2.cross_matrix(),
        p * a1.cross_matrix(),
    ];
    let gap_gradient = [*n, -xi.x * n, -xi.y * n, -xi.z * n];
    let coupling: [Matrix3<f64>; 4] =
        std::array::from_fn(|j| slope * n * gap_gradient[j].transpose() + force * turning[j]);
    let tangents = Matrix2x3::from_rows(&[a1.transpose(), a2.transpose()]);
    let nt: RowVector3<f64> = n.transpose();
    let zero = RowVector3::zeros();
    // ∂(rhs_α)/∂x_j: a_α for the node; −ξ_k a_α + g n·∂a_α/∂x_k for corner k.
    let rhs = [
        tangents,
        -xi.x * tangents + gap * Matrix2x3::from_rows(&[-nt, -nt]),
        -xi.y * tangents + gap * Matrix2x3::from_rows(&[nt, zero]),
        -xi.z * tangents + gap * Matrix2x3::from_rows(&[zero, nt]),
    ];
    let gradients: [Matrix3<f64>; 4] = std::array::from_fn(|j| {
        let x = inverse * rhs[j];
        let (d1, d2) = (x.row(0).into_owned(), x.row(1).into_owned());
        Matrix3::from_rows(&[-(d1 + d2), d1, d2])
    });
    (coupling, gradients)
}
