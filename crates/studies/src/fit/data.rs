//! The measured curve a fit is made to: two columns of a CSV file, chosen by header name
//! and scaled to engineering strain [1] and engineering stress [Pa]. Points outside the
//! test's stretching range 0 < strain ≤ 20 % are left out (and counted): at zero strain
//! the active test holds while it activates, so a curve written by `musclefem elongate`
//! has many stresses there.

use std::path::Path;

use anyhow::{Context, Result, bail};

/// Which columns hold the curve, and their units.
#[derive(Debug, Clone, PartialEq)]
pub struct Columns {
    /// Header name of the strain column, e.g. "engineering_strain".
    pub strain: String,
    /// Header name of the stress column, e.g. "engineering_stress_pa".
    pub stress: String,
    /// Strain [1] = value × this (0.01 for percent).
    pub strain_scale: f64,
    /// Stress [Pa] = value × this (e.g. 7000 for percent of σ₀ = 700 kPa).
    pub stress_scale: f64,
}

/// The points used, sorted by strain, and how many were left out.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredCurve {
    /// Engineering strain [1].
    pub strain: Vec<f64>,
    /// Engineering stress [Pa].
    pub stress: Vec<f64>,
    /// Points outside the range read.
    pub left_out: usize,
}

/// The abscissae of the points a fit keeps: low < x ≤ high, or low ≤ x ≤ high.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    pub low: f64,
    pub high: f64,
    pub low_inclusive: bool,
}

impl Range {
    /// Whether `x` is kept (the high end with a relative slack of 1e-12).
    pub fn contains(&self, x: f64) -> bool {
        let above = if self.low_inclusive {
            x >= self.low
        } else {
            x > self.low
        };
        above && x <= self.high + 1e-12 * self.high.abs()
    }
}

/// Read `path`, keeping the points whose strain (abscissa) is in `range`.
pub fn read_curve(path: &Path, columns: &Columns, range: Range) -> Result<MeasuredCurve> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("reading --data {}", path.display()))?;
    parse_curve(&text, path, columns, range)
}

/// [`read_curve`] on the file's text.
pub fn parse_curve(
    text: &str,
    path: &Path,
    columns: &Columns,
    range: Range,
) -> Result<MeasuredCurve> {
    let table = musclefem_io::delimited::parse_delimited(text)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    if table.names.is_empty() {
        bail!("{}: empty (expected a header line)", path.display());
    }
    let names = &table.names;
    let find = |name: &str, flag: &str| -> Result<usize> {
        names.iter().position(|n| n == name).with_context(|| {
            format!(
                "{}: no column '{name}' (see {flag}); the header has {}",
                path.display(),
                names.join(", ")
            )
        })
    };
    let strain_at = find(&columns.strain, "--strain-column")?;
    let stress_at = find(&columns.stress, "--stress-column")?;
    let mut points = Vec::new();
    let mut left_out = 0;
    for row in &table.rows {
        let cell = |at: usize| -> Result<f64> {
            table
                .number(row, at)
                .ok()
                .filter(|x| x.is_finite())
                .with_context(|| {
                    format!(
                        "{} line {}: '{}' in column '{}' is not a finite number",
                        path.display(),
                        row.line,
                        row.fields.get(at).map_or("", String::as_str),
                        names[at]
                    )
                })
        };
        let strain = columns.strain_scale * cell(strain_at)?;
        let stress = columns.stress_scale * cell(stress_at)?;
        if range.contains(strain) {
            points.push((strain, stress));
        } else {
            left_out += 1;
        }
    }
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(MeasuredCurve {
        strain: points.iter().map(|p| p.0).collect(),
        stress: points.iter().map(|p| p.1).collect(),
        left_out,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const STRAIN_TO_20_PERCENT: Range = Range {
        low: 0.0,
        high: 0.2,
        low_inclusive: false,
    };

    fn percent() -> Columns {
        Columns {
            strain: "Strain".into(),
            stress: "ta".into(),
            strain_scale: 0.01,
            stress_scale: 7000.0,
        }
    }

    #[test]
    fn columns_by_name_scaled_sorted_and_out_of_range_points_left_out() {
        let text = "\"Strain\",\"other\",\"ta\"\n12.5,9,2\n-3,9,0\n\n5,9,1\n25,9,4\n0,9,3\n";
        let curve =
            parse_curve(text, Path::new("d.csv"), &percent(), STRAIN_TO_20_PERCENT).unwrap();
        assert_eq!(curve.strain, vec![0.05, 0.125]);
        assert_eq!(curve.stress, vec![7000.0, 14000.0]);
        assert_eq!(curve.left_out, 3);
    }

    #[test]
    fn errors_name_the_file_line_and_column() {
        let missing = parse_curve(
            "x,y\n1,2\n",
            Path::new("d.csv"),
            &percent(),
            STRAIN_TO_20_PERCENT,
        )
        .unwrap_err()
        .to_string();
        assert!(missing.contains("d.csv") && missing.contains("no column 'Strain'"));
        assert!(missing.contains("--strain-column"), "{missing}");
        let bad = parse_curve(
            "Strain,ta\n1,2\n3,abc\n",
            Path::new("d.csv"),
            &percent(),
            STRAIN_TO_20_PERCENT,
        )
        .unwrap_err()
        .to_string();
        assert!(
            bad.contains("d.csv line 3") && bad.contains("'abc'"),
            "{bad}"
        );
    }

    /// The case: the curve saved by a spreadsheet as "CSV UTF-8" (a byte-order
    /// mark before the header) read "no column 'engineering_strain'"; the same curve
    /// with `;` and decimal commas, or tabs, reads as the plain one.
    #[test]
    fn a_spreadsheet_csv_reads_like_a_plain_one() {
        let columns = Columns {
            strain: "engineering_strain".into(),
            stress: "engineering_stress_pa".into(),
            strain_scale: 1.0,
            stress_scale: 1.0,
        };
        let read = |text: &str| {
            parse_curve(text, Path::new("m.csv"), &columns, STRAIN_TO_20_PERCENT).unwrap()
        };
        let plain = read("engineering_strain,engineering_stress_pa\n0.05,1200\n0.1,2500.5\n");
        assert_eq!(plain.strain, vec![0.05, 0.1]);
        for text in [
            "\u{feff}engineering_strain,engineering_stress_pa\r\n0.05,1200\r\n0.1,2500.5\r\n",
            "engineering_strain;engineering_stress_pa\n0,05;1200\n0,1;2500,5\n",
            "engineering_strain\tengineering_stress_pa\n0.05\t1200\n0.1\t2500.5\n",
        ] {
            assert_eq!(read(text), plain, "{text:?}");
        }
    }
}
