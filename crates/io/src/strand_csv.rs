//! Tendon strands as CSV: one row per strand with its two end nodes (labels of the mesh
//! file the scene's `[[strands]]` entry names), its slack length ℓ₀ [m], its strain
//! stiffness k = E A [N] and the spread strain ε_l of its toe region [-], header exactly
//! [`STRANDS_CSV_HEADER`]. `musclefem knee` writes it for the Visible Human knee; a scene
//! reads it with `[[strands]] file = "..."` (`docs/scene-format.md`). The law is
//! `musclefem_contact::ToeLinearLaw`.

use std::path::Path;

use crate::OutputError;
use crate::csv::{format_table, read_table_lines};

/// The header of a strands file.
pub const STRANDS_CSV_HEADER: &str = "node_a,node_b,slack_length,strain_stiffness,toe_strain";

/// One strand as the file gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct StrandRow {
    /// Node a's label in the mesh file (the muscle's end: the side whose pull is reported).
    pub node_a: i64,
    /// Node b's label (e.g. a node carried with a bone).
    pub node_b: i64,
    /// Slack length ℓ₀ [m]: no tension at or below it.
    pub slack_length: f64,
    /// k = E A: tension per unit strain in the linear region [N].
    pub strain_stiffness: f64,
    /// Spread strain ε_l of the toe region (the toe ends at 2 ε_l) [-].
    pub toe_strain: f64,
}

/// The strands file text (numbers as the shortest decimals that read back bit for bit).
pub fn format_strands_csv(rows: &[StrandRow]) -> String {
    format_table(
        STRANDS_CSV_HEADER,
        rows.iter().map(|r| {
            [
                r.node_a as f64,
                r.node_b as f64,
                r.slack_length,
                r.strain_stiffness,
                r.toe_strain,
            ]
        }),
    )
}

/// Read a strands file, each row with its 1-based line. Errors name the file and line:
/// a wrong header, a non-numeric field, a fractional node label. The values themselves
/// (ℓ₀ > 0, k > 0, ε_l ≥ 0, two different nodes) are checked where the strands are
/// built (`musclefem_contact::TendonStrands::new`), which names the strand.
pub fn read_strands_csv(path: &Path) -> Result<Vec<(usize, StrandRow)>, OutputError> {
    let error = |line: usize, message: String| OutputError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    let label = |line: usize, value: f64, column: &str| {
        if value.fract() != 0.0 || value.abs() > 2f64.powi(53) {
            Err(error(line, format!("{column} {value} is not a node label")))
        } else {
            Ok(value as i64)
        }
    };
    read_table_lines(path, STRANDS_CSV_HEADER)?
        .into_iter()
        .map(|(line, row)| {
            Ok((
                line,
                StrandRow {
                    node_a: label(line, row[0], "node_a")?,
                    node_b: label(line, row[1], "node_b")?,
                    slack_length: row[2],
                    strain_stiffness: row[3],
                    toe_strain: row[4],
                },
            ))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str, text: &str) -> std::path::PathBuf {
        let dir =
            std::env::temp_dir().join(format!("musclefem-strands-csv-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn strands_read_back_bit_for_bit() {
        let rows = vec![
            StrandRow {
                node_a: 7,
                node_b: 1234567,
                slack_length: 0.046_5,
                strain_stiffness: 1.0 / 3.0 * 1e4,
                toe_strain: 0.015,
            },
            StrandRow {
                node_a: 8,
                node_b: 1234567,
                slack_length: 0.1 + 0.2,
                strain_stiffness: 50_000.0,
                toe_strain: 0.0,
            },
        ];
        let path = temp("round_trip.csv", &format_strands_csv(&rows));
        let read: Vec<StrandRow> = read_strands_csv(&path)
            .unwrap()
            .into_iter()
            .map(|(_, r)| r)
            .collect();
        assert_eq!(read, rows);
    }

    #[test]
    fn a_fractional_label_names_its_line() {
        let text = format!("{STRANDS_CSV_HEADER}\n1,2,0.01,100,0.01\n1.5,2,0.01,100,0.01\n");
        let path = temp("fractional.csv", &text);
        let message = read_strands_csv(&path).unwrap_err().to_string();
        assert!(message.contains("line 3"), "{message}");
        assert!(
            message.contains("node_a 1.5 is not a node label"),
            "{message}"
        );
    }
}
