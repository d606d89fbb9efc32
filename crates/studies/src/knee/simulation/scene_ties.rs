//! The squat's bone ties as a scene's `[[rigid_ties]]` (issue 30, step 4): each muscle's
//! origin on the femur (the vasti) or pinned to the pelvis at the centre of its nodes
//! (the rectus femoris), each insertion on the patella, with the knee's follower kinds
//! ([`super::followers`]). A tie names the part (block) that holds its node set.
//!
//! With the parts on `muscles.inp`'s blocks sharing its nodes (`shared_nodes = true`)
//! the ties hold the knee's own nodes (`super::scene_tests`).

use std::fmt::Write as _;

use anyhow::{Result, bail};
use nalgebra::Vector3;

use super::followers::{closed_chain_motion, patella_motion};
use super::model::KneeGeometry;
use super::scene_files::PATELLA_TABLE_CSV;
use crate::knee::anatomy::Quadriceps;
use crate::knee::anatomy::squat::Bone;

/// The block of `geometry`'s mesh that holds every node of node set `set` (the first,
/// in block order). A set of nodes in no element (a strands' attachment) comes with
/// every part sharing `muscles.inp`: the first block.
fn block_holding(geometry: &KneeGeometry, set: &str) -> Result<String> {
    let nodes = geometry.mesh.node_set(set)?;
    let mut in_an_element = vec![false; geometry.mesh.node_count()];
    for block in &geometry.mesh.blocks {
        let mut held = vec![false; geometry.mesh.node_count()];
        for &n in &block.connectivity {
            held[n as usize] = true;
            in_an_element[n as usize] = true;
        }
        if nodes.iter().all(|&n| held[n as usize]) {
            return Ok(block.name.clone());
        }
    }
    if nodes.iter().all(|&n| !in_an_element[n as usize]) {
        return Ok(geometry.block_name(0).to_string());
    }
    bail!("no block of the knee's mesh holds every node of '{set}'")
}

/// The `motion` table of `geometry`'s patella on `patella_table.csv`: the insertions'
/// and the patella's rigid body's (one table, so one follower that moves them all).
pub fn knee_patella_motion(geometry: &KneeGeometry) -> String {
    patella_motion(
        PATELLA_TABLE_CSV,
        geometry.patella_table.tendon(),
        &geometry.motions.chain,
        &geometry.motions.squat,
    )
}

/// The `[[rigid_ties]]` entries of `geometry`'s squat: `<abbreviation>_origin` and
/// `<abbreviation>_insertion` per muscle, as [`super::model::KneeModel`] names them.
pub fn knee_tie_entries(geometry: &KneeGeometry) -> Result<String> {
    let (chain, squat) = (&geometry.motions.chain, &geometry.motions.squat);
    let patella = knee_patella_motion(geometry);
    let mut text = String::new();
    for (b, muscle) in geometry.muscles.iter().enumerate() {
        let name = geometry.block_name(b);
        let origin = match muscle {
            // The centre of the origin's nodes, as `KneeGeometry::origin_motion` takes it.
            Quadriceps::RectusFemoris => {
                let nodes = geometry.end_nodes(b, "origin")?;
                let centre = nodes
                    .iter()
                    .map(|&n| geometry.mesh.nodes.position(n as usize))
                    .sum::<Vector3<f64>>()
                    / nodes.len() as f64;
                closed_chain_motion(Bone::PelvisPin(centre), chain, squat)
            }
            _ => closed_chain_motion(Bone::Femur, chain, squat),
        };
        for (end, motion) in [("origin", &origin), ("insertion", &patella)] {
            let set = format!("{name}_{end}");
            let _ = writeln!(
                text,
                "[[rigid_ties]]\nname = \"{}_{end}\"\npart = {:?}\nnodes = {set:?}\nmotion = \
                 {motion}\n",
                muscle.abbreviation(),
                block_holding(geometry, &set)?,
            );
        }
    }
    Ok(text)
}
