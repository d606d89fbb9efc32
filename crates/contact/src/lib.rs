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
//! - [`penalty`]: [`PenaltyContact`], frictionless node-to-surface penalty contact, at the
//!   closest point or along the smooth normal field of the main surface
//!   ([`PenaltyContact::with_smooth_normals`]; the field itself: `normal_field.rs`);
//! - [`cohesive`]: [`CohesiveInterface`], surfaces bonded by a traction–separation law with
//!   damage ([`CohesiveSettings`]);
//! - [`strands`]: [`TendonStrands`], tension-only toe-then-linear springs between pairs of
//!   nodes (aponeuroses and tendons as 1-D strands; the law [`ToeLinearLaw`] is the knee's
//!   patellar tendon's).
//!
//! Use: build the secondary side from mesh faces, the main side from faces or a rigid
//! shape, and hand the contact to `run_implicit_with` / `run_explicit_with`:
//!
//! ```text
//! let skin = DeformableSurface::from_mesh_surface(&mesh, "z0")?;
//! let bone = RigidSurface::sphere("femur head", centre, 0.02, 5)?.with_motion(motion);
//! let contact = PenaltyContact::with_default_penalty("skin on bone", skin, bone, youngs)?;
//! let mut interactions: Vec<Box<dyn Interaction>> = vec![Box::new(contact)];
//! ```
//!
//! Speed (`cargo run --release -p musclefem-contact --example contact_bench`): one
//! step's `search` + `forces` for 49 928 main triangles against 50 176 secondary nodes,
//! all in contact, 8.4 candidate triangles per node, measured on the 2-core machine while
//! another build ran on it (load 5): deformable main 44 ms on 1 thread (search 17 ms,
//! forces 27 ms), 34 ms on 2; rigid main 43 ms on 1 thread, 23 ms on 2. Above the 20 ms
//! target: the BVH traversal (parry's `intersect_aabb`, ~30 % of the time) and the
//! closest-point loop over the candidates (~45 %) dominate.

pub mod broadphase;
pub mod cohesive;
pub mod error;
pub(crate) mod main_side;
pub(crate) mod normal_field;
pub mod penalty;
pub mod projection;
pub mod rigid_surface;
pub mod strands;
pub mod surface;
#[cfg(test)]
mod test_surfaces;

pub use broadphase::Broadphase;
pub use cohesive::{
    Bond, CohesiveError, CohesiveInterface, CohesiveLaw, CohesiveSettings, TangentialMode,
};
pub use error::ContactError;
pub use penalty::{PenaltyContact, default_penalty};
pub use projection::{Feature, Projection, closest_feature, project_on_triangle};
pub use rigid_surface::RigidSurface;
pub use strands::{Strand, StrandError, StrandState, TendonStrands, ToeLinearLaw};
pub use surface::{ContactTarget, DeformableSurface};

/// The README's examples, compiled and run by `cargo test --doc`.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
