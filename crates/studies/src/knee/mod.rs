//! The knee flexion–extension scene of the paper (seed §2.4, issue 8): a squat with the
//! four quadriceps between the femur/pelvis and the patella.
//!
//! - [`anatomy`]: the procedural anatomy built into the program (bones, quadriceps meshes,
//!   patellar tendon, kinematics), its moment arms, and the squat's bone motions
//!   ([`Anatomy::procedural_knee`]).
//!
//! - [`simulation`]: the finite-element squat on that anatomy (or user meshes), with
//!   fibers, cohesive and contact interactions, and the muscles' peak stresses.
//!
//! - [`command`]: `musclefem knee` (and the Python module's `musclefem.knee`): both squats
//!   side by side, their files, tables and chart.

pub mod anatomy;
pub mod command;
pub mod simulation;

pub use anatomy::{Anatomy, BoneMotions, PatellarTendon, Quadriceps, Resolution, Squat};
