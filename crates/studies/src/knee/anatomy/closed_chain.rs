//! The squat as the paper drives it (seed §2.4): "the pelvis was assigned a kinematic
//! profile in the vertical direction. The distal end of tibia was pinned, and tibial
//! rotation was permitted in the sagittal plane."
//!
//! **The chain.** Ankle A (the pin at the centre of the tibia's distal end), knee axis K,
//! hip centre H, all in the sagittal plane. The knee flexes by θ (the tibia's rotation
//! relative to the femur, [`super::kinematics`]). The tibia tilts forward about the pin
//! by β, so the femur is inclined backwards by θ − β; β follows from the pelvis moving
//! vertically, i.e. the hip centre keeping its horizontal position:
//!
//! ```text
//! K(β) = A + R(β)(−s(θ) e_x − A),   H(β) = K(β) + R(β − θ) H₀,   H_x(β) = H₀_x,
//! ```
//!
//! with R(a) = R_z(−a) the flexion rotation ([`flexion_rotation`]), H₀ the hip centre
//! in the femur's frame (the global frame at 0°) and s(θ) the femur's rollback over the
//! tibia ([`super::rollback`]; 0 for a fixed flexion axis): the femur is placed where the
//! knee's kinematics put it relative to the tibia. H_x grows monotonically with β on
//! [−θ/2, θ + π/2], where it is solved by bisection. With the procedural anatomy (tibia
//! 398 mm, femur 445 mm) β = 23.9° at θ = 45° and 48.4° at θ = 90°.
//!
//! **The pelvis.** It moves vertically with the hip centre and tilts forward by the
//! tibia's angle β (the trunk stays parallel to the shank), so the hip flexes by
//! (θ − β) + β = θ: hip flexion equals knee flexion. That is the squat of the
//! rectus femoris reference (Rajagopal–Lai–Uhlrich 2023,
//! `rajagopal_lai_uhlrich2023_recfem_hip_knee.csv`, hip = knee flexion), in which the
//! rectus, crossing both joints, stays within 8 mm of its length from 0° to 90° instead of
//! lengthening by 64 mm with the hip held at 0°. A pelvis that only translated would flex
//! the hip by θ − β = 42° at θ = 90° and stretch the rectus by about 30 mm.
//!
//! **What moves.** Everything is placed by rigid motions of the global frame: the tibia
//! about the pin, the femur (and with it the patella's pose in the femur's frame, the
//! vasti's origins and the femoral surfaces the muscles slide on) and the pelvis (the
//! rectus's origin at the anterior inferior iliac spine). Gravity is left out, as in the
//! paper; the inertial forces of the moving frame enter the dynamic runs.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

use super::dimensions::KneeDimensions;
use super::kinematics::flexion_rotation;
use super::rollback::Rollback;

/// The leg's closed chain: the pin at the ankle and the hip centre (see the module
/// documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosedChain {
    /// The pin at the tibia's distal end [m], in the tibia's frame (the global frame at
    /// 0°).
    pub ankle: Vector3<f64>,
    /// The hip centre [m], in the femur's frame (the global frame at 0°).
    pub hip: Vector3<f64>,
    /// The femur's rollback on the tibia ([`Rollback::FIXED_AXIS`]: none).
    pub rollback: Rollback,
}

/// The pose of the leg's bones at one knee flexion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LegPose {
    /// Knee flexion θ [rad].
    pub knee_flexion: f64,
    /// Forward tilt β of the tibia about the pin [rad] (ankle dorsiflexion).
    pub tibia_tilt: f64,
    /// Hip flexion, the femur's rotation relative to the pelvis [rad] (= θ).
    pub hip_flexion: f64,
    /// The bones' placements: a point at reference position X is at iso · X.
    pub femur: Isometry3<f64>,
    pub tibia: Isometry3<f64>,
    pub pelvis: Isometry3<f64>,
    /// The hip centre [m].
    pub hip_centre: Vector3<f64>,
}

