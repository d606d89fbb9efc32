//! `musclefem knee --anatomy visible-human`: the squat on the Visible Human Female's
//! segmented quadriceps ([`crate::knee::anatomy::visible_human`]): its tet10 meshes, its
//! femur (shaft and distal cartilage), tibia and patella, the mechanism on its landmarks,
//! and tendon strands from the muscles' fiber outlets to the patella.

use std::sync::Arc;

use anyhow::{Context, Result, bail};

use super::super::anatomy::visible_human::{MeshResolution, VisibleHumanKnee, mechanism};
use super::super::anatomy::{Resolution, Squat, TendonSpring};
use super::model::{KneeGeometry, PASSIVE_SLACK_FLEXION};
use super::patella::PatellaTable;

/// The name `--anatomy` takes for the Visible Human knee.
pub const VISIBLE_HUMAN: &str = "visible-human";

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
        passive_slack: vec![1.0; knee.muscles.len()],
        patella_table: Arc::new(patella_table),
        strands: knee.strands.clone(),
        dimensions: kinematics.dimensions,
    };
    geometry.name_outer_surfaces()?;
    let fibers = geometry.fibers()?;
    let pennation = (0..knee.muscles.len())
        .map(|b| {
            let block = musclefem_core::mesh::Mesh::new(
                knee.mesh.nodes.clone(),
                vec![knee.mesh.blocks[b].clone()],
            );
            super::super::anatomy::visible_human::mean_pennation(&block, fibers.block_directions(b))
        })
        .collect::<Result<Vec<_>>>()?;
    geometry.passive_slack =
        mechanism::passive_slack(&knee, &kinematics, &pennation, PASSIVE_SLACK_FLEXION)?;
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
        println!("passive slack λ_PE: {:.4?}", geometry.passive_slack);
        for &slack in &geometry.passive_slack {
            assert!((1.0..1.5).contains(&slack), "{slack}");
        }
        let error = visible_human_geometry(Resolution::Fine, &squat).unwrap_err();
        assert!(format!("{error:#}").contains("not fine"));
    }
}
