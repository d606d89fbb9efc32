//! The run directory: every output of one run in one place.
//!
//! ```text
//! DIR/
//!   result.pvd              time series index for ParaView (open this one)
//!   frames/frame_00000.vtu  one VTU file per frame, numbered from 0 (5 digits, more
//!   frames/frame_00001.vtu  when there are more than 100000 frames)
//!   rigid.pvd               with rigid bodies: their time series (open it too)
//!   frames/rigid_00000.vtu  the rigid bodies at the instant of frame_00000.vtu (see
//!                           [`super::rigid_frames`])
//!   history.csv             reactions, energies, time step (see [`super::history`])
//!   scene.toml              the scene file the run was started with, verbatim
//!   run.log                 program version, settings, timings, frames written
//!   checkpoint.bin          while the run goes: where it resumes from (see
//!                           [`super::checkpoint`])
//!   .musclefem.lock         while the run writes: its process (see [`super::lock`])
//! ```
//!
//! Every file is written atomically. [`RunDirectory::write_frame`] commits the frame's
//! VTU file first and rewrites `result.pvd` after it, so `result.pvd` only ever lists
//! complete frames. If the process dies between the two renames, the last frame's VTU
//! file exists but is not listed; if rewriting `result.pvd` fails, the frame is not
//! counted and the next frame takes its number (and file name). The rigid bodies' file of
//! a frame ([`RunDirectory::write_rigid_frame`]) follows it the same way, and a resumed
//! run cuts both series back to the checkpoint's frames.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use musclefem_core::mesh::Mesh;
use musclefem_core::solver::element_fields::PartFields;
use musclefem_core::solver::explicit::HistoryRow;
use musclefem_core::solver::implicit::ImplicitHistoryRow;
use musclefem_core::solver::{Analysis, NodalField};
use nalgebra::Vector3;

use super::checkpoint::CHECKPOINT_FILE;
use super::element_fields::ElementFieldArrays;
use super::frame::Frame;
use super::history::{
    HistoryColumns, HistoryWriter, write_explicit_history, write_implicit_history,
};
use super::lock::OutputLock;
use super::pvd::{PvdEntry, write_pvd};
use super::rigid_frames::{RigidBodyFrame, encode_rigid_vtu};
use super::vtu::write_vtu;
use crate::OutputError;
use crate::atomic::write_atomically;

/// File name of the time series index.
pub const PVD_FILE: &str = "result.pvd";
/// Directory of the frames.
pub const FRAMES_DIR: &str = "frames";
/// File name of the rigid bodies' time series index.
pub const RIGID_PVD_FILE: &str = "rigid.pvd";
/// File name of the history.
pub const HISTORY_FILE: &str = "history.csv";
/// File name of the scene copy.
pub const SCENE_FILE: &str = "scene.toml";
/// File name of the run log.
pub const RUN_LOG_FILE: &str = "run.log";

/// What [`RunDirectory::create`] does when the directory already holds results.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExistingResults {
    /// Fail, naming the file found.
    Refuse,
    /// Delete the previous run's files (only the names listed in the module
    /// documentation, `result.pvd` first), keep anything else.
    Replace,
}

/// The output directory of one run.
#[derive(Debug)]
pub struct RunDirectory {
    root: PathBuf,
    frames: Vec<PvdEntry>,
    /// The rigid bodies' files written so far (one per frame, when there are bodies).
    rigid: Vec<PvdEntry>,
    created: Instant,
    /// Held for as long as the run writes here: a second run into the same directory
    /// is refused before it deletes or writes anything.
    _lock: OutputLock,
}

impl RunDirectory {
    /// Create `root` and `root/frames` (and missing parents), locked for this run.
    pub fn create(root: &Path, existing: ExistingResults) -> Result<Self, OutputError> {
        let lock = OutputLock::acquire(root)?;
        let frames_dir = root.join(FRAMES_DIR);
        fs::create_dir_all(&frames_dir)
            .map_err(|e| OutputError::io("create the directory", &frames_dir, e))?;
        let mut previous: Vec<PathBuf> = [
            PVD_FILE,
            RIGID_PVD_FILE,
            HISTORY_FILE,
            SCENE_FILE,
            RUN_LOG_FILE,
            CHECKPOINT_FILE,
        ]
        .iter()
        .map(|name| root.join(name))
        .filter(|p| p.exists())
        .collect();
        let listing =
            fs::read_dir(&frames_dir).map_err(|e| OutputError::io("list", &frames_dir, e))?;
        for entry in listing {
            let entry = entry.map_err(|e| OutputError::io("list", &frames_dir, e))?;
            let name = entry.file_name().to_string_lossy().into_owned();
            if is_frame_name(&name) || is_rigid_frame_name(&name) {
                previous.push(entry.path());
            }
        }
        if let Some(first) = previous.first() {
            match existing {
                ExistingResults::Refuse => {
                    return Err(OutputError::Data {
                        path: first.clone(),
                        message: "the run directory already holds results of another run".into(),
                    });
                }
                ExistingResults::Replace => {
                    // `previous` starts with result.pvd and rigid.pvd when there are
                    // some: no listing of deleted frames survives.
                    for path in &previous {
                        fs::remove_file(path).map_err(|e| OutputError::io("remove", path, e))?;
                    }
                }
            }
        }
        Ok(Self {
            root: root.to_path_buf(),
            frames: Vec::new(),
            rigid: Vec::new(),
            created: Instant::now(),
            _lock: lock,
        })
    }

