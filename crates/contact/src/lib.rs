//! # musclefem-contact
//!
//! Surfaces of parts, parry3d broadphase, closest-point narrowphase, penalty contact and
//! cohesive traction-separation with damage.
//!
//! Not built yet: the interactions issue fills this crate. It exposes no API until then.

pub mod cohesive;

pub use cohesive::{
    CohesiveError, CohesiveInterface, CohesiveLaw, CohesiveSettings, TangentialMode,
};
