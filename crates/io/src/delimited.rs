//! Tables of text as people save them: a header line and rows of fields, read with the
//! `csv` crate whatever the spreadsheet or script that wrote them did —
//!
//! - a UTF-8 byte-order mark before the header (Excel's "CSV UTF-8") is dropped, so the
//!   first column's name is what it looks like;
//! - the separator is found from the header line: `,`, `;` (spreadsheets in locales
//!   whose decimal mark is a comma) or a tab, whichever splits it into most fields
//!   (outside quotes), `,` when none does;
//! - fields may be quoted (`"strain, %"`) and are trimmed; Windows line ends are read;
//! - with `;` or tab separators a number may have a decimal comma (`0,25`);
//! - empty lines are skipped; errors name the line.
//!
//! [`crate::csv`] reads the program's own tables with it, and `fit` the measured curves.

use std::fmt;

/// A table: the header's names and the rows, each with its 1-based line in the text.
#[derive(Debug, Clone, PartialEq)]
pub struct DelimitedTable {
    pub names: Vec<String>,
    pub rows: Vec<DelimitedRow>,
    /// The separator found.
    pub separator: char,
}

/// One row of fields and its line.
#[derive(Debug, Clone, PartialEq)]
pub struct DelimitedRow {
    pub line: usize,
    pub fields: Vec<String>,
}

/// What is wrong with a table, and on which line.
#[derive(Debug, Clone, PartialEq)]
pub struct DelimitedError {
    pub line: usize,
    pub message: String,
}

impl fmt::Display for DelimitedError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for DelimitedError {}

/// The byte-order mark some programs write before UTF-8 text.
const BYTE_ORDER_MARK: char = '\u{feff}';

/// Read `text` (see the module documentation).
pub fn parse_delimited(text: &str) -> Result<DelimitedTable, DelimitedError> {
    let text = text.strip_prefix(BYTE_ORDER_MARK).unwrap_or(text);
    let Some(header_line) = text.lines().find(|l| !l.trim().is_empty()) else {
        return Err(DelimitedError {
            line: 1,
            message: "empty (expected a header line)".into(),
        });
    };
    let separator = find_separator(header_line);
    let mut reader = csv::ReaderBuilder::new()
        .delimiter(separator as u8)
        .trim(csv::Trim::All)
        .flexible(true)
        .has_headers(false)
        .from_reader(text.as_bytes());
    let mut names = None;
    let mut rows = Vec::new();
    // The line of a record from its byte offset: the csv crate's own line count skips
    // blank lines and miscounts Windows line ends, and a record's offset is that of the
    // blank lines before it.
    // Records come in the order of their offsets, so the newlines are counted once, from
    // the last record's offset on (counting from the start each time took seconds on a
    // knee's 30 000-row fiber table).
    let mut counted = (0usize, 1usize);
    let mut line_at = |p: &csv::Position| {
        let start = (p.byte() as usize).min(text.len());
        let skipped = text[start..].len() - text[start..].trim_start_matches(['\r', '\n']).len();
        let end = start + skipped;
        let (from, line) = counted;
        let line = if end >= from {
            line + text[from..end].matches('\n').count()
        } else {
            text[..end].matches('\n').count() + 1
        };
        counted = (end, line);
        line
    };
    for record in reader.records() {
        let record = record.map_err(|e| DelimitedError {
            line: e.position().map_or(0, &mut line_at),
            message: e.to_string(),
        })?;
        let line = record.position().map_or(0, &mut line_at);
        if record.iter().all(str::is_empty) {
            continue;
        }
        let fields: Vec<String> = record.iter().map(str::to_string).collect();
        match names {
            None => names = Some(fields),
            Some(_) => rows.push(DelimitedRow { line, fields }),
        }
    }
    Ok(DelimitedTable {
        names: names.unwrap_or_default(),
        rows,
        separator,
    })
}

impl DelimitedTable {
    /// The number in `field` of `row` (a decimal comma allowed unless the separator is a
    /// comma), or an error naming the line, the field and its column.
    pub fn number(&self, row: &DelimitedRow, column: usize) -> Result<f64, DelimitedError> {
        let name = self.names.get(column).map_or("?", String::as_str);
        let Some(field) = row.fields.get(column) else {
            return Err(DelimitedError {
                line: row.line,
                message: format!(
                    "{} fields, no value in column '{name}' ({} columns)",
                    row.fields.len(),
                    self.names.len()
                ),
            });
        };
        let parsed = field.parse::<f64>().or_else(|e| {
            if self.separator != ',' && field.matches(',').count() == 1 {
                field.replace(',', ".").parse::<f64>()
            } else {
                Err(e)
            }
        });
        parsed.map_err(|_| DelimitedError {
            line: row.line,
            message: format!("'{field}' in column '{name}' is not a number"),
        })
    }
}

