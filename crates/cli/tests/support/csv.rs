//! CSV files that the commands write, read back as text for the tests: a header line of
//! names, then rows of fields split at every comma (a quoted field that holds commas
//! comes apart; the tests that read one allow for it).

#![allow(dead_code)]

use std::path::Path;

/// A CSV file's header names and its rows of fields, as text.
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let split = |line: &str| line.split(',').map(str::to_string).collect::<Vec<_>>();
    let header = split(lines.next().unwrap_or_default());
    (header, lines.map(split).collect())
}

/// A field as a number, naming the field when it is not one.
pub fn number(field: &str) -> f64 {
    field
        .parse()
        .unwrap_or_else(|e| panic!("'{field}' is not a number: {e}"))
}
