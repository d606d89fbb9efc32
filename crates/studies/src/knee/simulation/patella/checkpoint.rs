//! The patella's part of a knee checkpoint: the pull reports its pose follows (the latest
//! measured pull and the two filter stages at it). The cached pose is not stored: it is
//! a function of the reports and the time, recomputed on the first request.

use musclefem_core::solver::{CheckpointReader, CheckpointWriter, SolverError};

use super::TendonPatella;

impl TendonPatella {
    /// Writes the reports for a checkpoint.
    pub fn save_reports(&self, out: &mut CheckpointWriter) {
        let reports = self.reports();
        out.optional_f64(reports.latest.map(|(time, _)| time));
        out.f64(reports.latest.map_or(0.0, |(_, tension)| tension));
        out.f64s(&reports.stages_at_latest);
    }

    /// Reads what [`TendonPatella::save_reports`] wrote.
    pub fn restore_reports(&self, input: &mut CheckpointReader) -> Result<(), SolverError> {
        let time = input.optional_f64()?;
        let tension = input.f64()?;
        let mut stages = [0.0; 2];
        input.f64s_into("the patella's pull stages", &mut stages)?;
        let mut reports = self.reports();
        reports.latest = time.map(|t| (t, tension));
        reports.stages_at_latest = stages;
        reports.cached = None;
        Ok(())
    }
}