/// The separator that splits `header` into most fields outside quotes: `,`, `;` or tab
/// (`,` on a tie or when none occurs).
fn find_separator(header: &str) -> char {
    let count = |separator: char| {
        let mut quoted = false;
        header
            .chars()
            .filter(|&c| {
                if c == '"' {
                    quoted = !quoted;
                }
                !quoted && c == separator
            })
            .count()
    };
    let mut best = (',', count(','));
    for separator in [';', '\t'] {
        let n = count(separator);
        if n > best.1 {
            best = (separator, n);
        }
    }
    best.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn numbers(table: &DelimitedTable) -> Vec<Vec<f64>> {
        table
            .rows
            .iter()
            .map(|row| {
                (0..table.names.len())
                    .map(|c| table.number(row, c).unwrap())
                    .collect()
            })
            .collect()
    }

    /// The same table as a script writes it, as Excel's "CSV UTF-8" saves it (a
    /// byte-order mark, Windows line ends, quoted names), as a German spreadsheet saves it
    /// (`;` and decimal commas) and as tab-separated text: the same names and numbers.
    #[test]
    fn spreadsheet_variants_read_alike() {
        let plain = "engineering_strain,engineering_stress_pa\n0.05,1200\n0.1,2500.5\n";
        let excel = "\u{feff}\"engineering_strain\",\"engineering_stress_pa\"\r\n0.05,1200\r\n0.1,2500.5\r\n";
        let german = "engineering_strain;engineering_stress_pa\n0,05;1200\n0,1;2500,5\n\n";
        let tabs = "engineering_strain\tengineering_stress_pa\n0.05\t1200\n 0.1 \t 2500.5\n";
        let expected = parse_delimited(plain).unwrap();
        assert_eq!(
            expected.names,
            ["engineering_strain", "engineering_stress_pa"]
        );
        assert_eq!(numbers(&expected), [[0.05, 1200.0], [0.1, 2500.5]]);
        for (text, separator) in [(excel, ','), (german, ';'), (tabs, '\t')] {
            let table = parse_delimited(text).unwrap();
            assert_eq!(table.separator, separator, "{text:?}");
            assert_eq!(table.names, expected.names, "{text:?}");
            assert_eq!(numbers(&table), numbers(&expected), "{text:?}");
        }
    }

    /// A row's line counts the blank lines before it, with Unix or Windows line ends.
    #[test]
    fn lines_count_blank_lines_and_windows_line_ends() {
        for text in ["a;b\n1;2\n\n3;4\n", "\u{feff}a;b\r\n1;2\r\n\r\n3;4\r\n"] {
            let table = parse_delimited(text).unwrap();
            let lines: Vec<usize> = table.rows.iter().map(|r| r.line).collect();
            assert_eq!(lines, [2, 4], "{text:?}");
        }
    }

    /// On a long table with blank lines here and there every row keeps its own line (the
    /// lines are counted once, from one record to the next).
    #[test]
    fn a_long_table_numbers_its_lines() {
        let mut text = String::from("x,y\n");
        let mut expected = Vec::new();
        let mut line = 1;
        for k in 0..2000 {
            if k % 7 == 3 {
                text += "\r\n";
                line += 1;
            }
            text += &format!("{k},{}\n", 2 * k);
            line += 1;
            expected.push(line);
        }
        let table = parse_delimited(&text).unwrap();
        let lines: Vec<usize> = table.rows.iter().map(|r| r.line).collect();
        assert_eq!(lines, expected);
    }

    /// A quoted name may hold the separator; a decimal comma is not read where the comma
    /// separates fields; errors name the line and the column.
    #[test]
    fn quotes_and_errors() {
        let table = parse_delimited("\"strain, %\",stress\n1,2\n3,x\n").unwrap();
        assert_eq!(table.names, ["strain, %", "stress"]);
        assert_eq!(table.number(&table.rows[0], 0).unwrap(), 1.0);
        let error = table.number(&table.rows[1], 1).unwrap_err();
        assert_eq!(error.line, 3);
        assert_eq!(
            error.to_string(),
            "line 3: 'x' in column 'stress' is not a number"
        );
        let short = parse_delimited("a,b\n1\n").unwrap();
        let error = short.number(&short.rows[0], 1).unwrap_err();
        assert!(error.to_string().contains("line 2: 1 fields"), "{error}");
        assert_eq!(parse_delimited(" \n").unwrap_err().line, 1);
    }
}
