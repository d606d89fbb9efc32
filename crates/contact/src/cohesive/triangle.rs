//! A main-surface triangle as a bond sees it: the closest point to a node (with its
//! barycentric coordinates) and the local frame (n, s, t) of the traction law.

use nalgebra::{Matrix3, Vector3};

/// Barycentric coordinates ξ = (ξ_a, ξ_b, ξ_c) of the point of triangle (a, b, c) closest
/// to `p` (Ericson, Real-Time Collision Detection, §5.1.5: the Voronoi regions of the
/// vertices, the edges and the face), and the squared distance [m²].
pub fn closest_point(
    p: &Vector3<f64>,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
) -> (Vector3<f64>, f64) {
    let coordinates = closest_coordinates(p, a, b, c);
    let point = coordinates.x * a + coordinates.y * b + coordinates.z * c;
    (coordinates, (p - point).norm_squared())
}

fn closest_coordinates(
    p: &Vector3<f64>,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
) -> Vector3<f64> {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return Vector3::new(1.0, 0.0, 0.0);
    }
    let bp = p - b;
    let d3 = ab.dot(&bp);
    let d4 = ac.dot(&bp);
    if d3 >= 0.0 && d4 <= d3 {
        return Vector3::new(0.0, 1.0, 0.0);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return Vector3::new(1.0 - v, v, 0.0);
    }
    let cp = p - c;
    let d5 = ab.dot(&cp);
    let d6 = ac.dot(&cp);
    if d6 >= 0.0 && d5 <= d6 {
        return Vector3::new(0.0, 0.0, 1.0);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return Vector3::new(1.0 - w, 0.0, w);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return Vector3::new(0.0, 1.0 - w, w);
    }
    let denominator = 1.0 / (va + vb + vc);
    let v = vb * denominator;
    let w = vc * denominator;
    Vector3::new(1.0 - v - w, v, w)
}

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

#[cfg(test)]
mod tests {
    use super::*;

    fn brute_force(
        p: &Vector3<f64>,
        a: &Vector3<f64>,
        b: &Vector3<f64>,
        c: &Vector3<f64>,
    ) -> f64 {
        let n = 400;
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=(n - i) {
                let (u, v) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                let q = a + u * (b - a) + v * (c - a);
                best = best.min((p - q).norm_squared());
            }
        }
        best
    }

    #[test]
    fn the_closest_point_is_closest_in_every_region() {
        let a = Vector3::new(0.0, 0.0, 0.0);
        let b = Vector3::new(2.0, 0.1, 0.0);
        let c = Vector3::new(0.3, 1.5, 0.2);
        for p in [
            Vector3::new(0.5, 0.4, 0.7),   // face
            Vector3::new(-1.0, -1.0, 0.3), // vertex a
            Vector3::new(3.0, 0.0, -0.5),  // vertex b
            Vector3::new(0.3, 2.5, 0.0),   // vertex c
            Vector3::new(1.0, -1.0, 0.0),  // edge ab
            Vector3::new(-1.0, 0.7, 0.0),  // edge ac
            Vector3::new(1.5, 1.2, 0.4),   // edge bc
        ] {
            let (xi, distance2) = closest_point(&p, &a, &b, &c);
            assert!((xi.sum() - 1.0).abs() < 1e-14);
            assert!(xi.iter().all(|&x| x >= 0.0));
            let reference = brute_force(&p, &a, &b, &c);
            assert!(distance2 <= reference + 1e-12, "{p:?}");
            assert!(distance2 >= reference - 1e-4, "{p:?}");
        }
    }

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
        let degenerate = frame(&Vector3::zeros(), &Vector3::zeros(), &Vector3::x(), &Vector3::y());
        assert_eq!(Vector3::from(degenerate.column(0)), Vector3::<f64>::y());
        assert!((degenerate.determinant() - 1.0).abs() < 1e-15);
    }
}
