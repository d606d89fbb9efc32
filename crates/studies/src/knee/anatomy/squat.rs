//! The squat: knee flexion 0° → peak → 0°, and the rigid motions of the bones that drive
//! it in a finite-element run.
//!
//! **How it is driven.** As the paper does (seed §2.4): the distal tibia is pinned and
//! free to rotate in the sagittal plane, and the pelvis moves vertically, so the femur
//! and the pelvis move in space and the hip flexes with the knee ([`super::closed_chain`]
//! gives every bone's pose from the knee angle). The femur carries the vasti's origins,
//! the surfaces the muscles slide on and the patella's groove; the pelvis carries the
//! rectus femoris's origin. The patella's pose in the femur's frame comes from the run
//! (the patellar tendon against the measured pull, `knee::simulation::patella`).
//!
//! **Profile.** θ(t) = θ_peak (1 − cos(2π t / T)) / 2 for t ∈ [0, T]: smooth, at rest at
//! both ends and at the peak (t = T/2). The bones follow it exactly: each motion asks the
//! chain for its pose at θ(t) ([`LegBone`]).

use std::sync::Arc;

use anyhow::{Result, bail};
use nalgebra::{Isometry3, Vector3};

use musclefem_core::solver::{PoseFollower, RigidMotion};

use super::closed_chain::{ClosedChain, LegPose};

/// A squat: duration and peak flexion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Squat {
    /// Duration T of the whole 0 → peak → 0 cycle [s].
    pub duration: f64,
    /// Peak knee flexion θ_peak [rad].
    pub peak_flexion: f64,
}

/// The bones the chain places.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bone {
    Femur,
    Tibia,
    Pelvis,
    /// A point of the pelvis [m, reference position] and what is pinned to it: carried
    /// with the pelvis without turning (a tendon attached at a small bony area, free to
    /// swing about it).
    PelvisPin(Vector3<f64>),
}

/// One bone of the leg following the squat: its pose at time t is the chain's at θ(t).
#[derive(Clone, Debug)]
pub struct LegBone {
    pub bone: Bone,
    pub chain: ClosedChain,
    pub squat: Squat,
}

impl LegBone {
    /// The leg's pose at `time` [s].
    pub fn leg_at(&self, time: f64) -> LegPose {
        self.chain.pose(self.squat.flexion_at(time))
    }
}

impl PoseFollower for LegBone {
    fn isometry_at(&self, time: f64) -> Isometry3<f64> {
        let pose = self.leg_at(time);
        match self.bone {
            Bone::Femur => pose.femur,
            Bone::Tibia => pose.tibia,
            Bone::Pelvis => pose.pelvis,
            Bone::PelvisPin(point) => {
                let moved = pose.pelvis * nalgebra::Point3::from(point);
                Isometry3::from_parts((moved.coords - point).into(), Default::default())
            }
        }
    }

    /// The knee axis point for the femur, the pin for the tibia, the hip centre for the
    /// pelvis.
    fn reference_point(&self) -> Vector3<f64> {
        match self.bone {
            Bone::Femur => Vector3::zeros(),
            Bone::Tibia => self.chain.ankle,
            Bone::Pelvis => self.chain.hip,
            Bone::PelvisPin(point) => point,
        }
    }
}

/// The prescribed motions of the femur, tibia and pelvis (the reference poses are those
/// at 0°).
#[derive(Clone, Debug)]
pub struct BoneMotions {
    pub femur: RigidMotion,
    pub tibia: RigidMotion,
    pub pelvis: RigidMotion,
    /// The chain and the squat they follow.
    pub chain: ClosedChain,
    pub squat: Squat,
}

impl Squat {
    /// The procedural knee's squat: 0° → 90° → 0° in `duration` [s].
    pub fn to_ninety_degrees(duration: f64) -> Self {
        Self {
            duration,
            peak_flexion: std::f64::consts::FRAC_PI_2,
        }
    }

    /// Knee flexion θ(t) [rad] (constant outside [0, T]).
    pub fn flexion_at(&self, time: f64) -> f64 {
        let phase = (time / self.duration).clamp(0.0, 1.0);
        0.5 * self.peak_flexion * (1.0 - (2.0 * std::f64::consts::PI * phase).cos())
    }

