//! Atomic file replacement: the target path holds either its old content or the complete
//! new content, never a prefix of it.
//!
//! The new content goes to a hidden temporary file in the target's directory (same file
//! system, so the final rename is atomic), is flushed to disk with `fsync`, and is then
//! renamed onto the target; the directory is synced too, so the rename survives a crash.
//! If anything fails before the rename, or a [`PendingFile`] is dropped without being
//! committed, the temporary file is removed. (A process killed outright can leave a
//! hidden `.NAME.PID-N.tmp*` file behind, but never a half-written `NAME`.)
//!
//! Staging several files first and committing them after all were produced
//! ([`PendingFile::stage`], [`PendingFile::commit`]) keeps a failure while producing
//! the second file from leaving the first one behind.

use std::fs::{self, File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::OutputError;

/// Counter that makes temporary names unique within the process.
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// How many temporary names to try before giving up (they only clash with leftovers).
const TEMP_ATTEMPTS: u32 = 64;

/// Write `contents` to `path` atomically (see the module documentation).
pub fn write_atomically(path: &Path, contents: &[u8]) -> Result<(), OutputError> {
    PendingFile::stage_bytes(path, contents)?.commit()
}

/// A complete, synced temporary file waiting to be renamed onto its target.
/// Dropping it without [`commit`](Self::commit) deletes the temporary file.
#[derive(Debug)]
pub struct PendingFile {
    target: PathBuf,
    temp: PathBuf,
    committed: bool,
}

impl PendingFile {
    /// Stage `contents` for `target`.
    pub fn stage_bytes(target: &Path, contents: &[u8]) -> Result<Self, OutputError> {
        let (pending, mut file) = Self::reserve(target)?;
        file.write_all(contents)
            .map_err(|e| OutputError::io("write", &pending.temp, e))?;
        file.sync_all()
            .map_err(|e| OutputError::io("sync", &pending.temp, e))?;
        Ok(pending)
    }

    /// Stage a file that `produce` writes at the temporary path it is given (for writers
    /// that want a path rather than bytes, such as an image encoder). The temporary path
    /// keeps the target's extension, so format detection by extension works.
    pub fn stage(
        target: &Path,
        produce: impl FnOnce(&Path) -> Result<(), OutputError>,
    ) -> Result<Self, OutputError> {
        let (pending, file) = Self::reserve(target)?;
        drop(file);
        produce(&pending.temp)?;
        File::open(&pending.temp)
            .and_then(|f| f.sync_all())
            .map_err(|e| OutputError::io("sync", &pending.temp, e))?;
        Ok(pending)
    }

    /// The path the file will have once committed.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// The temporary path holding the staged content.
    pub fn temp_path(&self) -> &Path {
        &self.temp
    }

    /// Rename the staged file onto the target (replacing any file there) and sync the
    /// directory.
    pub fn commit(mut self) -> Result<(), OutputError> {
        fs::rename(&self.temp, &self.target)
            .map_err(|e| OutputError::io("rename the temporary file onto", &self.target, e))?;
        self.committed = true;
        sync_directory(&parent_directory(&self.target))
    }

    /// Create an empty, new temporary file next to `target`.
    fn reserve(target: &Path) -> Result<(Self, File), OutputError> {
        let name = target
            .file_name()
            .ok_or_else(|| OutputError::NotAFile {
                path: target.to_path_buf(),
            })?
            .to_string_lossy()
            .into_owned();
        let extension = target
            .extension()
            .map(|e| format!(".{}", e.to_string_lossy()))
            .unwrap_or_default();
        let directory = parent_directory(target);
        let mut last_error = None;
        for _ in 0..TEMP_ATTEMPTS {
            let n = TEMP_COUNTER.fetch_add(1, Ordering::Relaxed);
            let temp = directory.join(format!(".{name}.{}-{n}.tmp{extension}", std::process::id()));
            match OpenOptions::new().write(true).create_new(true).open(&temp) {
                Ok(file) => {
                    let pending = PendingFile {
                        target: target.to_path_buf(),
                        temp,
                        committed: false,
                    };
                    return Ok((pending, file));
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last_error = Some(e),
                Err(e) => return Err(OutputError::io("create a temporary file for", target, e)),
            }
        }
        let error = last_error.unwrap_or_else(|| std::io::Error::other("no free temporary name"));
        Err(OutputError::io(
            "create a temporary file for",
            target,
            error,
        ))
    }
}

impl Drop for PendingFile {
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_file(&self.temp);
        }
    }
}

/// The directory holding `path` ("." for a bare file name).
fn parent_directory(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Make a rename in `directory` durable (a no-op where directories cannot be synced).
fn sync_directory(directory: &Path) -> Result<(), OutputError> {
    #[cfg(unix)]
    {
        File::open(directory)
            .and_then(|d| d.sync_all())
            .map_err(|e| OutputError::io("sync the directory", directory, e))?;
    }
    #[cfg(not(unix))]
    let _ = directory;
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A fresh, empty directory for one test.
    pub(crate) fn test_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir()
            .join("musclefem-io-tests")
            .join(format!("{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn atomic_write_replaces_content_and_leaves_no_temporary_file() {
        let dir = test_dir("atomic-replace");
        let path = dir.join("out.csv");
        write_atomically(&path, b"first version, rather long\n").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"first version, rather long\n");
        write_atomically(&path, b"second\n").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"second\n");
        assert_eq!(entries(&dir), vec!["out.csv".to_string()]);
    }

    #[test]
    fn failed_or_dropped_staging_leaves_nothing() {
        let dir = test_dir("atomic-failure");
        let path = dir.join("plot.png");
        let err = PendingFile::stage(&path, |temp| {
            fs::write(temp, b"half a fi").unwrap();
            Err(OutputError::Plot {
                path: path.clone(),
                message: "simulated failure".to_string(),
            })
        })
        .unwrap_err();
        assert!(err.to_string().contains("plot.png"), "{err}");
        let pending = PendingFile::stage_bytes(&path, b"complete").unwrap();
        assert!(pending.temp_path().exists());
        assert!(pending.temp_path().to_string_lossy().ends_with(".png"));
        drop(pending);
        assert!(entries(&dir).is_empty(), "{:?}", entries(&dir));
    }

    #[test]
    fn existing_file_survives_a_failed_replacement() {
        let dir = test_dir("atomic-keep");
        let path = dir.join("keep.txt");
        write_atomically(&path, b"old").unwrap();
        let _ = PendingFile::stage(&path, |temp| {
            fs::write(temp, b"new but broken").unwrap();
            Err(OutputError::NotAFile { path: temp.into() })
        });
        assert_eq!(fs::read(&path).unwrap(), b"old");
        assert_eq!(entries(&dir), vec!["keep.txt".to_string()]);
    }

    #[test]
    fn errors_name_the_path() {
        let dir = test_dir("atomic-errors");
        let missing = dir.join("no-such-dir").join("x.csv");
        let err = write_atomically(&missing, b"x").unwrap_err();
        assert!(err.to_string().contains("no-such-dir"), "{err}");
        assert!(std::error::Error::source(&err).is_some());
        let err = write_atomically(Path::new("/"), b"x").unwrap_err();
        assert!(matches!(err, OutputError::NotAFile { .. }), "{err}");
    }
}
