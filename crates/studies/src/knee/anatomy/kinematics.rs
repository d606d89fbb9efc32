//! Knee kinematics: the tibia's and the patella's poses as functions of the knee flexion
//! angle θ [rad], the femur fixed.
//!
//! The knee's landmarks are a [`KneeDimensions`] ([`KneeKinematics::new`] takes the
//! procedural knee's, [`KneeKinematics::from_dimensions`] any knee's).
//!
//! **Tibiofemoral joint.** The tibia rotates by θ about the flexion axis through the
//! origin along −z (see [`super::dimensions`]) and moves under it by the femur's
//! rollback s(θ) ([`super::rollback`]): x_tibia(θ) = R_z(−θ)(X + s(θ) e_x), with s = 0
//! (a fixed axis) unless the knee's dimensions ask for rolling.
//!
//! **Patellofemoral joint** (a planar model in the spirit of van Eijden et al. 1986,
//! J Biomech 19:219). The patella moves in the sagittal plane (its z, tilt and spin are
//! held by the groove's facets) with three coordinates: its centroid (x, y) and its
//! flexion φ (rotation about −z, like the tibia's). Two constraints hold them:
//!
//! 1. *contact with the trochlea*: the patella's articular ridge (the circle of radius
//!    ρ_p = [`KneeDimensions::patella_ridge_radius`] osculating its ellipsoid at the
//!    posterior pole) is tangent to the groove floor, the circle (C_g, r_g) continued
//!    proximally by the line x = x_g + r_g, so the ridge's centre lies on the offset
//!    curve at distance r_g + ρ_p, parameterised by its arclength u (u ≥ 0 on the
//!    straight part above C_g, u < 0 around the circle);
//! 2. *the patellar tendon at its length*: |A(u, φ) − T(θ)| = ℓ, A the apex, T the
//!    tuberosity moving with the tibia, ℓ = [`KneeDimensions::patellar_tendon_length`]
//!    for a slack tendon (the finite-element squat stretches it by its tension: see
//!    `knee::simulation::patella`, which uses [`KneeKinematics::with_tendon_length`]).
//!
//! The groove runs 120° round its circle below the straight part (to the notch); u is
//! kept on that range.
//!
//! The remaining degree of freedom is set by **equilibrium**: the quadriceps pull the
//! patella with tensions w_m along their paths, the contact is frictionless and the
//! tendon inextensible, so by virtual work the patella rests where the tension-weighted
//! total path length W(φ) = Σ_m w_m L_m(u(φ), φ) is stationary (a minimum: the pulled
//! patella settles where the muscles are shortest). The weights are the muscles'
//! Visible Human volumes, proportional to their force capacities for equal fiber
//! lengths. For each θ the tendon constraint is solved for u by bisection on a bracket
//! found by stepping down the groove from above, and W is minimised over φ by a 1°
//! scan followed by golden-section search.
//!
//! The resulting patellar flexion is ≈ 0.57 θ at 90°, and the patellar tendon's angle to
//! the tibia falls from 10° to 1° between 0° and 90° (van Eijden, de Boer & Weijs 1985,
//! J Biomech 18:803, measured about 21° → −7°); the ratio of the tendon's force to the
//! quadriceps' (the effective moment arm over the tendon's moment arm about the flexion
//! axis) stays 0.9–1.1 up to 45° and falls to 0.54 at 90°, the trend measured by
//! Huberti, Hayes, Stone & Shybut (1984, J Orthop Res 2:49). `tests/knee_anatomy.rs` prints and
//! checks these.

use anyhow::{Result, bail};
use nalgebra::{Isometry3, Rotation3, Translation3, UnitQuaternion, Vector3};

use super::dimensions::KneeDimensions;
use super::path::{WrapCylinder, free_path};

/// Arclength of the groove's straight proximal part available to the patella [m].
const GROOVE_PROXIMAL_LENGTH: f64 = 0.2;
/// How far round its circle the groove runs below its centre's level [rad]: 120°, to
/// the intercondylar notch.
const GROOVE_DISTAL_ANGLE: f64 = 120.0 * DEG;
/// Step of the downward search for the tendon constraint's bracket [m].
const GROOVE_SEARCH_STEP: f64 = 0.002;
/// Range of patellar flexion searched for the equilibrium [rad].
const PATELLA_FLEXION_RANGE: [f64; 2] = [-40.0 * DEG, 130.0 * DEG];
const DEG: f64 = std::f64::consts::PI / 180.0;

