//! The prescribed motion of a rigid body (a bone): translation and rotation about an axis,
//! shared by nodes tied to the body ([`super::RigidTie`]) and by rigid contact surfaces.
//! A body may instead follow a pose that the run sets as it goes ([`PoseFollower`]).

use std::fmt;
use std::sync::Arc;

use nalgebra::{Isometry3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3};

use musclefem_materials::Amplitude;

/// Rotation by `angle(t)` [rad] about the axis through `center` [m] along `axis`
/// (right-hand rule).
#[derive(Debug, Clone, PartialEq)]
pub struct RigidRotation {
    pub center: Vector3<f64>,
    pub axis: Unit<Vector3<f64>>,
    pub angle: Amplitude,
}

/// A pose that is not known before the run: the run updates it from the state (e.g. a
/// patella held by a tendon spring against the muscles' pull, which it hears through
/// [`PoseFollower::observe`]), and the solvers read it at the times they need.
/// Implementations must be cheap to evaluate and give the same pose for the same time
/// until an observation changes them.
pub trait PoseFollower: Send + Sync + fmt::Debug {
    /// The body's pose at `time` [s]: a point at reference position X is at iso · X.
    fn isometry_at(&self, time: f64) -> Isometry3<f64>;
    /// The body's reference point in the reference configuration [m]: the moments of
    /// the reactions are taken about its current position.
    fn reference_point(&self) -> Vector3<f64>;
    /// A recorded instant at `time` [s] with the reactions of the problem's rigid ties
    /// (in the order of `Loads::rigid_ties`): the solvers call this for every follower of
    /// a tie before the observer sees the instant, so a checkpoint taken there holds it.
    fn observe(&self, _time: f64, _tie_reactions: &[super::RigidReaction]) {}
    /// The follower's state for a checkpoint (nothing for a follower without one).
    fn save_state(&self, _out: &mut super::checkpoint::CheckpointWriter) {}
    /// The state [`PoseFollower::save_state`] wrote.
    fn restore_state(
        &self,
        _input: &mut super::checkpoint::CheckpointReader,
    ) -> Result<(), super::SolverError> {
        Ok(())
    }
}

/// The followers of `ties`, each once (ties may share one), in the order of their first
/// tie.
pub fn tie_followers(ties: &[super::RigidTie]) -> Vec<Arc<dyn PoseFollower>> {
    let mut followers: Vec<Arc<dyn PoseFollower>> = Vec::new();
    for follower in ties.iter().filter_map(|t| t.motion.follower.as_ref()) {
        if !followers.iter().any(|f| Arc::ptr_eq(f, follower)) {
            followers.push(follower.clone());
        }
    }
    followers
}

/// Tell every follower of `ties` of the recorded instant at `time`.
pub fn observe_followers(
    ties: &[super::RigidTie],
    time: f64,
    tie_reactions: &[super::RigidReaction],
) {
    for follower in tie_followers(ties) {
        follower.observe(time, tie_reactions);
    }
}

/// Write the states of the followers of `ties` (see [`tie_followers`]).
pub fn save_follower_states(
    ties: &[super::RigidTie],
    out: &mut super::checkpoint::CheckpointWriter,
) {
    let followers = tie_followers(ties);
    out.u64(followers.len() as u64);
    for follower in followers {
        let mut state = super::checkpoint::CheckpointWriter::new();
        follower.save_state(&mut state);
        out.bytes(&state.into_bytes());
    }
}

/// Restore what [`save_follower_states`] wrote into the followers of `ties`.
pub fn restore_follower_states(
    ties: &[super::RigidTie],
    input: &mut super::checkpoint::CheckpointReader,
) -> Result<(), super::SolverError> {
    let followers = tie_followers(ties);
    let count = input.u64()? as usize;
    if count != followers.len() {
        return Err(super::SolverError::Checkpoint(format!(
            "the checkpoint holds the states of {count} followers, the problem has {}",
            followers.len()
        )));
    }
    for follower in followers {
        let state = input.bytes()?;
        let mut reader = super::checkpoint::CheckpointReader::new(&state);
        follower.restore_state(&mut reader)?;
    }
    Ok(())
}