/// A rotation by `rotation` about the point `centre`, then a translation to `target`:
/// x = target + R (X − centre).
fn placement(centre: &Vector3<f64>, target: &Vector3<f64>, angle: f64) -> Isometry3<f64> {
    let rotation = UnitQuaternion::from_rotation_matrix(&flexion_rotation(angle));
    Isometry3::from_parts(Translation3::from(target - rotation * centre), rotation)
}

impl ClosedChain {
    /// The procedural knee's chain: the ankle pin at [`ANKLE`](super::dimensions::ANKLE), the
    /// hip at [`HIP_CENTRE`](super::dimensions::HIP_CENTRE).
    pub fn procedural_knee() -> Self {
        Self::from_dimensions(&KneeDimensions::procedural_knee())
    }

    /// The chain of the knee of `dimensions`: the ankle pin at its ankle, the hip at its
    /// hip centre.
    pub fn from_dimensions(dimensions: &KneeDimensions) -> Self {
        Self {
            ankle: dimensions.ankle,
            hip: dimensions.hip_centre,
            rollback: dimensions.rollback,
        }
    }

    /// The knee axis point (the origin of the femur's frame) with the knee flexed by
    /// `knee_flexion` and the tibia tilted by `tilt` [m]: in the tibia's frame the axis
    /// lies s(θ) behind the tibia's origin, so the ankle lies at A + s(θ) e_x from it.
    fn knee_at(&self, knee_flexion: f64, tilt: f64) -> Vector3<f64> {
        let ankle_from_axis = self.rollback.shifted(knee_flexion, &self.ankle);
        self.ankle - flexion_rotation(tilt) * ankle_from_axis
    }

    /// The hip centre with the knee flexed by `knee_flexion` and the tibia tilted by
    /// `tilt` [m].
    fn hip_at(&self, knee_flexion: f64, tilt: f64) -> Vector3<f64> {
        self.knee_at(knee_flexion, tilt) + flexion_rotation(tilt - knee_flexion) * self.hip
    }

    /// The tibia's forward tilt β [rad] that keeps the hip centre above its place at 0°
    /// with the knee flexed by `knee_flexion` [rad] (bisection to 1e-14 rad).
    pub fn tibia_tilt(&self, knee_flexion: f64) -> f64 {
        if knee_flexion == 0.0 {
            // Upright: exactly the reference pose.
            return 0.0;
        }
        let excess = |tilt: f64| self.hip_at(knee_flexion, tilt).x - self.hip.x;
        let (mut low, mut high) = (
            -0.5 * knee_flexion.abs(),
            knee_flexion.abs() + std::f64::consts::FRAC_PI_2,
        );
        for _ in 0..100 {
            let middle = 0.5 * (low + high);
            if excess(middle) < 0.0 {
                low = middle;
            } else {
                high = middle;
            }
            if high - low < 1e-14 {
                break;
            }
        }
        0.5 * (low + high)
    }

    /// The bones' poses at knee flexion `knee_flexion` [rad].
    pub fn pose(&self, knee_flexion: f64) -> LegPose {
        let tilt = self.tibia_tilt(knee_flexion);
        let knee = self.knee_at(knee_flexion, tilt);
        let hip_centre = self.hip_at(knee_flexion, tilt);
        LegPose {
            knee_flexion,
            tibia_tilt: tilt,
            hip_flexion: knee_flexion,
            femur: placement(&Vector3::zeros(), &knee, tilt - knee_flexion),
            tibia: placement(&self.ankle, &self.ankle, tilt),
            pelvis: placement(&self.hip, &hip_centre, tilt),
            hip_centre,
        }
    }

    /// The hip centre's height above the ankle pin at knee flexion `knee_flexion` [m].
    pub fn pelvis_height(&self, knee_flexion: f64) -> f64 {
        self.pose(knee_flexion).hip_centre.y - self.ankle.y
    }
}

