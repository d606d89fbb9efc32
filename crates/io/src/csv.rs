//! CSV tables of numbers at full precision, written atomically.
//!
//! Numbers are written so that parsing them gives back the same `f64` bit for bit: the
//! shortest round-trip decimal, in plain notation for magnitudes in [1e-4, 1e15) and in
//! scientific notation (`1.5e-7`) otherwise. Every CSV reader (Python, pandas, NumPy,
//! spreadsheets) reads both forms.

use std::fmt::Write as _;
use std::path::Path;

use musclefem_materials::driver::{UNIAXIAL_CSV_HEADER, UniaxialRow};

use crate::OutputError;
use crate::atomic::PendingFile;
use crate::delimited::{DelimitedTable, parse_delimited};

/// `x` as the shortest decimal that parses back to the same `f64`.
pub fn format_number(x: f64) -> String {
    let magnitude = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&magnitude) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A CSV text: the `header` line, then one line per row of numbers.
pub fn format_table<R: AsRef<[f64]>>(header: &str, rows: impl IntoIterator<Item = R>) -> String {
    let mut text = String::with_capacity(header.len() + 1);
    text.push_str(header);
    text.push('\n');
    for row in rows {
        for (i, &x) in row.as_ref().iter().enumerate() {
            if i > 0 {
                text.push(',');
            }
            // Writing to a String cannot fail.
            let _ = write!(text, "{}", format_number(x));
        }
        text.push('\n');
    }
    text
}

/// The columns of one driver row, in the order of [`UNIAXIAL_CSV_HEADER`].
fn uniaxial_columns(row: &UniaxialRow) -> [f64; 5] {
    [
        row.time,
        row.stretch,
        row.engineering_stress,
        row.cauchy_stress,
        row.jacobian,
    ]
}

/// The material-point driver's history as CSV text (header [`UNIAXIAL_CSV_HEADER`]).
pub fn format_uniaxial(rows: &[UniaxialRow]) -> String {
    format_table(UNIAXIAL_CSV_HEADER, rows.iter().map(uniaxial_columns))
}

/// Stage the driver's history for `path` (commit it with [`PendingFile::commit`]).
pub fn stage_uniaxial_csv(path: &Path, rows: &[UniaxialRow]) -> Result<PendingFile, OutputError> {
    PendingFile::stage_bytes(path, format_uniaxial(rows).as_bytes())
}

/// Write the driver's history to `path` atomically.
pub fn write_uniaxial_csv(path: &Path, rows: &[UniaxialRow]) -> Result<(), OutputError> {
    stage_uniaxial_csv(path, rows)?.commit()
}

/// Read a table written by [`format_table`]: checks the header, returns the rows. Errors
/// name the file and the line.
pub fn read_table(path: &Path, header: &str) -> Result<Vec<Vec<f64>>, OutputError> {
    Ok(read_table_lines(path, header)?
        .into_iter()
        .map(|(_, row)| row)
        .collect())
}

/// A numeric table with any header (a run's `history.csv`, say): the column names and
/// the columns [one `Vec` per name]. Read as [`crate::delimited`] reads tables (a
/// byte-order mark, `;` or tab separators, quotes); errors name the file and the line.
pub fn read_columns(path: &Path) -> Result<(Vec<String>, Vec<Vec<f64>>), OutputError> {
    let table = read_delimited(path)?;
    let mut columns = vec![Vec::new(); table.names.len()];
    for (_, row) in numeric_rows(path, &table)? {
        for (column, value) in columns.iter_mut().zip(row) {
            column.push(value);
        }
    }
    Ok((table.names, columns))
}

/// [`read_table`] with the 1-based line of each row, for checks that name the line.
pub fn read_table_lines(path: &Path, header: &str) -> Result<Vec<(usize, Vec<f64>)>, OutputError> {
    let table = read_delimited(path)?;
    let expected: Vec<&str> = header.split(',').collect();
    if table.names != expected {
        return Err(OutputError::Parse {
            path: path.to_path_buf(),
            line: 1,
            message: format!(
                "header '{}', expected '{header}'",
                table.names.join(&table.separator.to_string())
            ),
        });
    }
    numeric_rows(path, &table)
}

