//! The Visible Human knee's mechanism: the default knee's planar tibiofemoral and
//! patellofemoral model ([`super::super::kinematics`]) on the Visible Human's landmarks,
//! and each muscle's line of action, from which its moment arm and its passive slack
//! follow.
//!
//! **Dimensions** ([`dimensions`]). In the knee frame of [`super::landmarks`]: the
//! groove's circle and the tuberosity as fitted; the apex and the tuberosity at their
//! lateral offsets (the planar model keeps the patella's and the tibia's z, so the
//! patellar tendon's length is the 3-D apex–tuberosity distance in the data's pose); the
//! hip centre and the ankle pin as fitted; the condyle radius the mean of the two
//! condyles' spheres and the joint line 2 mm below it (as the default knee). The planar
//! model describes the patella by the ellipsoid whose sagittal osculating circle at its
//! posterior pole is its articular ridge: the fitted ridge radius ρ and the ridge
//! centre's distance d in front of the patella's centre (the bone's volume centroid)
//! give c = ρ − d and b = √(ρ c) (VHF: c = 13.1, b = 20.1 mm against the bone's half
//! thickness 11.9 and half height 22.6 mm). The patella's centre in the mechanism is the
//! point d behind the ridge centre at its height, so at 0° it lies within about a
//! millimetre of the centroid.
//!
//! **Lines of action** ([`pulls`]). Each muscle pulls the patella from the centroid of
//! its tendon strands' starts (its fiber outlets, weighted by their tributary areas) to
//! its attachment on the patella, weighted by its volume. A line of action cannot pass
//! through the femur: a release point behind the quadriceps tendon's wrapping surface
//! (the anterior femur x = x_g + r_g plus the wrap offset) is moved forward onto it (the
//! vastus intermedius's outlets lie on the lateral side of the femur, 23 mm in front of
//! the flexion axis).
//!
//! **Moment arms** ([`moment_arms_at`]). r = dL/dθ (central differences of
//! [`super::super::moment_arms::DIFFERENCE_STEP`]), L the length from the release point
//! to the attachment (wrapped over the trochlea) and on through the patellar tendon,
//! as for the default knee.
//!
//! **Passive slack** ([`passive_slack`]). As for the default knee, each muscle's parallel
//! element is slack up to the fiber stretch λ_PE its fibers reach at 60° of flexion in
//! the squat. The Visible Human's fibers are oblique and shorter than the muscle, so the
//! stretch is λ_PE = 1 + ΔL cos α / L_f: ΔL the musculotendon length change from 0° to
//! 60° (the hip flexing with the knee moves the rectus's origin, see
//! [`super::super::moment_arms::hip_length_change_in`]), α the mesh's mean fiber angle to
//! the muscle's long axis, and L_f the fiber length that Ward, Eng, Smallwood & Lieber
//! (2009, Clin Orthop Relat Res 467:1074, Table 1, cadaveric) measured: VI 99.3, VL 99.4,
//! VM 96.8, RF 75.9 mm.

use anyhow::{Context, Result};
use nalgebra::Vector3;

use musclefem_core::mesh::ElementRef;

use super::super::dimensions::KneeDimensions;
use super::super::kinematics::{KneeKinematics, PatellaPose, QuadricepsPull, flexion_rotation};
use super::super::moment_arms::DIFFERENCE_STEP;
use super::super::path::free_path;
use super::super::{ClosedChain, Quadriceps};
use super::knee::{VisibleHumanKnee, patellar_tendon_length};

/// Fiber length L_f [m] of each muscle (Ward et al. 2009, Table 1).
pub fn fiber_length(muscle: Quadriceps) -> f64 {
    1e-3 * match muscle {
        Quadriceps::VastusIntermedius => 99.3,
        Quadriceps::VastusLateralis => 99.4,
        Quadriceps::VastusMedialis => 96.8,
        Quadriceps::RectusFemoris => 75.9,
    }
}

/// Height of the tibial plateau below the condyles' circle [m], as the default knee's
/// (cartilage and menisci left out of the rigid bones).
const JOINT_GAP: f64 = 0.002;

