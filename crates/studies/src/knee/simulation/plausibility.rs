//! Whether a squat is believable: the forces and stretches a biomechanist checks before
//! reading a stress map, at every recorded instant and at the table's angles.
//!
//! - the quadriceps' pull on the patella, per muscle and in total: Σ |R| of the
//!   insertions' ties [N];
//! - the patellar tendon's force [N] and the knee extensor moment it makes about the
//!   flexion axis, M = ((T − O) × f_t e)·e_z with T the tuberosity, e the unit vector
//!   from it to the patella's apex and O the axis [N m] (the passive moment in vivo is of
//!   the order of 10 N m at 90°);
//! - the fiber stretch λ_f = |F a₀| over the muscle (belly) elements: median and 95th
//!   percentile (the matrix law was calibrated up to about 25 % strain);
//! - the force each muscle–femur interface carries (the resultant on the muscle), as a
//!   share of that muscle's pull: an interface that lets the muscle slide carries little;
//!   and its component along the muscle's pull (the insertion reaction's direction),
//!   which is what resists the slide: a frictionless interface under a muscle that the
//!   others press onto the bone carries their pressure across the pull;
//!   the same for the penalty contact with the femur (the quadriceps tendon's wrap over
//!   the trochlea in deep flexion is real and carries more);
//! - the peak von Mises stress of each muscle's tendon (reported apart from the muscles'
//!   vm95, which is over muscle elements only).

use std::path::Path;

use anyhow::{Result, bail};

use super::super::anatomy::{KneeDimensions, Quadriceps, Squat};
use super::patella::TendonState;
use super::peak_stress::{Phase, table_instants};

/// The plausibility measures at one recorded instant.
#[derive(Clone, Debug, PartialEq)]
pub struct PlausibilitySample {
    pub time: f64,
    /// Knee flexion [rad].
    pub flexion: f64,
    /// |R| of each muscle's insertion tie [N].
    pub insertion_pull: Vec<f64>,
    /// The patellar tendon's force [N] and the extensor moment it makes [N m].
    pub tendon_force: f64,
    pub extensor_moment: f64,
    /// Median and 95th percentile of the muscle elements' fiber stretch [1].
    pub fiber_stretch_median: f64,
    pub fiber_stretch_p95: f64,
    /// |resultant| of each muscle's cohesive interface with the femur, and of its penalty
    /// contact with the femur [N] (0 without one).
    pub femur_interface_force: Vec<f64>,
    /// |component| of each muscle–femur interface's resultant along that muscle's pull
    /// (the direction of its insertion reaction) [N].
    pub femur_interface_along_pull: Vec<f64>,
    pub femur_contact_force: Vec<f64>,
    /// The largest von Mises stress of each muscle's tendon elements [Pa] (0 without).
    pub tendon_peak: Vec<f64>,
}

impl PlausibilitySample {
    /// Σ |R| over the insertions [N].
    pub fn total_pull(&self) -> f64 {
        self.insertion_pull.iter().sum()
    }
}

/// The knee extensor moment [N m] of the patellar tendon in `state` in the knee of
/// `dimensions`: its force along the line from the tuberosity to the apex, about the
/// flexion axis (+z: extension), in the femur's frame.
pub fn extensor_moment(dimensions: &KneeDimensions, state: &TendonState) -> f64 {
    let apex = state.pose.to_world(&dimensions.apex);
    let tuberosity = dimensions.tuberosity_at(state.knee_angle);
    let Some(direction) = (apex - tuberosity).try_normalize(0.0) else {
        return 0.0;
    };
    tuberosity.cross(&(state.tendon_force * direction)).z
}

/// The samples' measures at one table angle and phase.
#[derive(Clone, Debug, PartialEq)]
pub struct PlausibilityRow {
    pub angle_degrees: f64,
    pub phase: Phase,
    /// The measures, each interpolated linearly in time between the recorded instants
    /// around the one at which the knee passes the angle.
    pub sample: PlausibilitySample,
}

