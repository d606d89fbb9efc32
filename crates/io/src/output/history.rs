//! CSV histories of a run (reaction forces, energies, time step), written atomically.
//!
//! The solvers return their histories as rows of numbers without names
//! ([`HistoryRow`], [`ImplicitHistoryRow`]); [`HistoryColumns`] names the reactions (one
//! name per prescribed displacement, in the order of `Loads::displacements`, and one per
//! rigid tie, in the order of `Loads::rigid_ties`) and turns the rows into CSV.
//!
//! Explicit header ([`HistoryColumns::explicit_header`]):
//!
//! ```text
//! time_s,time_step_s,reaction_<d>_n...,reaction_<tie>_x_n,reaction_<tie>_y_n,reaction_<tie>_z_n,
//! moment_<tie>_x_n_m,moment_<tie>_y_n_m,moment_<tie>_z_n_m...,internal_energy_j,
//! kinetic_energy_j,external_work_j,viscous_energy_j,hourglass_energy_j
//! ```
//!
//! (one line in the file). Implicit header ([`HistoryColumns::implicit_header`]): Newton
//! iterations, and the work of the internal and of the external forces (loads and
//! supports) with the kinetic energy (zero when quasi-static, where the two works agree
//! to the Newton tolerance):
//!
//! ```text
//! time_s,time_step_s,newton_iterations,reaction_<d>_n...,<the rigid-tie columns>,
//! internal_energy_j,kinetic_energy_j,external_work_j
//! ```
//!
//! With interactions (contact, cohesion), each adds, after the reactions,
//! `<i>_force_x_n,<i>_force_y_n,<i>_force_z_n,<i>_active_area_m2,<i>_bonded_area_m2,
//! <i>_stored_energy_j` (the resultant of the forces on the nodes, the area carrying a
//! traction, the area still bonded, the elastic energy of the law), and the explicit
//! history ends with `interaction_work_j` (W_c, part of the energy balance).
//!
//! With `[output] von_mises_percentile = P`, each part's P-th percentile of its elements'
//! von Mises stress comes last, `von_mises_p<P>_<part>_pa` ([`VonMisesPercentile`]).
//!
//! Units: time [s], force [N], moment [N m] (about the tie's current reference point),
//! energy [J]; `time_step_s` is the explicit step taken / the implicit increment.
//! Numbers are written at full precision ([`crate::csv::format_number`]); read them back
//! with [`crate::csv::read_table`].
//!
//! [`HistoryWriter`] keeps the rows of a running solve and rewrites the whole file
//! atomically at the first row, every `flush_every` rows after the last rewrite and at
//! [`HistoryWriter::finish`]: an interrupted or killed run leaves a complete CSV of the
//! rows up to the last rewrite.

use std::path::{Path, PathBuf};

use musclefem_core::solver::explicit::HistoryRow;
use musclefem_core::solver::implicit::ImplicitHistoryRow;
use musclefem_core::solver::{Analysis, InteractionReport, Record, Snapshot};

use crate::OutputError;
use crate::atomic::write_atomically;
use crate::csv::format_table;

pub use super::stress_percentile::VonMisesPercentile;

/// The energy columns of an explicit history, in order.
pub const ENERGY_COLUMNS: [&str; 5] = [
    "internal_energy_j",
    "kinetic_energy_j",
    "external_work_j",
    "viscous_energy_j",
    "hourglass_energy_j",
];

/// Names of a history's reaction columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HistoryColumns {
    /// One name per prescribed displacement (letters, digits, `_`, `-`, `.`).
    pub reactions: Vec<String>,
    /// One name per rigid tie (same characters).
    pub rigid_ties: Vec<String>,
    /// One name per interaction (same characters), in the order given to the solver.
    pub interactions: Vec<String>,
    /// Each part's von Mises percentile, last (see [`VonMisesPercentile`]); its values
    /// come from the run's element fields, so only [`HistoryColumns::record_row`] fills
    /// them.
    pub von_mises_percentile: Option<VonMisesPercentile>,
}

impl HistoryColumns {
    /// Columns for these reaction and rigid-tie names.
    pub fn new(reactions: Vec<String>, rigid_ties: Vec<String>) -> Self {
        Self {
            reactions,
            rigid_ties,
            interactions: Vec::new(),
            von_mises_percentile: None,
        }
    }

    /// The columns with those of `interactions` (names in solver order).
    pub fn with_interactions(mut self, interactions: Vec<String>) -> Self {
        self.interactions = interactions;
        self
    }

    /// The interaction columns (see the module documentation).
    fn interaction_columns(&self) -> Vec<String> {
        let mut columns = Vec::new();
        for name in &self.interactions {
            columns.extend(["x", "y", "z"].map(|c| format!("{name}_force_{c}_n")));
            columns.push(format!("{name}_active_area_m2"));
            columns.push(format!("{name}_bonded_area_m2"));
            columns.push(format!("{name}_stored_energy_j"));
        }
        columns
    }

