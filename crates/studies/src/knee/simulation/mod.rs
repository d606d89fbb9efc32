//! The finite-element squat (seed §2.4): the four quadriceps with their tendons, tied at
//! their origins to the femur and pelvis and at their insertions to the patella, sliding
//! on each other and on the femur, stretched by the closed-chain squat 0° → 90° → 0°,
//! passive or activated to 50 % from 35° of flexion on.
//!
//! - [`model`]: the geometry (procedural anatomy or user meshes), the fibers, the Hill
//!   muscle parts, the tendon parts and the bone ties;
//! - [`files`]: the muscles from a mesh file (`--anatomy DIR`);
//! - [`interactions`]: cohesive interfaces (sliding by default) and penalty contact;
//! - [`patella`]: the patella held by the patellar tendon (a nonlinear spring) against
//!   the pull the run measures;
//! - [`run`]: one squat with either solver, the muscles' vm95 at every recorded instant;
//! - [`peak_stress`]: vm95, where the peaks lie, and `peak_stress.csv`;
//! - [`plausibility`]: pull, tendon force, extensor moment, fiber stretch, interface
//!   shares, `plausibility.csv`;
//! - [`resolution`]: the measured cost and error of each resolution, `--tolerance`.
//!
//! **The closed chain** ([`super::anatomy::ClosedChain`]). As in the paper, the distal
//! tibia is pinned (free to turn in the sagittal plane) and the pelvis is lowered: the
//! hip stays above the ankle, so the tibia tilts forward (β = 23.9° at 45° of knee
//! flexion, 48.4° at 90°) and the hip flexes as much as the knee (the pelvis turns with
//! the thigh). The femur moves, and with it the vasti's origins; the rectus's origin
//! rides on the pelvis. `kinematics.csv` records the motion.
//!
//! **Tendons.** Each muscle ends in its lamina of the quadriceps tendon and distal
//! aponeurosis (block `<muscle>_tendon`; the rectus also starts with its direct tendon),
//! of the `tendon` material (fiber-reinforced, E ≈ 1 GPa along the fibers with a 2 %
//! toe region). The fibers of the flow solver run through the bellies only, from the
//! origin to the muscle–tendon junction; vm95 is over belly elements, and each tendon's
//! peak stress is reported apart.
//!
//! **Passive slack.** The paper's parallel element is stress-free at the reference
//! (0° of flexion); the relaxed quadriceps are slack in extension and their fibers
//! reach their optimal length at 60–70° (where the knee-extension torque peaks). Each
//! muscle's parallel element therefore starts at λ_PE, the mean belly stretch it
//! reaches at 60° of flexion in the squat ([`model::PASSIVE_SLACK_FLEXION`]). Without
//! it the passive squat's insertions pulled ~800 N at 90° (coarse, 2026-11-25), beyond
//! the passive extensor moments measured in vivo. User anatomies keep λ_PE = 1.
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

mod checkpoint;
pub mod files;
pub mod followers;
pub mod interactions;
pub mod model;
pub mod patella;
pub mod patella_clearance;
pub mod peak_stress;
pub mod plausibility;
mod recorder;
pub mod resolution;
pub mod run;
pub mod scene;
pub mod scene_bones;
pub mod scene_files;
pub mod scene_interactions;
pub mod scene_materials;
pub mod scene_run;
pub mod scene_step;
#[cfg(test)]
mod scene_tests;
pub mod scene_ties;
pub mod visible_human;

pub use model::{Activation, KneeGeometry, KneeModel};
pub use peak_stress::{PEAK_STRESS_CSV_HEADER, PeakLocation, PeakStressRow, Phase, StressSample};
pub use run::{SquatRun, SquatSettings};
pub use scene::SquatScene;
pub use scene_run::{SceneSquat, SquatDirectory, run_squat_in, run_squat_scene};
