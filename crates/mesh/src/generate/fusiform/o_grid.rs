//! The O-grid (butterfly) quadrilateral mesh of the unit disc that every cross-section of
//! the specimen is a scaled copy of.
//!
//! Logical picture: a square [−1, 1]² of `n × n` cells (the inner block), surrounded by a
//! ring of `4n × m` cells (`n` along each side of the square, `m` from the square out to
//! the circle). No cell is degenerate, unlike a polar grid with its triangles at the
//! centre.
//!
//! Geometry, for a point q of the square's boundary (max(|q_x|, |q_y|) = 1):
//!
//! - its **circle point** c(q) is on the unit circle, spaced equally in angle along each
//!   side: on the side q_x = 1, c = (cos(π q_y / 4), sin(π q_y / 4)), and likewise on the
//!   other sides; the square's corners go to the diagonals;
//! - its **inner-boundary point** is b(q) = s [(1 − β) q + β √2 c(q)]: the square of
//!   half-width s = [`INNER_HALF_WIDTH`] bulged a fraction β = [`INNER_BULGE`] of the way
//!   to the circle through its corners (radius s√2). The bulge opens the inner block's
//!   corner angles from 90° to about 123°, leaving about 118° to each of the two ring cells
//!   there (a flat square gives 90° and 135°); on the axes b is at radius
//!   s (1 + (√2 − 1) β) ≈ 0.572;
//! - inner-block nodes fill the bulged square by transfinite (Coons) interpolation of its
//!   four boundary curves; ring node j of 0..=m on the line from b(q) to c(q) is at
//!   b + (j/m)(c − b).
//!
//! The outer boundary is the regular 4n-gon inscribed in the unit circle (its corners are
//! equally spaced in angle), of area 2n sin(π / (2n)).

use std::f64::consts::{FRAC_PI_4, PI, SQRT_2};

use nalgebra::Vector2;

/// Half-width s of the inner block's square, as a fraction of the radius: its corners are
/// at radius s√2 ≈ 0.707.
pub const INNER_HALF_WIDTH: f64 = 0.5;
/// Fraction β of the way the inner block's sides are bulged from the square towards the
/// circle through its corners (0 = flat square sides).
pub const INNER_BULGE: f64 = 0.35;

/// Thickness of the ring at the middle of a side of the inner block, as a fraction of the
/// radius: 1 − s (1 + (√2 − 1) β) ≈ 0.428 (the ring is thinnest, 1 − s√2 ≈ 0.293, on the
/// diagonals).
pub fn ring_thickness() -> f64 {
    1.0 - INNER_HALF_WIDTH * (1.0 + (SQRT_2 - 1.0) * INNER_BULGE)
}

/// The O-grid of the unit disc: points, quads and the nodes the specimen names.
#[derive(Clone, Debug)]
pub struct UnitSection {
    /// Node positions in the unit disc (dimensionless, radius 1).
    pub points: Vec<Vector2<f64>>,
    /// Cells as node indices, counter-clockwise seen from +z.
    pub quads: Vec<[u32; 4]>,
    /// The node at the centre (0, 0).
    pub centre: u32,
    /// The node on the circle at (1, 0).
    pub rim_x: u32,
}

impl UnitSection {
    /// The O-grid with `per_side` cells along each side of the inner block (even, ≥ 2)
    /// and `radial` ring layers (≥ 1). Nodes: the inner block's (i, k) at
    /// i + (n + 1) k, i fastest along x; then the ring, layer j = 1..=m after layer j − 1,
    /// each layer counter-clockwise from the diagonal at (−1, −1).
    ///
    /// # Panics
    /// If `per_side` is odd or zero or `radial` is zero (the caller checks the spec).
    pub fn new(per_side: usize, radial: usize) -> Self {
        assert!(per_side >= 2 && per_side.is_multiple_of(2) && radial >= 1);
        let n = per_side;
        let logical = |i: usize| -1.0 + 2.0 * i as f64 / n as f64;
        let inner_id = |i: usize, k: usize| (i + (n + 1) * k) as u32;

        let mut points = Vec::with_capacity((n + 1) * (n + 1) + 4 * n * radial);
        for k in 0..=n {
            for i in 0..=n {
                points.push(coons(logical(i), logical(k)));
            }
        }
        let mut quads = Vec::with_capacity(n * n + 4 * n * radial);
        for k in 0..n {
            for i in 0..n {
                quads.push([
                    inner_id(i, k),
                    inner_id(i + 1, k),
                    inner_id(i + 1, k + 1),
                    inner_id(i, k + 1),
                ]);
            }
        }

        // The inner block's boundary nodes, counter-clockwise from corner (0, 0).
        let boundary: Vec<(usize, usize)> = (0..n)
            .map(|i| (i, 0))
            .chain((0..n).map(|k| (n, k)))
            .chain((0..n).map(|i| (n - i, n)))
            .chain((0..n).map(|k| (0, n - k)))
            .collect();
        let around = boundary.len();
        let first_ring = points.len();
        // Ring node of boundary position p in layer j (layer 0 is the inner block's).
        let ring_id = |p: usize, j: usize| {
            let p = p % around;
            if j == 0 {
                let (i, k) = boundary[p];
                inner_id(i, k)
            } else {
                (first_ring + (j - 1) * around + p) as u32
            }
        };
        for j in 1..=radial {
            let t = j as f64 / radial as f64;
            for &(i, k) in &boundary {
                let q = Vector2::new(logical(i), logical(k));
                let (b, c) = (inner_boundary(q), circle_point(q));
                points.push(b + t * (c - b));
            }
        }
        for j in 0..radial {
            for p in 0..around {
                // Outward, then along the ring: counter-clockwise.
                quads.push([
                    ring_id(p, j),
                    ring_id(p, j + 1),
                    ring_id(p + 1, j + 1),
                    ring_id(p + 1, j),
                ]);
            }
        }
        // (n, n/2) is the middle of the side x = 1: boundary position n + n/2.
        Self {
            points,
            quads,
            centre: inner_id(n / 2, n / 2),
            rim_x: ring_id(n + n / 2, radial),
        }
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.points.len()
    }
}

