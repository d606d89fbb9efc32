//! The smooth centreline and cross-section profiles of a swept muscle, interpolated
//! through its stations.
//!
//! - Position: a centripetal Catmull–Rom spline through the station centres P_0 … P_{n−1}
//!   (Yuksel, Schaefer & Keyser 2011): knots t_0 = 0, t_{i+1} = t_i + |P_{i+1} − P_i|^½,
//!   and on [t_i, t_{i+1}] the cubic Hermite curve between P_i and P_{i+1} with the
//!   derivatives P'(t_i) = (P_i − P_{i−1})/(t_i − t_{i−1})
//!   − (P_{i+1} − P_{i−1})/(t_{i+1} − t_{i−1}) + (P_{i+1} − P_i)/(t_{i+1} − t_i),
//!   with phantom end points P_{−1} = 2P_0 − P_1 and P_n = 2P_{n−1} − P_{n−2}. The curve
//!   passes through every centre, is C¹, and the centripetal knots keep it free of cusps
//!   and self-intersections within a segment.
//! - Scalars (the two semi-axes and each component of the width direction): the monotone
//!   piecewise-cubic Hermite interpolant of Fritsch & Carlson (1980) over the same knots,
//!   which is C¹ and never overshoots the station values (so semi-axes stay positive).
//!
//! Integrals along the curve use 5-point Gauss–Legendre quadrature on [`SUBDIVISIONS`]
//! equal sub-intervals of every segment.

use nalgebra::Vector3;

/// Sub-intervals per segment of the quadrature and of the arclength table.
pub const SUBDIVISIONS: usize = 32;