/// The rotation of a body flexed by `angle` [rad]: about −z, i.e. R_z(−angle).
pub fn flexion_rotation(angle: f64) -> Rotation3<f64> {
    Rotation3::from_axis_angle(&Vector3::z_axis(), -angle)
}

/// The pose of the patella: its centroid and its flexion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatellaPose {
    /// Position of the centroid [m].
    pub centre: Vector3<f64>,
    /// Patellar flexion φ [rad], about −z like the knee's.
    pub flexion: f64,
    /// Arclength coordinate u of the ridge's centre along the groove's offset curve [m]
    /// (≥ 0 on the straight proximal part).
    pub groove_coordinate: f64,
}

impl PatellaPose {
    /// World position of the patella-frame point `local` [m] (frame: origin at the
    /// centroid, axes along the global ones at φ = 0).
    pub fn to_world(&self, local: &Vector3<f64>) -> Vector3<f64> {
        self.centre + flexion_rotation(self.flexion) * local
    }

    /// The map from the patella's frame to the world.
    pub fn isometry(&self) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::from(self.centre),
            UnitQuaternion::from_rotation_matrix(&flexion_rotation(self.flexion)),
        )
    }
}

/// One muscle's pull on the patella: the straight (or wrapped) line from its femur-fixed
/// release point to its insertion, with a tension weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadricepsPull {
    /// Last femur-fixed point of the path [m].
    pub release: Vector3<f64>,
    /// Insertion on the patella [m], in the patella's frame.
    pub insertion: Vector3<f64>,
    /// Relative tension (any positive scale).
    pub weight: f64,
}

/// The knee's kinematics (see the module documentation).
#[derive(Clone, Debug)]
pub struct KneeKinematics {
    /// The knee's landmarks.
    pub dimensions: KneeDimensions,
    /// The quadriceps whose pull places the patella.
    pub pulls: Vec<QuadricepsPull>,
    /// The cylinder the quadriceps tendon wraps over.
    pub trochlea: WrapCylinder,
    /// Length ℓ of the patellar tendon [m].
    pub tendon_length: f64,
}

impl KneeKinematics {
    /// Kinematics with the procedural knee's dimensions and the given quadriceps pulls.
    pub fn new(pulls: Vec<QuadricepsPull>) -> Self {
        Self::from_dimensions(KneeDimensions::procedural_knee(), pulls)
    }

    /// Kinematics of the knee of `dimensions` with the given quadriceps pulls, its
    /// patellar tendon slack.
    pub fn from_dimensions(dimensions: KneeDimensions, pulls: Vec<QuadricepsPull>) -> Self {
        Self {
            pulls,
            trochlea: WrapCylinder::trochlea(&dimensions),
            tendon_length: dimensions.patellar_tendon_length,
            dimensions,
        }
    }

    /// The same knee with a patellar tendon of `length` [m] (stretched by its tension).
    pub fn with_tendon_length(&self, length: f64) -> Self {
        Self {
            tendon_length: length,
            ..self.clone()
        }
    }

    /// The tibia's pose at flexion `angle` [rad]: a rotation about the flexion axis and
    /// the rollback's translation ([`super::rollback`]).
    pub fn tibia_isometry(&self, angle: f64) -> Isometry3<f64> {
        self.dimensions.rollback.tibia_in_femur(angle)
    }

    /// The tibial tuberosity (the tendon's insertion) at flexion `angle` [m].
    pub fn tuberosity(&self, angle: f64) -> Vector3<f64> {
        self.dimensions.tuberosity_at(angle)
    }

    /// The groove floor's outward normal n and its axis point at groove coordinate `u`
    /// [m]: radial from the groove circle's centre C_g (n at the angle u/(r_g + ρ_p), axis
    /// point C_g) on the circle (u < 0), anterior (n = e_x, axis point (x_g, y_g + u)) on
    /// the straight proximal part. The floor lies r_g along n from the axis point, the
    /// ridge centre r_g + ρ_p.
    pub fn groove_frame(&self, u: f64) -> (Vector3<f64>, Vector3<f64>) {
        let [gx, gy] = self.dimensions.groove_centre;
        if u >= 0.0 {
            (Vector3::x(), Vector3::new(gx, gy + u, 0.0))
        } else {
            let radius = self.dimensions.groove_radius + self.dimensions.patella_ridge_radius();
            let angle = u / radius;
            (
                Vector3::new(angle.cos(), angle.sin(), 0.0),
                Vector3::new(gx, gy, 0.0),
            )
        }
    }