    /// The reaction columns (displacements, then rigid-tie forces and moments).
    fn reaction_columns(&self) -> Vec<String> {
        let mut columns: Vec<String> = self
            .reactions
            .iter()
            .map(|r| format!("reaction_{r}_n"))
            .collect();
        for tie in &self.rigid_ties {
            columns.extend(["x", "y", "z"].map(|c| format!("reaction_{tie}_{c}_n")));
            columns.extend(["x", "y", "z"].map(|c| format!("moment_{tie}_{c}_n_m")));
        }
        columns
    }

    /// The header of an explicit history (see the module documentation).
    pub fn explicit_header(&self) -> String {
        let mut columns = vec!["time_s".to_string(), "time_step_s".to_string()];
        columns.extend(self.reaction_columns());
        columns.extend(self.interaction_columns());
        columns.extend(ENERGY_COLUMNS.map(String::from));
        if !self.interactions.is_empty() {
            columns.push("interaction_work_j".to_string());
        }
        columns.extend(self.percentile_columns());
        columns.join(",")
    }

    /// The header of an implicit history (see the module documentation).
    pub fn implicit_header(&self) -> String {
        let mut columns = vec![
            "time_s".to_string(),
            "time_step_s".to_string(),
            "newton_iterations".to_string(),
        ];
        columns.extend(self.reaction_columns());
        columns.extend(self.interaction_columns());
        columns.extend(ENERGY_COLUMNS[..3].iter().map(|c| c.to_string()));
        columns.extend(self.percentile_columns());
        columns.join(",")
    }

    /// The header of the history a run of `analysis` writes.
    pub fn header(&self, analysis: &Analysis) -> String {
        match analysis {
            Analysis::Explicit(_) => self.explicit_header(),
            Analysis::Implicit(_) => self.implicit_header(),
        }
    }

    /// The numbers of a recorded row of either solver, in the order of its header
    /// ([`header`](Self::header)), the percentile columns from `snapshot`'s element
    /// fields; errors as [`explicit_row`](Self::explicit_row).
    pub fn record_row(
        &self,
        record: &Record,
        snapshot: &Snapshot,
        path: &Path,
    ) -> Result<Vec<f64>, OutputError> {
        let mut values = match record {
            Record::Explicit(row) => self.explicit_values(row, path)?,
            Record::Implicit(row) => self.implicit_values(row, path)?,
        };
        if let Some(percentile) = &self.von_mises_percentile {
            values.extend(percentile.values(snapshot, path)?);
        }
        Ok(values)
    }

    /// The percentile columns' names (none without them).
    fn percentile_columns(&self) -> Vec<String> {
        self.von_mises_percentile
            .as_ref()
            .map_or(Vec::new(), VonMisesPercentile::columns)
    }

    /// Check the names (valid, unique); `path` is the file they are for.
    pub fn check(&self, path: &Path) -> Result<(), OutputError> {
        let mut seen: Vec<&str> = Vec::new();
        for name in self
            .reactions
            .iter()
            .chain(&self.rigid_ties)
            .chain(&self.interactions)
        {
            let valid = !name.is_empty()
                && name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'));
            if !valid {
                return Err(data(
                    path,
                    format!("reaction name '{name}': use letters, digits, '_', '-', '.'"),
                ));
            }
            if seen.contains(&name.as_str()) {
                return Err(data(path, format!("two reactions are named '{name}'")));
            }
            seen.push(name);
        }
        Ok(())
    }

    /// The numbers of an explicit row, in header order; errors if the row has another
    /// number of reactions than there are names.
    pub fn explicit_row(&self, row: &HistoryRow, path: &Path) -> Result<Vec<f64>, OutputError> {
        self.without_percentiles(path)?;
        self.explicit_values(row, path)
    }

    /// The solver's columns of an explicit row (the percentile ones left out).
    fn explicit_values(&self, row: &HistoryRow, path: &Path) -> Result<Vec<f64>, OutputError> {
        let mut values = vec![row.time, row.time_step];
        self.push_reactions(
            &mut values,
            &row.reactions,
            &row.rigid_reactions,
            row.time,
            path,
        )?;
        self.push_interactions(&mut values, &row.interactions, row.time, path)?;
        values.extend([
            row.internal_energy,
            row.kinetic_energy,
            row.external_work,
            row.viscous_energy,
            row.hourglass_energy,
        ]);
        if !self.interactions.is_empty() {
            values.push(row.interaction_work);
        }
        Ok(values)
    }

