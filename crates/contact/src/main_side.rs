//! The main side of a cohesive interface or of a contact as the bonds and the smooth
//! normal field see it: the triangles of a [`ContactTarget`], whose corners are mesh nodes
//! (a deformable surface) or points of a rigid body placed by its
//! [`musclefem_core::solver::RigidMotion`] (a bone).

use nalgebra::{Isometry3, Point3, Vector3};

use crate::surface::ContactTarget;

/// Triangle corners of a main surface at an instant.
pub trait MainSide {
    /// Corner ids of every triangle (node ids, or indices of rigid vertices).
    fn triangles(&self) -> &[[u32; 3]];

    /// The mesh nodes of triangle `triangle`, for a deformable main.
    fn nodes(&self, triangle: usize) -> Option<[u32; 3]>;

    /// Bit `i` set when edge `i` (corner `i` to `i + 1`) of triangle `triangle` is on the
    /// rim of the surface (no other triangle shares it).
    fn rim(&self, triangle: usize) -> u8;

    /// The rigid body's placement at `time` (identity for a deformable main).
    fn placement(&self, time: f64) -> Isometry3<f64>;

    /// The corners of triangle `triangle` [m]: nodal `positions` for a deformable main,
    /// the rigid vertices placed by `placement` for a rigid one.
    fn corners(
        &self,
        triangle: usize,
        positions: &[Vector3<f64>],
        placement: &Isometry3<f64>,
    ) -> [Vector3<f64>; 3];
}

impl MainSide for ContactTarget {
    fn triangles(&self) -> &[[u32; 3]] {
        match self {
            ContactTarget::Deformable(s) => &s.triangles,
            ContactTarget::Rigid(s) => &s.triangles,
        }
    }

    #[inline]
    fn nodes(&self, triangle: usize) -> Option<[u32; 3]> {
        match self {
            ContactTarget::Deformable(s) => Some(s.triangles[triangle]),
            ContactTarget::Rigid(_) => None,
        }
    }

    #[inline]
    fn rim(&self, triangle: usize) -> u8 {
        match self {
            ContactTarget::Deformable(s) => s.boundary_edges[triangle],
            ContactTarget::Rigid(s) => s.boundary_edges[triangle],
        }
    }

    fn placement(&self, time: f64) -> Isometry3<f64> {
        match self {
            ContactTarget::Deformable(_) => Isometry3::identity(),
            ContactTarget::Rigid(s) => s.motion.isometry_at(time),
        }
    }

    #[inline]
    fn corners(
        &self,
        triangle: usize,
        positions: &[Vector3<f64>],
        placement: &Isometry3<f64>,
    ) -> [Vector3<f64>; 3] {
        match self {
            ContactTarget::Deformable(s) => s.corners(triangle, positions),
            ContactTarget::Rigid(s) => s.triangles[triangle]
                .map(|v| (placement * Point3::from(s.vertices[v as usize])).coords),
        }
    }
}