    /// Point (x, y) [m] of the ridge centre's path at arclength `u` (see the module
    /// documentation).
    fn ridge_centre(&self, u: f64) -> [f64; 2] {
        let radius = self.dimensions.groove_radius + self.dimensions.patella_ridge_radius();
        let (normal, axis) = self.groove_frame(u);
        let centre = axis + normal * radius;
        [centre.x, centre.y]
    }

    /// The patella with its ridge centre at groove coordinate `u` and flexion `phi`.
    fn patella_at(&self, u: f64, phi: f64) -> PatellaPose {
        let [x, y] = self.ridge_centre(u);
        // The ridge centre in the patella's frame: ρ_p in front of the posterior pole.
        let ridge = Vector3::new(
            self.dimensions.patella_ridge_radius() - self.dimensions.patella_semi_axes[2],
            0.0,
            0.0,
        );
        PatellaPose {
            centre: Vector3::new(x, y, 0.0) - flexion_rotation(phi) * ridge,
            flexion: phi,
            groove_coordinate: u,
        }
    }

    /// The patella at flexion `phi` that satisfies the tendon constraint at knee flexion
    /// `angle`: the most proximal root in u of |A − T| − ℓ, or `None` if the tendon
    /// cannot reach.
    fn tendon_constrained(&self, phi: f64, angle: f64) -> Option<PatellaPose> {
        let tuberosity = self.tuberosity(angle);
        let excess = |u: f64| {
            (self.patella_at(u, phi).to_world(&self.dimensions.apex) - tuberosity).norm()
                - self.tendon_length
        };
        let lowest = -GROOVE_DISTAL_ANGLE
            * (self.dimensions.groove_radius + self.dimensions.patella_ridge_radius());
        let mut high = GROOVE_PROXIMAL_LENGTH;
        if excess(high) <= 0.0 {
            return None;
        }
        let mut low = high;
        loop {
            low -= GROOVE_SEARCH_STEP;
            if low < lowest {
                return None;
            }
            if excess(low) <= 0.0 {
                break;
            }
            high = low;
        }
        for _ in 0..60 {
            let mid = 0.5 * (low + high);
            if excess(mid) <= 0.0 {
                low = mid;
            } else {
                high = mid;
            }
        }
        Some(self.patella_at(0.5 * (low + high), phi))
    }

    /// The tension-weighted length Σ w L of the quadriceps' free paths with the patella
    /// at `pose` [m].
    pub fn weighted_length(&self, pose: &PatellaPose) -> f64 {
        self.pulls
            .iter()
            .map(|pull| {
                pull.weight
                    * free_path(
                        &pull.release,
                        &pose.to_world(&pull.insertion),
                        &self.trochlea,
                    )
                    .length
            })
            .sum()
    }

    /// W(φ) at knee flexion `angle`, +∞ where the tendon cannot reach.
    fn work(&self, phi: f64, angle: f64) -> f64 {
        self.tendon_constrained(phi, angle)
            .map_or(f64::INFINITY, |pose| self.weighted_length(&pose))
    }

