//! A user's design: a CSV table of parameter sets, read by `sweep --design` (the runs)
//! and `fit --design` (the starting points of a multi-start fit).
//!
//! ```text
//! sigma0;b
//! 5e5;10
//! 7e5;20
//! ```
//!
//! The header names the parameters as `--vary` (sweep) or `--params` (fit) does (a
//! parameter of the scene's one material, `MATERIAL.NAME`, or a Hill parameter); every
//! row is one parameter set, in the header's order. The table is read by
//! `musclefem_io::delimited` (a byte-order mark, `,` `;` or tab separators, quoted
//! fields, decimal commas with `;` or tab); every value must be a finite number, and
//! errors name the file and the line.

use std::path::Path;

use anyhow::{Context, Result, bail};

use musclefem_io::delimited::parse_delimited;

/// The parameter sets of a design file.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignFile {
    /// The parameters, in the header's order.
    pub names: Vec<String>,
    /// One set of values per row, in the order of `names`.
    pub rows: Vec<Vec<f64>>,
    /// The 1-based line of each row in the file.
    pub lines: Vec<usize>,
}

impl DesignFile {
    /// Read the design at `path`.
    pub fn read(path: &Path) -> Result<DesignFile> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("reading the design {}", path.display()))?;
        Self::parse(&text, path)
    }

    /// The design of the CSV `text` (`path` names it in errors).
    pub fn parse(text: &str, path: &Path) -> Result<DesignFile> {
        let at = |line: usize| format!("{}:{line}", path.display());
        let table =
            parse_delimited(text).map_err(|e| anyhow::anyhow!("{}: {}", at(e.line), e.message))?;
        let mut names: Vec<String> = Vec::with_capacity(table.names.len());
        for name in &table.names {
            if name.is_empty() {
                bail!(
                    "{}: a column without a name; the header names the parameters",
                    at(1)
                );
            }
            if names.contains(name) {
                bail!("{}: parameter '{name}' has two columns", at(1));
            }
            names.push(name.clone());
        }
        let mut rows = Vec::with_capacity(table.rows.len());
        let mut lines = Vec::with_capacity(table.rows.len());
        for row in &table.rows {
            let values = (0..names.len())
                .map(|c| match table.number(row, c) {
                    Ok(x) if x.is_finite() => Ok(x),
                    Ok(x) => bail!(
                        "{}: {} = {x} is not a finite number",
                        at(row.line),
                        names[c]
                    ),
                    Err(e) => bail!("{}: {}", at(e.line), e.message),
                })
                .collect::<Result<Vec<f64>>>()?;
            rows.push(values);
            lines.push(row.line);
        }
        if rows.is_empty() {
            bail!(
                "{}: no parameter set (one row per run under the header)",
                path.display()
            );
        }
        Ok(DesignFile { names, rows, lines })
    }

    /// The column of each of `wanted` in this design (every name must have one, and
    /// the design no other column); `what` names the option in the error.
    pub fn columns_of(&self, wanted: &[String], what: &str, path: &Path) -> Result<Vec<usize>> {
        if let Some(extra) = self.names.iter().find(|n| !wanted.contains(n)) {
            bail!(
                "{}: column '{extra}' is not one of the parameters of {what} ({})",
                path.display(),
                wanted.join(", ")
            );
        }
        wanted
            .iter()
            .map(|name| {
                self.names.iter().position(|n| n == name).with_context(|| {
                    format!(
                        "{}: no column for parameter '{name}' of {what} (the header has {})",
                        path.display(),
                        self.names.join(", ")
                    )
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spreadsheet_table_with_a_byte_order_mark_and_semicolons_is_read() {
        let text = "\u{feff}sigma0;b\n5e5;10\n\n7e5;2,5\n";
        let design = DesignFile::parse(text, Path::new("d.csv")).unwrap();
        assert_eq!(design.names, ["sigma0", "b"]);
        assert_eq!(design.rows, vec![vec![5e5, 10.0], vec![7e5, 2.5]]);
        assert_eq!(design.lines, [2, 4]);
        // Windows line ends read the same.
        let windows = DesignFile::parse(&text.replace('\n', "\r\n"), Path::new("d.csv")).unwrap();
        assert_eq!(windows, design);
        let columns = design
            .columns_of(
                &["b".into(), "sigma0".into()],
                "--params",
                Path::new("d.csv"),
            )
            .unwrap();
        assert_eq!(columns, [1, 0]);
    }

    #[test]
    fn bad_designs_are_named_with_their_line() {
        for (text, expected) in [
            ("a,b\n1,x\n", "d.csv:2"),
            ("a,a\n1,2\n", "two columns"),
            ("a,b\n", "no parameter set"),
            ("a,b\n1,2\n3,inf\n", "d.csv:3"),
        ] {
            let error = DesignFile::parse(text, Path::new("d.csv"))
                .unwrap_err()
                .to_string();
            assert!(error.contains(expected), "{text:?}: {error}");
        }
        let design = DesignFile::parse("a,c\n1,2\n", Path::new("d.csv")).unwrap();
        let error = design
            .columns_of(&["a".into(), "b".into()], "--params", Path::new("d.csv"))
            .unwrap_err()
            .to_string();
        assert!(error.contains("column 'c'"), "{error}");
    }
}
