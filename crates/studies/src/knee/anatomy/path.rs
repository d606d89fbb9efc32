//! The free part of a quadriceps' musculotendon path: from its last femur-fixed point
//! (the *release* point) to its insertion on the patella, straight, or wrapped over the
//! trochlea where the straight line would cut through the femur.
//!
//! The trochlea is the cylinder about the groove axis (through the groove centre,
//! along z) of radius groove radius + half the tendon's thickness. Projected on the
//! sagittal (x, y) plane, the shortest path from V to I around a circle of centre C and
//! radius ρ on the side the straight line crosses is, when the chord VI passes closer
//! to C than ρ (equivalently when γ > α_V + α_I, γ = ∠VCI ≤ π, α_P = acos(ρ / |P − C|)),
//!
//! ℓ₂ = √(|V − C|² − ρ²) + ρ (γ − α_V − α_I) + √(|I − C|² − ρ²)
//!
//! (tangent, arc, tangent), and |V − I| otherwise. On a cylinder about z the shortest
//! path is that planar path unrolled with z varying linearly along it (a helix on the
//! arc), so the length is √(ℓ₂² + (z_V − z_I)²).
//!
//! An end inside the cylinder (a tendon that attaches deep on the patella while the
//! patella sits in the groove) is reached from the cylinder's surface: the path runs to
//! that end's radial projection I′ = C + ρ (I − C)/|I − C| as above and then radially
//! in, ℓ = ℓ(V, I′) + ρ − |I − C|, which is continuous with the outside case at
//! |I − C| = ρ. With both ends inside, the path is the straight line.

use nalgebra::Vector3;

use super::dimensions::KneeDimensions;

/// A wrapping cylinder about an axis along z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WrapCylinder {
    /// Axis position (x, y) [m].
    pub centre: [f64; 2],
    /// Radius [m].
    pub radius: f64,
}

impl WrapCylinder {
    /// The trochlea of the knee of `dimensions`: the groove circle grown by the wrap
    /// offset, half the tendon's thickness.
    pub fn trochlea(dimensions: &KneeDimensions) -> Self {
        Self {
            centre: dimensions.groove_centre,
            radius: dimensions.groove_radius + dimensions.tendon_wrap_offset,
        }
    }

    /// How far `point` lies inside the cylinder, ρ − |P − C| in the (x, y) plane [m], or
    /// `None` when it lies on or outside it.
    fn depth(&self, point: &Vector3<f64>) -> Option<f64> {
        let distance = (point.x - self.centre[0]).hypot(point.y - self.centre[1]);
        (distance < self.radius).then_some(self.radius - distance)
    }

    /// The ends moved radially out onto the surface where they lie inside it, and how far
    /// they were moved in all [m]; `None` when both lie inside (the module
    /// documentation).
    fn lifted_ends(
        &self,
        from: &Vector3<f64>,
        to: &Vector3<f64>,
    ) -> Option<(Vector3<f64>, Vector3<f64>, f64)> {
        let lift = |point: &Vector3<f64>| match self.depth(point) {
            Some(depth) => (self.surface_point(point), depth),
            None => (*point, 0.0),
        };
        match (self.depth(from), self.depth(to)) {
            (Some(_), Some(_)) => None,
            _ => {
                let ((from, a), (to, b)) = (lift(from), lift(to));
                Some((from, to, a + b))
            }
        }
    }

    /// The point of the cylinder's surface radially out from `point` (same z); `point`
    /// itself on the axis.
    fn surface_point(&self, point: &Vector3<f64>) -> Vector3<f64> {
        let [cx, cy] = self.centre;
        let (x, y) = (point.x - cx, point.y - cy);
        let distance = x.hypot(y);
        if distance == 0.0 {
            return *point;
        }
        let scale = self.radius / distance;
        Vector3::new(cx + scale * x, cy + scale * y, point.z)
    }
}

/// The free path's length and whether it wraps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FreePath {
    /// Length [m].
    pub length: f64,
    /// Whether the path wraps over the cylinder.
    pub wrapped: bool,
}

/// The shortest path from `from` to `to` [m] that does not cut through `cylinder` on
/// the side the straight line crosses (see the module documentation).
pub fn free_path(from: &Vector3<f64>, to: &Vector3<f64>, cylinder: &WrapCylinder) -> FreePath {
    match cylinder.lifted_ends(from, to) {
        None => FreePath {
            length: (from - to).norm(),
            wrapped: false,
        },
        Some((from, to, depth)) => {
            let path = outside_path(&from, &to, cylinder);
            FreePath {
                length: path.length + depth,
                ..path
            }
        }
    }
}