/// The text of `path` as a [`DelimitedTable`].
fn read_delimited(path: &Path) -> Result<DelimitedTable, OutputError> {
    let text = std::fs::read_to_string(path).map_err(|e| OutputError::io("read", path, e))?;
    parse_delimited(&text).map_err(|e| OutputError::Parse {
        path: path.to_path_buf(),
        line: e.line,
        message: e.message,
    })
}

/// Every row of `table` as numbers, one per column, with its line.
fn numeric_rows(
    path: &Path,
    table: &DelimitedTable,
) -> Result<Vec<(usize, Vec<f64>)>, OutputError> {
    let columns = table.names.len();
    let error = |line: usize, message: String| OutputError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    table
        .rows
        .iter()
        .map(|row| {
            if row.fields.len() != columns {
                return Err(error(
                    row.line,
                    format!("{} fields, expected {columns}", row.fields.len()),
                ));
            }
            let values = (0..columns)
                .map(|c| table.number(row, c).map_err(|e| error(e.line, e.message)))
                .collect::<Result<Vec<f64>, _>>()?;
            Ok((row.line, values))
        })
        .collect()
}

/// Read back a driver history written by [`write_uniaxial_csv`].
pub fn read_uniaxial_csv(path: &Path) -> Result<Vec<UniaxialRow>, OutputError> {
    Ok(read_table(path, UNIAXIAL_CSV_HEADER)?
        .into_iter()
        .map(|r| UniaxialRow {
            time: r[0],
            stretch: r[1],
            engineering_stress: r[2],
            cauchy_stress: r[3],
            jacobian: r[4],
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atomic::tests::test_dir;

    fn awkward_rows() -> Vec<UniaxialRow> {
        let values = [
            0.0,
            1.0,
            0.1 + 0.2,
            1.0 / 3.0,
            -2.5e-9,
            1.234_567_890_123_456_7e20,
            f64::MIN_POSITIVE,
            -f64::MAX,
            5e-324,
            12_345.678_901_234_5,
        ];
        values
            .windows(5)
            .enumerate()
            .map(|(i, w)| UniaxialRow {
                time: i as f64 * 1e-3,
                stretch: w[0],
                engineering_stress: w[1],
                cauchy_stress: w[2],
                jacobian: w[3] + w[4],
            })
            .collect()
    }

    #[test]
    fn numbers_round_trip_exactly() {
        for row in awkward_rows() {
            for x in uniaxial_columns(&row) {
                let text = format_number(x);
                assert_eq!(
                    text.parse::<f64>().unwrap().to_bits(),
                    x.to_bits(),
                    "{text}"
                );
            }
        }
        assert_eq!(format_number(0.001), "0.001");
        assert_eq!(format_number(1.5e-7), "1.5e-7");
        assert_eq!(format_number(1100.0), "1100");
    }

    #[test]
    fn uniaxial_csv_round_trips() {
        let dir = test_dir("csv-round-trip");
        let path = dir.join("history.csv");
        let rows = awkward_rows();
        write_uniaxial_csv(&path, &rows).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text.lines().next().unwrap(), UNIAXIAL_CSV_HEADER);
        assert_eq!(
            UNIAXIAL_CSV_HEADER,
            "time_s,stretch,engineering_stress_pa,cauchy_stress_pa,jacobian"
        );
        let back = read_uniaxial_csv(&path).unwrap();
        assert_eq!(back, rows);
    }

    #[test]
    fn bad_csv_names_file_and_line() {
        let dir = test_dir("csv-bad");
        let path = dir.join("bad.csv");
        std::fs::write(
            &path,
            format!("{UNIAXIAL_CSV_HEADER}\n0,1,2,3,4\n0,1,x,3,4\n"),
        )
        .unwrap();
        let err = read_uniaxial_csv(&path).unwrap_err().to_string();
        assert!(
            err.contains("bad.csv") && err.contains("line 3") && err.contains("'x'"),
            "{err}"
        );
        std::fs::write(&path, "a,b\n").unwrap();
        let err = read_uniaxial_csv(&path).unwrap_err().to_string();
        assert!(err.contains("line 1") && err.contains("header"), "{err}");
    }
}
