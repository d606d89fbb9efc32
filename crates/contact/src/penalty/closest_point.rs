//! The closest-point search of penalty contact: the nearest point of a node over its
//! broadphase candidates, skipping candidates whose bounds put them farther than the best
//! so far.

use nalgebra::Vector3;

use super::*;

/// The distance [m] from `x` to the box of the triangle of `corners`.
pub(super) fn box_distance(x: &Vector3<f64>, corners: &[Vector3<f64>; 3]) -> f64 {
    let low = corners[0].inf(&corners[1]).inf(&corners[2]);
    let high = corners[0].sup(&corners[1]).sup(&corners[2]);
    (x - x.sup(&low).inf(&high)).norm()
}

/// Lower bounds that let [`closest`] skip candidates without measuring them.
pub(super) struct Bounds<B, R> {
    /// `box_distance(t)` ≤ the distance from x to triangle t [m].
    pub box_distance: B,
    /// `rest_farther(k, d)`: every candidate from number k on is farther than d [m].
    pub rest_farther: R,
}

/// The closest point of `x` over the `candidates` (skipping those `skip` says), the
/// smallest |x − x_m| winning, ties to the lowest triangle index; active when g < 0 and
/// the node does not overhang the rim by the whole fade ([`rim_weight`]). A candidate is measured (`corners`, then the
/// closest feature) only when the `bounds` do not put it farther than the best so far;
/// the `previous` winner (`u32::MAX`: none) first.
pub(super) fn closest(
    x: &Vector3<f64>,
    candidates: &[u32],
    previous: u32,
    (rim_edges, rim_vertices): (&[u8], &[u8]),
    skip: impl Fn(usize) -> bool,
    bounds: Bounds<impl Fn(usize) -> f64, impl Fn(usize, f64) -> bool>,
    corners: impl Fn(usize) -> [Vector3<f64>; 3],
) -> NodeContact {
    let measure = |t: u32| {
        let c = corners(t as usize);
        let (weights, _) = closest_feature(x, &c);
        let distance =
            (x - (c[0] * weights[0] + c[1] * weights[1] + c[2] * weights[2])).norm_squared();
        (distance, t, c)
    };
    // Squared distances, with the best one's triangle and corners; the last winner, still
    // a candidate, is measured first (it usually wins again).
    let first =
        (previous != u32::MAX && !skip(previous as usize) && candidates.contains(&previous))
            .then_some(previous);
    let mut best: Option<(f64, u32, [Vector3<f64>; 3])> = first.map(measure);
    for (k, &t) in candidates.iter().enumerate() {
        if Some(t) == first {
            continue;
        }
        if let Some((d2, _, _)) = best {
            let d = d2.sqrt();
            if (bounds.rest_farther)(k, d) {
                break;
            }
            if skip(t as usize) || (bounds.box_distance)(t as usize) > d {
                continue;
            }
        } else if skip(t as usize) {
            continue;
        }
        let candidate = measure(t);
        let better = best
            .as_ref()
            .is_none_or(|(d, bt, _)| candidate.0 < *d || (candidate.0 == *d && t < *bt));
        if better {
            best = Some(candidate);
        }
    }
    let Some((_, t, c)) = best else {
        return NodeContact::default();
    };
    let p = project_on_triangle(x, &c);
    let rim_feature = match p.feature {
        Feature::Face => false,
        Feature::Edge(e) => rim_edges[t as usize] & (1 << e) != 0,
        Feature::Vertex(v) => rim_vertices[t as usize] & (1 << v) != 0,
    };
    // Past the rim the force fades with the overhang: the distance of x from the normal's
    // line through x_m.
    let offset = x - p.point;
    let along = offset.dot(&p.normal);
    let weight = if rim_feature {
        rim_weight((offset - p.normal * along).norm(), &c)
    } else {
        1.0
    };
    NodeContact {
        triangle: t,
        gap: p.gap,
        active: p.gap < 0.0 && weight > 0.0,
        weight,
        offset,
        geometry: FeatureGeometry::new(p.feature, &p.barycentric, &c),
    }
}
