//! The short summary printed after a material-point run: number of steps, engineering
//! stress at given stretches, peak engineering stress.

use std::fmt::Write as _;

use musclefem_materials::driver::UniaxialRow;

/// Stretches at which the summary reports the engineering stress.
pub const REPORTED_STRETCHES: [f64; 2] = [1.1, 1.2];

/// Relative tolerance within which a row's stretch counts as reaching a target (the
/// last knot of "0:1,2:1.2" may come out as 1.1999999999999997).
const REACH_TOLERANCE: f64 = 1e-12;

/// Engineering stress where the history reaches a stretch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StressAtStretch {
    /// Engineering stress P₁₁ [Pa], interpolated linearly between the bracketing rows.
    pub stress: f64,
    /// Time at which the stretch is reached [s], interpolated likewise.
    pub time: f64,
}

/// Engineering stress at `target` on the **last rise** of the stretch to it: the last
/// pair of consecutive rows with λᵢ < target ≤ λᵢ₊₁, interpolated linearly in λ. If the
/// history never rises to `target` but sits exactly on it (e.g. it starts there), the last
/// such row. `None` if the history never reaches `target`.
pub fn stress_at_stretch(rows: &[UniaxialRow], target: f64) -> Option<StressAtStretch> {
    let reached = |stretch: f64| stretch >= target - REACH_TOLERANCE * target.abs();
    let rise = (1..rows.len())
        .rev()
        .find(|&i| !reached(rows[i - 1].stretch) && reached(rows[i].stretch));
    match rise {
        Some(i) => {
            let (a, b) = (&rows[i - 1], &rows[i]);
            let w = ((target - a.stretch) / (b.stretch - a.stretch)).clamp(0.0, 1.0);
            Some(StressAtStretch {
                stress: a.engineering_stress + w * (b.engineering_stress - a.engineering_stress),
                time: a.time + w * (b.time - a.time),
            })
        }
        None => rows
            .iter()
            .rev()
            .find(|r| (r.stretch - target).abs() <= REACH_TOLERANCE * target.abs())
            .map(|r| StressAtStretch {
                stress: r.engineering_stress,
                time: r.time,
            }),
    }
}

/// The row of largest |engineering stress| (the first one on a tie).
pub fn peak_row(rows: &[UniaxialRow]) -> Option<&UniaxialRow> {
    rows.iter()
        .fold(None, |best: Option<&UniaxialRow>, row| match best {
            Some(b) if b.engineering_stress.abs() >= row.engineering_stress.abs() => Some(b),
            _ => Some(row),
        })
}

/// Summary lines (indented by two spaces) of a run.
pub fn summarize(rows: &[UniaxialRow]) -> String {
    let mut text = String::new();
    let steps = rows.len().saturating_sub(1);
    if let (Some(first), Some(last)) = (rows.first(), rows.last()) {
        let _ = writeln!(
            text,
            "  {steps} step{}, t = {} .. {} s, stretch {:.4} -> {:.4}",
            if steps == 1 { "" } else { "s" },
            first.time,
            last.time,
            first.stretch,
            last.stretch
        );
    }
    for target in REPORTED_STRETCHES {
        match stress_at_stretch(rows, target) {
            Some(at) => {
                let _ = writeln!(
                    text,
                    "  engineering stress at stretch {target}: {:.4} kPa (t = {:.4} s)",
                    at.stress / 1e3,
                    at.time
                );
            }
            None => {
                let _ = writeln!(
                    text,
                    "  engineering stress at stretch {target}: not reached"
                );
            }
        }
    }
    if let Some(peak) = peak_row(rows) {
        let _ = writeln!(
            text,
            "  peak engineering stress: {:.4} kPa (t = {:.4} s, stretch {:.4})",
            peak.engineering_stress / 1e3,
            peak.time,
            peak.stretch
        );
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(time: f64, stretch: f64, stress: f64) -> UniaxialRow {
        UniaxialRow {
            time,
            stretch,
            engineering_stress: stress,
            cauchy_stress: stress * stretch,
            jacobian: 1.0,
        }
    }

    #[test]
    fn interpolates_on_the_last_rise() {
        // Up to 1.2, down to 1.0, up to 1.2 again with a different stress.
        let rows = vec![
            row(0.0, 1.0, 0.0),
            row(1.0, 1.2, 200.0),
            row(2.0, 1.0, 0.0),
            row(3.0, 1.15, 500.0),
            row(4.0, 1.2, 700.0),
        ];
        let at = stress_at_stretch(&rows, 1.1).unwrap();
        assert!(
            (at.stress - (0.0 + (0.1 / 0.15) * 500.0)).abs() < 1e-9,
            "{at:?}"
        );
        assert!((at.time - (2.0 + 0.1 / 0.15)).abs() < 1e-12);
        let at = stress_at_stretch(&rows, 1.2).unwrap();
        assert_eq!((at.stress, at.time), (700.0, 4.0));
        assert!(stress_at_stretch(&rows, 1.3).is_none());
    }

    #[test]
    fn hold_then_rise_uses_the_rise() {
        // 0:1, 0.5:1, 2.5:1.2 with rows every 0.5 s; the last knot slightly below 1.2.
        let rows = vec![
            row(0.0, 1.0, 0.0),
            row(0.5, 1.0, 50.0),
            row(1.0, 1.05, 60.0),
            row(1.5, 1.1, 70.0),
            row(2.0, 1.15, 80.0),
            row(2.5, 1.199_999_999_999_999_7, 90.0),
        ];
        assert_eq!(stress_at_stretch(&rows, 1.1).unwrap().stress, 70.0);
        assert_eq!(stress_at_stretch(&rows, 1.2).unwrap().stress, 90.0);
        assert_eq!(stress_at_stretch(&rows, 1.0).unwrap().stress, 50.0);
        assert_eq!(peak_row(&rows).unwrap().time, 2.5);
    }

    #[test]
    fn summary_mentions_everything() {
        let rows = vec![row(0.0, 1.0, 0.0), row(1.0, 1.2, 2000.0)];
        let text = summarize(&rows);
        assert!(text.contains("1 step,"), "{text}");
        assert!(text.contains("stretch 1.1: 1.0000 kPa"), "{text}");
        assert!(text.contains("stretch 1.2: 2.0000 kPa"), "{text}");
        assert!(
            text.contains("peak engineering stress: 2.0000 kPa"),
            "{text}"
        );
        let text = summarize(&rows[..1]);
        assert!(text.contains("stretch 1.1: not reached"), "{text}");
    }
}
