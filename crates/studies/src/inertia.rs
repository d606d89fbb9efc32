//! Is an explicit run quasi-static? Mass scaling (or a fast load) gives the body kinetic
//! energy K; while K stays a small fraction of the internal (strain) energy W_int the
//! inertial forces are small against the internal ones and the response is the
//! quasi-static one. Past [`KINETIC_TO_INTERNAL_LIMIT`] the run is flagged (the usual
//! rule of thumb for mass-scaled quasi-static analyses is 5–10 %).

use musclefem_core::solver::explicit::HistoryRow;

/// Largest K/W_int [1] of a run that counts as quasi-static.
pub const KINETIC_TO_INTERNAL_LIMIT: f64 = 0.05;

/// The largest K/W_int over the history rows at or after `from_time` [s] with W_int > 0
/// (0 if none). Starting after the load has built up some strain energy avoids the
/// start-up, where W_int ≈ 0.
pub fn largest_kinetic_to_internal(rows: &[HistoryRow], from_time: f64) -> f64 {
    rows.iter()
        .filter(|r| r.time >= from_time && r.internal_energy > 0.0)
        .map(|r| r.kinetic_energy / r.internal_energy)
        .fold(0.0, f64::max)
}

/// A warning if `kinetic_to_internal` (K/W_int) exceeds [`KINETIC_TO_INTERNAL_LIMIT`].
pub fn inertia_warning(kinetic_to_internal: f64) -> Option<String> {
    (kinetic_to_internal > KINETIC_TO_INTERNAL_LIMIT).then(|| {
        format!(
            "the kinetic energy reached {:.1} % of the internal energy (limit {:.0} %): \
             inertia, e.g. from mass scaling, pollutes the quasi-static response; use a \
             smaller mass-scaling step or the implicit solver",
            100.0 * kinetic_to_internal,
            100.0 * KINETIC_TO_INTERNAL_LIMIT
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_large_kinetic_energy_is_flagged() {
        assert!(inertia_warning(0.01).is_none());
        let warning = inertia_warning(0.2).unwrap();
        assert!(
            warning.contains("20.0 %") && warning.contains("limit 5 %"),
            "{warning}"
        );
    }
}
