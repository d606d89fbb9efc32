//! `sweep.csv`: one row per run, in run order, rewritten atomically after every run so
//! that an interrupted sweep keeps every finished row and a rerun resumes from them.
//!
//! Columns: `run`, the varied parameters (full-precision values), `status` (`ok` or
//! `failed`), `wall_time_s`, `steps`, the study's outputs (for the elongation tests
//! `stress_10pct_pa` and `stress_20pct_pa`, the engineering stress at 10 % and 20 %
//! strain; for a scene the history columns asked for; empty if not reached or failed),
//! and `error` (quoted; empty for `ok`).

use std::path::Path;

use anyhow::{Context, Result, bail};

use musclefem_io::csv::format_number;

use super::run::Outcome;

/// Name of the table in the sweep's output directory.
pub const SWEEP_CSV: &str = "sweep.csv";

/// The columns of a sweep's table: the varied parameters and the study's outputs.
#[derive(Debug, Clone, PartialEq)]
pub struct Columns {
    pub parameters: Vec<String>,
    pub outputs: Vec<String>,
}

impl Columns {
    /// Cells in a row: run, parameters, status, wall time, steps, outputs, error.
    fn count(&self) -> usize {
        self.parameters.len() + self.outputs.len() + 5
    }
}

/// One row: the run's number (from 0, in the order the design lists the runs), its
/// parameter values and its outcome.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    pub run: usize,
    pub values: Vec<f64>,
    pub outcome: Outcome,
}

/// The header line.
pub fn header(columns: &Columns) -> String {
    std::iter::once("run")
        .chain(columns.parameters.iter().map(String::as_str))
        .chain(["status", "wall_time_s", "steps"])
        .chain(columns.outputs.iter().map(String::as_str))
        .chain(["error"])
        .collect::<Vec<_>>()
        .join(",")
}

/// The columns a table's `header` line names (run, parameters, status, wall_time_s,
/// steps, outputs, error), or `None` if it is not a sweep table's header.
pub fn columns_of(header: &str) -> Option<Columns> {
    let cells: Vec<&str> = header.trim_end().split(',').collect();
    let status = cells.iter().position(|&c| c == "status")?;
    if cells.first() != Some(&"run")
        || cells.get(status + 1) != Some(&"wall_time_s")
        || cells.get(status + 2) != Some(&"steps")
        || cells.last() != Some(&"error")
    {
        return None;
    }
    Some(Columns {
        parameters: cells[1..status].iter().map(|c| c.to_string()).collect(),
        outputs: cells[status + 3..cells.len() - 1]
            .iter()
            .map(|c| c.to_string())
            .collect(),
    })
}

/// The whole table, rows sorted by run.
pub fn format_table(columns: &Columns, records: &[Record]) -> String {
    let mut sorted: Vec<&Record> = records.iter().collect();
    sorted.sort_by_key(|r| r.run);
    let mut text = header(columns);
    text.push('\n');
    let optional = |x: Option<f64>| x.map_or_else(String::new, format_number);
    for record in sorted {
        let mut cells = vec![record.run.to_string()];
        cells.extend(record.values.iter().map(|&v| format_number(v)));
        match &record.outcome {
            Outcome::Finished {
                wall_time,
                steps,
                outputs,
            } => {
                cells.extend([
                    "ok".to_string(),
                    format!("{wall_time:.3}"),
                    steps.to_string(),
                ]);
                cells.extend(outputs.iter().map(|&x| optional(x)));
                cells.push(String::new());
            }
            Outcome::Failed { wall_time, error } => {
                cells.extend([
                    "failed".to_string(),
                    format!("{wall_time:.3}"),
                    String::new(),
                ]);
                cells.extend(columns.outputs.iter().map(|_| String::new()));
                cells.push(quote(error));
            }
        }
        text.push_str(&cells.join(","));
        text.push('\n');
    }
    text
}

/// Read the rows of a previous run of the same sweep from `path` (`text` its contents).
/// A different header means a different sweep: an error naming the file.
pub fn parse_table(text: &str, path: &Path, columns: &Columns) -> Result<Vec<Record>> {
    let mut lines = text.lines().enumerate();
    let expected = header(columns);
    match lines.next() {
        Some((_, line)) if line.trim_end() == expected => {}
        Some((_, line)) => bail!(
            "{}: its columns '{}' are not this sweep's '{expected}'; it was written by another \
             sweep (use another --out, or --force to start afresh)",
            path.display(),
            line.trim_end()
        ),
        None => bail!("{}: empty (no header line)", path.display()),
    }
    let mut records = Vec::new();
    for (index, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let record = parse_row(line, columns)
            .with_context(|| format!("{} line {}", path.display(), index + 1))?;
        records.push(record);
    }
    Ok(records)
}