    /// Reopen `root`, locked, to go on from a checkpoint that lists `frames`: the frame
    /// files written after them are removed and `result.pvd` lists those frames again;
    /// so do the rigid bodies' files and `rigid.pvd`, if the run has written some. The
    /// history is the caller's (its rows are in the checkpoint).
    pub fn resume(root: &Path, frames: Vec<PvdEntry>) -> Result<Self, OutputError> {
        let lock = OutputLock::acquire(root)?;
        let frames_dir = root.join(FRAMES_DIR);
        // Frame i's rigid bodies are in rigid_file(i), written before the checkpoint.
        let rigid: Vec<PvdEntry> = (frames.iter().enumerate())
            .map(|(i, f)| PvdEntry {
                time: f.time,
                file: Self::rigid_file(i),
            })
            .filter(|r| root.join(&r.file).is_file())
            .collect();
        let kept: std::collections::HashSet<&str> = (frames.iter().chain(&rigid))
            .filter_map(|f| f.file.strip_prefix(&format!("{FRAMES_DIR}/")))
            .collect();
        let listing =
            fs::read_dir(&frames_dir).map_err(|e| OutputError::io("list", &frames_dir, e))?;
        let pvd = root.join(PVD_FILE);
        write_pvd(&pvd, &frames)?;
        let rigid_pvd = root.join(RIGID_PVD_FILE);
        if !rigid.is_empty() || rigid_pvd.exists() {
            write_pvd(&rigid_pvd, &rigid)?;
        }
        for entry in listing {
            let entry = entry.map_err(|e| OutputError::io("list", &frames_dir, e))?;
            let name = entry.file_name().to_string_lossy().into_owned();
            let written = is_frame_name(&name) || is_rigid_frame_name(&name);
            if written && !kept.contains(name.as_str()) {
                fs::remove_file(entry.path())
                    .map_err(|e| OutputError::io("remove", entry.path(), e))?;
            }
        }
        Ok(Self {
            root: root.to_path_buf(),
            frames,
            rigid,
            created: Instant::now(),
            _lock: lock,
        })
    }

    /// Path of `checkpoint.bin`.
    pub fn checkpoint_path(&self) -> PathBuf {
        self.root.join(CHECKPOINT_FILE)
    }

