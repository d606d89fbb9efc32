//! `fit --design FILE.csv`: a multi-start fit. Levenberg–Marquardt finds the local
//! minimum of C = ½ Σ r² nearest its start; the rows of a design file (see
//! [`crate::sweep::design_file`]) are several starts, each fitted in turn, and the end
//! with the smallest C wins (a start whose runs fail is reported, not fatal, unless all
//! fail).

use std::path::PathBuf;

use anyhow::{Result, bail};

use crate::sweep::design_file::DesignFile;

use super::FitArgs;
use super::levenberg_marquardt::Solution;
use super::unknowns::Unknown;

/// The starts of `--design`, in the order of the fitted parameters.
pub(super) struct DesignStarts {
    pub(super) path: PathBuf,
    /// The fitted parameters: `--params`, else the file's columns.
    pub(super) names: Vec<String>,
    /// One start per row, in the order of `names`.
    pub(super) rows: Vec<Vec<f64>>,
    /// The file line of each row.
    pub(super) lines: Vec<usize>,
}

/// The starts of `args.design`, if given; its columns must be the `--params` (in any
/// order) when those are given.
pub(super) fn design_starts(args: &FitArgs) -> Result<Option<DesignStarts>> {
    let Some(path) = &args.design else {
        return Ok(None);
    };
    let file = DesignFile::read(path)?;
    let names: Vec<String> = if args.params.is_empty() {
        file.names.clone()
    } else {
        args.params.iter().map(|p| p.trim().to_string()).collect()
    };
    let columns = file.columns_of(&names, "--params", path)?;
    let rows = (file.rows.iter())
        .map(|row| columns.iter().map(|&c| row[c]).collect())
        .collect();
    Ok(Some(DesignStarts {
        path: path.clone(),
        names,
        rows,
        lines: file.lines,
    }))
}

impl DesignStarts {
    /// Row `k` as `--start` tokens NAME=VALUE (the shortest text that reads back to the
    /// same number).
    pub(super) fn start_tokens(&self, k: usize) -> Vec<String> {
        (self.names.iter().zip(&self.rows[k]))
            .map(|(name, value)| format!("{name}={value}"))
            .collect()
    }

    /// Every start must lie within the fitted parameters' bounds.
    pub(super) fn check_bounds(&self, unknowns: &[Unknown]) -> Result<()> {
        for (row, line) in self.rows.iter().zip(&self.lines) {
            for (unknown, &x) in unknowns.iter().zip(row) {
                if !(unknown.lower..=unknown.upper).contains(&x) {
                    bail!(
                        "{}:{line}: the start {} = {x} is outside its bounds [{}, {}]",
                        self.path.display(),
                        unknown.name,
                        unknown.lower,
                        unknown.upper
                    );
                }
            }
        }
        Ok(())
    }
}

/// The end of the fits from every start with the smallest cost ½ Σ r², its start's
/// index, and (with a design) lines for fit.txt on every start's end: its RMS residual
/// √(2 C / `points`) in `unit`, or why it failed. Errors with the first failure when
/// every start failed.
pub(super) fn best_end(
    ends: Vec<Result<Solution>>,
    design: Option<&DesignStarts>,
    points: f64,
    unit: &str,
) -> Result<(usize, Solution, String)> {
    let mut text = String::new();
    let mut best: Option<(usize, Solution)> = None;
    let mut first_error = None;
    for (k, end) in ends.into_iter().enumerate() {
        let line = design.map_or(0, |d| d.lines[k]);
        match end {
            Ok(solution) => {
                text.push_str(&format!(
                    "  start at line {line}: RMS residual {:.6e} {unit} after {} iterations\n",
                    (2.0 * solution.cost() / points).sqrt(),
                    solution.iterations
                ));
                if best
                    .as_ref()
                    .is_none_or(|(_, b)| solution.cost() < b.cost())
                {
                    best = Some((k, solution));
                }
            }
            Err(error) => {
                text.push_str(&format!(
                    "  start at line {line}: failed: {}\n",
                    format!("{error:#}").replace('\n', "; ")
                ));
                first_error.get_or_insert(error);
            }
        }
    }
    let Some((k, solution)) = best else {
        return Err(first_error.unwrap_or_else(|| anyhow::anyhow!("no start to fit from")));
    };
    let text = match design {
        None => String::new(),
        Some(design) => format!(
            "starts = {} from {}; the best from line {}\n{text}",
            design.rows.len(),
            design.path.display(),
            design.lines[k]
        ),
    };
    Ok((k, solution, text))
}
