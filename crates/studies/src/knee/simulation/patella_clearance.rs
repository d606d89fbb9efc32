//! How close the muscles come to the patella. The patella has no contact surface (the
//! muscles' insertions are tied to it), so every recorded instant measures the signed
//! distance of every muscle node not tied to it from the patella's surface at its pose
//! then (negative inside), and the run reports the closest approach: the measured case
//! for (or against) adding patellar contact.

use anyhow::Result;
use nalgebra::{Isometry3, Vector3};

use musclefem_contact::project_on_triangle;

use super::model::KneeGeometry;
use crate::knee::Quadriceps;
use crate::knee::anatomy::TriangleSurface;

/// Nodes farther than this from the patella's bounding box are not measured [m].
pub const CLEARANCE_RANGE: f64 = 0.01;

/// The closest a muscle node came to the patella.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatellaApproach {
    /// Signed distance from the node to the patella's surface, negative inside [m].
    pub distance: f64,
    /// When [s].
    pub time: f64,
    pub muscle: Quadriceps,
    /// The node (muscles' mesh numbering).
    pub node: usize,
}

/// The patella's surface at its reference pose and the nodes checked against it.
pub struct PatellaClearance {
    surface: TriangleSurface,
    lower: Vector3<f64>,
    upper: Vector3<f64>,
    /// Every muscle node not tied to the patella, with its muscle.
    nodes: Vec<(usize, Quadriceps)>,
    /// The closest approach so far (`None`: no node came within [`CLEARANCE_RANGE`] of
    /// the patella's bounding box).
    pub closest: Option<PatellaApproach>,
}

impl PatellaClearance {
    /// The patella of `geometry` and its muscles' nodes, less the insertions'.
    pub fn new(geometry: &KneeGeometry) -> Result<Self> {
        let mut nodes = Vec::new();
        for (b, &muscle) in geometry.muscles.iter().enumerate() {
            let insertion: Vec<usize> = geometry
                .end_nodes(b, "insertion")?
                .into_iter()
                .map(|n| n as usize)
                .collect();
            // The muscle's belly and tendons.
            let mut block_nodes: Vec<usize> = geometry
                .roles
                .iter()
                .enumerate()
                .filter(|(_, role)| role.muscle == muscle)
                .flat_map(|(block, _)| geometry.mesh.blocks[block].elements().flatten())
                .map(|&n| n as usize)
                .collect();
            block_nodes.sort_unstable();
            block_nodes.dedup();
            nodes.extend(
                block_nodes
                    .into_iter()
                    .filter(|n| !insertion.contains(n))
                    .map(|n| (n, muscle)),
            );
        }
        let (lower, upper) = geometry.patella.bounds();
        let range = Vector3::repeat(CLEARANCE_RANGE);
        Ok(PatellaClearance {
            surface: geometry.patella.clone(),
            lower: lower - range,
            upper: upper + range,
            nodes,
            closest: None,
        })
    }

    /// Checks the nodes at `time` [s], at `position(node)` [m], against the patella moved
    /// by `motion` from its reference pose.
    pub fn check(
        &mut self,
        time: f64,
        motion: &Isometry3<f64>,
        position: impl Fn(usize) -> Vector3<f64>,
    ) {
        let inverse = motion.inverse();
        for &(node, muscle) in &self.nodes {
            // In the patella's reference pose.
            let x = inverse * nalgebra::Point3::from(position(node));
            let x = x.coords;
            if (0..3).any(|i| x[i] < self.lower[i] || x[i] > self.upper[i]) {
                continue;
            }
            let unsigned = (0..self.surface.triangles.len())
                .map(|t| project_on_triangle(&x, &self.surface.corners(t)).gap.abs())
                .fold(f64::INFINITY, f64::min);
            let distance = if self.surface.contains(&x) {
                -unsigned
            } else {
                unsigned
            };
            if self.closest.is_none_or(|c| distance < c.distance) {
                self.closest = Some(PatellaApproach {
                    distance,
                    time,
                    muscle,
                    node,
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::knee::anatomy::{Anatomy, Resolution, Squat};

    #[test]
    fn a_node_inside_the_moved_patella_is_found_at_its_depth() {
        let anatomy = Anatomy::procedural_knee(Resolution::Coarse).unwrap();
        let geometry = KneeGeometry::procedural_knee(&anatomy, &Squat::to_ninety_degrees(2.0))
            .expect("the procedural knee");
        let rest = |n: usize| geometry.mesh.nodes.position(n);
        // At rest every node but the insertions' is outside the patella.
        let mut clearance = PatellaClearance::new(&geometry).unwrap();
        clearance.check(0.0, &Isometry3::identity(), rest);
        let closest = clearance.closest.expect("nodes near the patella");
        assert!(closest.distance > 0.0, "{closest:?}");
        // Move the patella so that its centre lands on a muscle node (not an insertion's).
        let (node, muscle) = clearance.nodes[0];
        let (lower, upper) = geometry.patella.bounds();
        let centre = 0.5 * (lower + upper);
        assert!(geometry.patella.contains(&centre));
        let depth = (0..geometry.patella.triangles.len())
            .map(|t| {
                project_on_triangle(&centre, &geometry.patella.corners(t))
                    .gap
                    .abs()
            })
            .fold(f64::INFINITY, f64::min);
        let motion = Isometry3::translation(
            rest(node).x - centre.x,
            rest(node).y - centre.y,
            rest(node).z - centre.z,
        );
        let mut clearance = PatellaClearance::new(&geometry).unwrap();
        clearance.check(0.5, &motion, rest);
        let closest = clearance.closest.unwrap();
        assert_eq!(
            (closest.node, closest.muscle, closest.time),
            (node, muscle, 0.5)
        );
        assert!(
            (closest.distance + depth).abs() < 1e-12,
            "{closest:?} vs {depth}"
        );
    }
}
