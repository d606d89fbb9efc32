//! The paper's outcome measure (seed §2.4): the peak stress of each muscle as the 95th
//! percentile of its elements' von Mises stress ("95 % vM stress"), and where the
//! elements above it lie.
//!
//! The percentile is taken over elements, unweighted (each element counts once, "the
//! 95th percentile peak element response"), by linear interpolation between order
//! statistics: with the n values sorted, v₍ₖ₎, k = 0…n−1, the p-quantile is
//! v₍⌊h⌋₎ + (h − ⌊h⌋)(v₍⌊h⌋₊₁₎ − v₍⌊h⌋₎), h = p (n − 1).
//!
//! The solvers record converged increments, not the instants at which the knee passes
//! 30°, 45°, 60° and 90°; the table takes each muscle's vm95 there by linear
//! interpolation in time between the two recorded instants around it.

use std::collections::BTreeSet;
use std::path::Path;

use anyhow::{Result, bail};

use musclefem_io::atomic::PendingFile;

use super::super::anatomy::{Quadriceps, Squat};
use super::model::{Activation, flexion_time};

/// Header of `peak_stress.csv`.
pub const PEAK_STRESS_CSV_HEADER: &str = "muscle,knee_angle_deg,phase,activation,vm95_pa";

/// The knee angles of the table (seed Fig. 6B) [°].
pub const TABLE_ANGLES_DEGREES: [f64; 4] = [30.0, 45.0, 60.0, 90.0];

/// The p-quantile of `values` (linear between order statistics; see the module
/// documentation); `None` if empty.
pub use musclefem_core::solver::element_fields::percentile;

/// Where a muscle's most stressed elements (von Mises ≥ its vm95) lie: counts of those
/// elements at its origin end (flow potential φ > 0.9), at its insertion end (φ < 0.1),
/// on an interface with another muscle (elsewhere, with a node bonded to it), and in the
/// rest of the belly.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PeakLocation {
    pub origin: usize,
    pub insertion: usize,
    pub interface: usize,
    pub belly: usize,
}

impl PeakLocation {
    pub fn total(&self) -> usize {
        self.origin + self.insertion + self.interface + self.belly
    }

    /// e.g. `insertion 60 %, origin 25 %, interface 10 %, belly 5 %` (largest first).
    pub fn describe(&self) -> String {
        let total = self.total().max(1) as f64;
        let mut parts = [
            ("origin", self.origin),
            ("insertion", self.insertion),
            ("interface", self.interface),
            ("belly", self.belly),
        ];
        parts.sort_by_key(|p| std::cmp::Reverse(p.1));
        parts
            .iter()
            .map(|(name, n)| format!("{name} {:.0} %", 100.0 * *n as f64 / total))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// What identifies each element of one muscle for [`PeakLocation`].
pub struct ElementRegions {
    /// Flow potential of each element (1 at the origin, 0 at the insertion).
    pub potential: Vec<f64>,
    /// Whether each element has a node on a muscle–muscle interface.
    pub on_interface: Vec<bool>,
}

impl ElementRegions {
    /// The regions of a block's elements from its `potential` and `connectivity`
    /// (`nodes_per_element` per element) against the `interface_nodes`.
    pub fn new(
        potential: Vec<f64>,
        connectivity: &[u32],
        nodes_per_element: usize,
        interface_nodes: &BTreeSet<u32>,
    ) -> Self {
        let on_interface = connectivity
            .chunks(nodes_per_element)
            .map(|nodes| nodes.iter().any(|n| interface_nodes.contains(n)))
            .collect();
        ElementRegions {
            potential,
            on_interface,
        }
    }

    /// The location of the elements whose `von_mises` is at least `threshold`.
    pub fn locate(&self, von_mises: &[f64], threshold: f64) -> PeakLocation {
        let mut location = PeakLocation::default();
        for (e, &s) in von_mises.iter().enumerate() {
            if s < threshold {
                continue;
            }
            let phi = self.potential[e];
            if phi > 0.9 {
                location.origin += 1;
            } else if phi < 0.1 {
                location.insertion += 1;
            } else if self.on_interface[e] {
                location.interface += 1;
            } else {
                location.belly += 1;
            }
        }
        location
    }
}

/// Each muscle's vm95 and its location at one recorded instant.
#[derive(Clone, Debug, PartialEq)]
pub struct StressSample {
    pub time: f64,
    /// Knee flexion [rad].
    pub flexion: f64,
    /// vm95 of each muscle block [Pa].
    pub vm95: Vec<f64>,
    pub location: Vec<PeakLocation>,
    /// The smallest det J of any element (corners and Gauss points) over its volume
    /// in the reference configuration [1]: positive unless an element has inverted.
    pub min_jacobian_ratio: f64,
}

/// Flexion (down) or extension (back up).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Phase {
    Flexion,
    Extension,
}

impl Phase {
    pub fn name(self) -> &'static str {
        match self {
            Phase::Flexion => "flexion",
            Phase::Extension => "extension",
        }
    }
}

