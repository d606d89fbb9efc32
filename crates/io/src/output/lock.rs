//! One writer per output directory: [`OutputLock`].
//!
//! A command that writes into a directory first creates `DIR/.musclefem.lock` with
//! `create_new` (atomic: of two processes, exactly one succeeds) holding its process id,
//! start time and command line, and removes it when it is done (dropped, also on an error
//! or Ctrl-C handled by the program). A second command aimed at the same directory finds
//! the file and stops before it writes anything, naming the first. A lock left by a process
//! that no longer runs (killed with SIGKILL, a crashed machine) is stale: on Linux,
//! where `/proc/<pid>` tells whether the process is alive, it is taken over with a notice;
//! elsewhere the error says to delete the file.

use std::fs::{self, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use crate::OutputError;

/// File name of the lock inside the output directory.
pub const LOCK_FILE: &str = ".musclefem.lock";

/// The lock on one output directory, released when dropped.
#[derive(Debug)]
pub struct OutputLock {
    path: PathBuf,
}

/// What a lock file says about its holder.
#[derive(Debug, Clone, PartialEq)]
struct Holder {
    pid: Option<u32>,
    started: String,
    command: String,
}

impl Holder {
    fn parse(text: &str) -> Holder {
        let field = |key: &str| {
            text.lines()
                .find_map(|line| line.strip_prefix(key)?.strip_prefix(" = "))
                .unwrap_or("")
                .to_string()
        };
        Holder {
            pid: field("pid").parse().ok(),
            started: field("started_unix_s"),
            command: field("command"),
        }
    }

    /// Whether the holder runs: `Some(false)` only when it surely does not.
    fn alive(&self) -> Option<bool> {
        let pid = self.pid?;
        let proc_root = Path::new("/proc");
        if !proc_root.join("self").exists() {
            return None;
        }
        Some(proc_root.join(pid.to_string()).exists())
    }
}

impl OutputLock {
    /// Lock `directory` (created if missing) for this process, or fail naming the process
    /// that holds it.
    pub fn acquire(directory: &Path) -> Result<OutputLock, OutputError> {
        fs::create_dir_all(directory)
            .map_err(|e| OutputError::io("create the directory", directory, e))?;
        let path = directory.join(LOCK_FILE);
        // Two attempts: the second after removing a stale lock.
        for _ in 0..2 {
            match OpenOptions::new().write(true).create_new(true).open(&path) {
                Ok(mut file) => {
                    let started = SystemTime::now()
                        .duration_since(UNIX_EPOCH)
                        .map_or(0, |d| d.as_secs());
                    let command: Vec<String> = std::env::args().collect();
                    let text = format!(
                        "pid = {}\nstarted_unix_s = {started}\ncommand = {}\n",
                        std::process::id(),
                        command.join(" ")
                    );
                    file.write_all(text.as_bytes())
                        .map_err(|e| OutputError::io("write", &path, e))?;
                    return Ok(OutputLock { path });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let holder = Holder::parse(&fs::read_to_string(&path).unwrap_or_default());
                    match holder.alive() {
                        Some(false) => {
                            eprintln!(
                                "note: {} was left by process {} (started at {} s after \
                                 1970, no longer running): taking the directory over",
                                path.display(),
                                holder.pid.map_or("?".to_string(), |p| p.to_string()),
                                holder.started
                            );
                            fs::remove_file(&path)
                                .map_err(|e| OutputError::io("remove", &path, e))?;
                        }
                        alive => {
                            let how = match alive {
                                Some(_) => "is writing into this directory: wait for it to \
                                            end or choose another output directory"
                                    .to_string(),
                                None => format!(
                                    "may still be writing into this directory (this system \
                                     cannot tell): choose another output directory, or \
                                     delete {} if no run is using it",
                                    path.display()
                                ),
                            };
                            return Err(OutputError::Data {
                                path: directory.to_path_buf(),
                                message: format!(
                                    "another musclefem run (process {}, `{}`) {how}",
                                    holder.pid.map_or("?".to_string(), |p| p.to_string()),
                                    holder.command
                                ),
                            });
                        }
                    }
                }
                Err(e) => return Err(OutputError::io("create", &path, e)),
            }
        }
        Err(OutputError::Data {
            path: directory.to_path_buf(),
            message: format!(
                "{} keeps reappearing: another run is starting there",
                path.display()
            ),
        })
    }

    /// Path of the lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        let _ = fs::remove_file(&self.path);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("musclefem-lock-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn a_second_writer_is_refused_until_the_first_is_done() {
        let dir = scratch("second");
        let first = OutputLock::acquire(&dir).unwrap();
        let message = OutputLock::acquire(&dir).unwrap_err().to_string();
        assert!(
            message.contains(&format!("process {}", std::process::id())),
            "{message}"
        );
        assert!(message.contains("another musclefem run"), "{message}");
        drop(first);
        assert!(!dir.join(LOCK_FILE).exists());
        let again = OutputLock::acquire(&dir).unwrap();
        drop(again);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_lock_left_by_a_dead_process_is_taken_over() {
        if !Path::new("/proc/self").exists() {
            return; // Liveness cannot be told here: the refusal path is the one tested.
        }
        let dir = scratch("stale");
        fs::create_dir_all(&dir).unwrap();
        // A child that has exited: its pid names no running process (it is reaped).
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        fs::write(
            dir.join(LOCK_FILE),
            format!("pid = {pid}\nstarted_unix_s = 0\ncommand = musclefem run x\n"),
        )
        .unwrap();
        let lock = OutputLock::acquire(&dir).unwrap();
        let text = fs::read_to_string(lock.path()).unwrap();
        assert!(
            text.contains(&format!("pid = {}", std::process::id())),
            "{text}"
        );
        drop(lock);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn holders_are_read_from_the_lock_file() {
        let holder = Holder::parse("pid = 42\nstarted_unix_s = 7\ncommand = musclefem knee\n");
        assert_eq!(holder.pid, Some(42));
        assert_eq!(holder.started, "7");
        assert_eq!(holder.command, "musclefem knee");
        assert_eq!(Holder::parse("garbage").pid, None);
    }
}
