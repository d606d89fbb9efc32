//! Musculotendon lengths and knee-extensor moment arms of the quadriceps.
//!
//! The musculotendon path of a quadriceps runs from its origin along its centreline to
//! its release station (femur-fixed, a constant length L_fixed), then freely to its
//! insertion on the patella (straight, or wrapped over the trochlea: [`super::path`]),
//! and on through the patellar tendon (apex to tuberosity, a constant ℓ):
//!
//! L(θ) = L_fixed + L_free(θ) + ℓ   [m].
//!
//! The knee-extensor moment arm is, by virtual work (the muscle's tension F does work
//! −F dL, the knee moment M does M dθ, so M = F dL/dθ),
//!
//! r(θ) = dL/dθ   [m per rad],
//!
//! evaluated by central differences with a step of [`DIFFERENCE_STEP`] (the patella's
//! pose re-solved at θ ± h), positive for an extensor (the muscle lengthens as the knee
//! flexes). This is what OpenSim reports as the moment arm about the knee coordinate
//! (Sherman, Seth & Delp 2013), so it compares with the Rajagopal–Lai–Uhlrich table.

use anyhow::Result;

use super::dimensions::KneeDimensions;
use super::kinematics::{KneeKinematics, PatellaPose, flexion_rotation};
use super::muscles::Muscle;
use super::path::free_path;

/// Step of the central differences for the moment arm [rad]: 0.5°.
pub const DIFFERENCE_STEP: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// A muscle's musculotendon length at one pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MusculotendonLength {
    /// Total length L [m].
    pub total: f64,
    /// The free part, release station to insertion [m].
    pub free: f64,
    /// Whether the free part wraps over the trochlea.
    pub wrapped: bool,
}

/// The musculotendon length of `muscle` with the patella at `patella`.
pub fn musculotendon_length(
    kinematics: &KneeKinematics,
    muscle: &Muscle,
    patella: &PatellaPose,
) -> MusculotendonLength {
    let pull = muscle.pull();
    let free = free_path(
        &pull.release,
        &patella.to_world(&pull.insertion),
        &kinematics.trochlea,
    );
    MusculotendonLength {
        total: muscle.fixed_length + free.length + kinematics.dimensions.patellar_tendon_length,
        free: free.length,
        wrapped: free.wrapped,
    }
}

/// The musculotendon lengths [m] of `muscles` at knee flexion `angle` [rad].
pub fn lengths_at(
    kinematics: &KneeKinematics,
    muscles: &[Muscle],
    angle: f64,
) -> Result<Vec<MusculotendonLength>> {
    let patella = kinematics.patella_pose(angle)?;
    Ok(muscles
        .iter()
        .map(|m| musculotendon_length(kinematics, m, &patella))
        .collect())
}

/// The knee-extensor moment arms r = dL/dθ [m] of `muscles` at knee flexion `angle`
/// [rad] (central differences, see the module documentation).
pub fn moment_arms_at(
    kinematics: &KneeKinematics,
    muscles: &[Muscle],
    angle: f64,
) -> Result<Vec<f64>> {
    let ahead = lengths_at(kinematics, muscles, angle + DIFFERENCE_STEP)?;
    let behind = lengths_at(kinematics, muscles, angle - DIFFERENCE_STEP)?;
    Ok(ahead
        .iter()
        .zip(&behind)
        .map(|(a, b)| (a.total - b.total) / (2.0 * DIFFERENCE_STEP))
        .collect())
}

/// How much hip flexion `hip` [rad] changes the musculotendon length of `muscle` [m]
/// in the procedural knee ([`hip_length_change_in`] with [`KneeDimensions::procedural_knee`]).
pub fn hip_length_change(muscle: &Muscle, hip: f64) -> f64 {
    hip_length_change_in(&KneeDimensions::procedural_knee(), muscle, hip)
}

/// How much hip flexion `hip` [rad] changes the musculotendon length of `muscle` [m]
/// (negative: shortens) in the knee of `dimensions`, for a muscle whose origin is on the
/// pelvis (the rectus femoris): the pelvis turns by R(hip) about the hip centre H
/// relative to the femur (forward and down, see [`super::closed_chain`]), which moves the
/// origin, and the path from it to the first femur-fixed station (a straight line)
/// changes by |H + R(hip)(O − H) − S₁| − |O − S₁|, R the flexion rotation. Zero for a
/// muscle whose origin is on the femur.
pub fn hip_length_change_in(dimensions: &KneeDimensions, muscle: &Muscle, hip: f64) -> f64 {
    if muscle.muscle != super::Quadriceps::RectusFemoris {
        return 0.0;
    }
    let origin = muscle.stations[0].centre;
    let first = muscle.stations[1].centre;
    let centre = dimensions.hip_centre;
    let moved = centre + flexion_rotation(hip) * (origin - centre);
    (moved - first).norm() - (origin - first).norm()
}

/// The mean fiber stretch of each muscle's belly when the squat reaches knee flexion
/// `angle` [rad] (the hip flexing with it, as in [`super::closed_chain`]):
/// λ = 1 + ΔL / L_belly, ΔL the musculotendon length change from 0° (the tendons taken
/// as inextensible) and L_belly the belly's centreline length.
pub fn belly_stretch_in_squat(
    kinematics: &KneeKinematics,
    muscles: &[Muscle],
    angle: f64,
) -> Result<Vec<f64>> {
    let extended = lengths_at(kinematics, muscles, 0.0)?;
    let flexed = lengths_at(kinematics, muscles, angle)?;
    Ok(muscles
        .iter()
        .zip(extended.iter().zip(&flexed))
        .map(|(m, (a, b))| {
            let change = b.total - a.total + hip_length_change_in(&kinematics.dimensions, m, angle);
            1.0 + change / (m.belly.1 - m.belly.0)
        })
        .collect())
}
