//! Where the trochlear groove runs under the patella: the groove floor's mediolateral
//! position at the patella's contact, from the Visible Human's distal femoral cartilage,
//! against the patella of the planar mechanism (issue #35's patellar tracking).
//!
//! **The section.** At knee flexion θ the mechanism's patella rests with its articular
//! ridge on the groove's sagittal profile (the circle (C_g, r_g) continued proximally by
//! the line x = x_g + r_g, [`super::super::kinematics`]) at groove coordinate u. The
//! contact's outward direction n is radial from C_g on the circle (u < 0) and anterior
//! (e_x) on the straight part (u ≥ 0) ([`KneeKinematics::groove_frame`]). The plane
//! through the contact spanned by n and the flexion axis e_z cuts the cartilage; each cut
//! point is (ρ, z), ρ its distance along n from the groove's axis (the circle's centre,
//! or x_g on the straight part). The
//! articular surface is the outer one: h(z) = the largest ρ in each 1 mm band of z
//! (bands the cut misses filled linearly, then smoothed by ¼, ½, ¼).
//!
//! **The groove.** The facets' crests are the highest points of h on either side of the
//! section's middle. The floor is the vertex of the least-squares parabola through h from
//! crest to crest: the groove's floor is flat over several millimetres on this mesh, and
//! the lowest band alone (or a parabola through the lowest millimetre) jumps by 3–6 mm
//! between sections 5° apart. The price is a bias towards the gentler facet: on a
//! V-groove h = s|x| + t x over |x| ≤ L the vertex lies at x = −8 t L / (15 s). Reported:
//! the floor's z, its depth below the lower crest and the crests' z.
//!
//! **Tilt is not reported.** The slope of the facets across the floor, read at ±10 mm,
//! was tried as the tilt a patella seated on both facets would take: it inherits the
//! floor's bias (on the V above, t + s x_v/10, which has the opposite sign to t for
//! s = 0.3, t = 0.05, L = 25 mm) and ranged over ±12° between neighbouring sections of
//! the Visible Human's cartilage, so it measures the estimator, not the patella. A tilt
//! needs the patella's facets in contact with the trochlea's (a 3-D patellofemoral
//! joint).
//!
//! **The patella.** The mechanism is planar: its patella keeps its data z, the articular
//! ridge's (the fitted circle's centre). The tracking error of the planar model at θ is
//! that z minus the floor's: how far off the groove's floor the patella rides.

use std::fmt::Write as _;

use anyhow::{Result, bail};
use nalgebra::Vector3;

use super::super::kinematics::KneeKinematics;
use super::super::surface::TriangleSurface;
use super::{VisibleHumanKnee, load_surface};

/// Width of the bands of z in which the articular profile h(z) is taken [m].
const BAND: f64 = 1e-3;

/// The trochlear groove in the section under the patella at one knee flexion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrooveSection {
    /// The contact's groove coordinate u [m] (module documentation).
    pub groove_coordinate: f64,
    /// z of the groove floor [m] (knee frame: lateral positive).
    pub floor: f64,
    /// Depth of the floor below the lower of the two facet crests [m].
    pub depth: f64,
    /// z of the medial and the lateral facet crests [m].
    pub crests: [f64; 2],
}

/// The points (ρ, z) where `cartilage` crosses the plane through `axis` spanned by the
/// outward direction `n` and e_z, on the outward side (ρ > 0).
fn cut(cartilage: &TriangleSurface, n: &Vector3<f64>, axis: &Vector3<f64>) -> Vec<(f64, f64)> {
    let normal = n.cross(&Vector3::z());
    let distance = |v: &Vector3<f64>| (v - axis).dot(&normal);
    let mut points = Vec::new();
    for triangle in &cartilage.triangles {
        let corners = triangle.map(|v| cartilage.vertices[v as usize]);
        for k in 0..3 {
            let (a, b) = (corners[k], corners[(k + 1) % 3]);
            let (da, db) = (distance(&a), distance(&b));
            if (da < 0.0) != (db < 0.0) {
                let point = a + (b - a) * (da / (da - db));
                let rho = (point - axis).dot(n);
                if rho > 0.0 {
                    points.push((rho, point.z));
                }
            }
        }
    }
    points
}