    /// The patella's equilibrium pose at knee flexion `angle` [rad] (see the module
    /// documentation). Errors if no patellar flexion in [−40°, 130°] lets the tendon
    /// reach the groove.
    pub fn patella_pose(&self, angle: f64) -> Result<PatellaPose> {
        let [first, last] = PATELLA_FLEXION_RANGE;
        let steps = ((last - first) / DEG).round() as usize;
        let scan: Vec<(f64, f64)> = (0..=steps)
            .map(|k| {
                let phi = first + (last - first) * k as f64 / steps as f64;
                (phi, self.work(phi, angle))
            })
            .collect();
        let Some(best) = (0..scan.len()).min_by(|&i, &j| scan[i].1.total_cmp(&scan[j].1)) else {
            bail!("no patellar flexion sampled");
        };
        if !scan[best].1.is_finite() {
            bail!(
                "at knee flexion {:.1}°, the patellar tendon cannot reach the groove for any \
                 patellar flexion",
                angle / DEG
            );
        }
        let (mut a, mut b) = (
            scan[best.saturating_sub(1)].0,
            scan[(best + 1).min(scan.len() - 1)].0,
        );
        let golden = 0.5 * (5f64.sqrt() - 1.0);
        let (mut c, mut d) = (b - golden * (b - a), a + golden * (b - a));
        let (mut fc, mut fd) = (self.work(c, angle), self.work(d, angle));
        for _ in 0..60 {
            if fc < fd {
                (b, d, fd) = (d, c, fc);
                c = b - golden * (b - a);
                fc = self.work(c, angle);
            } else {
                (a, c, fc) = (c, d, fd);
                d = a + golden * (b - a);
                fd = self.work(d, angle);
            }
        }
        let phi = 0.5 * (a + b);
        match self.tendon_constrained(phi, angle) {
            Some(pose) => Ok(pose),
            None => bail!(
                "at knee flexion {:.1}°, the patellar tendon cannot reach the groove at the \
                 equilibrium patellar flexion {:.1}°",
                angle / DEG,
                phi / DEG
            ),
        }
    }

