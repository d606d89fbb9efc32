//! Which resolution of the procedural knee meets an accuracy (`musclefem knee --tolerance`),
//! from the resolutions' measured costs and errors, and what each costs
//! ([`resolution_rationale`], printed with every run).
//!
//! The chart is the measured one: the passive squat (implicit with inertia, F-bar hex8,
//! 20 ms increments) on coarse and medium, 2026-11-24, 2-core AMD EPYC. The error is that
//! of `musclefem bench`: the largest deviation of the 32 passive vm95 entries
//! (4 muscles × 30°/45°/60°/90° × flexion/extension) from the reference run's, over its
//! largest vm95. The reference is medium, the finest run: its own error is not measured
//! (fine was not run), so no tolerance can promise more than "as medium".
//! `musclefem bench --problem knee` measures the same chart on the user's machine (and
//! `knee --tolerance` reads it when given); its run of 2026-11-24 reproduced 11.7 %, with
//! medium in 914 s. The wall times are those of the same day with the mixed pressure in
//! Newton's tangent and METIS's fill-reducing order (each squat alone; before METIS 21 s
//! and 268 s, before the mixed pressure 37 s and 934 s); the errors did not change with
//! either (11.7 %).

use anyhow::{Result, bail};

use super::super::anatomy::Resolution;

/// One measured resolution: the error against the reference (`None` for the reference
/// itself) [1] and the wall time of the passive squat alone [s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasuredResolution {
    pub resolution: Resolution,
    pub error: Option<f64>,
    pub passive_wall_s: f64,
}

/// The knee's resolution chart, cheapest first. Coarse against medium: per entry up to
/// 37 % (mean 18 %); as the bench measures, 11.7 % of the largest vm95.
pub const RESOLUTION_CHART: [MeasuredResolution; 2] = [
    MeasuredResolution {
        resolution: Resolution::Coarse,
        error: Some(0.117),
        passive_wall_s: 12.9,
    },
    MeasuredResolution {
        resolution: Resolution::Medium,
        error: None,
        passive_wall_s: 124.0,
    },
];

/// The cheapest resolution whose measured error is at most `percent`, or the reference
/// when none is (its own error unknown), with the reason to print.
pub fn resolution_within(percent: f64) -> Result<(Resolution, String)> {
    if !(percent.is_finite() && percent > 0.0) {
        bail!("--tolerance {percent} must be a positive percentage");
    }
    let tolerance = 1e-2 * percent;
    let name = |r: Resolution| format!("{r:?}").to_lowercase();
    let reference = RESOLUTION_CHART
        .iter()
        .find(|m| m.error.is_none())
        .expect("the chart has a reference");
    if let Some(m) = RESOLUTION_CHART
        .iter()
        .find(|m| m.error.is_some_and(|e| e <= tolerance))
    {
        return Ok((
            m.resolution,
            format!(
                "--tolerance {percent} %: {} resolution, the cheapest measured within it \
                 ({:.1} % off {} in the passive vm95 table; passive squat alone {:.0} s)",
                name(m.resolution),
                100.0 * m.error.unwrap_or(0.0),
                name(reference.resolution),
                m.passive_wall_s
            ),
        ));
    }
    let misses: Vec<String> = RESOLUTION_CHART
        .iter()
        .filter_map(|m| {
            m.error
                .map(|e| format!("{} is {:.1} % off", name(m.resolution), 100.0 * e))
        })
        .collect();
    Ok((
        reference.resolution,
        format!(
            "--tolerance {percent} %: {} resolution, the finest measured ({}; {}'s own error \
             is not measured, so {percent} % is not guaranteed; passive squat alone {:.0} s)",
            name(reference.resolution),
            misses.join(", "),
            name(reference.resolution),
            reference.passive_wall_s
        ),
    ))
}

/// What a resolution of the procedural knee costs and how far its answer is from a finer
/// one, as measured (README, "The knee"): printed with every run.
pub fn resolution_rationale(resolution: Resolution) -> &'static str {
    match resolution {
        Resolution::Coarse => {
            "the default, the closed-chain model's measured mesh: passive and active side \
             by side took 14 minutes on 2 cores (2026-11-26); its passive vm95 differed \
             from medium's by up to 17 % at 45° and 60° (90° not reached on medium), so \
             read the table as the coarse model's answer"
        }
        Resolution::Medium => {
            "6 times coarse's elements: not yet run to the end on the \
             closed-chain model (its implicit passive squat reached 58° of flexion, t = 0.63 s \
             of 2 s, in 25 minutes on 2 cores beside another run, 2026-11-25); expect hours"
        }
        Resolution::Fine => {
            "not run yet: 35 840 muscle elements, about 4 times medium's unknowns; expect \
             hours, and memory for a Cholesky factor of order 1e8 entries"
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_loose_tolerance_takes_coarse_and_a_tight_one_medium_with_a_warning() {
        let (resolution, why) = resolution_within(15.0).unwrap();
        assert_eq!(resolution, Resolution::Coarse);
        assert!(why.contains("11.7 % off medium"), "{why}");
        let (resolution, why) = resolution_within(12.0).unwrap();
        assert_eq!(resolution, Resolution::Coarse, "{why}");
        let (resolution, why) = resolution_within(5.0).unwrap();
        assert_eq!(resolution, Resolution::Medium);
        assert!(why.contains("coarse is 11.7 % off"), "{why}");
        assert!(why.contains("not guaranteed"), "{why}");
        for bad in [0.0, -3.0, f64::NAN] {
            assert!(resolution_within(bad).is_err());
        }
    }

    #[test]
    fn the_chart_is_cheapest_first_with_one_reference() {
        assert!(
            RESOLUTION_CHART
                .windows(2)
                .all(|w| w[0].passive_wall_s < w[1].passive_wall_s)
        );
        assert_eq!(
            RESOLUTION_CHART
                .iter()
                .filter(|m| m.error.is_none())
                .count(),
            1
        );
    }
}
