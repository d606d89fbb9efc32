//! The VUMAT and UMAT tests' shared steps: skipping without gfortran, running `musclefem`
//! and requiring success, and comparing the history.csv of two runs.

// Each test binary includes this file and uses a part of it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use musclefem_vumat::toolchain::Tool;

use super::run::{musclefem, text};

/// Whether gfortran is there; prints the skip message if not (panics if it is required:
/// MUSCLEFEM_REQUIRE_GFORTRAN, set by scripts/test).
pub fn gfortran_or_skip(test: &str) -> bool {
    if Tool::fortran().is_available() {
        return true;
    }
    assert!(
        std::env::var_os("MUSCLEFEM_REQUIRE_GFORTRAN").is_none(),
        "{test}: gfortran is required (MUSCLEFEM_REQUIRE_GFORTRAN is set) but not found"
    );
    eprintln!("SKIPPED {test}: gfortran is not installed (scripts/setup-fortran.sh installs it)");
    false
}

/// examples/vumat.
pub fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/vumat")
}

/// history.csv of a run: the header and the rows.
pub fn history(dir: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// The largest difference of the columns whose name starts with `prefix`, relative to their
/// largest value in `b`, and that value.
pub fn column_difference(a: &Path, b: &Path, prefix: &str) -> (f64, f64) {
    let (header, rows) = history(a);
    let (reference_header, reference_rows) = history(b);
    assert_eq!(header, reference_header);
    assert_eq!(rows.len(), reference_rows.len());
    let columns: Vec<usize> = (0..header.len())
        .filter(|&c| header[c].starts_with(prefix))
        .collect();
    assert!(!columns.is_empty(), "no {prefix} column in {header:?}");
    let scale = reference_rows
        .iter()
        .flat_map(|r| columns.iter().map(|&c| r[c].abs()))
        .fold(0.0, f64::max);
    let difference = rows
        .iter()
        .zip(&reference_rows)
        .flat_map(|(r, s)| columns.iter().map(move |&c| (r[c] - s[c]).abs()))
        .fold(0.0, f64::max);
    (difference / scale, scale)
}

/// The largest difference of the reaction columns, relative to the largest reaction.
pub fn reaction_difference(a: &Path, b: &Path) -> (f64, f64) {
    column_difference(a, b, "reaction_")
}

/// `musclefem ARGS` in `dir`, which must succeed: its stdout.
pub fn run_ok(dir: &Path, args: &[&str]) -> String {
    let out = musclefem(dir, args);
    assert!(
        out.status.success(),
        "musclefem {args:?}:\n{}\n{}",
        text(&out.stdout),
        text(&out.stderr)
    );
    text(&out.stdout)
}