/// The patella's centre in the knee frame at 0° [m] (see the module documentation).
pub fn patella_centre(knee: &VisibleHumanKnee) -> Vector3<f64> {
    let landmarks = &knee.landmarks;
    let ridge = landmarks.in_knee_frame(&landmarks.patellar_ridge);
    let centroid = knee.patella.volume_centroid();
    Vector3::new(centroid.x, ridge.y, 0.0)
}

/// The mechanism's dimensions on the Visible Human (module documentation).
pub fn dimensions(knee: &VisibleHumanKnee) -> Result<KneeDimensions> {
    let landmarks = &knee.landmarks;
    let at = |l| landmarks.in_knee_frame(l);
    let groove = at(&landmarks.trochlear_groove);
    let ridge = at(&landmarks.patellar_ridge);
    let radius = |l: &super::Landmark| l.radius.context("a fitted circle without a radius");
    let rho = radius(&landmarks.patellar_ridge)?;
    let centre = patella_centre(knee);
    let c = rho - (ridge.x - centre.x);
    if !(c > 0.0 && c < rho) {
        anyhow::bail!(
            "the patella's ridge (radius {:.1} mm) and centroid give no ellipsoid: c = {:.1} mm",
            rho * 1e3,
            c * 1e3
        );
    }
    let b = (rho * c).sqrt();
    let width = {
        let (low, high) = knee.patella.bounds();
        high.z - low.z
    };
    let condyle_radius =
        0.5 * (radius(&landmarks.medial_condyle)? + radius(&landmarks.lateral_condyle)?);
    Ok(KneeDimensions {
        condyle_radius,
        joint_line: -(condyle_radius + JOINT_GAP),
        groove_centre: [groove.x, groove.y],
        groove_radius: radius(&landmarks.trochlear_groove)?,
        patella_semi_axes: [0.5 * width, b, c],
        apex: at(&landmarks.patella_apex) - centre,
        tuberosity: at(&landmarks.tibial_tuberosity),
        patellar_tendon_length: patellar_tendon_length(landmarks),
        tendon_wrap_offset: KneeDimensions::default_knee().tendon_wrap_offset,
        hip_centre: at(&landmarks.femoral_head),
        ankle: at(&landmarks.ankle),
    })
}

/// Each muscle's line of action (module documentation), in [`Quadriceps::ALL`] order.
pub fn pulls(knee: &VisibleHumanKnee) -> Result<Vec<QuadricepsPull>> {
    let centre = patella_centre(knee);
    let dimensions = dimensions(knee)?;
    let front = dimensions.anterior_femur() + dimensions.tendon_wrap_offset;
    knee.muscles
        .iter()
        .enumerate()
        .map(|(b, &muscle)| {
            let volume = (0..knee.mesh.blocks[b].len() as u32)
                .map(|e| knee.mesh.element_volume(ElementRef::new(b as u32, e)))
                .sum::<Result<f64, _>>()?;
            let mut release = knee.outlet_centroid(muscle);
            release.x = release.x.max(front);
            Ok(QuadricepsPull {
                release,
                insertion: knee.attachment_point(muscle)? - centre,
                weight: volume,
            })
        })
        .collect()
}

/// The mechanism of the Visible Human knee.
pub fn kinematics(knee: &VisibleHumanKnee) -> Result<KneeKinematics> {
    Ok(KneeKinematics::from_dimensions(
        dimensions(knee)?,
        pulls(knee)?,
    ))
}

/// The closed chain of the squat on the Visible Human's hip and ankle.
pub fn closed_chain(knee: &VisibleHumanKnee) -> Result<ClosedChain> {
    Ok(ClosedChain::from_dimensions(&dimensions(knee)?))
}

/// Musculotendon length [m] of each pull with the patella at `patella`: release point to
/// attachment (wrapped over the trochlea), plus the patellar tendon.
pub fn lengths(kinematics: &KneeKinematics, patella: &PatellaPose) -> Vec<f64> {
    kinematics
        .pulls
        .iter()
        .map(|pull| {
            free_path(
                &pull.release,
                &patella.to_world(&pull.insertion),
                &kinematics.trochlea,
            )
            .length
                + kinematics.tendon_length
        })
        .collect()
}

