//! The full linearization of a sliding bond over the face of its triangle or past its rim:
//! the force f_s = T(g) n on the secondary node and f_k = −ξ_k f_s on corner k, with
//! T = A t_n(g) [N], n the unit normal of the current triangle, x_m = Σ ξ_k x_k the
//! closest point of the triangle, d = x_s − x_m and g = d·n the gap [m] (the distance to
//! the triangle's plane).
//!
//! With a₁ = x₁ − x₀, a₂ = x₂ − x₀, a = a₁ × a₂, P = I − n⊗n and T' = A dt_n/dg:
//! - ∂n/∂x₁ = −P [a₂]× / |a|, ∂n/∂x₂ = P [a₁]× / |a|, ∂n/∂x₀ = P ([a₂]× − [a₁]×) / |a|;
//! - ∂g/∂x_s = n, ∂g/∂x_k = −ξ_k n + (∂n/∂x_k)ᵀ d (the second term vanishes over the
//!   face, where d ∥ n);
//! - over the face, the closest point keeps d·a_α = 0, so
//!   M δξ = (a_α·(δx_s − Σ ξ_k δx_k) + g n·δa_α)_α with the metric M_αβ = a_α·a_β, for
//!   (ξ₁, ξ₂), and δξ₀ = −δξ₁ − δξ₂; past a rim edge from corner i to j = i + 1, x_m is the
//!   projection on the edge E = x_j − x_i: ξ_j = τ = (x_s − x_i)·E / E·E = 1 − ξ_i, with
//!   ∂τ/∂x_s = E/E·E, ∂τ/∂x_j = (x_s − x_i − 2τE)/E·E, ∂τ/∂x_i = −∂τ/∂x_s − ∂τ/∂x_j;
//!   past a rim vertex ξ stays;
//! - ∂f_s/∂x_j = T' n ⊗ ∂g/∂x_j + T ∂n/∂x_j, and the interface adds
//!   ∂f_k/∂x_j = −f_s ⊗ ∂ξ_k/∂x_j − ξ_k ∂f_s/∂x_j.
//!
//! Over an interior edge or vertex ([`pivot_tangent`]) the force is f_s = T(g) ν along
//! ν = d/g, g = |d|, with x_m on the edge (ξ as past a rim edge) or the vertex: with
//! S = T' ν⊗ν + (T/g)(I − ν⊗ν) and δd = δx_s − Σ ξ_k δx_k − E δτ,
//! ∂f_s/∂x_j = S ∂d/∂x_j.
//!
//! Over the face this is the Hessian of A Φ(g) with Φ' = t_n: symmetric, and consistent
//! while the law holds its branch. For a rigid main only ∂f_s/∂x_s enters.

use nalgebra::{Matrix2, Matrix2x3, Matrix3, RowVector3, Vector3};

use crate::projection::Feature;

/// Where on its triangle a sliding bond's closest point lies, for [`sliding_tangent`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Footing {
    /// Inside the face.
    Face,
    /// On rim edge `i` (corner `i` to `i + 1`), the node past it.
    RimEdge(u8),
    /// On a rim corner, the node past it.
    RimVertex,
}

impl Footing {
    /// The footing of a closest point on `feature` (over the face or past the rim).
    pub fn of(feature: Feature) -> Self {
        match feature {
            Feature::Face => Footing::Face,
            Feature::Edge(i) => Footing::RimEdge(i),
            Feature::Vertex(_) => Footing::RimVertex,
        }
    }
}