    /// Remove `checkpoint.bin` (a complete run has nothing to resume).
    pub fn remove_checkpoint(&self) -> Result<(), OutputError> {
        let path = self.checkpoint_path();
        match fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                Err(OutputError::io("remove", &path, e))
            }
            _ => Ok(()),
        }
    }

    /// The directory.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// Path of `result.pvd`.
    pub fn pvd_path(&self) -> PathBuf {
        self.root.join(PVD_FILE)
    }

    /// Path of `history.csv`.
    pub fn history_path(&self) -> PathBuf {
        self.root.join(HISTORY_FILE)
    }

    /// Path of frame number `index`, relative to the root (`frames/frame_00042.vtu`).
    pub fn frame_file(index: usize) -> String {
        format!("{FRAMES_DIR}/frame_{index:05}.vtu")
    }

    /// Path of the rigid bodies' file of frame number `index`, relative to the root
    /// (`frames/rigid_00042.vtu`).
    pub fn rigid_file(index: usize) -> String {
        format!("{FRAMES_DIR}/rigid_{index:05}.vtu")
    }

    /// The frames written so far (time and file relative to the root).
    pub fn frames(&self) -> &[PvdEntry] {
        &self.frames
    }

    /// The rigid bodies' files written so far (time and file relative to the root).
    pub fn rigid_frames(&self) -> &[PvdEntry] {
        &self.rigid
    }

    /// Write `bodies` at their pose at the time of the last frame written, as that
    /// frame's rigid file (`frames/rigid_NNNNN.vtu`, the number of the frame), then
    /// rewrite `rigid.pvd` to list it. Nothing without bodies. Returns the file's path.
    pub fn write_rigid_frame(
        &mut self,
        bodies: &[RigidBodyFrame<'_>],
    ) -> Result<Option<PathBuf>, OutputError> {
        let (Some(frame), false) = (self.frames.last(), bodies.is_empty()) else {
            return Ok(None);
        };
        let index = self.frames.len() - 1;
        let file = Self::rigid_file(index);
        let path = self.root.join(&file);
        let time = frame.time;
        if self.rigid.last().is_some_and(|last| last.time >= time) {
            return Err(OutputError::Data {
                path,
                message: format!("the rigid bodies at {time} s were written already"),
            });
        }
        let bytes = encode_rigid_vtu(&path, time, bodies)?;
        write_atomically(&path, &bytes)?;
        self.rigid.push(PvdEntry { time, file });
        if let Err(e) = write_pvd(&self.root.join(RIGID_PVD_FILE), &self.rigid) {
            self.rigid.pop();
            return Err(e);
        }
        Ok(Some(path))
    }

    /// Time since [`create`](Self::create).
    pub fn elapsed(&self) -> Duration {
        self.created.elapsed()
    }

    /// Write the frame of a solver's recorded state: the displacement of every node, the
    /// element fields of every part (stress, fibers, state, activation) and the
    /// interactions' per-node fields (contact pressure, cohesive traction, …; pass `&[]`
    /// for none). The one frame writer of the scene run, the knee and the elongation tests.
    pub fn write_state_frame(
        &mut self,
        mesh: &Mesh,
        time: f64,
        displacement: &[Vector3<f64>],
        parts: &[PartFields],
        nodal: &[NodalField],
    ) -> Result<PathBuf, OutputError> {
        let fields = ElementFieldArrays::gather(mesh, parts);
        self.write_frame(&state_frame(mesh, time, displacement, &fields, nodal))
    }

    /// Write `frame` as the next VTU file, then rewrite `result.pvd` to list it. Times
    /// must increase from frame to frame. Returns the VTU file's path.
    pub fn write_frame(&mut self, frame: &Frame<'_>) -> Result<PathBuf, OutputError> {
        let file = Self::frame_file(self.frames.len());
        let path = self.root.join(&file);
        if let Some(last) = self.frames.last()
            && frame.time <= last.time
        {
            return Err(OutputError::Data {
                path,
                message: format!(
                    "frame time {} s does not follow the previous frame's {} s",
                    frame.time, last.time
                ),
            });
        }
        write_vtu(&path, frame)?;
        self.frames.push(PvdEntry {
            time: frame.time,
            file,
        });
        if let Err(e) = write_pvd(&self.pvd_path(), &self.frames) {
            self.frames.pop();
            return Err(e);
        }
        Ok(path)
    }

    /// Write `scene.toml`: the scene text, verbatim.
    pub fn write_scene(&self, scene_text: &str) -> Result<(), OutputError> {
        write_atomically(&self.root.join(SCENE_FILE), scene_text.as_bytes())
    }

    /// Write `run.log`: `log` followed by the frames written and the time since
    /// [`create`](Self::create). Call it at the end (and, if wanted, along the way: it is
    /// rewritten whole).
    pub fn write_run_log(&self, log: &RunLog) -> Result<(), OutputError> {
        let mut text = log.format();
        text.push_str("\n[output]\n");
        text.push_str(&format!("frames = {}\n", self.frames.len()));
        text.push_str(&format!(
            "output_open_s = {}\n",
            self.elapsed().as_secs_f64()
        ));
        write_atomically(&self.root.join(RUN_LOG_FILE), text.as_bytes())
    }

    /// A streaming explicit history at `history.csv`.
    pub fn explicit_history(&self, columns: &HistoryColumns) -> Result<HistoryWriter, OutputError> {
        HistoryWriter::explicit(&self.history_path(), columns)
    }

    /// A streaming history at `history.csv` with the columns of the solver `analysis`
    /// runs.
    pub fn history(
        &self,
        columns: &HistoryColumns,
        analysis: &Analysis,
    ) -> Result<HistoryWriter, OutputError> {
        HistoryWriter::for_analysis(&self.history_path(), columns, analysis)
    }

    /// A streaming implicit history at `history.csv`.
    pub fn implicit_history(&self, columns: &HistoryColumns) -> Result<HistoryWriter, OutputError> {
        HistoryWriter::implicit(&self.history_path(), columns)
    }

    /// Write a finished explicit run's history to `history.csv`.
    pub fn write_explicit_history(
        &self,
        columns: &HistoryColumns,
        rows: &[HistoryRow],
    ) -> Result<(), OutputError> {
        write_explicit_history(&self.history_path(), columns, rows)
    }

    /// Write a finished implicit run's history to `history.csv`.
    pub fn write_implicit_history(
        &self,
        columns: &HistoryColumns,
        rows: &[ImplicitHistoryRow],
    ) -> Result<(), OutputError> {
        write_implicit_history(&self.history_path(), columns, rows)
    }
}

