//! Loads and kinematic constraints shared by both solvers: prescribed displacement
//! components, nodal forces, and nodes tied to a rigid body whose motion (translation and
//! rotation about an axis) is prescribed.
//!
//! Every constrained component ends up as a target displacement ū(t) on (node, component);
//! when several conditions name the same component the last one wins, in the order
//! displacements, then rigid ties (each list in its order).

use nalgebra::Vector3;

use musclefem_materials::Amplitude;

use super::SolverError;
use super::rigid_motion::RigidMotion;

/// Displacement component `dof` (0 = x, 1 = y, 2 = z) of `nodes` follows `amplitude`
/// (displacement [m] against time [s]).
#[derive(Debug, Clone)]
pub struct PrescribedDisplacement {
    pub nodes: Vec<u32>,
    pub dof: usize,
    pub amplitude: Amplitude,
}

/// A force on component `dof` of every node of `nodes`, `amplitude` giving the force per
/// node [N] against time [s] (a dead load: its direction does not follow the body).
#[derive(Debug, Clone)]
pub struct NodalForce {
    pub nodes: Vec<u32>,
    pub dof: usize,
    pub amplitude: Amplitude,
}

/// Nodes that move with a rigid body: each node follows `motion`, x(t) = c + R(t)(X − c)
/// + T(t), so its displacement is u = x − X. Every component of the nodes is held.
#[derive(Debug, Clone)]
pub struct RigidTie {
    /// Name used in messages and histories.
    pub name: String,
    pub nodes: Vec<u32>,
    pub motion: RigidMotion,
}

impl RigidTie {
    /// Nodes held in place (no translation, no rotation).
    pub fn fixed(name: &str, nodes: Vec<u32>) -> Self {
        RigidTie {
            name: name.to_string(),
            nodes,
            motion: RigidMotion::fixed(),
        }
    }
}

/// Resultant reaction of a rigid tie: the force the body exerts on the tied nodes' support,
/// i.e. the sum of the nodal reactions [N], and their moment about the body's current
/// reference point c + T(t) [N m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidReaction {
    pub force: Vector3<f64>,
    pub moment: Vector3<f64>,
}

/// Everything applied to a model besides its parts.
#[derive(Debug, Clone, Default)]
pub struct Loads {
    pub displacements: Vec<PrescribedDisplacement>,
    pub forces: Vec<NodalForce>,
    pub rigid_ties: Vec<RigidTie>,
}

impl From<Vec<PrescribedDisplacement>> for Loads {
    fn from(displacements: Vec<PrescribedDisplacement>) -> Self {
        Loads {
            displacements,
            ..Loads::default()
        }
    }
}

impl Loads {
    /// Checks components and node ids against a mesh of `node_count` nodes.
    pub fn validate(&self, node_count: usize) -> Result<(), SolverError> {
        let bad = |what: String| Err(SolverError::InvalidBoundaryCondition(what));
        let check_nodes =
            |what: &str, nodes: &[u32]| match nodes.iter().find(|&&n| n as usize >= node_count) {
                Some(n) => bad(format!(
                    "{what}: node {n} does not exist (the mesh has {node_count})"
                )),
                None => Ok(()),
            };
        for (i, bc) in self.displacements.iter().enumerate() {
            if bc.dof > 2 {
                return bad(format!(
                    "prescribed displacement {i}: component {} is not 0, 1 or 2",
                    bc.dof
                ));
            }
            check_nodes(&format!("prescribed displacement {i}"), &bc.nodes)?;
        }
        for (i, load) in self.forces.iter().enumerate() {
            if load.dof > 2 {
                return bad(format!(
                    "nodal force {i}: component {} is not 0, 1 or 2",
                    load.dof
                ));
            }
            check_nodes(&format!("nodal force {i}"), &load.nodes)?;
        }
        for tie in &self.rigid_ties {
            check_nodes(&format!("rigid tie '{}'", tie.name), &tie.nodes)?;
            if !tie.motion.is_finite() {
                return bad(format!(
                    "rigid tie '{}': the rotation axis and centre must be finite",
                    tie.name
                ));
            }
        }
        Ok(())
    }

    /// Whether each degree of freedom 3 node + component is constrained.
    pub fn constrained_components(&self, node_count: usize) -> Vec<bool> {
        let mut held = vec![false; 3 * node_count];
        for bc in &self.displacements {
            for &n in &bc.nodes {
                held[3 * n as usize + bc.dof] = true;
            }
        }
        for tie in &self.rigid_ties {
            for &n in &tie.nodes {
                held[3 * n as usize..3 * n as usize + 3].fill(true);
            }
        }
        held
    }