/// Area of the O-grid's outer polygon with `per_side` cells per side (the regular 4n-gon
/// inscribed in the unit circle): 2n sin(π/(2n)).
pub fn polygon_area(per_side: usize) -> f64 {
    let n = per_side as f64;
    2.0 * n * (PI / (2.0 * n)).sin()
}

/// The point of the unit circle that square-boundary point `q` goes to, equally spaced
/// in angle along each side (defined for any q ≠ 0 by its dominant coordinate).
fn circle_point(q: Vector2<f64>) -> Vector2<f64> {
    if q.x.abs() >= q.y.abs() {
        let angle = FRAC_PI_4 * q.y / q.x;
        q.x.signum() * Vector2::new(angle.cos(), angle.sin())
    } else {
        let angle = FRAC_PI_4 * q.x / q.y;
        q.y.signum() * Vector2::new(angle.sin(), angle.cos())
    }
}

/// The inner block's (bulged) boundary point of square-boundary point `q`:
/// s [(1 − β) q + β √2 c(q)].
fn inner_boundary(q: Vector2<f64>) -> Vector2<f64> {
    INNER_HALF_WIDTH * ((1.0 - INNER_BULGE) * q + INNER_BULGE * SQRT_2 * circle_point(q))
}

/// Transfinite (Coons) interpolation of the inner block's four boundary curves at logical
/// (u, v) ∈ [−1, 1]²: the sum of the two linear blends between opposite sides minus the
/// bilinear blend of the corners, which reproduces the boundary exactly.
fn coons(u: f64, v: f64) -> Vector2<f64> {
    let b = |x: f64, y: f64| inner_boundary(Vector2::new(x, y));
    let (a, c) = (0.5 * (1.0 + u), 0.5 * (1.0 + v));
    let sides = (1.0 - a) * b(-1.0, v) + a * b(1.0, v) + (1.0 - c) * b(u, -1.0) + c * b(u, 1.0);
    let corners = (1.0 - a) * (1.0 - c) * b(-1.0, -1.0)
        + a * (1.0 - c) * b(1.0, -1.0)
        + (1.0 - a) * c * b(-1.0, 1.0)
        + a * c * b(1.0, 1.0);
    sides - corners
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Signed area of a quad (shoelace), positive when counter-clockwise.
    fn quad_area(section: &UnitSection, quad: &[u32; 4]) -> f64 {
        (0..4)
            .map(|k| {
                let p = section.points[quad[k] as usize];
                let q = section.points[quad[(k + 1) % 4] as usize];
                p.x * q.y - q.x * p.y
            })
            .sum::<f64>()
            / 2.0
    }

    #[test]
    fn cells_are_counter_clockwise_and_tile_the_polygon() {
        for (n, m) in [(2, 1), (4, 2), (8, 3), (14, 4)] {
            let section = UnitSection::new(n, m);
            assert_eq!(section.quads.len(), n * n + 4 * n * m);
            assert_eq!(section.node_count(), (n + 1) * (n + 1) + 4 * n * m);
            let mut total = 0.0;
            for quad in &section.quads {
                let area = quad_area(&section, quad);
                assert!(area > 0.0, "n {n} m {m}: {quad:?} {area}");
                total += area;
            }
            assert!((total - polygon_area(n)).abs() < 1e-14, "{total}");
        }
    }

    #[test]
    fn outer_nodes_are_on_the_circle_and_named_nodes_where_stated() {
        let section = UnitSection::new(6, 2);
        let outer = &section.points[section.node_count() - 24..];
        for p in outer {
            assert!((p.norm() - 1.0).abs() < 1e-15, "{p}");
        }
        let centre = section.points[section.centre as usize];
        assert!(centre.norm() < 1e-15, "{centre}");
        let rim = section.points[section.rim_x as usize];
        assert!((rim - Vector2::new(1.0, 0.0)).norm() < 1e-15, "{rim}");
        // The inner block's corner is at radius s√2, the middle of its side at s + ring.
        let corner = section.points[(7 * 7 - 1) as usize];
        assert!((corner.norm() - INNER_HALF_WIDTH * SQRT_2).abs() < 1e-15);
        let side = section.points[(6 + 7 * 3) as usize];
        assert!((side.x - (1.0 - ring_thickness())).abs() < 1e-15, "{side}");
    }
}