/// Whether `name` is a frame file name: `frame_`, digits, `.vtu`.
fn is_frame_name(name: &str) -> bool {
    numbered(name, "frame_")
}

/// Whether `name` is a rigid bodies' file name: `rigid_`, digits, `.vtu`.
fn is_rigid_frame_name(name: &str) -> bool {
    numbered(name, "rigid_")
}

/// Whether `name` is `prefix`, digits, `.vtu`.
fn numbered(name: &str, prefix: &str) -> bool {
    name.strip_prefix(prefix)
        .and_then(|rest| rest.strip_suffix(".vtu"))
        .is_some_and(|digits| !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()))
}

/// The frame of a solver's recorded state as [`RunDirectory::write_state_frame`] writes
/// it: the displacement of every node [m], the interactions' per-node fields, then the
/// element fields gathered from the parts (stress, fibers, state, activation). Also what
/// the Python module's in-memory frames hold.
pub fn state_frame<'a>(
    mesh: &'a Mesh,
    time: f64,
    displacement: &'a [Vector3<f64>],
    fields: &'a ElementFieldArrays,
    nodal: &'a [NodalField],
) -> Frame<'a> {
    let mut frame = Frame::new(time, mesh, displacement);
    for field in nodal {
        frame = frame.with_point_components(&field.name, field.components, &field.values);
    }
    fields.attach(frame)
}

/// What `run.log` says about a run. The file is plain text:
///
/// ```text
/// # musclefem run log
/// program = musclefem
/// version = 0.1.0
///
/// [settings]
/// <the settings text, verbatim>
///
/// [timings]
/// <name>_s = <seconds>
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct RunLog {
    /// Program name.
    pub program: String,
    /// Program version (by default this crate's, which is the workspace's).
    pub version: String,
    /// The settings, as text (e.g. the solver settings' `Debug` output).
    pub settings: String,
    /// Named wall-clock timings [s], in order.
    pub timings: Vec<(String, f64)>,
}

impl RunLog {
    /// A log of `musclefem` at this crate's version (`CARGO_PKG_VERSION`).
    pub fn new(settings: impl Into<String>) -> Self {
        Self {
            program: "musclefem".to_string(),
            version: env!("CARGO_PKG_VERSION").to_string(),
            settings: settings.into(),
            timings: Vec::new(),
        }
    }

    /// Add a timing: `name` (written as `<name>_s`) took `duration`.
    pub fn timing(mut self, name: &str, duration: Duration) -> Self {
        self.timings
            .push((name.to_string(), duration.as_secs_f64()));
        self
    }

    /// The text of the log.
    pub fn format(&self) -> String {
        let mut text = format!(
            "# {} run log\nprogram = {}\nversion = {}\n\n[settings]\n{}",
            self.program, self.program, self.version, self.settings
        );
        if !text.ends_with('\n') {
            text.push('\n');
        }
        text.push_str("\n[timings]\n");
        for (name, seconds) in &self.timings {
            text.push_str(&format!("{name}_s = {seconds}\n"));
        }
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_names() {
        assert_eq!(RunDirectory::frame_file(42), "frames/frame_00042.vtu");
        assert_eq!(RunDirectory::frame_file(123_456), "frames/frame_123456.vtu");
        assert!(is_frame_name("frame_00042.vtu"));
        assert!(!is_frame_name(".frame_00042.vtu.1-2.tmp.vtu"));
        assert!(!is_frame_name("frame_.vtu"));
        assert!(!is_frame_name("frame_1a.vtu"));
        assert_eq!(RunDirectory::rigid_file(7), "frames/rigid_00007.vtu");
        assert!(is_rigid_frame_name("rigid_00007.vtu"));
        assert!(!is_rigid_frame_name("frame_00007.vtu"));
        assert!(!is_frame_name("rigid_00007.vtu"));
    }

    #[test]
    fn run_log_text() {
        let log = RunLog::new("end_time = 1")
            .timing("solve", Duration::from_millis(1500))
            .timing("output", Duration::from_millis(250));
        let text = log.format();
        assert!(text.starts_with("# musclefem run log\n"), "{text}");
        assert!(text.contains(&format!("version = {}\n", env!("CARGO_PKG_VERSION"))));
        assert!(
            text.contains("[settings]\nend_time = 1\n\n[timings]\n"),
            "{text}"
        );
        assert!(text.ends_with("solve_s = 1.5\noutput_s = 0.25\n"), "{text}");
    }
}