/// The knee-extensor moment arms r = dL/dθ [m] of the pulls at knee flexion `angle` [rad].
pub fn moment_arms_at(kinematics: &KneeKinematics, angle: f64) -> Result<Vec<f64>> {
    let ahead = lengths(
        kinematics,
        &kinematics.patella_pose(angle + DIFFERENCE_STEP)?,
    );
    let behind = lengths(
        kinematics,
        &kinematics.patella_pose(angle - DIFFERENCE_STEP)?,
    );
    Ok(ahead
        .iter()
        .zip(&behind)
        .map(|(a, b)| (a - b) / (2.0 * DIFFERENCE_STEP))
        .collect())
}

/// How much the hip's flexion `hip` [rad] lengthens the rectus femoris [m]: its origin
/// (the centre of its origin nodes) turns with the pelvis about the hip centre, and the
/// line from it to the release point changes length. Zero for the vasti.
fn hip_length_change(
    knee: &VisibleHumanKnee,
    muscle: Quadriceps,
    hip_centre: &Vector3<f64>,
    hip: f64,
) -> Result<f64> {
    if muscle != Quadriceps::RectusFemoris {
        return Ok(0.0);
    }
    let nodes = knee.mesh.node_set(&format!("{}_origin", muscle.name()))?;
    let origin = nodes
        .iter()
        .map(|&n| knee.mesh.nodes.position(n as usize))
        .sum::<Vector3<f64>>()
        / nodes.len() as f64;
    let release = knee.outlet_centroid(muscle);
    let moved = hip_centre + flexion_rotation(hip) * (origin - hip_centre);
    Ok((moved - release).norm() - (origin - release).norm())
}

/// λ_PE of each muscle (module documentation): the fiber stretch at knee flexion `angle`
/// [rad] in the squat (hip flexion = knee flexion), at least 1, given each muscle's mean
/// fiber angle `pennation` [rad] to its long axis.
pub fn passive_slack(
    knee: &VisibleHumanKnee,
    kinematics: &KneeKinematics,
    pennation: &[f64],
    angle: f64,
) -> Result<Vec<f64>> {
    let extended = lengths(kinematics, &kinematics.patella_pose(0.0)?);
    let flexed = lengths(kinematics, &kinematics.patella_pose(angle)?);
    let hip = kinematics.dimensions.hip_centre;
    knee.muscles
        .iter()
        .enumerate()
        .map(|(m, &muscle)| {
            let change = flexed[m] - extended[m] + hip_length_change(knee, muscle, &hip, angle)?;
            Ok((1.0 + change * pennation[m].cos() / fiber_length(muscle)).max(1.0))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::MeshResolution;
    use super::*;

    #[test]
    fn the_mechanism_keeps_the_patella_where_the_data_has_it_in_extension() {
        let knee = VisibleHumanKnee::load(MeshResolution::Coarse).unwrap();
        let kinematics = kinematics(&knee).unwrap();
        let pose = kinematics.patella_pose(0.0).unwrap();
        let centre = patella_centre(&knee);
        let dims = &kinematics.dimensions;
        println!(
            "patella at 0°: centre {:.1?} mm (data {:.1?}), flexion {:.2}°; semi-axes {:.1?} mm; \
             tendon {:.1} mm",
            pose.centre * 1e3,
            centre * 1e3,
            pose.flexion.to_degrees(),
            dims.patella_semi_axes.map(|s| s * 1e3),
            dims.patellar_tendon_length * 1e3
        );
        for angle in [0.0_f64, 30.0, 60.0, 90.0] {
            let arms = moment_arms_at(&kinematics, angle.to_radians()).unwrap();
            let pose = kinematics.patella_pose(angle.to_radians()).unwrap();
            println!(
                "{angle}°: moment arms {:.1?} mm, patellar flexion {:.1}°",
                arms.iter().map(|r| r * 1e3).collect::<Vec<_>>(),
                pose.flexion.to_degrees()
            );
        }
        assert!((pose.centre.xy() - centre.xy()).norm() < 3e-3);
        assert!(pose.flexion.abs() < 5f64.to_radians());
    }
}