    /// The numbers of an implicit row, in header order (errors as
    /// [`explicit_row`](Self::explicit_row)).
    pub fn implicit_row(
        &self,
        row: &ImplicitHistoryRow,
        path: &Path,
    ) -> Result<Vec<f64>, OutputError> {
        self.without_percentiles(path)?;
        self.implicit_values(row, path)
    }

    /// The solver's columns of an implicit row (the percentile ones left out).
    fn implicit_values(
        &self,
        row: &ImplicitHistoryRow,
        path: &Path,
    ) -> Result<Vec<f64>, OutputError> {
        let mut values = vec![row.time, row.increment, row.iterations as f64];
        self.push_reactions(
            &mut values,
            &row.reactions,
            &row.rigid_reactions,
            row.time,
            path,
        )?;
        self.push_interactions(&mut values, &row.interactions, row.time, path)?;
        values.extend([
            row.energy.internal_work,
            row.energy.kinetic,
            row.energy.external_work,
        ]);
        Ok(values)
    }

    /// The solver's rows alone cannot fill the percentile columns.
    fn without_percentiles(&self, path: &Path) -> Result<(), OutputError> {
        match self.von_mises_percentile {
            None => Ok(()),
            Some(_) => Err(data(
                path,
                "the von Mises percentile columns need the run's element fields: write the \
                 rows with record_row"
                    .into(),
            )),
        }
    }

    fn push_reactions(
        &self,
        values: &mut Vec<f64>,
        reactions: &[f64],
        rigid: &[musclefem_core::solver::RigidReaction],
        time: f64,
        path: &Path,
    ) -> Result<(), OutputError> {
        if reactions.len() != self.reactions.len() || rigid.len() != self.rigid_ties.len() {
            return Err(data(
                path,
                format!(
                    "the row at t = {time} s has {} reactions and {} rigid-tie reactions, \
                     the header names {} and {}",
                    reactions.len(),
                    rigid.len(),
                    self.reactions.len(),
                    self.rigid_ties.len()
                ),
            ));
        }
        values.extend_from_slice(reactions);
        for r in rigid {
            values.extend([r.force.x, r.force.y, r.force.z]);
            values.extend([r.moment.x, r.moment.y, r.moment.z]);
        }
        Ok(())
    }
}

impl HistoryColumns {
    fn push_interactions(
        &self,
        values: &mut Vec<f64>,
        reports: &[InteractionReport],
        time: f64,
        path: &Path,
    ) -> Result<(), OutputError> {
        if reports.len() != self.interactions.len() {
            return Err(data(
                path,
                format!(
                    "the row at t = {time} s has {} interactions, the header names {}",
                    reports.len(),
                    self.interactions.len()
                ),
            ));
        }
        for r in reports {
            values.extend([r.force.x, r.force.y, r.force.z]);
            values.extend([r.active_area, r.bonded_area, r.stored_energy]);
        }
        Ok(())
    }
}

fn data(path: &Path, message: String) -> OutputError {
    OutputError::Data {
        path: path.to_path_buf(),
        message,
    }
}

/// Write an explicit solver's history to `path` atomically, in one call.
pub fn write_explicit_history(
    path: &Path,
    columns: &HistoryColumns,
    rows: &[HistoryRow],
) -> Result<(), OutputError> {
    let mut writer = HistoryWriter::explicit(path, columns)?.all_at_once();
    for row in rows {
        writer.push_explicit(row)?;
    }
    writer.finish()
}

/// Write an implicit solver's history to `path` atomically, in one call.
pub fn write_implicit_history(
    path: &Path,
    columns: &HistoryColumns,
    rows: &[ImplicitHistoryRow],
) -> Result<(), OutputError> {
    let mut writer = HistoryWriter::implicit(path, columns)?.all_at_once();
    for row in rows {
        writer.push_implicit(row)?;
    }
    writer.finish()
}

/// A CSV history filled row by row, rewritten whole and atomically every `flush_every`
/// rows (default [`HistoryWriter::DEFAULT_FLUSH_EVERY`]) and at [`finish`](Self::finish).
/// Rewriting costs O(rows) per flush; histories are short (the explicit solver records
/// about a hundred rows per step by default), so this stays cheap.
#[derive(Debug)]
pub struct HistoryWriter {
    path: PathBuf,
    header: String,
    columns: Option<HistoryColumns>,
    rows: Vec<Vec<f64>>,
    flush_every: usize,
    unflushed: usize,
    /// Rewrite the file at the first row (streaming writers; not the one-call ones, which
    /// write all or nothing).
    flush_first_row: bool,
}

impl HistoryWriter {
    /// Rows between two rewrites by default.
    pub const DEFAULT_FLUSH_EVERY: usize = 50;

