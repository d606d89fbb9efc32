//! The frame and the landmark dimensions of the default right knee, in one place.
//!
//! # Frame
//! Origin at the knee's flexion axis, midway between the epicondyles; **x anterior,
//! y proximal (along the femur's mechanical axis), z lateral** (right leg). Lengths in
//! metres; the constants below are written in millimetres times [`MM`]. The femur is
//! fixed in this frame; the knee flexes by rotating the tibia about the fixed flexion
//! axis through the origin along −z (so a positive flexion angle θ swings the distal
//! tibia posteriorly): a fixed transepicondylar axis, which the posterior condyles'
//! circular profiles about it make exact for the rigid condyles (Churchill et al. 1998,
//! Clin Orthop 356:111 found the flexion axis within a few millimetres of the
//! transepicondylar axis over 15–90° of flexion). Screw-home rotation and varus–valgus
//! are left out; the femur's rollback on the plateau is a knee's choice
//! ([`KneeDimensions::rollback`], [`super::rollback`]): none for the procedural knee.
//!
//! # Sagittal mechanism (see [`super::kinematics`])
//! In the sagittal plane the trochlear groove's floor is a circle of centre
//! [`GROOVE_CENTRE`] and radius [`GROOVE_RADIUS`] continued proximally by the flat
//! anterior femur x = [`ANTERIOR_FEMUR`]; the patella's articular ridge, the osculating
//! circle of its ellipsoid at the posterior pole, rides on it; the patellar tendon of
//! length [`PATELLAR_TENDON_LENGTH`] runs from the patella's [`APEX`] to the tibial
//! tuberosity [`TUBEROSITY`]. The values of the groove, tendon and tuberosity were
//! chosen within their anatomical ranges (sources on each) so that the quadriceps' moment
//! arms match the Rajagopal–Lai–Uhlrich 2023 model (`tests/knee_anatomy.rs`).
//!
//! # Landmarks as data
//! The mechanism (kinematics, wrap, moment arms, tendon spring, closed chain) reads these
//! landmarks from a [`KneeDimensions`], so that a knee measured from data runs the same
//! squat; [`KneeDimensions::procedural_knee`] is the constants below.

use nalgebra::Vector3;

use super::rollback::Rollback;

/// One millimetre [m].
pub const MM: f64 = 1e-3;

/// A point given in millimetres, in metres.
pub const fn mm(x: f64, y: f64, z: f64) -> Vector3<f64> {
    Vector3::new(x * MM, y * MM, z * MM)
}

/// Radius of the posterior femoral condyles' circular profile about the flexion axis
/// [m]: 21 mm (the flexion facets' radii, ≈ 20–22 mm: Iwaki, Pinskerova & Freeman 2000,
/// J Bone Joint Surg Br 82:1189).
pub const CONDYLE_RADIUS: f64 = 21.0 * MM;

/// Height of the tibial plateau (the joint line) below the flexion axis [m]: the condyle
/// radius plus 2 mm for the articular cartilage and meniscus left out of the rigid
/// bones, so the femur and tibia never touch as the knee flexes.
pub const JOINT_LINE: f64 = -23.0 * MM;

/// Centre (x, y) of the trochlear groove floor's sagittal circle [m]: 17.4 mm anterior,
/// 3.4 mm proximal to the flexion axis.
pub const GROOVE_CENTRE: [f64; 2] = [17.4 * MM, 3.4 * MM];

/// Radius of the trochlear groove floor's sagittal circle [m]: 18.1 mm (the deepest
/// points of the groove fit a circle of 23 ± 4 mm: Iranpour et al. 2010, Clin Orthop
/// Relat Res 468:782).
pub const GROOVE_RADIUS: f64 = 18.1 * MM;

/// The anterior femoral surface above the groove, x = groove centre + radius [m]
/// (35.5 mm in front of the flexion axis: the distal femur is 35.5 + 21 ≈ 57 mm deep
/// at the groove and ≈ 62 mm over the lateral facet, as adult male femora).
pub const ANTERIOR_FEMUR: f64 = GROOVE_CENTRE[0] + GROOVE_RADIUS;