fn parse_row(line: &str, columns: &Columns) -> Result<Record> {
    // The error column comes last and may hold commas: split off the others only.
    let cells: Vec<&str> = line.splitn(columns.count(), ',').collect();
    if cells.len() != columns.count() {
        bail!("{} cells, expected {}", cells.len(), columns.count());
    }
    let parameters = columns.parameters.len();
    let number = |i: usize| -> Result<f64> {
        cells[i]
            .parse::<f64>()
            .with_context(|| format!("cell {} '{}' is not a number", i + 1, cells[i]))
    };
    let optional = |i: usize| -> Result<Option<f64>> {
        if cells[i].is_empty() {
            Ok(None)
        } else {
            number(i).map(Some)
        }
    };
    let run = cells[0]
        .parse()
        .with_context(|| format!("run number '{}' is not a whole number", cells[0]))?;
    let values = (1..=parameters).map(number).collect::<Result<Vec<_>>>()?;
    let at = parameters + 1;
    let wall_time = number(at + 1)?;
    let outcome = match cells[at] {
        "ok" => Outcome::Finished {
            wall_time,
            steps: cells[at + 2]
                .parse()
                .with_context(|| format!("steps '{}' is not a whole number", cells[at + 2]))?,
            outputs: (0..columns.outputs.len())
                .map(|k| optional(at + 3 + k))
                .collect::<Result<_>>()?,
        },
        "failed" => Outcome::Failed {
            wall_time,
            error: unquote(cells[columns.count() - 1]),
        },
        other => bail!("status '{other}' is neither 'ok' nor 'failed'"),
    };
    Ok(Record {
        run,
        values,
        outcome,
    })
}

/// A CSV field on one line: in double quotes, inner quotes doubled, line breaks as "; ".
fn quote(text: &str) -> String {
    let one_line = text.replace(['\r', '\n'], "; ");
    format!("\"{}\"", one_line.replace('"', "\"\""))
}

fn unquote(field: &str) -> String {
    field
        .strip_prefix('"')
        .and_then(|f| f.strip_suffix('"'))
        .unwrap_or(field)
        .replace("\"\"", "\"")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_read_back_exactly_with_errors_holding_commas_and_quotes() {
        let columns = Columns {
            parameters: vec!["sigma0".to_string(), "D".to_string()],
            outputs: vec!["stress_10pct_pa".to_string(), "stress_20pct_pa".to_string()],
        };
        let records = vec![
            Record {
                run: 1,
                values: vec![9e5, 1.0000000000000002e-9],
                outcome: Outcome::Failed {
                    wall_time: 0.25,
                    error: "solver: \"diverged\", at t = 1.2 s\nnext line".into(),
                },
            },
            Record {
                run: 0,
                values: vec![7e5, 5e-9],
                outcome: Outcome::Finished {
                    wall_time: 1.5,
                    steps: 82,
                    outputs: vec![Some(29_480.123456789), None],
                },
            },
        ];
        let text = format_table(&columns, &records);
        assert!(text.starts_with(
            "run,sigma0,D,status,wall_time_s,steps,stress_10pct_pa,stress_20pct_pa,error\n0,"
        ));
        let read = parse_table(&text, Path::new("sweep.csv"), &columns).unwrap();
        assert_eq!(read[0], records[1]);
        assert_eq!(read[1].values, records[0].values);
        assert_eq!(
            read[1].outcome,
            Outcome::Failed {
                wall_time: 0.25,
                error: "solver: \"diverged\", at t = 1.2 s; next line".into(),
            }
        );
    }

    #[test]
    fn another_sweeps_table_is_refused_by_name() {
        let columns = Columns {
            parameters: vec!["c".into()],
            outputs: vec!["reaction_a_n".into()],
        };
        let error = parse_table("run,b,status\n", Path::new("out/sweep.csv"), &columns)
            .unwrap_err()
            .to_string();
        assert!(error.contains("out/sweep.csv"), "{error}");
        assert!(error.contains("another sweep"), "{error}");
    }
}
