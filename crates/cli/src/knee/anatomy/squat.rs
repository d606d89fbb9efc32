//! The squat: knee flexion 0° → peak → 0°, and the rigid motions of the three bones
//! that drive it in a finite-element run.
//!
//! **How it is driven.** The paper (seed §2.4) pins the distal tibia (free to rotate in
//! the sagittal plane) and prescribes a vertical motion of the pelvis. What loads the
//! quadriceps is the relative motion of the bones they join (origins on the femur and
//! pelvis, insertions on the patella), so we prescribe the same relative motion in the
//! femur's frame: the femur (and the pelvis with it, the hip held at 0°) stays fixed,
//! the tibia rotates by θ(t) about the flexion axis, and the patella follows its
//! equilibrium pose ([`super::kinematics`]). This is an observer change: a quasi-static
//! run without gravity gives the same muscle deformation in either frame; the inertial
//! forces the two frames would weigh differently are ~ρ a L ≈ 1060 kg/m³ · 2 m/s² ·
//! 0.3 m ≈ 0.6 kPa for a 2 s squat, well below the muscles' tens of kPa to MPa. In a real
//! squat the hip flexes too (which keeps the rectus femoris nearly isometric, see
//! `rajagopal_lai_uhlrich2023_recfem_hip_knee.csv`); holding it at 0° stretches the
//! rectus like the other three.
//!
//! **Profile.** θ(t) = θ_peak (1 − cos(2π t / T)) / 2 for t ∈ [0, T]: smooth, at rest at
//! both ends and at the peak (t = T/2). The rigid motions are piecewise linear between
//! `knots` samples (their [`Amplitude`]s), which follows the profile to
//! θ_peak π² / (4 (knots − 1)²) (0.002° for 361 knots and 90°).

use anyhow::{Context, Result, bail};
use nalgebra::{Unit, Vector3};

use musclefem_core::solver::{RigidMotion, RigidRotation};
use musclefem_materials::Amplitude;

use super::kinematics::{KneeKinematics, PatellaPose};

/// A squat: duration, peak flexion and sampling of the drive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Squat {
    /// Duration T of the whole 0 → peak → 0 cycle [s].
    pub duration: f64,
    /// Peak knee flexion θ_peak [rad].
    pub peak_flexion: f64,
    /// Samples of the piecewise-linear drive over [0, T] (≥ 3).
    pub knots: usize,
}

/// The prescribed motions of the three bones (the reference poses are those at 0°).
#[derive(Clone, Debug)]
pub struct BoneMotions {
    /// The femur (and pelvis): fixed.
    pub femur: RigidMotion,
    /// The tibia: rotation by θ(t) about the flexion axis.
    pub tibia: RigidMotion,
    /// The patella: rotation by φ(θ(t)) − φ(0) about −z through its 0° centroid, and
    /// the translation of that centroid.
    pub patella: RigidMotion,
}

impl Squat {
    /// The default knee's squat: 0° → 90° → 0° in `duration` [s], 361 knots.
    pub fn to_ninety_degrees(duration: f64) -> Self {
        Self {
            duration,
            peak_flexion: std::f64::consts::FRAC_PI_2,
            knots: 361,
        }
    }

    /// Knee flexion θ(t) [rad] (constant outside [0, T]).
    pub fn flexion_at(&self, time: f64) -> f64 {
        let phase = (time / self.duration).clamp(0.0, 1.0);
        0.5 * self.peak_flexion * (1.0 - (2.0 * std::f64::consts::PI * phase).cos())
    }

    /// The bones' motions, the patella's from `kinematics` relative to its pose
    /// `reference` at 0°. Errors if the squat is not usable (non-positive duration, fewer
    /// than three knots) or the patella has no equilibrium at some angle.
    pub fn motions(
        &self,
        kinematics: &KneeKinematics,
        reference: &PatellaPose,
    ) -> Result<BoneMotions> {
        if !(self.duration.is_finite() && self.duration > 0.0) || self.knots < 3 {
            bail!(
                "a squat needs a positive duration and at least three knots: {} s, {}",
                self.duration,
                self.knots
            );
        }
        let times: Vec<f64> = (0..self.knots)
            .map(|k| self.duration * k as f64 / (self.knots - 1) as f64)
            .collect();
        let mut flexion = Vec::with_capacity(self.knots);
        let mut patella_angle = Vec::with_capacity(self.knots);
        let mut shift = [
            Vec::with_capacity(self.knots),
            Vec::with_capacity(self.knots),
        ];
        for &t in &times {
            let angle = self.flexion_at(t);
            let pose = kinematics
                .patella_pose(angle)
                .with_context(|| format!("the patella at t = {t} s"))?;
            flexion.push((t, angle));
            patella_angle.push((t, pose.flexion - reference.flexion));
            shift[0].push((t, pose.centre.x - reference.centre.x));
            shift[1].push((t, pose.centre.y - reference.centre.y));
        }
        let amplitude = |knots| Amplitude::new(knots).context("building the squat's amplitudes");
        let flexion_axis = Unit::new_normalize(-Vector3::z());
        Ok(BoneMotions {
            femur: RigidMotion::fixed(),
            tibia: RigidMotion {
                translation: [None, None, None],
                rotation: Some(RigidRotation {
                    center: Vector3::zeros(),
                    axis: flexion_axis,
                    angle: amplitude(flexion)?,
                }),
                follower: None,
            },
            patella: RigidMotion {
                translation: [
                    Some(amplitude(shift[0].clone())?),
                    Some(amplitude(shift[1].clone())?),
                    None,
                ],
                rotation: Some(RigidRotation {
                    center: reference.centre,
                    axis: flexion_axis,
                    angle: amplitude(patella_angle)?,
                }),
                follower: None,
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::knee::anatomy::Quadriceps;

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
    fn the_drive_samples_the_kinematics() {
        let kinematics = KneeKinematics::new(Quadriceps::ALL.iter().map(|m| m.pull()).collect());
        let reference = kinematics.patella_pose(0.0).unwrap();
        let squat = Squat {
            duration: 1.0,
            peak_flexion: std::f64::consts::FRAC_PI_2,
            knots: 11,
        };
        let motions = squat.motions(&kinematics, &reference).unwrap();
        // At a knot the drive is exact: the tibia is turned by θ, the patella is at its pose.
        let t = 0.3;
        let angle = squat.flexion_at(t);
        let tibia = motions.tibia.isometry_at(t);
        assert!((tibia.rotation.angle() - angle).abs() < 1e-12);
        let pose = kinematics.patella_pose(angle).unwrap();
        let apex = motions.patella.position_at(&reference.to_world(&APEX), t);
        assert!((apex - pose.to_world(&APEX)).norm() < 1e-12);
        assert!(
            Squat { knots: 2, ..squat }
                .motions(&kinematics, &reference)
                .is_err()
        );
    }

    use super::super::dimensions::APEX;
}
