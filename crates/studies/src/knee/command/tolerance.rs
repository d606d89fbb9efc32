//! `musclefem knee --tolerance PERCENT`: the cheapest measured setting of the squat (solver,
//! element, resolution, step) whose passive vm95 error against the medium mesh is within a
//! tolerance.

use std::path::Path;

use anyhow::{Context, Result, bail};

use crate::bench::csv::WorkPrecisionRow;
use crate::bench::knee::squat_of;
use crate::bench::{Problem, reference_method, select};
use crate::elongation::Solver;
use crate::knee::Resolution;
use crate::knee::simulation::SquatSettings;
use crate::knee::simulation::resolution::resolution_within;

/// The cheapest measured squat setting within `percent` [%] and why: from the knee rows
/// of the work–precision table `table` (see [`crate::bench::select`]) when it has
/// some, else from the resolution chart measured with the program
/// ([`resolution_within`]). When no measured run is within it: the bench's reference
/// (medium), whose own error is not measured.
pub fn setting_within(percent: f64, table: &Path) -> Result<(SquatSettings, Resolution, String)> {
    if !(percent.is_finite() && percent > 0.0) {
        bail!("--tolerance {percent} must be a positive percentage");
    }
    let rows: Vec<WorkPrecisionRow> = match std::fs::read_to_string(table) {
        Ok(text) => select::read_table(&text)
            .with_context(|| format!("reading {}", table.display()))?
            .into_iter()
            .filter(|r| r.problem == Problem::Knee.name())
            .collect(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Vec::new(),
        Err(e) => return Err(e).with_context(|| format!("reading {}", table.display())),
    };
    if rows.is_empty() {
        let (resolution, why) = resolution_within(percent)?;
        let why = format!(
            "{why}; implicit hex8-fbar (no knee runs in {}: `musclefem bench --problem knee` \
             measures them on this machine)",
            table.display()
        );
        return Ok((
            SquatSettings::recommended(Solver::Implicit),
            resolution,
            why,
        ));
    }
    let tolerance = 1e-2 * percent;
    let (method, why) = match select::cheapest_within(&rows, Problem::Knee.name(), tolerance) {
        Some(row) => {
            let method = select::method_of(row)?;
            let why = format!(
                "--tolerance {percent} %: {} ({:.1} % off the medium reference, passive squat \
                 {:.0} s), the cheapest within it of the {} knee runs in {}",
                method.describe(),
                100.0 * row.error,
                row.wall_s,
                rows.len(),
                table.display()
            );
            (method, why)
        }
        None => {
            let best = rows
                .iter()
                .filter(|r| r.error.is_finite())
                .map(|r| r.error)
                .fold(f64::INFINITY, f64::min);
            let method = reference_method(Problem::Knee, false);
            let why = format!(
                "--tolerance {percent} %: {}, the bench's reference: none of the {} knee runs \
                 in {} is within it (the best is {:.1} % off), and the reference's own error \
                 is not measured, so {percent} % is not guaranteed",
                method.describe(),
                rows.len(),
                table.display(),
                100.0 * best
            );
            (method, why)
        }
    };
    let (settings, resolution) = squat_of(&method)?;
    Ok((settings, resolution, why))
}
