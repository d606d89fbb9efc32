//! The finite-element squat (seed §2.4): the four quadriceps, tied at their origins to the
//! femur and pelvis and at their insertions to the patella, bonded to each other and to
//! the femur, stretched by the knee's flexion 0° → 90° → 0°, passive or activated to
//! 50 % from 35° of flexion on.
//!
//! - [`model`]: the geometry (default anatomy or user meshes), the fibers, the Hill
//!   muscle parts and the bone ties;
//! - [`files`]: the muscles from a mesh file (`--anatomy DIR`);
//! - [`interactions`]: cohesive bonds and penalty contact;
//! - [`patella`]: the patella held by the patellar tendon (a nonlinear spring) against
//!   the pull the run measures;
//! - [`run`]: one squat with either solver, the muscles' vm95 at every recorded instant;
//! - [`peak_stress`]: vm95, where the peaks lie, and `peak_stress.csv`;
//! - [`resolution`]: the measured cost and error of each resolution, `--tolerance`.
//!
//! **Activation during extension.** The paper activates the quadriceps at about 35° and
//! holds the level "until maximum flexion was achieved"; it does not say what follows.
//! We hold 50 % through the extension back to 0° (the quadriceps extend the knee while
//! rising from a squat), so the extension rows of the active run are at 50 %.
//!
//! **The patellar tendon.** A nonlinear spring from the patella's apex to the tibial
//! tuberosity ([`super::anatomy::tendon`]). The patella is not prescribed: at each
//! increment it takes the pose where the tendon balances the quadriceps' pull that the
//! run measured at the insertions ([`patella`]), so the tendon stretches (and the
//! muscles shorten) as the pull grows.

pub mod files;
pub mod interactions;
pub mod model;
pub mod patella;
pub mod patella_clearance;
pub mod peak_stress;
pub mod resolution;
pub mod run;

pub use model::{Activation, KneeGeometry, KneeModel};
pub use peak_stress::{PEAK_STRESS_CSV_HEADER, PeakLocation, PeakStressRow, Phase, StressSample};
pub use run::{SquatRun, SquatSettings, SquatStart, SquatWatcher, run_squat};