/// `value` of the samples around `time`, interpolated linearly.
fn interpolate(a: &PlausibilitySample, b: &PlausibilitySample, time: f64) -> PlausibilitySample {
    let w = if b.time > a.time {
        ((time - a.time) / (b.time - a.time)).clamp(0.0, 1.0)
    } else {
        1.0
    };
    let mix = |x: f64, y: f64| x + w * (y - x);
    let mix_all = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(&p, &q)| mix(p, q)).collect();
    PlausibilitySample {
        time,
        flexion: mix(a.flexion, b.flexion),
        insertion_pull: mix_all(&a.insertion_pull, &b.insertion_pull),
        tendon_force: mix(a.tendon_force, b.tendon_force),
        extensor_moment: mix(a.extensor_moment, b.extensor_moment),
        fiber_stretch_median: mix(a.fiber_stretch_median, b.fiber_stretch_median),
        fiber_stretch_p95: mix(a.fiber_stretch_p95, b.fiber_stretch_p95),
        femur_interface_force: mix_all(&a.femur_interface_force, &b.femur_interface_force),
        femur_interface_along_pull: mix_all(
            &a.femur_interface_along_pull,
            &b.femur_interface_along_pull,
        ),
        femur_contact_force: mix_all(&a.femur_contact_force, &b.femur_contact_force),
        tendon_peak: mix_all(&a.tendon_peak, &b.tendon_peak),
    }
}

/// The rows at the table's angles in both phases. Errors if the samples do not cover an
/// angle's time.
pub fn plausibility_rows(
    samples: &[PlausibilitySample],
    squat: &Squat,
) -> Result<Vec<PlausibilityRow>> {
    let mut rows = Vec::new();
    for (phase, degrees, time) in table_instants(squat) {
        let Some(after) = samples.iter().position(|s| s.time >= time - 1e-12) else {
            bail!(
                "the run ended before the knee reached {degrees}° in {}",
                phase.name()
            );
        };
        let before = after.saturating_sub(1);
        rows.push(PlausibilityRow {
            angle_degrees: degrees,
            phase,
            sample: interpolate(&samples[before], &samples[after], time),
        });
    }
    Ok(rows)
}

/// Header of `plausibility.csv` for `muscles`.
pub fn plausibility_header(muscles: &[Quadriceps]) -> String {
    let mut header = "knee_angle_deg,phase,total_pull_n".to_string();
    for m in muscles {
        header.push_str(&format!(",{}_pull_n", m.abbreviation()));
    }
    header.push_str(
        ",patellar_tendon_force_n,extensor_moment_nm,fiber_stretch_median,fiber_stretch_p95",
    );
    for suffix in [
        "femur_interface_n",
        "femur_interface_along_pull_n",
        "femur_contact_n",
        "tendon_peak_pa",
    ] {
        for m in muscles {
            header.push_str(&format!(",{}_{suffix}", m.abbreviation()));
        }
    }
    header
}

/// Writes `plausibility.csv` (atomically).
pub fn write_plausibility_csv(
    path: &Path,
    rows: &[PlausibilityRow],
    muscles: &[Quadriceps],
) -> Result<()> {
    let mut text = plausibility_header(muscles);
    text.push('\n');
    for row in rows {
        let s = &row.sample;
        let mut fields = vec![
            format!("{}", row.angle_degrees),
            row.phase.name().to_string(),
        ];
        let mut numbers = vec![s.total_pull()];
        numbers.extend(&s.insertion_pull);
        numbers.extend([
            s.tendon_force,
            s.extensor_moment,
            s.fiber_stretch_median,
            s.fiber_stretch_p95,
        ]);
        numbers.extend(&s.femur_interface_force);
        numbers.extend(&s.femur_interface_along_pull);
        numbers.extend(&s.femur_contact_force);
        numbers.extend(&s.tendon_peak);
        fields.extend(numbers.iter().map(|&x| musclefem_io::csv::format_number(x)));
        text.push_str(&fields.join(","));
        text.push('\n');
    }
    musclefem_io::atomic::write_atomically(path, text.as_bytes())?;
    Ok(())
}

