//! The added mass of mass scaling, carried by a moving frame without its inertia.
//!
//! Mass scaling raises each node's mass from m to m + Δm so that the explicit step can be
//! longer. On a model that rides on a moving body (the knee's muscles on the femur in the
//! closed-chain squat) the added mass then also feels the body's acceleration: a node
//! carried by the frame Q(t) needs the force (m + Δm) a_Q to follow it, where only m a_Q
//! is physical. With the knee's Δm ≈ 100 m the vasti's inertia at the turn of the squat
//! (a_Q ≈ 1.5 m/s²) is tens of newtons, as large as their passive pull on the patella.
//!
//! With a carrier frame the added mass is given the frame's acceleration as a body force,
//!
//!   f_i = Δm_i a_Q(x_i, t),   a_Q(x, t) = ∂²/∂t² [Q(t) X] at X = Q(t)⁻¹ x,
//!
//! so that its equation of motion, (m + Δm) ẍ = f_int + f_ext + Δm a_Q, keeps the added
//! mass's inertia for motion relative to the frame only (deformation, sliding), where
//! the mass-scaled step needs it, and gives the physical mass alone the frame's
//! acceleration. A node that moves with the frame then carries exactly its physical
//! inertia. The force is an external load: it enters the reactions and the external
//! work of the energy balance. a_Q is the central second difference of the frame's pose
//! over [`FRAME_DIFFERENCE_STEP`] (a forward one at the start), exact to round-off for
//! the smooth motions of a squat; at a kink of a piecewise-linear amplitude it is the
//! kink's impulse spread over the difference step.

use nalgebra::{Isometry3, Point3, Vector3};

use super::RigidMotion;

/// Time step of the second difference of the frame's pose [s].
pub const FRAME_DIFFERENCE_STEP: f64 = 1e-4;

/// The added masses Δm_i and the frame that carries them.
pub(super) struct AddedMassFrame<'a> {
    frame: &'a RigidMotion,
    added: Vec<f64>,
}

impl<'a> AddedMassFrame<'a> {
    /// Δm_i = scaled − physical mass of each node [kg].
    pub fn new(frame: &'a RigidMotion, physical: &[f64], scaled: &[f64]) -> Self {
        let added = (scaled.iter().zip(physical))
            .map(|(s, p)| (s - p).max(0.0))
            .collect();
        Self { frame, added }
    }

    /// Add f_i = Δm_i a_Q(x_i, t) [N] to `force`, with the nodes at `positions` [m].
    pub fn add_forces(&self, time: f64, positions: &[Vector3<f64>], force: &mut [Vector3<f64>]) {
        let h = FRAME_DIFFERENCE_STEP;
        // Three poses Q_k at the times of the second difference, and Q(t)⁻¹.
        let times = if time >= h {
            [time - h, time, time + h]
        } else {
            [time, time + h, time + 2.0 * h]
        };
        let poses: [Isometry3<f64>; 3] = times.map(|t| self.frame.isometry_at(t));
        let now_inverse = self.frame.isometry_at(time).inverse();
        for ((f, x), &dm) in force.iter_mut().zip(positions).zip(&self.added) {
            if dm == 0.0 {
                continue;
            }
            let body = now_inverse.transform_point(&Point3::from(*x));
            let [a, b, c] = poses.map(|q| q.transform_point(&body).coords);
            *f += dm * (a - 2.0 * b + c) / (h * h);
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use nalgebra::{Translation3, UnitQuaternion};

    use super::*;
    use crate::solver::PoseFollower;

    /// A frame turning about z through the origin by φ(t) = t² rad while it moves along
    /// x by s(t) = 0.1 t³ m.
    #[derive(Debug)]
    struct Turning;

    impl PoseFollower for Turning {
        fn isometry_at(&self, time: f64) -> Isometry3<f64> {
            Isometry3::from_parts(
                Translation3::new(0.1 * time.powi(3), 0.0, 0.0),
                UnitQuaternion::from_axis_angle(&Vector3::z_axis(), time * time),
            )
        }
        fn reference_point(&self) -> Vector3<f64> {
            Vector3::zeros()
        }
    }

    /// The acceleration of the frame-fixed point at radius r and polar angle φ(t) + α:
    /// r φ̈ ê_φ − r φ̇² ê_r + s̈ ê_x.
    fn closed_form(time: f64, r: f64, alpha: f64) -> (Vector3<f64>, Vector3<f64>) {
        let angle = time * time + alpha;
        let radial = Vector3::new(angle.cos(), angle.sin(), 0.0);
        let tangential = Vector3::new(-angle.sin(), angle.cos(), 0.0);
        let position = r * radial + Vector3::new(0.1 * time.powi(3), 0.0, 0.25);
        let acceleration =
            r * 2.0 * tangential - r * (2.0 * time).powi(2) * radial + Vector3::x() * 0.6 * time;
        (position, acceleration)
    }

    #[test]
    fn a_node_on_the_frame_gets_its_added_mass_times_the_frames_acceleration() {
        let frame = RigidMotion::followed(Arc::new(Turning));
        // Node 0 has 2 kg added, node 1 none.
        let carrier = AddedMassFrame::new(&frame, &[1.0, 2.0], &[3.0, 2.0]);
        // At the start (forward difference) and later (central).
        for (time, r, alpha) in [(0.0, 0.5, 0.3), (0.7, 0.4, -1.1), (1.3, 0.2, 2.0)] {
            let (x, acceleration) = closed_form(time, r, alpha);
            let mut force = vec![Vector3::new(1.0, 0.0, 0.0); 2];
            carrier.add_forces(time, &[x, x], &mut force);
            let expected = Vector3::new(1.0, 0.0, 0.0) + 2.0 * acceleration;
            // Central: O(h²) with h = 0.1 ms; forward: O(h).
            let tolerance = if time < FRAME_DIFFERENCE_STEP {
                1e-3
            } else {
                1e-6
            };
            assert!(
                (force[0] - expected).norm() < tolerance * expected.norm(),
                "t = {time}: {:?} against {expected:?}",
                force[0]
            );
            assert_eq!(force[1], Vector3::new(1.0, 0.0, 0.0));
        }
    }
}
