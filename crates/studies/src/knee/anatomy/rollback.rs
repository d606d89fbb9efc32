//! The femur's rollback on the tibial plateau: the tibiofemoral joint as a condyle that
//! rolls in early flexion and slides beyond.
//!
//! In the femur's frame the tibia turns by the knee flexion θ about the flexion axis
//! (the origin, along −z) and moves along its own anterior axis e_x by s(θ):
//!
//! x_tibia(θ) = R(θ) (X + s(θ) e_x),
//!
//! with R(θ) = R_z(−θ) the flexion rotation. A condyle of radius R_c rolling without
//! slipping on the flat plateau moves its centre (the flexion axis) posteriorly over the
//! tibia by R_c per radian, i.e. the tibia moves anteriorly under the axis: s′ = R_c. The
//! knee rolls in early flexion and slides more and more as it flexes (the femoral
//! condyles' "rolling–gliding"; the lateral condyle rolls back over the plateau while the
//! medial one stays nearly in place: Iwaki, Pinskerova & Freeman 2000, J Bone Joint
//! Surg Br 82:1189). The rolling rate here falls linearly from k R_c at full extension to
//! zero at θ_end:
//!
//! s′(θ) = k R_c (1 − θ/θ_end) for θ < θ_end, 0 beyond, so
//! s(θ) = k R_c (θ − θ²/(2 θ_end)) up to θ_end and k R_c θ_end / 2 after it [m].
//!
//! k = 0 is the fixed flexion axis of [`super::kinematics`]. The plateau stays at the
//! joint line in the tibia's frame, so the condyle and the plateau keep their gap.
//! Why it matters: the tibia's tuberosity, and with it the patellar tendon and the
//! patella, move with s(θ); the quadriceps' moment arms follow
//! (`docs/knee-model.md`, "Two measurements towards the fix").

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::kinematics::flexion_rotation;

/// The femur's rollback (module documentation): the rolling rate at full extension and
/// the flexion at which rolling has given way to sliding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rollback {
    /// ds/dθ at full extension, k R_c [m/rad] (0: a fixed flexion axis).
    pub rate: f64,
    /// Flexion θ_end past which the condyles slide without rolling [rad].
    pub end: f64,
}

impl Rollback {
    /// A fixed flexion axis: no translation.
    pub const FIXED_AXIS: Rollback = Rollback {
        rate: 0.0,
        end: std::f64::consts::FRAC_PI_2,
    };

    /// A condyle of radius `condyle_radius` [m] rolling a share `share` of pure rolling
    /// at full extension, down to sliding alone at `end` [rad].
    pub fn rolling(condyle_radius: f64, share: f64, end: f64) -> Self {
        assert!(end > 0.0, "rolling must end at a positive flexion");
        Rollback {
            rate: share * condyle_radius,
            end,
        }
    }

    /// The same rollback on a knee similar by `factor` (lengths times `factor`).
    pub fn scaled(&self, factor: f64) -> Self {
        Rollback {
            rate: factor * self.rate,
            ..*self
        }
    }

    /// Whether the tibia turns about a fixed axis.
    pub fn is_fixed_axis(&self) -> bool {
        self.rate == 0.0
    }

    /// The tibia's anterior translation s(θ) under the flexion axis at knee flexion
    /// `angle` [rad], in metres (module documentation).
    pub fn translation(&self, angle: f64) -> f64 {
        if self.is_fixed_axis() {
            return 0.0;
        }
        let theta = angle.min(self.end);
        self.rate * (theta - theta * theta / (2.0 * self.end))
    }

    /// The tibia-frame point `point` [m] shifted by the rollback at knee flexion `angle`
    /// [rad]: X + s(θ) e_x (X itself, bit for bit, on a fixed axis).
    pub fn shifted(&self, angle: f64, point: &Vector3<f64>) -> Vector3<f64> {
        if self.is_fixed_axis() {
            *point
        } else {
            point + Vector3::x() * self.translation(angle)
        }
    }

    /// Where the tibia-frame point `point` [m] is in the femur's frame at knee flexion
    /// `angle` [rad]: R(θ)(X + s(θ) e_x). On a fixed axis, R(θ) X bit for bit.
    pub fn tibia_point(&self, angle: f64, point: &Vector3<f64>) -> Vector3<f64> {
        flexion_rotation(angle) * self.shifted(angle, point)
    }

    /// The tibia's placement in the femur's frame at knee flexion `angle` [rad].
    pub fn tibia_in_femur(&self, angle: f64) -> Isometry3<f64> {
        let rotation = flexion_rotation(angle);
        let translation = if self.is_fixed_axis() {
            Translation3::identity()
        } else {
            Translation3::from(rotation * Vector3::x() * self.translation(angle))
        };
        Isometry3::from_parts(translation, UnitQuaternion::from_rotation_matrix(&rotation))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DEG: f64 = std::f64::consts::PI / 180.0;

    #[test]
    fn the_tibia_rolls_at_the_condyles_rate_and_then_slides() {
        let radius = 0.02;
        let rollback = Rollback::rolling(radius, 1.0, 60.0 * DEG);
        // Pure rolling at full extension: s' = R_c.
        let h = 1e-6;
        let rate = (rollback.translation(h) - rollback.translation(-h)) / (2.0 * h);
        assert!((rate - radius).abs() < 1e-9, "{rate}");
        // s(θ_end) = R_c θ_end / 2 and no more after it; s' is continuous there.
        let end = rollback.translation(60.0 * DEG);
        assert!((end - 0.5 * radius * 60.0 * DEG).abs() < 1e-15);
        assert_eq!(rollback.translation(90.0 * DEG), end);
        let below = (end - rollback.translation(60.0 * DEG - h)) / h;
        assert!(below.abs() < 1e-7, "{below}");
        // The translation is along the tibia's own anterior axis, turned with it.
        let pose = rollback.tibia_in_femur(90.0 * DEG);
        let origin = pose.transform_point(&nalgebra::Point3::origin()).coords;
        let expected = flexion_rotation(90.0 * DEG) * Vector3::new(end, 0.0, 0.0);
        assert!((origin - expected).norm() < 1e-15);
        let point = Vector3::new(0.03, -0.04, 0.01);
        let moved = pose.transform_point(&point.into()).coords;
        assert!((moved - rollback.tibia_point(90.0 * DEG, &point)).norm() < 1e-15);
    }

    #[test]
    fn a_fixed_axis_only_turns_the_tibia() {
        let fixed = Rollback::FIXED_AXIS;
        let point = Vector3::new(0.0356, -0.0431, 0.002);
        for degrees in [0.0, 30.0, 90.0] {
            let angle = degrees * DEG;
            assert_eq!(fixed.translation(angle), 0.0);
            assert_eq!(
                fixed.tibia_point(angle, &point),
                flexion_rotation(angle) * point
            );
            assert_eq!(
                fixed.tibia_in_femur(angle).translation,
                Translation3::identity()
            );
        }
    }
}