/// Semi-axes of the patella's ellipsoid [m]: mediolateral 25 mm, proximodistal 22 mm,
/// anteroposterior 10.85 mm. Width 50 and height 44 mm are those of adult male patellae
/// (the Visible Human Male's right patella spans 52.1 × 46.8 mm); the thickness makes
/// the volume 4/3 π · 25 · 22 · 10.85 mm³ = 25.0 cm³, the VHM patella's volume
/// (`visible_human_andreassen2023_quadriceps_mesh_stats.csv`).
pub const PATELLA_SEMI_AXES: [f64; 3] = [25.0 * MM, 22.0 * MM, 10.85 * MM];

/// Radius of the patella's articular ridge in the sagittal plane [m]: the osculating
/// circle of its ellipse at the posterior pole, b²/c = 22²/10.85 mm = 44.6 mm.
pub const PATELLA_RIDGE_RADIUS: f64 =
    PATELLA_SEMI_AXES[1] * PATELLA_SEMI_AXES[1] / PATELLA_SEMI_AXES[2];

/// The patellar tendon's origin on the patella [m], in the patella's frame (origin at
/// its centroid, axes along the global ones at 0° of patellar flexion): the apex, 3 mm
/// behind the distal pole's tip, on the ellipsoid.
pub const APEX: Vector3<f64> = mm(-3.0, -21.142, 0.0);

/// The patellar tendon's insertion on the tibial tuberosity [m], in the tibia's frame
/// (the global frame at 0° of flexion): 35.6 mm anterior, 43.1 mm distal to the flexion
/// axis, i.e. 20 mm below the joint line and 7 mm in front of the plateau's anterior
/// rim.
pub const TUBEROSITY: Vector3<f64> = mm(35.6, -43.1, 0.0);

/// Length of the patellar tendon from apex to tuberosity [m]: 49.6 mm, an
/// Insall–Salvati ratio 49.6 / 44 = 1.13 (normal 1.02 ± 0.13: Insall & Salvati 1971,
/// Radiology 101:101).
pub const PATELLAR_TENDON_LENGTH: f64 = 49.6 * MM;

/// Offset of the quadriceps tendon's wrapping cylinder beyond the groove floor [m]:
/// half the tendon's thickness, 2.5 mm.
pub const TENDON_WRAP_OFFSET: f64 = 2.5 * MM;

/// Centre of the femoral head, the hip joint centre [m]: 445 mm above the knee, 5 mm
/// medial; with the head's 24 mm radius and the condyles' 21 mm the femur is 490 mm long
/// (Trotter & Gleser 1952, Am J Phys Anthropol 10:463: stature = 2.38 × femur length
/// + 61.4 cm gives 498 mm for the 1.80 m Visible Human Male).
pub const HIP_CENTRE: Vector3<f64> = mm(10.0, 445.0, -5.0);

/// The pin of the closed-chain squat at the tibia's distal end [m], in the tibia's frame
/// (the global frame at 0°): the centre of the tibia's distal articular surface, 398 mm
/// below the flexion axis (the tibia of [`super::bones`] ends there; adult male tibiae
/// are 370–420 mm long).
pub const ANKLE: Vector3<f64> = mm(1.0, -398.0, 0.0);

