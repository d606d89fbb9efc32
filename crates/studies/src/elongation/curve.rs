//! The elongation test's result: engineering stress against engineering strain, written as
//! CSV with the header [`CURVE_CSV_HEADER`], and read off at given strains.

use std::path::Path;

use musclefem_io::PendingFile;
use musclefem_io::csv::format_table;
use musclefem_materials::Amplitude;

/// Header of `curve.csv`, exactly.
pub const CURVE_CSV_HEADER: &str =
    "time_s,engineering_strain,reaction_force_n,engineering_stress_pa";

/// One recorded instant of an elongation test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvePoint {
    /// Time [s].
    pub time: f64,
    /// Elongation / reference length [1].
    pub strain: f64,
    /// Axial reaction force on the pulled end [N] (positive in tension).
    pub force: f64,
    /// Reaction force / reference mid-belly cross-section area [Pa].
    pub stress: f64,
}

/// What turns a test's recorded rows (time, reaction of the pulled end) into curve
/// points: the pulled end's displacement against time and the specimen's reference
/// length and mid-belly area.
#[derive(Debug, Clone)]
pub struct CurveScale {
    /// Displacement of the pulled end [m] against time [s].
    pub pulled: Amplitude,
    /// Reference length L [m].
    pub length: f64,
    /// Reference area [m²]: the fusiform's π r_mid², the cylinder's own section
    /// ([`super::specimen::SpecimenMesh::reference_area`]).
    pub area: f64,
}

impl CurveScale {
    /// The point at `time` [s] with the pulled end's reaction `force` [N]: strain u(t)/L,
    /// stress F/A.
    pub fn point(&self, time: f64, force: f64) -> CurvePoint {
        CurvePoint {
            time,
            strain: self.pulled.value_at(time) / self.length,
            force,
            stress: force / self.area,
        }
    }

    /// The curve of recorded (time, force) rows, starting stress-free at t = 0 when the
    /// first row is later (the implicit solver records converged increments only).
    pub fn curve(&self, rows: impl IntoIterator<Item = (f64, f64)>) -> Curve {
        let mut points: Vec<CurvePoint> = rows
            .into_iter()
            .map(|(time, force)| self.point(time, force))
            .collect();
        self.start_at_rest(&mut points);
        Curve { points }
    }

    /// Put the stress-free point at t = 0 in front of `points` if they start later.
    pub fn start_at_rest(&self, points: &mut Vec<CurvePoint>) {
        if points.first().is_none_or(|p| p.time > 0.0) {
            points.insert(0, self.point(0.0, 0.0));
        }
    }
}

/// The points of a run in time order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Curve {
    pub points: Vec<CurvePoint>,
}

impl Curve {
    /// `curve.csv` text.
    pub fn to_csv(&self) -> String {
        format_table(
            CURVE_CSV_HEADER,
            self.points
                .iter()
                .map(|p| [p.time, p.strain, p.force, p.stress]),
        )
    }

    /// Stage `curve.csv` at `path` (commit with [`PendingFile::commit`]).
    pub fn stage_csv(&self, path: &Path) -> Result<PendingFile, musclefem_io::OutputError> {
        PendingFile::stage_bytes(path, self.to_csv().as_bytes())
    }

    /// Engineering stress at `strain` [Pa], linear between the recorded points of the
    /// stretching phase (the last point at each strain, so an isometric hold at zero
    /// strain counts with its final stress); `None` outside the recorded range.
    pub fn stress_at_strain(&self, strain: f64) -> Option<f64> {
        let stretching = self.stretching();
        // Strains accumulate round-off from the time stepping: 0.2 may be 0.19999999999999998.
        let reached = |p: &CurvePoint| p.strain >= strain - 1e-12 * strain.abs().max(1e-3);
        let after = stretching.iter().position(reached)?;
        let upper = stretching[after];
        if after == 0 || upper.strain <= strain {
            return reached(&upper).then_some(upper.stress);
        }
        let lower = stretching[after - 1];
        let weight = (strain - lower.strain) / (upper.strain - lower.strain);
        Some(lower.stress + weight * (upper.stress - lower.stress))
    }

    /// The points from the last one at the smallest strain on, i.e. without the hold.
    pub fn stretching(&self) -> &[CurvePoint] {
        let start = self
            .points
            .windows(2)
            .rposition(|w| w[1].strain <= w[0].strain)
            .map_or(0, |i| i + 1);
        &self.points[start..]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(time: f64, strain: f64, stress: f64) -> CurvePoint {
        CurvePoint {
            time,
            strain,
            force: stress * 1e-4,
            stress,
        }
    }

    #[test]
    fn the_stress_at_a_strain_interpolates_the_stretching_phase() {
        let curve = Curve {
            points: vec![
                point(0.0, 0.0, 0.0),
                point(0.25, 0.0, 50.0),
                point(0.5, 0.0, 100.0),
                point(1.0, 0.05, 200.0),
                point(1.5, 0.1, 400.0),
            ],
        };
        assert_eq!(curve.stretching().len(), 3);
        assert_eq!(curve.stress_at_strain(0.0), Some(100.0));
        assert_eq!(curve.stress_at_strain(0.075), Some(300.0));
        assert_eq!(curve.stress_at_strain(0.1), Some(400.0));
        assert_eq!(curve.stress_at_strain(0.2), None);
        assert!(curve.to_csv().starts_with(CURVE_CSV_HEADER));
    }
}
