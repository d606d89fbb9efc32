//! OpenSim storage files (`.sto`, `.mot`): a header of `key=value` lines closed by
//! `endheader`, then a table whose first row names the columns (`time` first), separated
//! by tabs (or by spaces, as some tools write them).
//!
//! Controls (excitations) from computed muscle control, states (`.../activation`
//! columns) from a forward simulation and motion files all have this shape;
//! [`read_storage`] gives the columns by name, checked for numbers and increasing times.

use std::path::Path;

use crate::delimited::{DelimitedError, parse_delimited};

/// A storage file's table: the column names and the values row by row.
#[derive(Debug, Clone, PartialEq)]
pub struct Storage {
    pub names: Vec<String>,
    /// One row per sample, a value per column.
    pub rows: Vec<Vec<f64>>,
}

impl Storage {
    /// The samples (time, value) of column `name` against the column `time`, or the
    /// names that are there.
    pub fn column(&self, time: &str, name: &str) -> Result<Vec<(f64, f64)>, String> {
        let index = |wanted: &str| {
            self.names.iter().position(|n| n == wanted).ok_or_else(|| {
                format!(
                    "no column '{wanted}'; the columns are: {}",
                    self.names.join(", ")
                )
            })
        };
        let (t, v) = (index(time)?, index(name)?);
        Ok(self.rows.iter().map(|row| (row[t], row[v])).collect())
    }
}

/// Parse the text of a storage file (errors name the line in the file).
pub fn parse_storage(text: &str) -> Result<Storage, DelimitedError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let lines: Vec<&str> = text.lines().collect();
    let Some(end) = lines
        .iter()
        .position(|l| l.trim().eq_ignore_ascii_case("endheader"))
    else {
        return Err(DelimitedError {
            line: 1,
            message: "no 'endheader' line: not an OpenSim storage file".into(),
        });
    };
    // Tabs as OpenSim writes them; runs of spaces from other tools become tabs.
    let table: String = lines[end + 1..]
        .iter()
        .map(|line| {
            if line.contains('\t') {
                line.to_string()
            } else {
                line.split_whitespace().collect::<Vec<_>>().join("\t")
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let delimited = parse_delimited(&table).map_err(|e| DelimitedError {
        line: e.line + end + 1,
        message: e.message,
    })?;
    let mut rows = Vec::with_capacity(delimited.rows.len());
    for row in &delimited.rows {
        let values = (0..delimited.names.len())
            .map(|c| delimited.number(row, c))
            .collect::<Result<Vec<f64>, _>>()
            .map_err(|e| DelimitedError {
                line: e.line + end + 1,
                message: e.message,
            })?;
        rows.push(values);
    }
    Ok(Storage {
        names: delimited.names,
        rows,
    })
}

/// Read the storage file at `path`.
pub fn read_storage(path: &Path) -> Result<Storage, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse_storage(&text).map_err(|e| format!("{}:{}: {}", path.display(), e.line, e.message))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The head of a computed-muscle-control controls file (OpenSim 4 writes this).
    const CONTROLS: &str = "subject01_walk1_controls\nversion=1\nnRows=3\nnColumns=3\n\
        inDegrees=no\nendheader\ntime\tvasmed_r\tvaslat_r\n0.5\t0.01\t0.02\n0.51\t0.2\t0.25\n\
        0.52\t0.4\t0.41\n";

    #[test]
    fn reads_the_columns_of_a_controls_file() {
        let storage = parse_storage(CONTROLS).unwrap();
        assert_eq!(storage.names, ["time", "vasmed_r", "vaslat_r"]);
        assert_eq!(
            storage.column("time", "vaslat_r").unwrap(),
            [(0.5, 0.02), (0.51, 0.25), (0.52, 0.41)]
        );
        let missing = storage.column("time", "recfem_r").unwrap_err();
        assert!(missing.contains("vasmed_r, vaslat_r"), "{missing}");
    }

    #[test]
    fn space_separated_tables_and_bad_numbers_are_read_or_named() {
        let spaced = "version=1\nendheader\ntime  a   b\n0 0.1 0.2\n1 0.3 0.4\n";
        assert_eq!(parse_storage(spaced).unwrap().rows[1], [1.0, 0.3, 0.4]);
        let bad = "version=1\nendheader\ntime\ta\n0\t0.1\n1\tx\n";
        let error = parse_storage(bad).unwrap_err();
        assert_eq!(error.line, 5, "{error}");
        assert!(parse_storage("time,a\n0,1\n").is_err());
    }
}