    /// The patellar tendon's angle to the tibia's long axis at knee flexion `angle`
    /// [rad]: positive when the apex lies anterior to the tuberosity in the tibia's frame
    /// (the convention of van Eijden et al. 1985).
    pub fn patellar_tendon_angle(&self, angle: f64, pose: &PatellaPose) -> f64 {
        let apex = pose.to_world(&self.dimensions.apex);
        let tendon = flexion_rotation(angle).inverse() * (apex - self.tuberosity(angle));
        tendon.x.atan2(tendon.y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::knee::anatomy::Quadriceps;
    use crate::knee::anatomy::dimensions::{
        APEX, GROOVE_CENTRE, GROOVE_RADIUS, PATELLA_RIDGE_RADIUS, PATELLA_SEMI_AXES,
        PATELLAR_TENDON_LENGTH, TUBEROSITY,
    };

    fn kinematics() -> KneeKinematics {
        KneeKinematics::new(Quadriceps::ALL.iter().map(|m| m.pull()).collect())
    }

    #[test]
    fn the_tibia_turns_about_the_flexion_axis() {
        let k = kinematics();
        // At 90° the tuberosity, 35.6 mm in front and 43.1 mm below the axis, is 43.1 mm
        // behind and 35.6 mm below it.
        let t = k.tuberosity(std::f64::consts::FRAC_PI_2);
        assert!((t - Vector3::new(-43.1e-3, -35.6e-3, 0.0)).norm() < 1e-15);
        let motion = k.tibia_isometry(0.3);
        assert!(
            (motion.transform_point(&TUBEROSITY.into()).coords - k.tuberosity(0.3)).norm() < 1e-15
        );
    }

    #[test]
    fn the_equilibrium_pose_meets_both_constraints_and_minimises_the_pull() {
        let k = kinematics();
        for degrees in [0.0, 25.0, 60.0, 95.0] {
            let angle = f64::to_radians(degrees);
            let pose = k.patella_pose(angle).unwrap();
            // Tendon: |A − T| = ℓ.
            let tendon = (pose.to_world(&APEX) - k.tuberosity(angle)).norm();
            assert!(
                (tendon - PATELLAR_TENDON_LENGTH).abs() < 1e-12,
                "{degrees}°"
            );
            // Contact: the ridge's centre is r_g + ρ_p from the groove's axis, or on the
            // straight part's offset line above it.
            let ridge = pose.to_world(&Vector3::new(
                PATELLA_RIDGE_RADIUS - PATELLA_SEMI_AXES[2],
                0.0,
                0.0,
            ));
            let [gx, gy] = GROOVE_CENTRE;
            let offset = GROOVE_RADIUS + PATELLA_RIDGE_RADIUS;
            let distance = if ridge.y > gy {
                ridge.x - gx
            } else {
                (ridge.x - gx).hypot(ridge.y - gy)
            };
            assert!((distance - offset).abs() < 1e-12, "{degrees}°: {distance}");
            // Equilibrium: tilting the patella either way (re-solving the constraints)
            // lengthens the quadriceps.
            let w = k.weighted_length(&pose);
            for delta in [-0.01, 0.01] {
                let tilted = k.tendon_constrained(pose.flexion + delta, angle).unwrap();
                assert!(k.weighted_length(&tilted) > w, "{degrees}° {delta}");
            }
        }
    }

    #[test]
    fn a_tendon_too_short_to_reach_is_reported() {
        // A 0.5 m tendon would hold the patella beyond the groove's 0.2 m straight part.
        let mut k = kinematics();
        k.tendon_length = 0.5;
        let error = k.patella_pose(0.2).unwrap_err();
        assert!(error.to_string().contains("cannot reach"), "{error}");
    }

    #[test]
    fn the_default_dimensions_give_the_procedural_knee_bit_for_bit() {
        let pulls: Vec<QuadricepsPull> = Quadriceps::ALL.iter().map(|m| m.pull()).collect();
        let default = KneeKinematics::new(pulls.clone());
        let from_data = KneeKinematics::from_dimensions(KneeDimensions::procedural_knee(), pulls);
        assert_eq!(from_data.trochlea, default.trochlea);
        assert_eq!(from_data.tendon_length, default.tendon_length);
        for degrees in (0..=90).step_by(15) {
            let angle = f64::from(degrees).to_radians();
            assert_eq!(
                from_data.patella_pose(angle).unwrap(),
                default.patella_pose(angle).unwrap(),
                "{degrees}°"
            );
        }
    }

    /// `knee` scaled by `scale` about the flexion axis: its landmarks and its pulls'
    /// points.
    fn scaled(knee: &KneeKinematics, scale: f64) -> KneeKinematics {
        let pulls = knee
            .pulls
            .iter()
            .map(|p| QuadricepsPull {
                release: scale * p.release,
                insertion: scale * p.insertion,
                weight: p.weight,
            })
            .collect();
        KneeKinematics::from_dimensions(knee.dimensions.scaled(scale), pulls)
    }

    #[test]
    fn a_knee_scaled_about_the_axis_moves_its_patella_similarly() {
        // Every landmark and every pull's points × s about the flexion axis: the tendon
        // constraint and the contact scale, W scales by s, so the patella's equilibrium
        // is the default's with its centre × s and the same flexion.
        let default = kinematics();
        // × 1/2 rounds nothing: the poses are the default's halved, bit for bit.
        let half = scaled(&default, 0.5);
        for degrees in (0..=90).step_by(15) {
            let angle = f64::from(degrees).to_radians();
            let (big, small) = (
                default.patella_pose(angle).unwrap(),
                half.patella_pose(angle).unwrap(),
            );
            assert_eq!(small.centre, 0.5 * big.centre, "{degrees}°");
            assert_eq!(small.flexion, big.flexion, "{degrees}°");
        }
        // × 0.85 rounds: at the same patellar flexion the constrained pose and the pull's
        // work scale to round-off; the equilibrium, the minimum of a flat W(φ), is found
        // to √ε ≈ 1.5e-8 either way (measured: flexions within 2.4e-8 rad, centres within
        // 4.5e-9 relative).
        let scale = 0.85;
        let small_knee = scaled(&default, scale);
        for degrees in (0..=90).step_by(15) {
            let angle = f64::from(degrees).to_radians();
            let big = default.patella_pose(angle).unwrap();
            let small = small_knee.tendon_constrained(big.flexion, angle).unwrap();
            let centre_error = (small.centre - scale * big.centre).norm();
            assert!(
                centre_error <= 1e-12 * scale * big.centre.norm(),
                "{degrees}°: centre off by {centre_error} m"
            );
            let work = (
                small_knee.weighted_length(&small),
                default.weighted_length(&big),
            );
            assert!(
                (work.0 - scale * work.1).abs() <= 1e-12 * work.1,
                "{degrees}°: {work:?}"
            );
            let equilibrium = small_knee.patella_pose(angle).unwrap();
            let centre_error = (equilibrium.centre - scale * big.centre).norm();
            assert!(
                centre_error <= 1e-7 * scale * big.centre.norm(),
                "{degrees}°: centre off by {centre_error} m"
            );
            assert!(
                (equilibrium.flexion - big.flexion).abs() <= 1e-7,
                "{degrees}°: flexion {} against {}",
                equilibrium.flexion,
                big.flexion
            );
        }
    }
}
