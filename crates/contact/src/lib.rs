//! # musclefem-contact
//!
//! Surfaces of parts, a parry3d broadphase, a closest-point narrowphase, penalty contact
//! and cohesive traction–separation with damage, entering the solvers of `musclefem-core`
//! through its [`musclefem_core::solver::Interaction`] trait.
//!
//! - [`surface`]: [`DeformableSurface`] (triangles of mesh faces, tributary areas) and
//!   [`ContactTarget`], the main side of a contact;
//! - [`rigid_surface`]: [`RigidSurface`], triangles moving with a prescribed rigid motion
//!   (generated planes, spheres, cylinders; STL and OBJ files);
//! - [`broadphase`]: parry3d BVH of the main side, candidate triangles per node;
//! - [`projection`]: closest point on a triangle, barycentric coordinates, signed gap;
//! - [`cohesive`]: [`CohesiveInterface`], surfaces bonded by a traction–separation law with
//!   damage ([`CohesiveSettings`]).

pub mod broadphase;
pub mod cohesive;
pub mod error;
pub mod projection;
pub mod rigid_surface;
pub mod surface;

pub use broadphase::Broadphase;
pub use cohesive::{
    CohesiveError, CohesiveInterface, CohesiveLaw, CohesiveSettings, TangentialMode,
};
pub use error::ContactError;
pub use projection::{Feature, Projection, project_on_triangle};
pub use rigid_surface::RigidSurface;
pub use surface::{ContactTarget, DeformableSurface};