/// The landmarks a knee's mechanism reads: the groove's sagittal circle, the patella's
/// ellipsoid, the patellar tendon, the wrap offset and the closed chain's hip and ankle
/// (see the module documentation), in this module's frame, lengths in metres.
/// [`KneeDimensions::procedural_knee`] holds the constants above; a knee measured from
/// data (the Visible Human Female's, issue #35) brings its own. The procedural bones
/// ([`super::bones`]) are the procedural knee's shapes and keep reading the constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KneeDimensions {
    /// Radius of the posterior femoral condyles' circular profile about the flexion axis
    /// [m] (default [`CONDYLE_RADIUS`]).
    pub condyle_radius: f64,
    /// Height of the tibial plateau (the joint line) relative to the flexion axis [m],
    /// negative: below it (default [`JOINT_LINE`]).
    pub joint_line: f64,
    /// Centre (x, y) of the trochlear groove floor's sagittal circle [m] (default
    /// [`GROOVE_CENTRE`]).
    pub groove_centre: [f64; 2],
    /// Radius of the trochlear groove floor's sagittal circle [m] (default
    /// [`GROOVE_RADIUS`]).
    pub groove_radius: f64,
    /// Semi-axes of the patella's ellipsoid [m]: mediolateral, proximodistal,
    /// anteroposterior (default [`PATELLA_SEMI_AXES`]).
    pub patella_semi_axes: [f64; 3],
    /// The patellar tendon's origin on the patella [m], in the patella's frame (origin at
    /// its centroid, axes along the global ones at 0° of patellar flexion): the apex
    /// (default [`APEX`]).
    pub apex: Vector3<f64>,
    /// The patellar tendon's insertion on the tibial tuberosity [m], in the tibia's frame
    /// (the global frame at 0° of flexion) (default [`TUBEROSITY`]).
    pub tuberosity: Vector3<f64>,
    /// Length of the slack patellar tendon from apex to tuberosity [m] (default
    /// [`PATELLAR_TENDON_LENGTH`]).
    pub patellar_tendon_length: f64,
    /// Offset of the quadriceps tendon's wrapping cylinder beyond the groove floor [m]:
    /// half the tendon's thickness (default [`TENDON_WRAP_OFFSET`]).
    pub tendon_wrap_offset: f64,
    /// Centre of the femoral head, the hip joint centre [m], in the femur's frame
    /// (default [`HIP_CENTRE`]).
    pub hip_centre: Vector3<f64>,
    /// The pin of the closed-chain squat at the tibia's distal end [m], in the tibia's
    /// frame (default [`ANKLE`]).
    pub ankle: Vector3<f64>,
    /// The femur's rollback on the tibial plateau (default
    /// [`Rollback::FIXED_AXIS`]: the tibia turns about the fixed flexion axis).
    pub rollback: Rollback,
}

impl KneeDimensions {
    /// The default right knee: the constants of this module.
    pub fn procedural_knee() -> Self {
        Self {
            condyle_radius: CONDYLE_RADIUS,
            joint_line: JOINT_LINE,
            groove_centre: GROOVE_CENTRE,
            groove_radius: GROOVE_RADIUS,
            patella_semi_axes: PATELLA_SEMI_AXES,
            apex: APEX,
            tuberosity: TUBEROSITY,
            patellar_tendon_length: PATELLAR_TENDON_LENGTH,
            tendon_wrap_offset: TENDON_WRAP_OFFSET,
            hip_centre: HIP_CENTRE,
            ankle: ANKLE,
            rollback: Rollback::FIXED_AXIS,
        }
    }

    /// The anterior femoral surface above the groove, x = x_g + r_g [m] (default
    /// [`ANTERIOR_FEMUR`]).
    pub fn anterior_femur(&self) -> f64 {
        self.groove_centre[0] + self.groove_radius
    }

    /// Radius of the patella's articular ridge in the sagittal plane [m]: the osculating
    /// circle of its ellipse at the posterior pole, ρ_p = b²/c for the proximodistal and
    /// anteroposterior semi-axes b, c (default [`PATELLA_RIDGE_RADIUS`]).
    pub fn patella_ridge_radius(&self) -> f64 {
        let [_, b, c] = self.patella_semi_axes;
        b * b / c
    }

    /// The tibial tuberosity at knee flexion `angle` [rad], in the femur's frame [m].
    pub fn tuberosity_at(&self, angle: f64) -> Vector3<f64> {
        self.rollback.tibia_point(angle, &self.tuberosity)
    }

    /// The knee similar to this one by `factor` about the flexion axis (the origin):
    /// every length and every point times `factor`.
    pub fn scaled(&self, factor: f64) -> Self {
        let [gx, gy] = self.groove_centre;
        Self {
            condyle_radius: factor * self.condyle_radius,
            joint_line: factor * self.joint_line,
            groove_centre: [factor * gx, factor * gy],
            groove_radius: factor * self.groove_radius,
            patella_semi_axes: self.patella_semi_axes.map(|s| factor * s),
            apex: factor * self.apex,
            tuberosity: factor * self.tuberosity,
            patellar_tendon_length: factor * self.patellar_tendon_length,
            tendon_wrap_offset: factor * self.tendon_wrap_offset,
            hip_centre: factor * self.hip_centre,
            ankle: factor * self.ankle,
            rollback: self.rollback.scaled(factor),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_procedural_knees_dimensions_are_the_constants() {
        let knee = KneeDimensions::procedural_knee();
        assert_eq!(knee.anterior_femur(), ANTERIOR_FEMUR);
        assert_eq!(knee.patella_ridge_radius(), PATELLA_RIDGE_RADIUS);
        assert_eq!(knee.scaled(1.0), knee);
    }
}
