//! The local frame (n, s, t) of a main-surface triangle, in which the traction law acts.

use nalgebra::{Matrix3, Vector3};

/// The local frame of triangle (a, b, c) as the columns of a rotation R = [n s t]: the
/// unit normal n = (b − a) × (c − a) / |·| (right-hand rule: out of the main body for
/// faces ordered as [`musclefem_core::mesh::Mesh::face_nodes`] orders them), the first
/// in-plane direction s along b − a, and t = n × s. A degenerate triangle (zero area)
/// takes `fallback` as its normal.
pub fn frame(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
    fallback: &Vector3<f64>,
) -> Matrix3<f64> {
    let ab = b - a;
    let cross = ab.cross(&(c - a));
    let area2 = cross.norm();
    let n = if area2 > 0.0 && area2.is_finite() {
        cross / area2
    } else {
        *fallback
    };
    // b − a is in the plane; if degenerate, any direction normal to n.
    let mut s = ab - n * n.dot(&ab);
    if s.norm() <= 1e-300 {
        s = n.cross(&if n.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        });
    }
    let s = s.normalize();
    let t = n.cross(&s);
    Matrix3::from_columns(&[n, s, t])
}

/// ∂n/∂x_k of the unit normal n = a₁ × a₂ / |a₁ × a₂| of triangle (x₀, x₁, x₂)
/// (a₁ = x₁ − x₀, a₂ = x₂ − x₀) for k = 0, 1, 2 [1/m]: with P = I − n⊗n,
/// ∂n/∂x₁ = −P [a₂]× / |a|, ∂n/∂x₂ = P [a₁]× / |a|, ∂n/∂x₀ = −∂n/∂x₁ − ∂n/∂x₂.
/// Zero for a degenerate triangle (its normal is the fallback, a constant).
pub fn normal_derivatives(corners: &[Vector3<f64>; 3]) -> [Matrix3<f64>; 3] {
    let a1 = corners[1] - corners[0];
    let a2 = corners[2] - corners[0];
    let cross = a1.cross(&a2);
    let length = cross.norm();
    if !(length > 0.0 && length.is_finite()) {
        return [Matrix3::zeros(); 3];
    }
    let n = cross / length;
    let p = (Matrix3::identity() - n * n.transpose()) / length;
    let d1 = -p * a2.cross_matrix();
    let d2 = p * a1.cross_matrix();
    [-d1 - d2, d1, d2]
}

/// ∂(R δ)/∂x_k [1 per m of δ] for k = 0, 1, 2 of a fixed local vector δ = (δ_n, δ_s, δ_t)
/// turned by the frame R = [n s t] of triangle (x₀, x₁, x₂) ([`frame`]):
/// δ_n ∂n/∂x_k + δ_s ∂s/∂x_k + δ_t ∂t/∂x_k, with ([`normal_derivatives`] for ∂n)
/// - s = u/|u|, u = x₁ − x₀ (in the plane, so n·u = 0):
///   ∂s = (I − s⊗s)/|u| (P ∂u − n ⊗ (∂nᵀ u)), P = I − n⊗n, ∂u/∂x₀ = −I, ∂u/∂x₁ = I;
/// - t = n × s: ∂t = −[s]× ∂n + [n]× ∂s.
///
/// Zero for a degenerate triangle (its frame is built from the fallback normal, a constant).
pub fn turned_vector_derivatives(
    corners: &[Vector3<f64>; 3],
    local: &Vector3<f64>,
) -> [Matrix3<f64>; 3] {
    let dn = normal_derivatives(corners);
    let u = corners[1] - corners[0];
    let length = u.norm();
    // A degenerate triangle (no normal derivative) or a collapsed first edge.
    let degenerate = dn.iter().all(|m| m.iter().all(|&x| x == 0.0));
    if degenerate || length.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return [Matrix3::zeros(); 3];
    }
    let r = frame(&corners[0], &corners[1], &corners[2], &Vector3::x());
    let n: Vector3<f64> = r.column(0).into_owned();
    let s: Vector3<f64> = r.column(1).into_owned();
    let project_normal = Matrix3::identity() - n * n.transpose();
    let project_s = (Matrix3::identity() - s * s.transpose()) / length;
    let du = [-Matrix3::identity(), Matrix3::identity(), Matrix3::zeros()];
    std::array::from_fn(|k| {
        let ds = project_s * (project_normal * du[k] - n * (u.transpose() * dn[k]));
        let dt = -s.cross_matrix() * dn[k] + n.cross_matrix() * ds;
        dn[k] * local.x + ds * local.y + dt * local.z
    })
}