/// [`free_path`] between two points on or outside the cylinder.
fn outside_path(from: &Vector3<f64>, to: &Vector3<f64>, cylinder: &WrapCylinder) -> FreePath {
    let [cx, cy] = cylinder.centre;
    let rho = cylinder.radius;
    let (v, i) = ([from.x - cx, from.y - cy], [to.x - cx, to.y - cy]);
    let (dv, di) = (v[0].hypot(v[1]), i[0].hypot(i[1]));
    let dz = from.z - to.z;
    let straight = FreePath {
        length: (from - to).norm(),
        wrapped: false,
    };
    // On the surface (up to rounding), a point's tangent has zero length.
    let (dv, di) = (dv.max(rho), di.max(rho));
    let gamma = (v[0] * i[1] - v[1] * i[0])
        .atan2(v[0] * i[0] + v[1] * i[1])
        .abs();
    let arc = gamma - (rho / dv).acos() - (rho / di).acos();
    if arc <= 0.0 {
        return straight;
    }
    let planar = (dv * dv - rho * rho).sqrt() + rho * arc + (di * di - rho * rho).sqrt();
    FreePath {
        length: planar.hypot(dz),
        wrapped: true,
    }
}

/// The points of the path of [`free_path`] for drawing: the two ends, and when it wraps
/// the two tangent points with `arc_points` points along the arc between them (z
/// varying linearly with the planar arclength).
pub fn free_path_points(
    from: &Vector3<f64>,
    to: &Vector3<f64>,
    cylinder: &WrapCylinder,
    arc_points: usize,
) -> Vec<Vector3<f64>> {
    let Some((lifted_from, lifted_to, _)) = cylinder.lifted_ends(from, to) else {
        return vec![*from, *to];
    };
    let mut points = outside_path_points(&lifted_from, &lifted_to, cylinder, arc_points);
    if lifted_from != *from {
        points.insert(0, *from);
    }
    if lifted_to != *to {
        points.push(*to);
    }
    points
}