/// ∂f_s/∂x_j and ∂ξ/∂x_j (row k = ∂ξ_k/∂x_j) for j = the secondary node at `x` [m] and
/// corners 0, 1, 2 of the triangle `corners` [m] with unit normal `normal`, its closest
/// point of barycentric coordinates `xi` on `footing`, the gap `gap` [m]; `force` = T [N]
/// and `slope` = T' [N/m].
pub fn sliding_tangent(
    corners: &[Vector3<f64>; 3],
    footing: Footing,
    x: &Vector3<f64>,
    xi: &Vector3<f64>,
    normal: &Vector3<f64>,
    gap: f64,
    (force, slope): (f64, f64),
) -> ([Matrix3<f64>; 4], [Matrix3<f64>; 4]) {
    let n = normal;
    let a1 = corners[1] - corners[0];
    let a2 = corners[2] - corners[0];
    let length = a1.cross(&a2).norm();
    let metric = Matrix2::new(a1.dot(&a1), a1.dot(&a2), a1.dot(&a2), a2.dot(&a2));
    let (Some(inverse), true) = (metric.try_inverse(), length > 0.0) else {
        // A collapsed triangle: the node–point stiffness alone.
        let k = slope * n * n.transpose();
        let coupling = [k, -xi.x * k, -xi.y * k, -xi.z * k];
        return (coupling, [Matrix3::zeros(); 4]);
    };
    let p = (Matrix3::identity() - n * n.transpose()) / length;
    let turning = [
        Matrix3::zeros(),
        p * (a2.cross_matrix() - a1.cross_matrix()),
        -p * a2.cross_matrix(),
        p * a1.cross_matrix(),
    ];
    let offset = x - xi.x * corners[0] - xi.y * corners[1] - xi.z * corners[2];
    let gap_gradient: [Vector3<f64>; 4] = std::array::from_fn(|j| match j {
        0 => *n,
        _ => -xi[j - 1] * n + turning[j].transpose() * offset,
    });
    let coupling: [Matrix3<f64>; 4] =
        std::array::from_fn(|j| slope * n * gap_gradient[j].transpose() + force * turning[j]);
    let gradients = match footing {
        Footing::Face => face_shift(&inverse, &a1, &a2, xi, n, gap),
        Footing::RimEdge(i) => edge_shift(corners, i as usize, x),
        Footing::RimVertex => [Matrix3::zeros(); 4],
    };
    (coupling, gradients)
}

/// ∂f_s/∂x_j and ∂ξ/∂x_j (as [`sliding_tangent`]) of a bond whose closest point lies on
/// interior edge `i` (`vertex` false) or at interior corner `i` (`vertex` true) of the
/// triangle `corners` [m], the node at `x` [m], its direction `nu` and gap `gap` [m].
pub fn pivot_tangent(
    corners: &[Vector3<f64>; 3],
    (i, vertex): (usize, bool),
    x: &Vector3<f64>,
    nu: &Vector3<f64>,
    gap: f64,
    (force, slope): (f64, f64),
) -> ([Matrix3<f64>; 4], [Matrix3<f64>; 4]) {
    let along = nu * nu.transpose();
    let secant = if gap != 0.0 { force / gap } else { slope };
    let s = slope * along + secant * (Matrix3::identity() - along);
    let mut coupling = [Matrix3::zeros(); 4];
    if vertex {
        coupling[0] = s;
        coupling[1 + i] = -s;
        return (coupling, [Matrix3::zeros(); 4]);
    }
    let j = (i + 1) % 3;
    let edge = corners[j] - corners[i];
    let gradients = edge_shift(corners, i, x);
    // ∂τ/∂x is row j of ∂ξ/∂x (ξ_j = τ).
    let shift = |column: usize| edge * gradients[column].row(j);
    let tau = (x - corners[i]).dot(&edge) / edge.norm_squared();
    coupling[0] = s * (Matrix3::identity() - shift(0));
    coupling[1 + i] = s * (-(1.0 - tau) * Matrix3::identity() - shift(1 + i));
    coupling[1 + j] = s * (-tau * Matrix3::identity() - shift(1 + j));
    (coupling, gradients)
}

/// ∂ξ/∂x_j of the closest point inside the face (see the module docs).
fn face_shift(
    inverse: &Matrix2<f64>,
    a1: &Vector3<f64>,
    a2: &Vector3<f64>,
    xi: &Vector3<f64>,
    n: &Vector3<f64>,
    gap: f64,
) -> [Matrix3<f64>; 4] {
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
    std::array::from_fn(|j| {
        let x = inverse * rhs[j];
        let (d1, d2) = (x.row(0).into_owned(), x.row(1).into_owned());
        Matrix3::from_rows(&[-(d1 + d2), d1, d2])
    })
}

/// ∂ξ/∂x_j of the projection on rim edge `i` (see the module docs).
fn edge_shift(corners: &[Vector3<f64>; 3], i: usize, x: &Vector3<f64>) -> [Matrix3<f64>; 4] {
    let j = (i + 1) % 3;
    let edge = corners[j] - corners[i];
    let squared = edge.norm_squared();
    let tau = (x - corners[i]).dot(&edge) / squared;
    let by_node = edge / squared;
    let by_end = (x - corners[i] - 2.0 * tau * edge) / squared;
    let by_start = -by_node - by_end;
    let mut gradients = [Matrix3::zeros(); 4];
    for (column, d_tau) in [(0, by_node), (1 + i, by_start), (1 + j, by_end)] {
        gradients[column].set_row(i, &(-d_tau.transpose()));
        gradients[column].set_row(j, &d_tau.transpose());
    }
    gradients
}
