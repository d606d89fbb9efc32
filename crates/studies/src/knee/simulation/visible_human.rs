//! `musclefem knee --anatomy visible-human`: the squat on the Visible Human Female's
//! segmented quadriceps ([`crate::knee::anatomy::visible_human`]): its tet10 meshes, its
//! femur (shaft and distal cartilage), tibia and patella, the mechanism on its landmarks,
//! and tendon strands from the muscles' fiber outlets to the patella.

use std::sync::Arc;

use anyhow::{Context, Result, bail};

use super::super::anatomy::visible_human::tracking::PatellaTracking;
use super::super::anatomy::visible_human::{MeshResolution, VisibleHumanKnee, mechanism};
use super::super::anatomy::{Quadriceps, Resolution, Squat, TendonSpring};
use super::model::{FiberReference, KneeGeometry};
use super::patella::PatellaTable;

/// The name `--anatomy` takes for the Visible Human knee.
pub const VISIBLE_HUMAN: &str = "visible-human";

/// The fiber stretch λ_r from the mesh's pose (0° of flexion) at which a muscle's relaxed
/// fibers are at the paper's rest length: the median isochoric fiber stretch of its
/// elements at 50° of flexion in the coarse passive squat (explicit, 2026-11-27, with the
/// paper's laws referenced to 0°; interpolated between its frames at 45.0° and 58.9°).
///
/// Why: the paper's laws (matrix, parallel element, force–length) are referenced to the
/// test specimen's rest length, near optimal. The segmentation's pose, 0°, is shorter:
/// resting vastus lateralis sarcomeres are near optimal length at 50° of flexion (Chen,
/// Sanchez, Schnitzer & Delp 2016, J Biomech 49:2989: 2.84 µm at 50°, 3.17 µm at 110°),
/// and its fascicles lengthen from 97 to 133 mm between full extension and 110° (Fukunaga
/// et al. 1997, J Appl Physiol 82:354). With the laws referenced to 0°, the squat's
/// fibers (median 1.19, 95th percentile 1.31 at 90°) met the paper's exponential matrix
/// beyond its calibrated range: 0.77 MPa passive vm95 in the vastus medialis, several
/// times what relaxed muscle carries. The rule is the same for the rectus femoris, which
/// stays nearly isometric in the squat (its hip flexes with the knee).
pub fn fiber_rest_stretch(muscle: Quadriceps) -> f64 {
    match muscle {
        Quadriceps::VastusIntermedius => 1.122,
        Quadriceps::VastusLateralis => 1.140,
        Quadriceps::VastusMedialis => 1.153,
        Quadriceps::RectusFemoris => 1.028,
    }
}

/// The committed meshes of `resolution` (coarse and medium; fine is not committed).
pub fn mesh_resolution(resolution: Resolution) -> Result<MeshResolution> {
    Ok(match resolution {
        Resolution::Coarse => MeshResolution::Coarse,
        Resolution::Medium => MeshResolution::Medium,
        Resolution::Fine => bail!(
            "--anatomy {VISIBLE_HUMAN} has coarse and medium meshes (target edge 9 and 6 mm), \
             not fine"
        ),
    })
}

/// The squat's geometry on the Visible Human knee at `resolution`, squatting `squat`.
pub fn visible_human_geometry(resolution: Resolution, squat: &Squat) -> Result<KneeGeometry> {
    let knee =
        VisibleHumanKnee::load(mesh_resolution(resolution)?).context("the Visible Human knee")?;
    let kinematics = mechanism::kinematics(&knee)?;
    let motions = squat
        .motions(&mechanism::closed_chain(&knee)?)
        .context("the squat's bone motions")?;
    let patella_table = PatellaTable::new(
        &kinematics,
        TendonSpring::from_dimensions(&kinematics.dimensions),
        squat.peak_flexion,
    )
    .context("the patella's poses with the tendon stretched")?;
    let mut geometry = KneeGeometry {
        mesh: knee.mesh.clone(),
        muscles: knee.muscles.clone(),
        roles: knee.roles.clone(),
        femur: knee.femur.clone(),
        femur_normals: None,
        tibia: knee.tibia.clone(),
        patella: knee.patella.clone(),
        motions,
        fiber_reference: (knee.muscles.iter())
            .map(|&m| FiberReference::rest_at(fiber_rest_stretch(m)))
            .collect(),
        patella_table: Arc::new(patella_table),
        strands: knee.strands.clone(),
        dimensions: kinematics.dimensions,
        patella_tracking: Some(
            PatellaTracking::of_visible_human(&knee, &kinematics, squat.peak_flexion)
                .context("the patella's tracking in the trochlear groove")?,
        ),
    };
    geometry.name_outer_surfaces()?;
    Ok(geometry)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_visible_human_geometry_builds_with_strands_and_slack() {
        let squat = Squat::to_ninety_degrees(2.0);
        let geometry = visible_human_geometry(Resolution::Coarse, &squat).unwrap();
        assert_eq!(geometry.muscles.len(), 4);
        assert!(!geometry.strands.is_empty());
        for (reference, &muscle) in geometry.fiber_reference.iter().zip(&geometry.muscles) {
            let rest = fiber_rest_stretch(muscle);
            assert!((1.0..1.2).contains(&rest), "{muscle:?}: {rest}");
            assert_eq!(reference.matrix_slack, rest);
            assert_eq!(reference.parallel_slack, rest);
            assert_eq!(reference.optimal_stretch, 1.05 * rest);
        }
        let error = visible_human_geometry(Resolution::Fine, &squat).unwrap_err();
        assert!(format!("{error:#}").contains("not fine"));
    }
}