/// One row of `peak_stress.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct PeakStressRow {
    pub muscle: Quadriceps,
    pub angle_degrees: f64,
    pub phase: Phase,
    pub activation: Activation,
    pub vm95: f64,
    /// The location at the recorded instant nearest in time.
    pub location: PeakLocation,
}

/// The instants of the table: (phase, angle [°], time [s]) at which the knee passes each
/// of [`TABLE_ANGLES_DEGREES`] in flexion, then in extension.
pub fn table_instants(squat: &Squat) -> Vec<(Phase, f64, f64)> {
    let mut instants = Vec::new();
    for phase in [Phase::Flexion, Phase::Extension] {
        // A shallow squat's table stops at its peak.
        for &degrees in TABLE_ANGLES_DEGREES
            .iter()
            .filter(|d| d.to_radians() <= squat.peak_flexion + 1e-9)
        {
            let down = flexion_time(squat, degrees.to_radians());
            let time = match phase {
                Phase::Flexion => down,
                Phase::Extension => squat.duration - down,
            };
            instants.push((phase, degrees, time));
        }
    }
    instants
}

/// The rows of one run: every muscle at every table angle in both phases, interpolated
/// from `samples` (in time order). Errors if the samples do not cover an angle's time.
pub fn peak_stress_rows(
    samples: &[StressSample],
    muscles: &[Quadriceps],
    squat: &Squat,
    activation: Activation,
) -> Result<Vec<PeakStressRow>> {
    let mut rows = Vec::new();
    for (phase, degrees, time) in table_instants(squat) {
        let after = samples.iter().position(|s| s.time >= time - 1e-12);
        let (Some(after), Some(first)) = (after, samples.first()) else {
            bail!(
                "the run ended before the knee reached {degrees}° in {} (t = {time:.4} s)",
                phase.name()
            );
        };
        if first.time > time + 1e-12 {
            bail!("no recorded instant before t = {time:.4} s");
        }
        let before = after.saturating_sub(1);
        let (a, b) = (&samples[before], &samples[after]);
        let weight = if b.time > a.time {
            ((time - a.time) / (b.time - a.time)).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let nearest = if weight < 0.5 { a } else { b };
        for (m, &muscle) in muscles.iter().enumerate() {
            rows.push(PeakStressRow {
                muscle,
                angle_degrees: degrees,
                phase,
                activation,
                vm95: a.vm95[m] + weight * (b.vm95[m] - a.vm95[m]),
                location: nearest.location[m],
            });
        }
    }
    Ok(rows)
}

/// The vm95 column of block `name` in a scene run's `history.csv`
/// (`[output] von_mises_percentile = 95`).
pub fn vm95_column(name: &str) -> String {
    format!("von_mises_p95_{name}_pa")
}

/// The rows of [`peak_stress_rows`] from a scene run's `history.csv` at `path`: each
/// muscle's vm95 interpolated from its belly's column [`vm95_column`] (`bellies`: the
/// muscles' block names, in the order of `muscles`). The history holds no peak
/// locations: the rows' are empty.
pub fn peak_stress_from_history(
    path: &Path,
    bellies: &[&str],
    muscles: &[Quadriceps],
    squat: &Squat,
    activation: Activation,
) -> Result<Vec<PeakStressRow>> {
    let (names, columns) = musclefem_io::csv::read_columns(path)?;
    let column = |name: &str| -> Result<&Vec<f64>> {
        match names.iter().position(|n| n == name) {
            Some(i) => Ok(&columns[i]),
            None => bail!("{} has no column '{name}'", path.display()),
        }
    };
    let time = column("time_s")?;
    let vm95 = (bellies.iter())
        .map(|belly| column(&vm95_column(belly)))
        .collect::<Result<Vec<_>>>()?;
    let samples: Vec<StressSample> = (0..time.len())
        .map(|i| StressSample {
            time: time[i],
            flexion: squat.flexion_at(time[i]),
            vm95: vm95.iter().map(|column| column[i]).collect(),
            location: vec![PeakLocation::default(); bellies.len()],
            min_jacobian_ratio: f64::NAN,
        })
        .collect();
    peak_stress_rows(&samples, muscles, squat, activation)
}

/// `peak_stress.csv` of `rows`, staged for `path`.
pub fn stage_peak_stress_csv(path: &Path, rows: &[PeakStressRow]) -> Result<PendingFile> {
    let mut text = format!("{PEAK_STRESS_CSV_HEADER}\n");
    for row in rows {
        text.push_str(&format!(
            "{},{},{},{},{}\n",
            row.muscle.abbreviation(),
            row.angle_degrees,
            row.phase.name(),
            row.activation.name(),
            musclefem_io::csv::format_number(row.vm95)
        ));
    }
    Ok(PendingFile::stage_bytes(path, text.as_bytes())?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_percentile_interpolates_between_order_statistics() {
        let values: Vec<f64> = (0..=100).rev().map(f64::from).collect();
        assert_eq!(percentile(&values, 0.95), Some(95.0));
        assert_eq!(percentile(&[3.0, 1.0], 0.5), Some(2.0));
        assert_eq!(percentile(&[7.0], 0.95), Some(7.0));
        assert_eq!(percentile(&[], 0.95), None);
        // 20 values 1..=20: h = 0.95 × 19 = 18.05, between 19 and 20.
        let twenty: Vec<f64> = (1..=20).map(f64::from).collect();
        assert!((percentile(&twenty, 0.95).unwrap() - 19.05).abs() < 1e-12);
    }

    #[test]
    fn the_table_interpolates_each_angle_in_both_phases() {
        let squat = Squat::to_ninety_degrees(2.0);
        // vm95 = 1000 × t for one muscle, recorded every 0.1 s.
        let samples: Vec<StressSample> = (0..=20)
            .map(|k| {
                let time = 0.1 * f64::from(k);
                StressSample {
                    time,
                    flexion: squat.flexion_at(time),
                    vm95: vec![1000.0 * time],
                    location: vec![PeakLocation::default()],
                    min_jacobian_ratio: 1.0,
                }
            })
            .collect();
        let rows = peak_stress_rows(
            &samples,
            &[Quadriceps::VastusMedialis],
            &squat,
            Activation::Active,
        )
        .unwrap();
        assert_eq!(rows.len(), 8);
        for row in &rows {
            let down = flexion_time(&squat, row.angle_degrees.to_radians());
            let time = match row.phase {
                Phase::Flexion => down,
                Phase::Extension => 2.0 - down,
            };
            assert!((row.vm95 - 1000.0 * time).abs() < 1e-9, "{row:?}");
        }
        assert!(
            peak_stress_rows(
                &samples[..5],
                &[Quadriceps::VastusMedialis],
                &squat,
                Activation::Active
            )
            .is_err()
        );
    }

    #[test]
    fn peaks_are_located_by_potential_then_interface() {
        let interface: BTreeSet<u32> = [4].into_iter().collect();
        let regions = ElementRegions::new(
            vec![0.95, 0.05, 0.5, 0.5],
            &[0, 1, 2, 3, 4, 5, 6, 7],
            2,
            &interface,
        );
        let location = regions.locate(&[10.0, 10.0, 10.0, 1.0], 5.0);
        assert_eq!(
            location,
            PeakLocation {
                origin: 1,
                insertion: 1,
                interface: 1,
                belly: 0
            }
        );
        assert!(location.describe().starts_with("origin 33 %"));
    }
}