/// A point at reference position X goes to x(t) = c + R(t)(X − c) + T(t), with R the
/// rotation about the axis through c and T the translation, unless a `follower` sets
/// the pose instead: x(t) = follower(t) · X.
#[derive(Debug, Clone, Default)]
pub struct RigidMotion {
    /// Translation T(t) of each component [m]; `None` = 0.
    pub translation: [Option<Amplitude>; 3],
    /// Rotation; `None` = no rotation.
    pub rotation: Option<RigidRotation>,
    /// The pose set while the run goes, in place of the translation and rotation.
    pub follower: Option<Arc<dyn PoseFollower>>,
}

/// Two motions are equal when their translations and rotations are, and they follow the
/// same follower (the same object, not an equal one).
impl PartialEq for RigidMotion {
    fn eq(&self, other: &Self) -> bool {
        self.translation == other.translation
            && self.rotation == other.rotation
            && match (&self.follower, &other.follower) {
                (None, None) => true,
                (Some(a), Some(b)) => Arc::ptr_eq(a, b),
                _ => false,
            }
    }
}

impl RigidMotion {
    /// No motion at all.
    pub fn fixed() -> Self {
        Self::default()
    }

    /// A body whose pose `follower` sets.
    pub fn followed(follower: Arc<dyn PoseFollower>) -> Self {
        Self {
            translation: [None, None, None],
            rotation: None,
            follower: Some(follower),
        }
    }

    /// The reference point c in the reference configuration [m]: the follower's, else
    /// the centre of the rotation, else the origin.
    fn center(&self) -> Vector3<f64> {
        match (&self.follower, &self.rotation) {
            (Some(follower), _) => follower.reference_point(),
            (None, Some(rotation)) => rotation.center,
            (None, None) => Vector3::zeros(),
        }
    }

    /// The translation T(t) [m].
    pub fn translation_at(&self, time: f64) -> Vector3<f64> {
        if let Some(follower) = &self.follower {
            let center = self.center();
            return follower
                .isometry_at(time)
                .transform_point(&center.into())
                .coords
                - center;
        }
        Vector3::from_fn(|i, _| {
            self.translation[i]
                .as_ref()
                .map_or(0.0, |a| a.value_at(time))
        })
    }

    /// The rotation R(t).
    pub fn rotation_at(&self, time: f64) -> Rotation3<f64> {
        if let Some(follower) = &self.follower {
            return follower.isometry_at(time).rotation.to_rotation_matrix();
        }
        self.rotation
            .as_ref()
            .map_or_else(Rotation3::identity, |r| {
                Rotation3::from_axis_angle(&r.axis, r.angle.value_at(time))
            })
    }

    /// The current position of the body's reference point c: c + T(t) [m] (the
    /// follower's reference point, the centre of rotation, or the origin).
    pub fn reference_point_at(&self, time: f64) -> Vector3<f64> {
        self.center() + self.translation_at(time)
    }

    /// The motion at `time` as one isometry: x = iso · X.
    pub fn isometry_at(&self, time: f64) -> Isometry3<f64> {
        if let Some(follower) = &self.follower {
            return follower.isometry_at(time);
        }
        let rotation = self.rotation_at(time);
        let center = self.center();
        let shift = center - rotation * center + self.translation_at(time);
        Isometry3::from_parts(
            Translation3::from(shift),
            UnitQuaternion::from_rotation_matrix(&rotation),
        )
    }

    /// Position x(X, t) = c + R(t)(X − c) + T(t) [m] of the point at `reference`.
    pub fn position_at(&self, reference: &Vector3<f64>, time: f64) -> Vector3<f64> {
        if let Some(follower) = &self.follower {
            return follower
                .isometry_at(time)
                .transform_point(&(*reference).into())
                .coords;
        }
        let rotated = match &self.rotation {
            Some(r) => r.center + self.rotation_at(time) * (reference - r.center),
            None => *reference,
        };
        rotated + self.translation_at(time)
    }

    /// Displacement u(X, t) = x(X, t) − X [m] of the point at `reference`.
    pub fn displacement_at(&self, reference: &Vector3<f64>, time: f64) -> Vector3<f64> {
        self.position_at(reference, time) - reference
    }

