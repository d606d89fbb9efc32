//! A fit's output files: `fit.csv`, `fit_curve.csv`, `fit.txt` and `fit.png`, checked
//! before the fit starts (so a long fit does not end in a refusal) and written together
//! at its end.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};

use musclefem_io::PendingFile;
use musclefem_io::output::OutputLock;
use musclefem_io::plot::stage_png;

use super::Fitted;

/// The files, in the order they are written.
pub const FILES: [&str; 4] = ["fit.csv", "fit_curve.csv", "fit.txt", "fit.png"];

/// The output directory of one fit, locked while it runs.
pub struct Outputs {
    dir: PathBuf,
    /// Held while the fit runs: one writer per output directory.
    _lock: OutputLock,
}

impl Outputs {
    /// The directory `dir`, created; a previous fit's files there are an error unless
    /// `force`.
    pub fn new(dir: &Path, force: bool) -> Result<Self> {
        let existing = FILES.iter().map(|f| dir.join(f)).find(|p| p.exists());
        if let (false, Some(existing)) = (force, existing) {
            bail!(
                "{} exists: a previous fit is in {} (use --force to replace it)",
                existing.display(),
                dir.display()
            );
        }
        // Creates the directory; a second fit into it is refused while this one runs.
        let lock = OutputLock::acquire(dir)?;
        Ok(Outputs {
            dir: dir.to_path_buf(),
            _lock: lock,
        })
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Write the files of `fitted`.
    pub fn write(&self, fitted: &Fitted) -> Result<()> {
        let staged = [
            PendingFile::stage_bytes(&self.dir.join(FILES[0]), fitted.table.as_bytes())?,
            PendingFile::stage_bytes(&self.dir.join(FILES[1]), fitted.curve_table.as_bytes())?,
            PendingFile::stage_bytes(&self.dir.join(FILES[2]), fitted.summary.as_bytes())?,
            stage_png(&self.dir.join(FILES[3]), &fitted.figure)?,
        ];
        for file in staged {
            file.commit()?;
        }
        Ok(())
    }
}