/// [`free_path_points`] between two points on or outside the cylinder.
fn outside_path_points(
    from: &Vector3<f64>,
    to: &Vector3<f64>,
    cylinder: &WrapCylinder,
    arc_points: usize,
) -> Vec<Vector3<f64>> {
    if !outside_path(from, to, cylinder).wrapped {
        return vec![*from, *to];
    }
    let [cx, cy] = cylinder.centre;
    let rho = cylinder.radius;
    let (v, i) = ([from.x - cx, from.y - cy], [to.x - cx, to.y - cy]);
    let (dv, di) = (v[0].hypot(v[1]), i[0].hypot(i[1]));
    let (dv, di) = (dv.max(rho), di.max(rho));
    let side = (v[0] * i[1] - v[1] * i[0]).signum();
    let start = v[1].atan2(v[0]) + side * (rho / dv).acos();
    let end = i[1].atan2(i[0]) - side * (rho / di).acos();
    let mut sweep = end - start;
    // The arc runs from start to end in the direction `side`, less than a turn.
    while sweep * side < 0.0 {
        sweep += side * 2.0 * std::f64::consts::PI;
    }
    let first = (dv * dv - rho * rho).sqrt();
    let planar = first + rho * sweep.abs() + (di * di - rho * rho).sqrt();
    let mut points = vec![*from];
    for k in 0..=arc_points.max(1) {
        let f = k as f64 / arc_points.max(1) as f64;
        let angle = start + f * sweep;
        let along = first + rho * sweep.abs() * f;
        let z = from.z + (to.z - from.z) * along / planar;
        points.push(Vector3::new(
            cx + rho * angle.cos(),
            cy + rho * angle.sin(),
            z,
        ));
    }
    points.push(*to);
    points
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;

    const UNIT: WrapCylinder = WrapCylinder {
        centre: [0.0, 0.0],
        radius: 1.0,
    };

    #[test]
    fn a_line_clear_of_the_cylinder_is_straight() {
        let path = free_path(
            &Vector3::new(2.0, 3.0, 0.5),
            &Vector3::new(2.0, -3.0, 0.0),
            &UNIT,
        );
        assert!(!path.wrapped);
        assert!((path.length - (36.0f64 + 0.25).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn a_path_over_the_cylinder_is_tangent_arc_tangent() {
        // From (0, 2) to (0, −2) past the +x side: γ = π, α = acos(1/2) = π/3 at both
        // ends, so tangents of √3 each and an arc of π − 2π/3 = π/3.
        let from = Vector3::new(1e-12, 2.0, 0.0);
        let to = Vector3::new(1e-12, -2.0, 0.0);
        let path = free_path(&from, &to, &UNIT);
        assert!(path.wrapped);
        let expected = 2.0 * 3f64.sqrt() + PI / 3.0;
        assert!(
            (path.length - expected).abs() < 1e-9,
            "{} {expected}",
            path.length
        );
        // With an axial offset the planar path is unrolled into a helix.
        let lifted = free_path(&from, &(to + Vector3::new(0.0, 0.0, 1.5)), &UNIT);
        assert!((lifted.length - expected.hypot(1.5)).abs() < 1e-9);
    }

    #[test]
    fn the_drawn_path_has_the_computed_length() {
        let from = Vector3::new(0.3, 2.0, 0.2);
        let to = Vector3::new(0.5, -1.6, -0.4);
        let path = free_path(&from, &to, &UNIT);
        assert!(path.wrapped);
        let points = free_path_points(&from, &to, &UNIT, 2000);
        let drawn: f64 = points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        assert!(
            (drawn - path.length).abs() < 1e-6 * path.length,
            "{drawn} {}",
            path.length
        );
        // The tangent points are on the cylinder and the arc passes the +x side.
        assert!(
            points[1..points.len() - 1]
                .iter()
                .all(|p| (p.x.hypot(p.y) - 1.0).abs() < 1e-12 && p.x > 0.0)
        );
    }

    #[test]
    fn an_end_inside_the_cylinder_is_reached_radially_from_its_surface() {
        // From (0, 2) round the +x side to 0.5 (0.6, −0.8), half a radius inside: the
        // tangent √3 (α_V = π/3), the arc γ − π/3 to the end's angle (γ = π/2 + 0.927),
        // then 0.5 radially in.
        let from = Vector3::new(1e-12, 2.0, 0.0);
        let direction = Vector3::new(0.6, -0.8, 0.0);
        let to = 0.5 * direction;
        let path = free_path(&from, &to, &UNIT);
        assert!(path.wrapped);
        let arc = (-0.8f64).atan2(0.6).abs() + PI / 2.0 - PI / 3.0;
        let expected = 3f64.sqrt() + arc + 0.5;
        assert!(
            (path.length - expected).abs() < 1e-9,
            "{} {expected}",
            path.length
        );
        assert_eq!(free_path(&to, &from, &UNIT), path);
        // The drawn path ends with the radial leg and has the same length.
        let points = free_path_points(&from, &to, &UNIT, 2000);
        let drawn: f64 = points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        assert!((drawn - path.length).abs() < 1e-6, "{drawn}");
        assert_eq!(points[points.len() - 2], direction);
        // Both ends inside: the straight line.
        let inside = free_path(&to, &Vector3::new(0.0, 0.5, 0.0), &UNIT);
        assert!(!inside.wrapped);
        assert!((inside.length - (0.3f64.powi(2) + 0.9f64.powi(2)).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn the_length_is_continuous_where_an_end_crosses_the_surface() {
        // Move the end radially through the surface, on a wrapped and on a straight path.
        for from in [Vector3::new(1e-12, 2.0, 0.3), Vector3::new(2.0, 0.5, 0.0)] {
            let length =
                |r: f64| free_path(&from, &Vector3::new(0.6 * r, -0.8 * r, 0.0), &UNIT).length;
            for r in [1.0 - 1e-9, 1.0, 1.0 + 1e-9] {
                assert!(
                    (length(r) - length(1.0)).abs() < 1e-8,
                    "{r}: {} {}",
                    length(r),
                    length(1.0)
                );
            }
            // Inside, the length grows by the depth.
            assert!((length(0.9) - length(1.0) - 0.1).abs() < 1e-12);
        }
    }

    #[test]
    fn the_length_is_continuous_where_wrapping_starts() {
        // Slide the end point so the chord passes the circle: no jump at the transition.
        let from = Vector3::new(1.5, 3.0, 0.0);
        let lengths: Vec<(f64, bool)> = (0..=400)
            .map(|k| {
                let angle = -0.5 - 1.5 * k as f64 / 400.0;
                let to = Vector3::new(1.3 * angle.cos(), 1.3 * angle.sin(), 0.0);
                let p = free_path(&from, &to, &UNIT);
                (p.length, p.wrapped)
            })
            .collect();
        assert!(lengths.iter().any(|l| l.1) && lengths.iter().any(|l| !l.1));
        for w in lengths.windows(2) {
            assert!((w[1].0 - w[0].0).abs() < 0.02, "{w:?}");
        }
    }
}