/// H_kj = ∂(T_kᵀ f)/∂x_j [N/m] for k, j = 0, 1, 2, with T_k = ∂(R δ)/∂x_k
/// ([`turned_vector_derivatives`]) and a fixed force `force` f [N]: the Hessian of the
/// scalar f · R δ over the corners, the stiffness the main corners get from a rest offset
/// δ (`local` [m]) turning under a force. Central differences of the analytic T_kᵀ f, step
/// 1e-6 of the longest edge (error ~1e-10 of |f| |δ| / h²), symmetrized (the exact Hessian
/// is symmetric).
pub fn turned_vector_curvature(
    corners: &[Vector3<f64>; 3],
    local: &Vector3<f64>,
    force: &Vector3<f64>,
) -> [[Matrix3<f64>; 3]; 3] {
    let edge = (0..3)
        .map(|i| (corners[(i + 1) % 3] - corners[i]).norm())
        .fold(0.0, f64::max);
    let mut curvature = [[Matrix3::zeros(); 3]; 3];
    if !(edge > 0.0 && edge.is_finite()) {
        return curvature;
    }
    let step = 1e-6 * edge;
    let gradient = |at: &[Vector3<f64>; 3]| -> [Vector3<f64>; 3] {
        turned_vector_derivatives(at, local).map(|t| t.transpose() * force)
    };
    for j in 0..3 {
        for axis in 0..3 {
            let (mut plus, mut minus) = (*corners, *corners);
            plus[j][axis] += step;
            minus[j][axis] -= step;
            let (gp, gm) = (gradient(&plus), gradient(&minus));
            for k in 0..3 {
                let column = (gp[k] - gm[k]) / (2.0 * step);
                curvature[k][j].set_column(axis, &column);
            }
        }
    }
    for k in 0..3 {
        for j in k..3 {
            let mean = 0.5 * (curvature[k][j] + curvature[j][k].transpose());
            curvature[k][j] = mean;
            curvature[j][k] = mean.transpose();
        }
    }
    curvature
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_frame_is_a_right_handed_rotation_with_the_face_normal() {
        let r = frame(
            &Vector3::new(0.0, 0.0, 1.0),
            &Vector3::new(1.0, 0.0, 1.0),
            &Vector3::new(0.0, 1.0, 1.0),
            &Vector3::x(),
        );
        assert_eq!(Vector3::from(r.column(0)), Vector3::<f64>::z());
        assert_eq!(Vector3::from(r.column(1)), Vector3::<f64>::x());
        assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-15);
        assert!((r.determinant() - 1.0).abs() < 1e-15);
        let degenerate = frame(
            &Vector3::zeros(),
            &Vector3::zeros(),
            &Vector3::x(),
            &Vector3::y(),
        );
        assert_eq!(Vector3::from(degenerate.column(0)), Vector3::<f64>::y());
        assert!((degenerate.determinant() - 1.0).abs() < 1e-15);
    }

    /// The test triangle of the derivative checks.
    const CORNERS: [Vector3<f64>; 3] = [
        Vector3::new(0.1, -0.2, 0.3),
        Vector3::new(1.2, 0.1, 0.2),
        Vector3::new(0.3, 0.9, 0.7),
    ];

    /// `derivatives[k]` (column j: ∂/∂x_k,j) of `value` at [`CORNERS`] against central
    /// differences.
    fn check_corner_derivatives(
        value: impl Fn(&[Vector3<f64>; 3]) -> Vector3<f64>,
        derivatives: &[Matrix3<f64>; 3],
    ) {
        let h = 1e-7;
        for k in 0..3 {
            for j in 0..3 {
                let (mut plus, mut minus) = (CORNERS, CORNERS);
                plus[k][j] += h;
                minus[k][j] -= h;
                let fd = (value(&plus) - value(&minus)) / (2.0 * h);
                let exact = derivatives[k].column(j).into_owned();
                assert!(
                    (fd - exact).norm() < 1e-8,
                    "corner {k}, axis {j}: {fd} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn the_turned_vector_derivatives_match_central_differences() {
        let local = Vector3::new(0.3, -0.7, 0.45);
        check_corner_derivatives(
            |c| frame(&c[0], &c[1], &c[2], &Vector3::x()) * local,
            &turned_vector_derivatives(&CORNERS, &local),
        );
    }

    #[test]
    fn the_normal_derivatives_match_central_differences() {
        check_corner_derivatives(
            |c| {
                frame(&c[0], &c[1], &c[2], &Vector3::x())
                    .column(0)
                    .into_owned()
            },
            &normal_derivatives(&CORNERS),
        );
    }
}