    /// Whether the rotation axis and centre are finite.
    pub fn is_finite(&self) -> bool {
        self.rotation.as_ref().is_none_or(|r| {
            r.axis.iter().all(|x| x.is_finite()) && r.center.iter().all(|x| x.is_finite())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(value: f64) -> Amplitude {
        Amplitude::ramp(1.0, value).unwrap()
    }

    #[test]
    fn a_rigid_rotation_keeps_distances_and_turns_by_the_angle() {
        let motion = RigidMotion {
            translation: [Some(ramp(0.1)), None, None],
            rotation: Some(RigidRotation {
                center: Vector3::new(1.0, 0.0, 0.0),
                axis: Vector3::z_axis(),
                angle: ramp(std::f64::consts::FRAC_PI_2),
            }),
            follower: None,
        };
        let x = Vector3::new(2.0, 0.0, 0.5);
        // Quarter turn about z through (1, 0, 0): (2, 0, .5) → (1, 1, .5), then +0.1 x.
        let moved = x + motion.displacement_at(&x, 1.0);
        assert!((moved - Vector3::new(1.1, 1.0, 0.5)).norm() < 1e-14);
        let y = Vector3::new(0.3, -0.7, 2.0);
        let distance = (y - x).norm();
        let moved_y = y + motion.displacement_at(&y, 0.37);
        let moved_x = x + motion.displacement_at(&x, 0.37);
        assert!(((moved_y - moved_x).norm() - distance).abs() < 1e-14);
        assert!((motion.reference_point_at(1.0) - Vector3::new(1.1, 0.0, 0.0)).norm() < 1e-15);
    }

    #[test]
    fn the_isometry_is_the_motion() {
        let motion = RigidMotion {
            translation: [Some(ramp(0.1)), None, Some(ramp(-0.3))],
            rotation: Some(RigidRotation {
                center: Vector3::new(1.0, 0.5, 0.0),
                axis: Unit::new_normalize(Vector3::new(1.0, 2.0, 2.0)),
                angle: ramp(1.2),
            }),
            follower: None,
        };
        let x = Vector3::new(0.3, -0.7, 2.0);
        for time in [0.0, 0.37, 1.0] {
            let by_isometry = motion.isometry_at(time) * nalgebra::Point3::from(x);
            assert!((by_isometry.coords - motion.position_at(&x, time)).norm() < 1e-14);
        }
    }

    /// A body turning about z through (1, 0, 0) at 1 rad/s, its pose set by a follower.
    #[derive(Debug)]
    struct Spinning;

    impl PoseFollower for Spinning {
        fn isometry_at(&self, time: f64) -> Isometry3<f64> {
            let center = Vector3::new(1.0, 0.0, 0.0);
            let rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), time);
            Isometry3::from_parts(Translation3::from(center - rotation * center), rotation)
        }
        fn reference_point(&self) -> Vector3<f64> {
            Vector3::new(1.0, 0.0, 0.0)
        }
    }

    #[test]
    fn a_follower_sets_the_pose_in_place_of_the_amplitudes() {
        let followed = RigidMotion::followed(Arc::new(Spinning));
        let prescribed = RigidMotion {
            translation: [None, None, None],
            rotation: Some(RigidRotation {
                center: Vector3::new(1.0, 0.0, 0.0),
                axis: Vector3::z_axis(),
                angle: Amplitude::ramp(2.0, 2.0).unwrap(),
            }),
            follower: None,
        };
        let x = Vector3::new(2.0, 0.3, -0.5);
        for time in [0.0, 0.4, 1.7] {
            assert!(
                (followed.position_at(&x, time) - prescribed.position_at(&x, time)).norm() < 1e-14
            );
            assert!(
                (followed.displacement_at(&x, time) - prescribed.displacement_at(&x, time)).norm()
                    < 1e-14
            );
            assert!(
                (followed.rotation_at(time).matrix() - prescribed.rotation_at(time).matrix())
                    .norm()
                    < 1e-14
            );
            assert!(
                (followed.reference_point_at(time) - prescribed.reference_point_at(time)).norm()
                    < 1e-14
            );
            let by_isometry = followed.isometry_at(time) * nalgebra::Point3::from(x);
            assert!((by_isometry.coords - prescribed.position_at(&x, time)).norm() < 1e-14);
        }
    }
}