/// `outer` with each band the cut missed (−∞) filled linearly from the bands beside it;
/// `None` if no band has a value.
fn filled(outer: &[f64]) -> Option<Vec<f64>> {
    let known: Vec<usize> = (0..outer.len()).filter(|&b| outer[b].is_finite()).collect();
    let (&first, &last) = (known.first()?, known.last()?);
    let mut profile = outer.to_vec();
    for b in 0..outer.len() {
        if outer[b].is_finite() {
            continue;
        }
        profile[b] = if b < first {
            outer[first]
        } else if b > last {
            outer[last]
        } else {
            let below = known[known.partition_point(|&k| k < b) - 1];
            let above = known[known.partition_point(|&k| k < b)];
            let t = (b - below) as f64 / (above - below) as f64;
            outer[below] * (1.0 - t) + outer[above] * t
        };
    }
    Some(profile)
}

/// `profile` smoothed by the weights ¼, ½, ¼ (the ends kept).
fn smoothed(profile: &[f64]) -> Vec<f64> {
    (0..profile.len())
        .map(|b| {
            if b == 0 || b + 1 == profile.len() {
                profile[b]
            } else {
                0.25 * profile[b - 1] + 0.5 * profile[b] + 0.25 * profile[b + 1]
            }
        })
        .collect()
}

/// The groove in the section at groove coordinate `u`, or `None` where the plane misses
/// the cartilage or finds no groove between two crests (above the trochlea).
pub fn groove_section(
    cartilage: &TriangleSurface,
    kinematics: &KneeKinematics,
    u: f64,
) -> Option<GrooveSection> {
    let (n, axis) = kinematics.groove_frame(u);
    let points = cut(cartilage, &n, &axis);
    let (low, high) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
            (l.min(p.1), h.max(p.1))
        });
    if high - low <= 4.0 * BAND || high.is_nan() || low.is_nan() {
        return None;
    }
    let bands = ((high - low) / BAND).ceil() as usize;
    let mut outer = vec![f64::NEG_INFINITY; bands];
    for &(rho, z) in &points {
        let band = (((z - low) / BAND) as usize).min(bands - 1);
        outer[band] = outer[band].max(rho);
    }
    let profile = smoothed(&filled(&outer)?);
    let z_of = |band: f64| low + (band + 0.5) * BAND;
    let middle = bands / 2;
    let highest =
        |range: std::ops::Range<usize>| range.max_by(|&a, &b| profile[a].total_cmp(&profile[b]));
    let (medial, lateral) = (highest(0..middle)?, highest(middle..bands)?);
    let lowest = (medial + 1..lateral).min_by(|&a, &b| profile[a].total_cmp(&profile[b]))?;
    let depth = profile[medial].min(profile[lateral]) - profile[lowest];
    if depth <= 0.0 || depth.is_nan() {
        return None;
    }
    // The floor: the vertex of the least-squares parabola through the profile from crest
    // to crest (module documentation).
    let z_centre = z_of(lowest as f64);
    let mut normal = nalgebra::Matrix3::<f64>::zeros();
    let mut right = Vector3::<f64>::zeros();
    for b in medial..=lateral {
        let z = z_of(b as f64) - z_centre;
        let row = Vector3::new(1.0, z, z * z);
        normal += row * row.transpose();
        right += row * profile[b];
    }
    let [_, slope, curvature] = normal.lu().solve(&right)?.into();
    if curvature <= 0.0 || curvature.is_nan() {
        return None;
    }
    let floor_z = z_centre - slope / (2.0 * curvature);
    if !(z_of(medial as f64)..z_of(lateral as f64)).contains(&floor_z) {
        return None;
    }
    Some(GrooveSection {
        groove_coordinate: u,
        floor: floor_z,
        depth,
        crests: [z_of(medial as f64), z_of(lateral as f64)],
    })
}

