//! The patella's equilibrium table as a CSV file beside a scene (`patella_table.csv`),
//! so that a scene's `knee-patella` follower poses the patella from the same numbers the
//! knee tabulated: one row per grid point (knee flexion θ every 1°, tendon strain every
//! 1 %, angle-major) with the patella's pose P(θ, ℓ) and the tendon's share of the pull
//! r(θ, ℓ). Every number is the shortest decimal that parses back to the same `f64`
//! ([`musclefem_io::csv::format_number`]), so the table read back is the table written,
//! bit for bit. The patella moves in the sagittal plane: `centre_z_m` is the reference
//! pose's (the same on every row).

use std::path::Path;

use anyhow::{Context, Result, bail};
use nalgebra::Vector3;

use musclefem_io::delimited::parse_delimited;

use super::{ANGLE_STEP, PatellaTable, STRAIN_STEP};
use crate::knee::anatomy::{PatellaPose, TendonSpring};

/// Header of `patella_table.csv`.
pub const PATELLA_TABLE_CSV_HEADER: &str = "knee_flexion_rad,tendon_strain,centre_x_m,centre_y_m,\
     centre_z_m,patella_flexion_rad,groove_coordinate_m,force_ratio";

/// The columns of the header.
const COLUMNS: usize = 8;

impl PatellaTable {
    /// The table as the text of `patella_table.csv`.
    pub fn csv_text(&self) -> String {
        let rows = self
            .poses
            .iter()
            .zip(&self.ratios)
            .enumerate()
            .map(|(i, (pose, ratio))| {
                let (a, s) = (i / self.strain_count, i % self.strain_count);
                [
                    a as f64 * ANGLE_STEP,
                    s as f64 * STRAIN_STEP,
                    pose[0],
                    pose[1],
                    self.reference.centre.z,
                    pose[2],
                    pose[3],
                    *ratio,
                ]
            });
        musclefem_io::csv::format_table(PATELLA_TABLE_CSV_HEADER, rows)
    }

    /// The table of `patella_table.csv` text `text`, with the tendon `tendon` it was
    /// built with. Errors name the line: a header other than
    /// [`PATELLA_TABLE_CSV_HEADER`], a field that is not a number, or a grid that is not
    /// the knee's (θ = a · 1°, strain = s · 1 %, angle-major, at least 2 × 2 points).
    pub fn from_csv_text(text: &str, tendon: TendonSpring) -> Result<Self> {
        let table = parse_delimited(text)?;
        if table.names.join(",") != PATELLA_TABLE_CSV_HEADER {
            bail!(
                "the header is '{}', expected '{PATELLA_TABLE_CSV_HEADER}'",
                table.names.join(",")
            );
        }
        let rows = table
            .rows
            .iter()
            .map(|row| {
                if row.fields.len() != COLUMNS {
                    bail!(
                        "line {}: {} fields, expected {COLUMNS}",
                        row.line,
                        row.fields.len()
                    );
                }
                let values = (0..COLUMNS)
                    .map(|c| table.number(row, c))
                    .collect::<Result<Vec<f64>, _>>()?;
                Ok((row.line, values))
            })
            .collect::<Result<Vec<_>>>()?;
        let Some((_, first)) = rows.first() else {
            bail!("the table has no rows");
        };
        let strain_count = rows.iter().take_while(|(_, r)| r[0] == first[0]).count();
        let angle_count = rows.len() / strain_count.max(1);
        if strain_count < 2 || angle_count < 2 || angle_count * strain_count != rows.len() {
            bail!(
                "{} rows of {strain_count} strains each: the table needs at least 2 knee \
                 angles by 2 strains, every angle with the same strains",
                rows.len()
            );
        }
        for (i, (line, row)) in rows.iter().enumerate() {
            let (a, s) = (i / strain_count, i % strain_count);
            let (angle, strain) = (a as f64 * ANGLE_STEP, s as f64 * STRAIN_STEP);
            if row[0] != angle || row[1] != strain {
                bail!(
                    "line {line}: knee flexion {} rad and strain {} where the grid (1°, 1 %) \
                     has {angle} rad and {strain}",
                    row[0],
                    row[1]
                );
            }
        }
        let reference = PatellaPose {
            centre: Vector3::new(first[2], first[3], first[4]),
            flexion: first[5],
            groove_coordinate: first[6],
        };
        Ok(Self {
            tendon,
            angle_count,
            strain_count,
            poses: rows.iter().map(|(_, r)| [r[2], r[3], r[5], r[6]]).collect(),
            ratios: rows.iter().map(|(_, r)| r[7]).collect(),
            reference,
        })
    }

    /// Write the table to `path` (atomically).
    pub fn write_csv(&self, path: &Path) -> Result<()> {
        musclefem_io::atomic::write_atomically(path, self.csv_text().as_bytes())
            .with_context(|| format!("writing {}", path.display()))
    }

    /// Read the table at `path` with the tendon `tendon` it was built with.
    pub fn read_csv(path: &Path, tendon: TendonSpring) -> Result<Self> {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        Self::from_csv_text(&text, tendon).with_context(|| format!("{}", path.display()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::knee::anatomy::{KneeKinematics, Quadriceps};

    fn table() -> PatellaTable {
        let kinematics = KneeKinematics::new(Quadriceps::ALL.iter().map(|m| m.pull()).collect());
        PatellaTable::new(
            &kinematics,
            TendonSpring::procedural_knee(),
            4f64.to_radians(),
        )
        .unwrap()
    }

    #[test]
    fn the_table_read_back_is_the_table_written_bit_for_bit() {
        let written = table();
        let text = written.csv_text();
        assert!(text.starts_with(PATELLA_TABLE_CSV_HEADER));
        // 4° → 6 angles (0° … 5°), strains 0 … 30 %: 6 × 31 rows.
        assert_eq!(written.angle_count, 6);
        assert_eq!(text.lines().count(), 1 + 6 * 31);
        let read = PatellaTable::from_csv_text(&text, *written.tendon()).unwrap();
        assert_eq!((read.angle_count, read.strain_count), (6, 31));
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&read.ratios), bits(&written.ratios));
        assert_eq!(bits(&read.poses.concat()), bits(&written.poses.concat()));
        assert_eq!(read.reference, written.reference);
        // And so every equilibrium.
        for (angle, tension) in [(0.01, 300.0), (0.05, 2500.0), (0.07, 9000.0)] {
            assert_eq!(
                read.equilibrium(angle, tension),
                written.equilibrium(angle, tension)
            );
        }
    }

    #[test]
    fn a_table_off_the_grid_or_with_a_bad_field_names_the_line() {
        let text = table().csv_text();
        let tendon = TendonSpring::procedural_knee();
        let error = |text: &str| {
            format!(
                "{:#}",
                PatellaTable::from_csv_text(text, tendon).unwrap_err()
            )
        };
        let off_grid = text.replacen("\n0.017453292519943295,0.01,", "\n0.0175,0.01,", 1);
        assert!(
            error(&off_grid).starts_with("line 34: knee flexion 0.0175 rad"),
            "{}",
            error(&off_grid)
        );
        let lines: Vec<&str> = text.lines().collect();
        let mut bad = lines.clone();
        let broken = lines[3].replacen(',', ",x", 1);
        bad[3] = &broken;
        assert!(
            error(&bad.join("\n")).contains("line 4"),
            "{}",
            error(&bad.join("\n"))
        );
        let short = lines[..40].join("\n");
        assert!(
            error(&short).contains("39 rows of 31 strains"),
            "{}",
            error(&short)
        );
        assert!(error("a,b\n1,2\n").starts_with("the header is 'a,b'"));
    }
}
