//! Penalty contact along the smooth normal field of the main surface
//! ([`super::PenaltyContact::with_smooth_normals`], [`crate::normal_field`]).
//!
//! - Pairing: the node's closest triangle among its broadphase candidates (as the
//!   closest-point contact finds it) starts a [`walk`] along the normal field to the foot
//!   of the node's projection: x − x_m = g N, N = Σ φ_k n_k interpolated from the vertex
//!   normals.
//! - Gap d = g |N| [m], direction ν = N / |N|. In contact when d < 0: the traction
//!   ε ⟨−d⟩ [Pa] pushes the node out along ν, f_s = k d ν [N] in the solver's sign
//!   convention (k = ε A_s [N/m], A_s the node's area), −φ_k f_s on the corners of a
//!   deformable main triangle (forces and moments balance: x − x_m ∥ ν), the rigid body
//!   takes −f_s. Stored energy ½ ε d² A_s (the forces are not its exact gradient off a
//!   flat surface: ν is not the gradient of d).
//! - Past the rim of an open main surface the walk stops on a rim triangle with the foot
//!   extrapolated outside it. With x_r the point of that triangle closest to the foot, the
//!   node overhangs the rim by s = |foot − x_r| and its force fades to zero over a quarter
//!   of the triangle's size ([`super::rim_weight`], the closest-point contact's rule: on
//!   a flat surface s is the same distance). A foot outside its triangle for another
//!   reason (an edge into a triangle the node belongs to, or a walk that ran out of hops)
//!   is treated the same way.
//! - Tangent: [`smooth_tangent`] with t = ε d, t' = ε (the vertex normals held fixed):
//!   exact on a rigid main; on a deformable main the turn of the vertex normals with the
//!   nodes around the triangle is left out (a relative error of the order of the
//!   penetration over the element size, small for penalty contact: in the tests 1.4e-2
//!   and 6e-2 of the largest entry in the main nodes' columns at penetrations of up to
//!   8 % of the triangles' size). Not symmetric.

use nalgebra::{Isometry3, Matrix3, Vector3};

use super::rim_weight;
use crate::main_side::MainSide;
use crate::normal_field::{NormalField, NormalProjection, OUTSIDE, smooth_tangent, walk};
use crate::projection::closest_feature;
use crate::surface::ContactTarget;

/// The smooth normal field of the main surface and the state of each secondary node.
#[derive(Debug, Clone)]
pub(super) struct SmoothNormals {
    pub field: NormalField,
    pub contacts: Vec<SmoothContact>,
}

impl SmoothNormals {
    /// The field of `target` (a deformable one's normals come with the first evaluation)
    /// for `count` secondary nodes.
    pub fn new(target: &ContactTarget, count: usize) -> Self {
        SmoothNormals {
            field: NormalField::new(target, &[]),
            contacts: vec![SmoothContact::NONE; count],
        }
    }
}

/// One secondary node's projection along the normal field at the last force evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct SmoothContact {
    /// The main triangle of the foot (`u32::MAX`: no candidate).
    pub triangle: u32,
    /// Gap d = g |N| [m] (0 without a candidate).
    pub gap: f64,
    /// Carries a force.
    pub active: bool,
    /// The force's share past the rim ([`rim_weight`]; 1 over the face).
    pub weight: f64,
    /// The projection on `triangle`.
    pub projection: NormalProjection,
}

impl SmoothContact {
    /// No main triangle within the search distance.
    pub const NONE: SmoothContact = SmoothContact {
        triangle: u32::MAX,
        gap: 0.0,
        active: false,
        weight: 0.0,
        projection: NormalProjection {
            barycentric: Vector3::new(1.0, 0.0, 0.0),
            along: 0.0,
            normal: Vector3::new(0.0, 0.0, 1.0),
            inverse: None,
            normals: [Vector3::new(0.0, 0.0, 1.0); 3],
        },
    };

    /// The projection of secondary node `node` at `x` [m] on `main` (placed at `at`: nodal
    /// positions [m] and the rigid body's placement), walking along `field` from triangle
    /// `start` (`u32::MAX`: none, no contact); see the module docs.
    pub fn new(
        field: &NormalField,
        main: &ContactTarget,
        at: (&[Vector3<f64>], &Isometry3<f64>),
        node: u32,
        start: u32,
        x: &Vector3<f64>,
    ) -> Self {
        if start == u32::MAX {
            return SmoothContact::NONE;
        }
        let foot = walk(field, main, at, node, start, x);
        let projection = foot.projection;
        let gap = projection.gap();
        let weight = if projection.barycentric.min() < OUTSIDE {
            let corners = main.corners(foot.triangle as usize, at.0, at.1);
            rim_weight(overhang(&corners, &projection.barycentric), &corners)
        } else {
            1.0
        };
        SmoothContact {
            triangle: foot.triangle,
            gap,
            active: gap < 0.0 && weight > 0.0,
            weight,
            projection,
        }
    }

    /// The direction ν = N/|N| and |N|.
    fn direction(&self) -> (Vector3<f64>, f64) {
        let length = self.projection.normal.norm();
        (self.projection.normal / length, length)
    }

    /// The force f_s = k d ν [N] on the secondary node (the corners take −φ_k f_s), with
    /// `k` = w ε A_s [N/m] (w the rim weight).
    pub fn force(&self, k: f64) -> Vector3<f64> {
        k * self.gap * self.direction().0
    }

    /// Calls `add(a, b, K_ab)` with the stiffness blocks [N/m] of an active node `node`
    /// with `k` = w ε A_s [N/m] on a main triangle with mesh nodes `corners` (a deformable
    /// main) or on a rigid main (`None`: K_ss only). With f_k = −φ_k f_s,
    /// K_kj = −f_s ⊗ ∂φ_k/∂x_j − φ_k K_sj over j = the node and the corners.
    pub fn blocks(
        &self,
        k: f64,
        node: u32,
        corners: Option<[u32; 3]>,
        add: &mut dyn FnMut(u32, u32, &Matrix3<f64>),
    ) {
        let (direction, length) = self.direction();
        let (coupling, gradients) =
            smooth_tangent(&self.projection, &direction, length, (k * self.gap, k));
        let Some(corners) = corners else {
            add(node, node, &coupling[0]);
            return;
        };
        let force = k * self.gap * direction;
        let phi = self.projection.barycentric;
        let nodes = [node, corners[0], corners[1], corners[2]];
        for (j, &column) in nodes.iter().enumerate() {
            add(node, column, &coupling[j]);
            for (c, &corner) in corners.iter().enumerate() {
                let block = -force * gradients[j].row(c) - phi[c] * coupling[j];
                add(corner, column, &block);
            }
        }
    }
}

/// How far [m] the foot with barycentric coordinates `phi` (some negative: outside) on the
/// triangle `corners` lies from the triangle's point closest to it.
fn overhang(corners: &[Vector3<f64>; 3], phi: &Vector3<f64>) -> f64 {
    let point = |w: &[f64]| corners[0] * w[0] + corners[1] * w[1] + corners[2] * w[2];
    let foot = point(phi.as_slice());
    let (weights, _) = closest_feature(&foot, corners);
    (foot - point(&weights)).norm()
}

#[cfg(test)]
mod tests;