/// The groove under the mechanism's patella at each knee flexion of `angles` [rad]
/// (`None` where the patella is above the trochlea).
pub fn groove_under_patella(
    cartilage: &TriangleSurface,
    kinematics: &KneeKinematics,
    angles: &[f64],
) -> Result<Vec<Option<GrooveSection>>> {
    if cartilage.triangles.is_empty() {
        bail!("the cartilage surface has no triangles");
    }
    angles
        .iter()
        .map(|&angle| {
            let pose = kinematics.patella_pose(angle)?;
            Ok(groove_section(
                cartilage,
                kinematics,
                pose.groove_coordinate,
            ))
        })
        .collect()
}

/// The planar patella against the groove at a series of knee flexions.
#[derive(Clone, Debug, PartialEq)]
pub struct PatellaTracking {
    /// z of the patella's articular ridge [m], which the planar mechanism keeps.
    pub ridge: f64,
    /// Knee flexion [rad] and the groove under the patella there.
    pub rows: Vec<(f64, Option<GrooveSection>)>,
}

/// Header of `patella_tracking.csv`.
pub const PATELLA_TRACKING_CSV_HEADER: &str = "knee_angle_deg,groove_coordinate_mm,\
    groove_floor_z_mm,patella_ridge_z_mm,ridge_lateral_of_floor_mm,groove_depth_mm,\
    medial_crest_z_mm,lateral_crest_z_mm";

impl PatellaTracking {
    /// The tracking of the Visible Human knee's patella with `kinematics` every 5° from 0°
    /// to `peak_flexion` [rad].
    pub fn of_visible_human(
        knee: &VisibleHumanKnee,
        kinematics: &KneeKinematics,
        peak_flexion: f64,
    ) -> Result<PatellaTracking> {
        let cartilage = load_surface("femur_cartilage_distal")?.transformed(&knee.frame);
        let steps = (peak_flexion.to_degrees() / 5.0).floor() as usize;
        let angles: Vec<f64> = (0..=steps).map(|i| (5.0 * i as f64).to_radians()).collect();
        let sections = groove_under_patella(&cartilage, kinematics, &angles)?;
        Ok(PatellaTracking {
            ridge: knee
                .landmarks
                .in_knee_frame(&knee.landmarks.patellar_ridge)
                .z,
            rows: angles.into_iter().zip(sections).collect(),
        })
    }

    /// The table as CSV ([`PATELLA_TRACKING_CSV_HEADER`]; the groove's columns empty
    /// where the patella is above the trochlea).
    pub fn csv(&self) -> String {
        let mut text = format!("{PATELLA_TRACKING_CSV_HEADER}\n");
        for (angle, section) in &self.rows {
            let _ = match section {
                Some(s) => writeln!(
                    text,
                    "{:.1},{:.2},{:.2},{:.2},{:.2},{:.2},{:.2},{:.2}",
                    angle.to_degrees(),
                    s.groove_coordinate * 1e3,
                    s.floor * 1e3,
                    self.ridge * 1e3,
                    (self.ridge - s.floor) * 1e3,
                    s.depth * 1e3,
                    s.crests[0] * 1e3,
                    s.crests[1] * 1e3
                ),
                None => writeln!(
                    text,
                    "{:.1},,,{:.2},,,,",
                    angle.to_degrees(),
                    self.ridge * 1e3
                ),
            };
        }
        text
    }

