//! `checkpoint.bin`: what a stopped run needs to go on ([`RunCheckpoint`]).
//!
//! A run writes it (atomically, replacing the previous one) after every frame: the
//! solver's state there (`musclefem_core::solver::checkpoint`), the history rows and the
//! frames written up to that row, and a fingerprint of the model. A resumed run checks the
//! fingerprint, cuts the run directory back to those rows and frames, and continues; its
//! files then end as an uninterrupted run's would, byte for byte. The file goes away when
//! the run completes.
//!
//! Layout: the line `musclefem checkpoint 3` (3: the solver's state ends with its pose
//! followers' states, e.g. the knee's patella's pull), then, in the little-endian encoding of
//! `CheckpointWriter`, the fingerprint, the history header and rows, the frames (time,
//! file), the solver's name, time and state, and the study's own state (bytes a study
//! that observes the run beside the writer keeps, e.g. the knee's stress samples; empty for
//! a scene run).

use std::path::Path;

use musclefem_core::solver::{Checkpoint, CheckpointReader, CheckpointWriter, SolverError};

use super::pvd::PvdEntry;
use crate::OutputError;
use crate::atomic::write_atomically;

/// File name of the checkpoint in a run directory.
pub const CHECKPOINT_FILE: &str = "checkpoint.bin";

/// The first line of the file.
const MAGIC: &[u8] = b"musclefem checkpoint 3\n";

/// A run's checkpoint (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct RunCheckpoint {
    /// Of the model the run solves (scene, mesh, settings): a checkpoint resumes only
    /// the model it was taken from.
    pub fingerprint: u64,
    /// `history.csv`'s header and its rows up to the checkpoint.
    pub history_header: String,
    pub history_rows: Vec<Vec<f64>>,
    /// The frames written up to the checkpoint.
    pub frames: Vec<PvdEntry>,
    /// The solver's state.
    pub solver: Checkpoint,
    /// What the study that observed the run keeps beyond the history (empty for none).
    pub study: Vec<u8>,
}

impl RunCheckpoint {
    /// Write the checkpoint to `path`, atomically.
    pub fn write(&self, path: &Path) -> Result<(), OutputError> {
        let mut out = CheckpointWriter::new();
        out.u64(self.fingerprint);
        out.text(&self.history_header);
        out.u64(self.history_rows.len() as u64);
        self.history_rows.iter().for_each(|row| out.f64s(row));
        out.u64(self.frames.len() as u64);
        for frame in &self.frames {
            out.f64(frame.time);
            out.text(&frame.file);
        }
        out.text(&self.solver.solver);
        out.f64(self.solver.time);
        out.bytes(&self.solver.state);
        out.bytes(&self.study);
        let mut bytes = MAGIC.to_vec();
        bytes.extend(out.into_bytes());
        write_atomically(path, &bytes)
    }

    /// Read the checkpoint at `path`.
    pub fn read(path: &Path) -> Result<Self, OutputError> {
        let bytes = std::fs::read(path).map_err(|e| OutputError::io("read", path, e))?;
        let body = bytes.strip_prefix(MAGIC).ok_or_else(|| OutputError::Data {
            path: path.to_path_buf(),
            message: "not a musclefem checkpoint (or one of another version)".into(),
        })?;
        let corrupt = |e: SolverError| OutputError::Data {
            path: path.to_path_buf(),
            message: format!("a damaged checkpoint: {e}"),
        };
        let mut input = CheckpointReader::new(body);
        let mut read = || -> Result<RunCheckpoint, SolverError> {
            let fingerprint = input.u64()?;
            let history_header = input.text()?;
            let rows = input.index()?;
            let history_rows = (0..rows).map(|_| input.f64s()).collect::<Result<_, _>>()?;
            let frames = input.index()?;
            let frames = (0..frames)
                .map(|_| {
                    Ok(PvdEntry {
                        time: input.f64()?,
                        file: input.text()?,
                    })
                })
                .collect::<Result<_, SolverError>>()?;
            let solver = Checkpoint {
                solver: input.text()?,
                time: input.f64()?,
                state: input.bytes()?,
            };
            let study = input.bytes()?;
            input.finish()?;
            Ok(RunCheckpoint {
                fingerprint,
                history_header,
                history_rows,
                frames,
                solver,
                study,
            })
        };
        read().map_err(corrupt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_checkpoint_round_trips_and_a_damaged_one_is_refused() {
        let dir = std::env::temp_dir().join(format!("musclefem_checkpoint_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(CHECKPOINT_FILE);
        let checkpoint = RunCheckpoint {
            fingerprint: 0x1234_5678_9abc_def0,
            history_header: "time_s,reaction_n".into(),
            history_rows: vec![vec![0.0, 0.0], vec![0.1, 1.0 / 3.0]],
            frames: vec![PvdEntry {
                time: 0.1,
                file: "frames/frame_00000.vtu".into(),
            }],
            solver: Checkpoint {
                solver: "explicit".into(),
                time: 0.1,
                state: vec![1, 2, 3],
            },
            study: vec![4, 5],
        };
        checkpoint.write(&path).unwrap();
        assert_eq!(RunCheckpoint::read(&path).unwrap(), checkpoint);

        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..bytes.len() - 2]).unwrap();
        let error = RunCheckpoint::read(&path).unwrap_err().to_string();
        assert!(error.contains("damaged checkpoint"), "{error}");
        std::fs::write(&path, b"hello").unwrap();
        let error = RunCheckpoint::read(&path).unwrap_err().to_string();
        assert!(error.contains("not a musclefem checkpoint"), "{error}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
