//! Narrowphase: the closest point of a node on a triangle, its barycentric coordinates,
//! the feature it lies on, and the signed gap.
//!
//! For a node at x [m] and a triangle x₁ x₂ x₃ with unit normal n = (x₂ − x₁) × (x₃ − x₁)
//! / |…| (pointing out of the main body), the closest point is x_m = Σ N_i x_i with
//! barycentric coordinates N_i ≥ 0, Σ N_i = 1, found by the Voronoi regions of the
//! triangle (Ericson, Real-Time Collision Detection, §5.1.5):
//! - inside the face: x_m is the orthogonal projection, and the gap g = (x − x_m)·n [m];
//! - on an edge or a vertex (the node projects outside the triangle): x_m is the closest
//!   point of that feature, and g = s |x − x_m| with s the sign of (x − x_m)·n (+ when it
//!   is zero). The direction ν = (x − x_m)/g then is the unit vector with g ν = x − x_m,
//!   which is n on the face.
//!
//! g < 0 is a penetration. Over a surface the node takes the triangle with the smallest
//! |x − x_m| (ties to the lowest triangle index): g is then the signed distance to the
//! surface, continuous across edges, and its gradient ν is the direction of the contact
//! force. Tangential slip between two instants is the change of the closest point,
//! measured on the tangent plane.

use nalgebra::Vector3;

/// The feature of a triangle a closest point lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feature {
    /// The interior of the face (all three barycentric coordinates positive).
    Face,
    /// Edge `i`, from vertex `i` to vertex `(i + 1) % 3`.
    Edge(u8),
    /// Vertex `i`.
    Vertex(u8),
}

/// The closest point of a node on a triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    /// The closest point x_m [m].
    pub point: Vector3<f64>,
    /// Its barycentric coordinates N₁, N₂, N₃ (non-negative, summing to 1).
    pub barycentric: [f64; 3],
    /// The triangle's unit normal n (right-hand rule).
    pub normal: Vector3<f64>,
    /// The signed gap g [m] (negative = penetration).
    pub gap: f64,
    /// The unit direction ν with g ν = x − x_m (n on the face).
    pub direction: Vector3<f64>,
    /// Where x_m lies.
    pub feature: Feature,
}

/// The barycentric coordinates of the closest point of `x` on the triangle `corners` and
/// the feature it lies on (no normal, no square root: the cheap part of
/// [`project_on_triangle`]).
pub fn closest_feature(x: &Vector3<f64>, corners: &[Vector3<f64>; 3]) -> ([f64; 3], Feature) {
    let [a, b, c] = corners;
    let ab = b - a;
    let ac = c - a;
    let ap = x - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return ([1.0, 0.0, 0.0], Feature::Vertex(0));
    }
    let bp = x - b;
    let d3 = ab.dot(&bp);
    let d4 = ac.dot(&bp);
    if d3 >= 0.0 && d4 <= d3 {
        return ([0.0, 1.0, 0.0], Feature::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let t = d1 / (d1 - d3);
        return ([1.0 - t, t, 0.0], Feature::Edge(0));
    }
    let cp = x - c;
    let d5 = ab.dot(&cp);
    let d6 = ac.dot(&cp);
    if d6 >= 0.0 && d5 <= d6 {
        return ([0.0, 0.0, 1.0], Feature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let t = d2 / (d2 - d6);
        return ([1.0 - t, 0.0, t], Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return ([0.0, 1.0 - t, t], Feature::Edge(1));
    }
    let denominator = 1.0 / (va + vb + vc);
    let v = vb * denominator;
    let w = vc * denominator;
    ([1.0 - v - w, v, w], Feature::Face)
}

/// The closest point of `x` on the triangle `corners` (see the module docs).
pub fn project_on_triangle(x: &Vector3<f64>, corners: &[Vector3<f64>; 3]) -> Projection {
    let [a, b, c] = corners;
    let normal = (b - a).cross(&(c - a)).normalize();
    let (barycentric, feature) = closest_feature(x, corners);
    let point = a * barycentric[0] + b * barycentric[1] + c * barycentric[2];
    let offset = x - point;
    let (gap, direction) = if feature == Feature::Face {
        (offset.dot(&normal), normal)
    } else {
        let distance = offset.norm();
        if distance > 0.0 {
            let sign = if offset.dot(&normal) < 0.0 { -1.0 } else { 1.0 };
            (sign * distance, offset / (sign * distance))
        } else {
            (0.0, normal)
        }
    };
    Projection {
        point,
        barycentric,
        normal,
        gap,
        direction,
        feature,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle() -> [Vector3<f64>; 3] {
        [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(2.0, 0.0, 0.0),
            Vector3::new(0.0, 2.0, 0.0),
        ]
    }

    #[test]
    fn points_over_the_face_project_orthogonally_with_a_signed_gap() {
        let p = project_on_triangle(&Vector3::new(0.5, 0.25, -0.3), &triangle());
        assert_eq!(p.feature, Feature::Face);
        assert!((p.gap + 0.3).abs() < 1e-15);
        assert!((p.point - Vector3::new(0.5, 0.25, 0.0)).norm() < 1e-15);
        let [n1, n2, n3] = p.barycentric;
        assert!((n1 - 0.625).abs() < 1e-15 && (n2 - 0.25).abs() < 1e-15);
        assert!((n3 - 0.125).abs() < 1e-15);
        assert_eq!(p.direction, Vector3::z());
    }

    /// Each Voronoi region of the triangle: the closest point agrees with a brute-force
    /// search over a fine sampling of the triangle.
    #[test]
    fn edges_and_vertices_are_the_closest_features() {
        let corners = [
            Vector3::new(0.1, -0.2, 0.3),
            Vector3::new(1.7, 0.4, -0.2),
            Vector3::new(0.3, 1.9, 0.5),
        ];
        let samples = 400;
        let mut cases = 0;
        for (i, x) in [
            Vector3::new(-1.0, -1.0, 0.2),
            Vector3::new(3.0, 0.0, -0.5),
            Vector3::new(0.0, 3.0, 1.0),
            Vector3::new(1.0, -1.0, 0.1),
            Vector3::new(1.5, 1.5, -0.4),
            Vector3::new(-1.0, 1.0, 0.3),
            Vector3::new(0.6, 0.6, -0.7),
        ]
        .iter()
        .enumerate()
        {
            let p = project_on_triangle(x, &corners);
            let mut best = f64::INFINITY;
            for u in 0..=samples {
                for v in 0..=samples - u {
                    let (s, t) = (u as f64 / samples as f64, v as f64 / samples as f64);
                    let q = corners[0] * (1.0 - s - t) + corners[1] * s + corners[2] * t;
                    best = best.min((x - q).norm());
                }
            }
            let distance = (x - p.point).norm();
            assert!(
                distance <= best + 1e-12 && distance > best - 1e-2,
                "case {i}"
            );
            assert!((p.gap.abs() - distance).abs() < 1e-14);
            assert!((p.direction * p.gap - (x - p.point)).norm() < 1e-14);
            let sum: f64 = p.barycentric.iter().sum();
            assert!((sum - 1.0).abs() < 1e-14 && p.barycentric.iter().all(|&n| n >= 0.0));
            cases += usize::from(p.feature != Feature::Face);
        }
        assert_eq!(cases, 6);
    }
}
