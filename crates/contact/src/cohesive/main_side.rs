//! The main side of a cohesive interface as its bonds see it: triangles whose vertices are
//! mesh nodes (a deformable surface) or points of a rigid body moving with a
//! [`RigidMotion`] (a rigid surface, e.g. a bone).

use nalgebra::{Isometry3, Point3, Vector3};

use musclefem_core::solver::RigidMotion;

/// Triangles of the main surface.
#[derive(Debug, Clone)]
pub enum MainSide {
    /// Vertices are mesh nodes: `triangles` holds node ids.
    Deformable { triangles: Vec<[u32; 3]> },
    /// Vertices are points of a rigid body: `triangles` index `vertices` (reference
    /// positions [m]), which move as x(t) = `motion`(t) · X.
    Rigid {
        vertices: Vec<Vector3<f64>>,
        triangles: Vec<[u32; 3]>,
        motion: RigidMotion,
    },
}

impl MainSide {
    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.triangles().len()
    }

    /// Vertex ids of every triangle (node ids, or indices of rigid vertices).
    pub fn triangles(&self) -> &[[u32; 3]] {
        match self {
            MainSide::Deformable { triangles } | MainSide::Rigid { triangles, .. } => triangles,
        }
    }

    /// The mesh nodes of triangle `triangle`, for a deformable main.
    pub fn nodes(&self, triangle: usize) -> Option<[u32; 3]> {
        match self {
            MainSide::Deformable { triangles } => Some(triangles[triangle]),
            MainSide::Rigid { .. } => None,
        }
    }

    /// The rigid body's placement at `time` (identity for a deformable main).
    pub fn placement(&self, time: f64) -> Isometry3<f64> {
        match self {
            MainSide::Deformable { .. } => Isometry3::identity(),
            MainSide::Rigid { motion, .. } => motion.isometry_at(time),
        }
    }

    /// The vertices of triangle `triangle` [m]: nodal `positions` for a deformable main,
    /// the rigid vertices placed by `placement` for a rigid one.
    pub fn vertices(
        &self,
        triangle: usize,
        positions: &[Vector3<f64>],
        placement: &Isometry3<f64>,
    ) -> [Vector3<f64>; 3] {
        match self {
            MainSide::Deformable { triangles } => {
                triangles[triangle].map(|node| positions[node as usize])
            }
            MainSide::Rigid {
                vertices,
                triangles,
                ..
            } => triangles[triangle]
                .map(|v| (placement * Point3::from(vertices[v as usize])).coords),
        }
    }
}
