//! Fiber fields as CSV: one row per element with its id, centroid [m] and unit fiber
//! direction, header exactly [`FIBERS_CSV_HEADER`]. `musclefem fibers` writes it; a scene
//! part reads it with `fibers = { file = "..." }`.
//!
//! Element ids are the mesh file's element labels for a part read from a file, and the
//! 0-based element index for a generated mesh.

use std::path::Path;

use nalgebra::Vector3;

use crate::OutputError;
use crate::csv::{format_table, read_table_lines};

/// The header of a fibers file.
pub const FIBERS_CSV_HEADER: &str = "element,cx,cy,cz,fx,fy,fz";

/// One element's fiber.
#[derive(Clone, Debug, PartialEq)]
pub struct FiberRow {
    /// Element id (file label, or 0-based index of a generated mesh).
    pub element: i64,
    /// Element centroid [m].
    pub centroid: Vector3<f64>,
    /// Fiber direction (unit when written; normalised when read).
    pub direction: Vector3<f64>,
}

/// The fibers file text.
pub fn format_fibers_csv(rows: &[FiberRow]) -> String {
    format_table(
        FIBERS_CSV_HEADER,
        rows.iter().map(|r| {
            [
                r.element as f64,
                r.centroid.x,
                r.centroid.y,
                r.centroid.z,
                r.direction.x,
                r.direction.y,
                r.direction.z,
            ]
        }),
    )
}

/// Read a fibers file, each row with its 1-based line. Errors name the file and line: a
/// wrong header, a non-numeric field, a fractional or out-of-range element id, a
/// non-finite or zero direction. Directions come back normalised; one that is unit to
/// round-off (|‖d‖ − 1| ≤ 4ε) comes back as written, bit for bit.
pub fn read_fibers_csv(path: &Path) -> Result<Vec<(usize, FiberRow)>, OutputError> {
    let error = |line: usize, message: String| OutputError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    read_table_lines(path, FIBERS_CSV_HEADER)?
        .into_iter()
        .map(|(line, row)| {
            let id = row[0];
            if id.fract() != 0.0 || id.abs() > 2f64.powi(53) {
                return Err(error(line, format!("element id {id} is not an integer")));
            }
            let direction = Vector3::new(row[4], row[5], row[6]);
            let norm = direction.norm();
            if !(norm.is_finite() && norm > 0.0) {
                return Err(error(
                    line,
                    format!(
                        "fiber direction {:?} is not a direction",
                        row[4..7].to_vec()
                    ),
                ));
            }
            Ok((
                line,
                FiberRow {
                    element: id as i64,
                    centroid: Vector3::new(row[1], row[2], row[3]),
                    direction: unit(direction, norm),
                },
            ))
        })
        .collect()
}

/// Largest |‖d‖ − 1| of a direction taken as already unit: a few rounding errors of the
/// norm of a normalised vector.
const UNIT_TOLERANCE: f64 = 4.0 * f64::EPSILON;

/// `direction` (of norm `norm`) made unit: as written when it is unit to round-off, so
/// that a field written with round-trip numbers reads back bit for bit (dividing by its
/// norm again would move its last bits); else divided by its norm.
fn unit(direction: Vector3<f64>, norm: f64) -> Vector3<f64> {
    if (norm - 1.0).abs() <= UNIT_TOLERANCE {
        direction
    } else {
        direction / norm
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str, text: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("musclefem-fibers-csv-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn fibers_round_trip_and_come_back_normalised() {
        let rows = vec![
            FiberRow {
                element: 17,
                centroid: Vector3::new(0.1, 0.2, 0.3),
                direction: Vector3::new(0.0, 0.6, 0.8),
            },
            FiberRow {
                element: -2,
                centroid: Vector3::zeros(),
                direction: Vector3::new(2.0, 0.0, 0.0),
            },
        ];
        let path = temp("round.csv", &format_fibers_csv(&rows));
        let read = read_fibers_csv(&path).unwrap();
        assert_eq!(read[0], (2, rows[0].clone()));
        assert_eq!(read[1].1.direction, Vector3::x());
    }

    #[test]
    fn unit_directions_read_back_bit_for_bit() {
        // Normalised vectors whose norm is not exactly 1: dividing by it again would move
        // the last bits of some of them.
        let rows: Vec<FiberRow> = (1..200)
            .map(|k| {
                let k = f64::from(k);
                FiberRow {
                    element: k as i64,
                    centroid: Vector3::zeros(),
                    direction: Vector3::new(k.sin(), (2.0 * k).cos(), 0.3 * k.sqrt()).normalize(),
                }
            })
            .collect();
        let moved = rows
            .iter()
            .filter(|r| r.direction / r.direction.norm() != r.direction)
            .count();
        assert!(moved > 0, "no direction would have moved");
        let path = temp("unit.csv", &format_fibers_csv(&rows));
        let read = read_fibers_csv(&path).unwrap();
        for ((_, read), written) in read.iter().zip(&rows) {
            assert_eq!(
                read.direction.map(f64::to_bits),
                written.direction.map(f64::to_bits)
            );
        }
    }

    #[test]
    fn bad_rows_are_named_by_line() {
        let cases = [
            ("element,cx,cy,cz,fx,fy\n", 1, "header"),
            (
                "element,cx,cy,cz,fx,fy,fz\n1,0,0,0,1,0,0\n2.5,0,0,0,1,0,0\n",
                3,
                "integer",
            ),
            (
                "element,cx,cy,cz,fx,fy,fz\n1,0,0,0,0,0,0\n",
                2,
                "not a direction",
            ),
            (
                "element,cx,cy,cz,fx,fy,fz\n1,0,0,0,x,0,0\n",
                2,
                "not a number",
            ),
        ];
        for (i, (text, line, what)) in cases.into_iter().enumerate() {
            let path = temp(&format!("bad{i}.csv"), text);
            let message = read_fibers_csv(&path).unwrap_err().to_string();
            assert!(
                message.contains(&format!("line {line}:")) && message.contains(what),
                "{message}"
            );
        }
    }
}