impl LegPose {
    /// Where the femur-frame point `point` [m] is.
    pub fn on_femur(&self, point: &Vector3<f64>) -> Vector3<f64> {
        (self.femur * Point3::from(*point)).coords
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::knee::anatomy::KneeDimensions;
    use crate::knee::anatomy::kinematics::KneeKinematics;

    const DEG: f64 = std::f64::consts::PI / 180.0;

    #[test]
    fn the_ankle_stays_pinned_and_the_hip_moves_straight_down() {
        let chain = ClosedChain::procedural_knee();
        let upright = chain.pose(0.0);
        assert!(upright.tibia_tilt.abs() < 1e-12);
        assert!((upright.femur.translation.vector).norm() < 1e-15);
        let mut height = chain.pelvis_height(0.0);
        for degrees in [10.0, 30.0, 45.0, 60.0, 90.0] {
            let pose = chain.pose(degrees * DEG);
            // The pin does not move; the hip stays above where it was.
            let ankle = (pose.tibia * Point3::from(chain.ankle)).coords;
            assert!((ankle - chain.ankle).norm() < 1e-15);
            assert!(
                (pose.hip_centre.x - chain.hip.x).abs() < 1e-12,
                "{degrees}°"
            );
            assert!(pose.hip_centre.z == chain.hip.z);
            // The pelvis goes down as the knee flexes.
            let h = chain.pelvis_height(degrees * DEG);
            assert!(h < height, "{degrees}°: {h} after {height}");
            height = h;
        }
    }

    #[test]
    fn femur_and_tibia_keep_the_knee_and_the_hip_flexes_with_it() {
        let fixed = ClosedChain::procedural_knee();
        let rolling = ClosedChain {
            rollback: Rollback::rolling(0.021, 1.0, 60.0 * DEG),
            ..fixed
        };
        for chain in [fixed, rolling] {
            let dimensions = KneeDimensions {
                rollback: chain.rollback,
                ..KneeDimensions::procedural_knee()
            };
            let knee = KneeKinematics::from_dimensions(dimensions, Vec::new());
            for degrees in [15.0, 45.0, 90.0] {
                let angle = degrees * DEG;
                let pose = chain.pose(angle);
                // In the femur's frame the tibia is where the knee's kinematics put it:
                // turned by θ about the flexion axis (and rolled back under it).
                let relative = pose.femur.inverse() * pose.tibia;
                let expected = knee.tibia_isometry(angle);
                assert!((relative.translation.vector - expected.translation.vector).norm() < 1e-14);
                assert!(relative.rotation.angle_to(&expected.rotation) < 1e-14);
                // The pin stays; the hip stays above where it was.
                let ankle = (pose.tibia * Point3::from(chain.ankle)).coords;
                assert!((ankle - chain.ankle).norm() < 1e-15);
                assert!((pose.hip_centre.x - chain.hip.x).abs() < 1e-12);
                // The femur and the pelvis meet at the hip centre; the hip flexes by θ.
                let from_femur = pose.on_femur(&chain.hip);
                let from_pelvis = (pose.pelvis * Point3::from(chain.hip)).coords;
                assert!((from_femur - pose.hip_centre).norm() < 1e-14);
                assert!((from_pelvis - pose.hip_centre).norm() < 1e-14);
                let hip = pose.pelvis.rotation.inverse() * pose.femur.rotation;
                assert!((hip.angle() - angle).abs() < 1e-12);
                // Flexion swings the femur's distal end forward (+x) of the pelvis: about +z.
                assert!(hip.axis().unwrap().z > 0.0);
            }
        }
        let (fixed_tilt, rolling_tilt) =
            (fixed.tibia_tilt(90.0 * DEG), rolling.tibia_tilt(90.0 * DEG));
        // The femur rolled back over the tibia puts the hip further behind the knee, so
        // the tibia leans further forward to keep the hip above its place.
        assert!(rolling_tilt > fixed_tilt, "{rolling_tilt} ≤ {fixed_tilt}");
        // The numbers of the module documentation.
        for (degrees, tilt) in [(45.0, 23.9), (90.0, 48.4)] {
            let measured = fixed.tibia_tilt(degrees * DEG) / DEG;
            assert!(
                (measured - tilt).abs() < 0.05,
                "{degrees}°: tibia tilt {measured}°"
            );
        }
    }
}