    /// One line: where the patella enters the groove and how far off its floor it rides.
    pub fn summary(&self) -> String {
        let engaged: Vec<(f64, &GrooveSection)> = self
            .rows
            .iter()
            .filter_map(|(a, s)| s.as_ref().map(|s| (*a, s)))
            .collect();
        let Some(first) = engaged.first() else {
            return "patellar tracking: the patella does not reach the trochlear groove".into();
        };
        let offsets: Vec<f64> = engaged.iter().map(|(_, s)| self.ridge - s.floor).collect();
        let (low, high) = offsets
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), o| {
                (l.min(*o), h.max(*o))
            });
        format!(
            "patellar tracking (planar mechanism against the trochlear groove): in the groove \
             from {:.0}°, its ridge {:.1} to {:.1} mm lateral of the groove's floor (the floor \
             moves over {:.1} mm mediolaterally; the patella's tilt is not modelled)",
            first.0.to_degrees(),
            low * 1e3,
            high * 1e3,
            (high - low) * 1e3
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::knee::anatomy::KneeDimensions;

    /// A trochlea as a thick shell about the groove's axis: outer radius
    /// r₀ + s |z − z_f| + t (z − z_f) (a V-groove with its floor at z_f, the lateral facet
    /// steeper by 2t) for |z − z_f| ≤ 25 mm, inner radius r₀ − 3 mm, over the circle's arc
    /// from −100° to 10°, as a closed surface of quads split in two.
    fn trochlea(kinematics: &KneeKinematics, floor: f64, slope: f64, tilt: f64) -> TriangleSurface {
        let dimensions = &kinematics.dimensions;
        let [gx, gy] = dimensions.groove_centre;
        let r0 = dimensions.groove_radius;
        let (arcs, widths) = (60, 100);
        let mut surface = TriangleSurface {
            vertices: Vec::new(),
            triangles: Vec::new(),
        };
        for layer in 0..2 {
            for i in 0..=arcs {
                let angle = (-100.0 + 110.0 * i as f64 / arcs as f64).to_radians();
                for j in 0..=widths {
                    let x = -0.025 + 0.05 * j as f64 / widths as f64;
                    let r = if layer == 0 {
                        r0 + slope * x.abs() + tilt * x
                    } else {
                        r0 - 3e-3
                    };
                    surface.vertices.push(Vector3::new(
                        gx + r * angle.cos(),
                        gy + r * angle.sin(),
                        floor + x,
                    ));
                }
            }
        }
        let index = |layer: usize, i: usize, j: usize| {
            (layer * (arcs + 1) * (widths + 1) + i * (widths + 1) + j) as u32
        };
        for layer in 0..2 {
            for i in 0..arcs {
                for j in 0..widths {
                    let q = [
                        index(layer, i, j),
                        index(layer, i + 1, j),
                        index(layer, i + 1, j + 1),
                        index(layer, i, j + 1),
                    ];
                    surface.triangles.push([q[0], q[1], q[2]]);
                    surface.triangles.push([q[0], q[2], q[3]]);
                }
            }
        }
        surface
    }

    #[test]
    fn the_floor_of_a_v_groove_is_its_best_parabolas_vertex() {
        let kinematics = KneeKinematics::from_dimensions(KneeDimensions::procedural_knee(), vec![]);
        let (floor, slope, half_width) = (4e-3, 0.3, 0.025);
        for tilt in [0.0, 0.05] {
            let surface = trochlea(&kinematics, floor, slope, tilt);
            // The closed form of the module documentation: on a symmetric V the vertex.
            let expected = floor - 8.0 * tilt * half_width / (15.0 * slope);
            for u in [-0.03, -0.01] {
                let section = groove_section(&surface, &kinematics, u).unwrap();
                assert!(
                    (section.floor - expected).abs() < 0.2e-3,
                    "tilt {tilt}, u = {u}: floor at {:.2} mm, expected {:.2}",
                    section.floor * 1e3,
                    expected * 1e3
                );
                // The crests are the section's ends, the depth the lower one's height
                // (its band's centre, half a band in).
                let depth = (slope - tilt) * (half_width - 0.5e-3);
                assert!(
                    (section.depth - depth).abs() < 0.3e-3,
                    "tilt {tilt}: depth {:.2} mm, expected {:.2}",
                    section.depth * 1e3,
                    depth * 1e3
                );
                assert!((section.crests[0] - (floor - half_width)).abs() < 1e-3);
                assert!((section.crests[1] - (floor + half_width)).abs() < 1e-3);
            }
            // Above the trochlea (the straight part, 50 mm up) the plane misses it.
            assert!(groove_section(&surface, &kinematics, 0.05).is_none());
        }
    }
}