    /// Target displacements ū(t) [m] of the constrained components, written into
    /// `target[3 node + component]` (other entries untouched). `reference` holds the
    /// nodes' reference positions.
    pub fn prescribed_displacements(
        &self,
        time: f64,
        reference: &[Vector3<f64>],
        target: &mut [f64],
    ) {
        for bc in &self.displacements {
            let value = bc.amplitude.value_at(time);
            for &n in &bc.nodes {
                target[3 * n as usize + bc.dof] = value;
            }
        }
        for tie in &self.rigid_ties {
            // The body's pose once per tie, not per node (a follower's pose takes a lock).
            let pose = tie.motion.isometry_at(time);
            for &n in &tie.nodes {
                let x = reference[n as usize];
                let u = pose.transform_point(&x.into()).coords - x;
                target[3 * n as usize..3 * n as usize + 3].copy_from_slice(u.as_slice());
            }
        }
    }

    /// External nodal forces f_ext(t) [N], overwriting `force`.
    pub fn external_forces(&self, time: f64, force: &mut [Vector3<f64>]) {
        force.fill(Vector3::zeros());
        for load in &self.forces {
            let value = load.amplitude.value_at(time);
            for &n in &load.nodes {
                force[n as usize][load.dof] += value;
            }
        }
    }

    /// Whether any nodal force is applied.
    pub fn has_forces(&self) -> bool {
        !self.forces.is_empty()
    }

    /// Reaction of each prescribed displacement: `reaction` (per node, zero where free)
    /// summed over its nodes in its direction [N].
    pub fn displacement_reactions(&self, reaction: &[Vector3<f64>]) -> Vec<f64> {
        self.displacements
            .iter()
            .map(|bc| bc.nodes.iter().map(|&n| reaction[n as usize][bc.dof]).sum())
            .collect()
    }

    /// Resultant force and moment of each rigid tie from the nodal `reaction` [N] at the
    /// nodes' current `positions` [m].
    pub fn rigid_reactions(
        &self,
        time: f64,
        positions: &[Vector3<f64>],
        reaction: &[Vector3<f64>],
    ) -> Vec<RigidReaction> {
        self.rigid_ties
            .iter()
            .map(|tie| {
                let point = tie.motion.reference_point_at(time);
                let mut resultant = RigidReaction {
                    force: Vector3::zeros(),
                    moment: Vector3::zeros(),
                };
                for &n in &tie.nodes {
                    let r = reaction[n as usize];
                    resultant.force += r;
                    resultant.moment += (positions[n as usize] - point).cross(&r);
                }
                resultant
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(value: f64) -> Amplitude {
        Amplitude::ramp(1.0, value).unwrap()
    }

    #[test]
    fn later_conditions_win_and_ties_hold_every_component() {
        let loads = Loads {
            displacements: vec![PrescribedDisplacement {
                nodes: vec![0, 1],
                dof: 1,
                amplitude: ramp(2.0),
            }],
            forces: vec![],
            rigid_ties: vec![RigidTie::fixed("base", vec![1])],
        };
        let reference = vec![Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0)];
        let mut target = vec![f64::NAN; 6];
        loads.prescribed_displacements(0.5, &reference, &mut target);
        assert_eq!(target[1], 1.0);
        assert!(target[0].is_nan() && target[2].is_nan());
        assert_eq!(&target[3..], &[0.0, 0.0, 0.0]);
        assert_eq!(
            loads.constrained_components(2),
            vec![false, true, false, true, true, true]
        );
    }

    #[test]
    fn bad_components_and_nodes_are_refused_with_the_condition_named() {
        let mut loads = Loads::default();
        loads.forces.push(NodalForce {
            nodes: vec![7],
            dof: 0,
            amplitude: ramp(1.0),
        });
        let message = loads.validate(3).unwrap_err().to_string();
        assert!(
            message.contains("nodal force 0") && message.contains("node 7"),
            "{message}"
        );
        loads.forces[0].nodes = vec![1];
        loads.forces[0].dof = 3;
        let message = loads.validate(3).unwrap_err().to_string();
        assert!(message.contains("component 3"), "{message}");
    }

    #[test]
    fn the_moment_of_a_tie_is_taken_about_its_moving_reference_point() {
        let tie = RigidTie {
            name: "b".into(),
            nodes: vec![0, 1],
            motion: RigidMotion {
                translation: [None, Some(ramp(1.0)), None],
                rotation: None,
                follower: None,
            },
        };
        let loads = Loads {
            rigid_ties: vec![tie],
            ..Loads::default()
        };
        let positions = vec![Vector3::new(1.0, 1.0, 0.0), Vector3::new(-1.0, 1.0, 0.0)];
        let reaction = vec![Vector3::new(0.0, 2.0, 0.0), Vector3::new(0.0, -2.0, 0.0)];
        let r = loads.rigid_reactions(1.0, &positions, &reaction)[0];
        assert_eq!(r.force, Vector3::zeros());
        // A couple: (1,0,0)×(0,2,0) + (−1,0,0)×(0,−2,0) = 4 e_z.
        assert!((r.moment - Vector3::new(0.0, 0.0, 4.0)).norm() < 1e-15);
    }
}