    /// A history of rows of `header.split(',').count()` numbers, for `path`.
    pub fn new(path: &Path, header: &str) -> Self {
        Self {
            path: path.to_path_buf(),
            header: header.to_string(),
            columns: None,
            rows: Vec::new(),
            flush_every: Self::DEFAULT_FLUSH_EVERY,
            unflushed: 0,
            flush_first_row: true,
        }
    }

    /// A history with the explicit header of `columns`.
    pub fn explicit(path: &Path, columns: &HistoryColumns) -> Result<Self, OutputError> {
        columns.check(path)?;
        let mut writer = Self::new(path, &columns.explicit_header());
        writer.columns = Some(columns.clone());
        Ok(writer)
    }

    /// A history with the implicit header of `columns`.
    pub fn implicit(path: &Path, columns: &HistoryColumns) -> Result<Self, OutputError> {
        columns.check(path)?;
        let mut writer = Self::new(path, &columns.implicit_header());
        writer.columns = Some(columns.clone());
        Ok(writer)
    }

    /// Write the file only at [`finish`](Self::finish): all rows or none.
    fn all_at_once(mut self) -> Self {
        self.flush_every = usize::MAX;
        self.flush_first_row = false;
        self
    }

    /// Rewrite the file every `rows` rows (at least 1).
    pub fn flush_every(mut self, rows: usize) -> Self {
        self.flush_every = rows.max(1);
        self
    }

    /// The file written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The header line (without newline).
    pub fn header(&self) -> &str {
        &self.header
    }

    /// The rows so far.
    pub fn rows(&self) -> &[Vec<f64>] {
        &self.rows
    }

    /// The writer holding `rows` already (a resumed run's rows up to its checkpoint):
    /// they are written with the next rewrite.
    pub fn with_rows(mut self, rows: Vec<Vec<f64>>) -> Result<Self, OutputError> {
        let columns = self.header.split(',').count();
        if let Some(row) = rows.iter().find(|row| row.len() != columns) {
            return Err(data(
                &self.path,
                format!(
                    "a row of {} numbers, the header has {columns} columns",
                    row.len()
                ),
            ));
        }
        self.rows = rows;
        Ok(self)
    }

    /// Append a row (as many numbers as header columns); rewrites the file when
    /// `flush_every` rows have come since the last rewrite, and at the first row.
    pub fn push(&mut self, row: Vec<f64>) -> Result<(), OutputError> {
        let columns = self.header.split(',').count();
        if row.len() != columns {
            return Err(data(
                &self.path,
                format!(
                    "a row of {} numbers, the header has {columns} columns",
                    row.len()
                ),
            ));
        }
        self.rows.push(row);
        self.unflushed += 1;
        // The first row at once: a run killed early still leaves its history.
        if self.unflushed >= self.flush_every || (self.flush_first_row && self.rows.len() == 1) {
            self.flush()?;
        }
        Ok(())
    }

    /// A history with the header of the solver that `analysis` runs.
    pub fn for_analysis(
        path: &Path,
        columns: &HistoryColumns,
        analysis: &Analysis,
    ) -> Result<Self, OutputError> {
        match analysis {
            Analysis::Explicit(_) => Self::explicit(path, columns),
            Analysis::Implicit(_) => Self::implicit(path, columns),
        }
    }

    /// Append a recorded row of either solver (the writer's header must be that
    /// solver's), with its percentile columns from `snapshot`.
    pub fn push_record(&mut self, record: &Record, snapshot: &Snapshot) -> Result<(), OutputError> {
        let values = self.columns()?.record_row(record, snapshot, &self.path)?;
        self.push(values)
    }

    /// Append an explicit solver row (needs a writer made by [`explicit`](Self::explicit)).
    pub fn push_explicit(&mut self, row: &HistoryRow) -> Result<(), OutputError> {
        let values = self.columns()?.explicit_row(row, &self.path)?;
        self.push(values)
    }

    /// Append an implicit solver row (needs a writer made by [`implicit`](Self::implicit)).
    pub fn push_implicit(&mut self, row: &ImplicitHistoryRow) -> Result<(), OutputError> {
        let values = self.columns()?.implicit_row(row, &self.path)?;
        self.push(values)
    }

    fn columns(&self) -> Result<&HistoryColumns, OutputError> {
        self.columns.as_ref().ok_or_else(|| {
            data(
                &self.path,
                "a writer made by HistoryWriter::new takes plain rows".into(),
            )
        })
    }

    /// Rewrite the file with every row so far.
    pub fn flush(&mut self) -> Result<(), OutputError> {
        write_atomically(
            &self.path,
            format_table(&self.header, &self.rows).as_bytes(),
        )?;
        self.unflushed = 0;
        Ok(())
    }

    /// Write the file a last time.
    pub fn finish(mut self) -> Result<(), OutputError> {
        self.flush()
    }
}