    /// The bones' motions along `chain`. Errors if the squat is not usable (non-positive
    /// duration or peak flexion outside (0°, 150°]).
    pub fn motions(&self, chain: &ClosedChain) -> Result<BoneMotions> {
        let duration_ok = self.duration.is_finite() && self.duration > 0.0;
        let peak_ok = self.peak_flexion > 0.0 && self.peak_flexion <= 150f64.to_radians();
        if !(duration_ok && peak_ok) {
            bail!(
                "a squat needs a positive duration and a peak flexion in (0°, 150°]: {} s, {}°",
                self.duration,
                self.peak_flexion.to_degrees()
            );
        }
        let follow = |bone| {
            RigidMotion::followed(Arc::new(LegBone {
                bone,
                chain: *chain,
                squat: *self,
            }))
        };
        Ok(BoneMotions {
            femur: follow(Bone::Femur),
            tibia: follow(Bone::Tibia),
            pelvis: follow(Bone::Pelvis),
            chain: *chain,
            squat: *self,
        })
    }
}

/// Header of `kinematics.csv`.
pub const KINEMATICS_CSV_HEADER: &str =
    "time_s,hip_flexion_deg,knee_flexion_deg,tibia_angle_deg,pelvis_height_m";

impl BoneMotions {
    /// The motion of `point` of the pelvis (its position at 0° [m]), carried with the
    /// pelvis without turning ([`Bone::PelvisPin`]).
    pub fn pinned_to_pelvis(&self, point: Vector3<f64>) -> RigidMotion {
        RigidMotion::followed(Arc::new(LegBone {
            bone: Bone::PelvisPin(point),
            chain: self.chain,
            squat: self.squat,
        }))
    }

    /// The leg's pose at `time` [s].
    pub fn leg_at(&self, time: f64) -> LegPose {
        self.chain.pose(self.squat.flexion_at(time))
    }

    /// `kinematics.csv`: at `intervals + 1` instants over the squat, the hip and knee
    /// flexion, the tibia's forward tilt from the vertical (the ankle's dorsiflexion) and
    /// the hip centre's height above the ankle pin.
    pub fn kinematics_csv(&self, intervals: usize) -> String {
        let intervals = intervals.max(1);
        let rows = (0..=intervals).map(|k| {
            let time = self.squat.duration * k as f64 / intervals as f64;
            let pose = self.leg_at(time);
            vec![
                time,
                pose.hip_flexion.to_degrees(),
                pose.knee_flexion.to_degrees(),
                pose.tibia_tilt.to_degrees(),
                pose.hip_centre.y - self.chain.ankle.y,
            ]
        });
        musclefem_io::csv::format_table(KINEMATICS_CSV_HEADER, rows)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_profile_rests_at_both_ends_and_peaks_halfway() {
        let squat = Squat::to_ninety_degrees(4.0);
        assert_eq!(squat.flexion_at(0.0), 0.0);
        assert!((squat.flexion_at(2.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!(squat.flexion_at(4.0).abs() < 1e-15);
        assert!((squat.flexion_at(1.0) - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
        // Symmetric about the peak, at rest (zero slope) at the ends and the peak.
        assert!((squat.flexion_at(0.7) - squat.flexion_at(3.3)).abs() < 1e-15);
        let h = 1e-6;
        for t in [h, 2.0 + h, 4.0 - h] {
            assert!((squat.flexion_at(t) - squat.flexion_at(t - h)).abs() < 1e-9);
        }
    }

    #[test]
    fn the_motions_place_the_bones_where_the_chain_says() {
        let chain = ClosedChain::procedural_knee();
        let squat = Squat::to_ninety_degrees(2.0);
        let motions = squat.motions(&chain).unwrap();
        for t in [0.0, 0.3, 1.0, 1.7] {
            let pose = chain.pose(squat.flexion_at(t));
            let point = Vector3::new(0.03, 0.2, -0.01);
            assert!((motions.femur.position_at(&point, t) - pose.on_femur(&point)).norm() < 1e-15);
            let hip = motions.pelvis.position_at(&chain.hip, t);
            assert!((hip - pose.hip_centre).norm() < 1e-14);
            let ankle = motions.tibia.position_at(&chain.ankle, t);
            assert!((ankle - chain.ankle).norm() < 1e-14);
        }
        assert!(
            Squat {
                duration: 0.0,
                ..squat
            }
            .motions(&chain)
            .is_err()
        );
    }
}
