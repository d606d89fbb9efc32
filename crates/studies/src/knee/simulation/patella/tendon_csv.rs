//! `tendon.csv`: at every report of the quadriceps' pull, the pull measured and the
//! patellar tendon's state the run's patella was posed with; and a one-line summary.

use std::path::Path;

use anyhow::Result;

use super::TendonState;

/// One report of the run: the pull it measured and the tendon's state it ran with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TendonRow {
    /// Time [s].
    pub time: f64,
    /// T = Σ |R| measured at the insertions at `time` [N].
    pub measured_tension: f64,
    /// The equilibrium the run's patella was in at `time` (posed with the applied pull,
    /// relaxed from the reports before).
    pub applied: TendonState,
}

/// Header of `tendon.csv`.
pub const TENDON_CSV_HEADER: &str = "time_s,knee_angle_deg,measured_tension_n,applied_tension_n,\
tendon_force_n,tendon_strain,force_ratio,patella_flexion_deg,patella_x_m,patella_y_m";

/// The values of one row of `tendon.csv`, in the order of [`TENDON_CSV_HEADER`].
pub fn tendon_values(row: &TendonRow) -> [f64; 10] {
    let state = &row.applied;
    [
        row.time,
        state.knee_angle.to_degrees(),
        row.measured_tension,
        state.quadriceps_tension,
        state.tendon_force,
        state.tendon_strain,
        state.force_ratio,
        state.pose.flexion.to_degrees(),
        state.pose.centre.x,
        state.pose.centre.y,
    ]
}

/// Writes `rows` to `path` (atomically: nothing half-written).
pub fn write_tendon_csv(path: &Path, rows: &[TendonRow]) -> Result<()> {
    let mut text = format!("{TENDON_CSV_HEADER}\n");
    for row in rows {
        let cells: Vec<String> = tendon_values(row).iter().map(f64::to_string).collect();
        text.push_str(&cells.join(","));
        text.push('\n');
    }
    musclefem_io::atomic::write_atomically(path, text.as_bytes())?;
    Ok(())
}

/// One line on the tendon over a run: its peak force and strain, and how far the pull
/// the patella was posed with (the applied pull) strayed from the pull then measured, over
/// the peak pull.
pub fn tendon_summary(rows: &[TendonRow]) -> String {
    let Some(peak) = rows
        .iter()
        .max_by(|a, b| a.applied.tendon_force.total_cmp(&b.applied.tendon_force))
    else {
        return "patellar tendon: no pull reported\n".to_string();
    };
    let largest_pull = rows.iter().map(|r| r.measured_tension).fold(0.0, f64::max);
    let lag = rows
        .iter()
        .map(|r| (r.applied.quadriceps_tension - r.measured_tension).abs())
        .fold(0.0, f64::max);
    format!(
        "patellar tendon: peak {:.0} N at {:.1}° of flexion ({:.1} % strain, {:.2} mm); the \
         patella was posed with a pull within {:.2} % of the peak pull ({:.0} N) of the one \
         then measured\n",
        peak.applied.tendon_force,
        peak.applied.knee_angle.to_degrees(),
        100.0 * peak.applied.tendon_strain,
        1e3 * (peak.applied.tendon_length
            - peak.applied.tendon_length / (1.0 + peak.applied.tendon_strain)),
        100.0 * lag / largest_pull.max(f64::MIN_POSITIVE),
        largest_pull,
    )
}