/// The rows in flexion as lines for the terminal and `run.log`.
pub fn plausibility_report(rows: &[PlausibilityRow], muscles: &[Quadriceps]) -> String {
    let mut text = String::from(
        "  plausibility (flexion): angle, quadriceps pull on the patella [N] (per muscle), \
         patellar tendon [N], extensor moment [N m], fiber stretch median / 95th pct, \
         muscle–femur interface force (all of it / along the pull) and contact force as a \
         share of each muscle's pull, tendon peak von Mises [MPa]\n",
    );
    for row in rows.iter().filter(|r| r.phase == Phase::Flexion) {
        let s = &row.sample;
        let pulls: Vec<String> = s.insertion_pull.iter().map(|p| format!("{p:.0}")).collect();
        let percent = |f: f64, p: f64| 100.0 * f / p.max(f64::MIN_POSITIVE);
        let share = |forces: &[f64]| -> String {
            muscles
                .iter()
                .zip(forces.iter().zip(&s.insertion_pull))
                .map(|(m, (&f, &p))| format!("{} {:.0} %", m.abbreviation(), percent(f, p)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let interface: Vec<String> = muscles
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let p = s.insertion_pull[i];
                format!(
                    "{} {:.0} / {:.0} %",
                    m.abbreviation(),
                    percent(s.femur_interface_force[i], p),
                    percent(s.femur_interface_along_pull[i], p)
                )
            })
            .collect();
        let peaks: Vec<String> = s
            .tendon_peak
            .iter()
            .map(|p| format!("{:.1}", 1e-6 * p))
            .collect();
        text.push_str(&format!(
            "    {:>3.0}°: pull {:.0} ({}), tendon {:.0}, moment {:.1}, stretch {:.3} / {:.3}; \
             interface {}; contact {}; tendon peak {}\n",
            row.angle_degrees,
            s.total_pull(),
            pulls.join(" "),
            s.tendon_force,
            s.extensor_moment,
            s.fiber_stretch_median,
            s.fiber_stretch_p95,
            interface.join(", "),
            share(&s.femur_contact_force),
            peaks.join(" "),
        ));
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::knee::anatomy::dimensions::APEX;
    use crate::knee::anatomy::{KneeKinematics, Quadriceps};
    use crate::knee::simulation::patella::TendonState;

    #[test]
    fn the_extensor_moment_is_the_tendon_force_times_its_lever_about_the_axis() {
        let kinematics = KneeKinematics::new(Quadriceps::ALL.iter().map(|m| m.pull()).collect());
        for degrees in [0.0f64, 45.0, 90.0] {
            let angle = degrees.to_radians();
            let pose = kinematics.patella_pose(angle).unwrap();
            let state = TendonState {
                knee_angle: angle,
                quadriceps_tension: 1000.0,
                tendon_force: 1000.0,
                tendon_length: 0.05,
                tendon_strain: 0.0,
                force_ratio: 1.0,
                pose,
                beyond_table: false,
            };
            // The lever: the distance from the axis to the tendon's line.
            let apex = pose.to_world(&APEX);
            let tuberosity = kinematics.tuberosity(angle);
            let e = (apex - tuberosity).normalize();
            let lever = (tuberosity - tuberosity.dot(&e) * e).norm();
            let moment = extensor_moment(&kinematics.dimensions, &state);
            assert!(
                (moment - 1000.0 * lever).abs() < 1e-9,
                "{degrees}°: {moment}"
            );
            // An extensor lever of 3–5 cm (the patellar tendon's in adults).
            assert!((0.025..0.055).contains(&lever), "{degrees}°: {lever}");
        }
    }
}