/// Nodes and weights of 5-point Gauss–Legendre quadrature on [−1, 1].
const GAUSS_5: [(f64, f64); 5] = [
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (-0.538_469_310_105_683, 0.478_628_670_499_366_5),
    (0.0, 0.568_888_888_888_888_9),
    (0.538_469_310_105_683, 0.478_628_670_499_366_5),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

/// A curve parameterised by the knot parameter t ∈ [0, t_{n−1}], with scalar profiles.
#[derive(Clone, Debug)]
pub struct Centreline {
    knots: Vec<f64>,
    points: Vec<Vector3<f64>>,
    /// dP/dt at each knot.
    derivatives: Vec<Vector3<f64>>,
    /// Scalar profiles: values and dv/dt at each knot.
    profiles: Vec<Profile>,
}

#[derive(Clone, Debug)]
struct Profile {
    values: Vec<f64>,
    slopes: Vec<f64>,
}

impl Centreline {
    /// The spline through `points` (at least two, consecutive ones distinct) carrying the
    /// scalar profiles `profiles` (each one value per point).
    ///
    /// # Panics
    /// If fewer than two points are given, two consecutive points coincide, or a profile
    /// has a different length (the caller checks its input).
    pub fn new(points: Vec<Vector3<f64>>, profiles: &[Vec<f64>]) -> Self {
        let n = points.len();
        assert!(n >= 2, "a centreline needs two points");
        let mut knots = vec![0.0; n];
        for i in 1..n {
            let step = (points[i] - points[i - 1]).norm().sqrt();
            assert!(step > 0.0, "centreline points {} and {i} coincide", i - 1);
            knots[i] = knots[i - 1] + step;
        }
        let before = 2.0 * points[0] - points[1];
        let after = 2.0 * points[n - 1] - points[n - 2];
        let point = |i: isize| -> Vector3<f64> {
            if i < 0 {
                before
            } else if i as usize >= n {
                after
            } else {
                points[i as usize]
            }
        };
        // Phantom knots continue the end steps.
        let knot = |i: isize| -> f64 {
            if i < 0 {
                -knots[1]
            } else if i as usize >= n {
                knots[n - 1] + (knots[n - 1] - knots[n - 2])
            } else {
                knots[i as usize]
            }
        };
        let derivatives = (0..n as isize)
            .map(|i| {
                let (t0, t1, t2) = (knot(i - 1), knot(i), knot(i + 1));
                (point(i) - point(i - 1)) / (t1 - t0) - (point(i + 1) - point(i - 1)) / (t2 - t0)
                    + (point(i + 1) - point(i)) / (t2 - t1)
            })
            .collect();
        let profiles = profiles
            .iter()
            .map(|values| {
                assert_eq!(values.len(), n, "one profile value per point");
                Profile {
                    slopes: monotone_slopes(&knots, values),
                    values: values.clone(),
                }
            })
            .collect();
        Self {
            knots,
            points,
            derivatives,
            profiles,
        }
    }

    /// The knots t_0 = 0 < … < t_{n−1}: the parameters of the points.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// The last knot t_{n−1}: the parameter runs over [0, end].
    pub fn end(&self) -> f64 {
        self.knots[self.knots.len() - 1]
    }

    /// Segment index i and Hermite coordinate u ∈ [0, 1] of parameter `t` (clamped).
    fn locate(&self, t: f64) -> (usize, f64, f64) {
        let t = t.clamp(0.0, self.end());
        let i = match self.knots.iter().position(|&k| k > t) {
            Some(0) => 0,
            Some(j) => j - 1,
            None => self.knots.len() - 2,
        };
        let width = self.knots[i + 1] - self.knots[i];
        (i, ((t - self.knots[i]) / width).clamp(0.0, 1.0), width)
    }

    /// Position P(t) [m].
    pub fn position(&self, t: f64) -> Vector3<f64> {
        let (i, u, h) = self.locate(t);
        let [h00, h10, h01, h11] = hermite(u);
        self.points[i] * h00
            + self.derivatives[i] * (h10 * h)
            + self.points[i + 1] * h01
            + self.derivatives[i + 1] * (h11 * h)
    }

    /// Derivative dP/dt [m per unit of t].
    pub fn derivative(&self, t: f64) -> Vector3<f64> {
        let (i, u, h) = self.locate(t);
        let [d00, d10, d01, d11] = hermite_derivative(u);
        (self.points[i] * d00 + self.points[i + 1] * d01) / h
            + self.derivatives[i] * d10
            + self.derivatives[i + 1] * d11
    }

    /// Value of scalar profile `k` at `t`.
    pub fn profile(&self, k: usize, t: f64) -> f64 {
        let (i, u, h) = self.locate(t);
        let p = &self.profiles[k];
        let [h00, h10, h01, h11] = hermite(u);
        p.values[i] * h00
            + p.slopes[i] * h * h10
            + p.values[i + 1] * h01
            + p.slopes[i + 1] * h * h11
    }

    /// ∫ f(t) dt over [0, end] by Gauss–Legendre on [`SUBDIVISIONS`] sub-intervals of
    /// every segment, with the running integral at every sub-interval end:
    /// `(t, ∫₀ᵗ f)` pairs from (0, 0) to (end, total).
    pub fn cumulative(&self, f: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
        let mut table = vec![(0.0, 0.0)];
        let mut total = 0.0;
        for w in self.knots.windows(2) {
            let h = (w[1] - w[0]) / SUBDIVISIONS as f64;
            for j in 0..SUBDIVISIONS {
                let a = w[0] + j as f64 * h;
                total += GAUSS_5
                    .iter()
                    .map(|&(x, weight)| 0.5 * h * weight * f(a + 0.5 * h * (x + 1.0)))
                    .sum::<f64>();
                table.push((a + h, total));
            }
        }
        table
    }
}

/// The parameter t at which the increasing running integral `table` (from
/// [`Centreline::cumulative`] of a positive integrand `f`) reaches `target`: linear
/// interpolation in the table, then Newton steps on ∫ f = target.
pub fn invert(table: &[(f64, f64)], target: f64, f: impl Fn(f64) -> f64) -> f64 {
    let last = table[table.len() - 1];
    if target <= 0.0 {
        return 0.0;
    }
    if target >= last.1 {
        return last.0;
    }
    let j = table.partition_point(|&(_, v)| v < target).max(1);
    let ((t0, v0), (t1, v1)) = (table[j - 1], table[j]);
    let mut t = t0 + (t1 - t0) * (target - v0) / (v1 - v0);
    // Newton on g(t) = v0 + ∫_{t0}^{t} f − target, the integral by 3-point Gauss.
    for _ in 0..3 {
        let half = 0.5 * (t - t0);
        let mid = 0.5 * (t + t0);
        let partial = half
            * ((5.0 / 9.0) * f(mid - half * 0.6f64.sqrt())
                + (8.0 / 9.0) * f(mid)
                + (5.0 / 9.0) * f(mid + half * 0.6f64.sqrt()));
        let slope = f(t);
        if slope <= 0.0 {
            break;
        }
        t = (t - (v0 + partial - target) / slope).clamp(t0, t1);
    }
    t
}

/// Cubic Hermite basis h00, h10, h01, h11 at u.
fn hermite(u: f64) -> [f64; 4] {
    let (u2, u3) = (u * u, u * u * u);
    [
        2.0 * u3 - 3.0 * u2 + 1.0,
        u3 - 2.0 * u2 + u,
        -2.0 * u3 + 3.0 * u2,
        u3 - u2,
    ]
}

/// Derivatives of [`hermite`] with respect to u.
fn hermite_derivative(u: f64) -> [f64; 4] {
    let u2 = u * u;
    [
        6.0 * u2 - 6.0 * u,
        3.0 * u2 - 4.0 * u + 1.0,
        -6.0 * u2 + 6.0 * u,
        3.0 * u2 - 2.0 * u,
    ]
}

/// Fritsch–Carlson slopes of the monotone cubic interpolant of `values` at `knots`:
/// zero at local extrema, the weighted harmonic mean of the neighbouring secants
/// elsewhere (Fritsch & Butland's form, which satisfies the monotonicity conditions),
/// the one-sided secant at the ends.
fn monotone_slopes(knots: &[f64], values: &[f64]) -> Vec<f64> {
    let n = knots.len();
    let h: Vec<f64> = knots.windows(2).map(|w| w[1] - w[0]).collect();
    let secant: Vec<f64> = (0..n - 1)
        .map(|i| (values[i + 1] - values[i]) / h[i])
        .collect();
    let mut slopes = vec![0.0; n];
    slopes[0] = secant[0];
    slopes[n - 1] = secant[n - 2];
    for i in 1..n - 1 {
        let (d0, d1) = (secant[i - 1], secant[i]);
        if d0 * d1 > 0.0 {
            let (w0, w1) = (2.0 * h[i] + h[i - 1], h[i] + 2.0 * h[i - 1]);
            slopes[i] = (w0 + w1) / (w0 / d0 + w1 / d1);
        }
    }
    // End slopes: keep the end cubic monotone (|m| ≤ 3 |secant|, same sign).
    for (i, d) in [(0, secant[0]), (n - 1, secant[n - 2])] {
        if slopes[i] * d <= 0.0 {
            slopes[i] = 0.0;
        } else if slopes[i].abs() > 3.0 * d.abs() {
            slopes[i] = 3.0 * d;
        }
    }
    slopes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_through_the_points_with_matching_profiles() {
        let points = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(0.1, 0.02, 0.0),
            Vector3::new(0.25, 0.0, 0.05),
            Vector3::new(0.3, -0.1, 0.05),
        ];
        let widths = vec![1.0, 3.0, 2.0, 2.5];
        let curve = Centreline::new(points.clone(), std::slice::from_ref(&widths));
        for (i, p) in points.iter().enumerate() {
            let t = curve.knots[i];
            assert!((curve.position(t) - p).norm() < 1e-14, "point {i}");
            assert!((curve.profile(0, t) - widths[i]).abs() < 1e-14);
        }
        // The derivative is the derivative of the position.
        for t in [0.05, 0.4, 0.61, curve.end() - 0.01] {
            let h = 1e-6;
            let numeric = (curve.position(t + h) - curve.position(t - h)) / (2.0 * h);
            assert!((numeric - curve.derivative(t)).norm() < 1e-6 * numeric.norm());
        }
    }

    #[test]
    fn profiles_never_overshoot_and_a_line_is_a_line() {
        let points: Vec<_> = (0..5)
            .map(|i| Vector3::new(0.0, 0.0, 0.1 * i as f64))
            .collect();
        let values = vec![0.01, 0.01, 0.04, 0.002, 0.002];
        let curve = Centreline::new(points, std::slice::from_ref(&values));
        for k in 0..=400 {
            let t = curve.end() * k as f64 / 400.0;
            let v = curve.profile(0, t);
            assert!((0.002..=0.04).contains(&v), "t {t}: {v}");
            let p = curve.position(t);
            assert!(p.x.abs() < 1e-15 && p.y.abs() < 1e-15);
        }
        // Equal steps: the knots are equally spaced and the curve is linear in t.
        let length = curve.cumulative(|t| curve.derivative(t).norm());
        assert!((length.last().unwrap().1 - 0.4).abs() < 1e-12);
        let t = invert(&length, 0.13, |t| curve.derivative(t).norm());
        assert!((curve.position(t).z - 0.13).abs() < 1e-12);
    }
}
