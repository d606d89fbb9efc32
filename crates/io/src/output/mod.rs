//! Output of a run for ParaView and for plotting: VTU frames, a PVD time series, CSV
//! histories, a copy of the scene and a run log, all written atomically.
//!
//! - [`element_fields`]: [`ElementFieldArrays`], the solvers' per-part element fields
//!   (stress, fiber direction, activation, state variables) as frame arrays;
//! - [`frame`]: [`Frame`], one output frame (mesh, nodal and element fields) filled from
//!   plain slices, with [`von_mises`] and the stress-order conversion;
//! - [`vtu`]: [`write_vtu`], the VTU file of a frame (cell types, node orders, array
//!   names and units are documented there);
//! - [`pvd`]: [`write_pvd`] / [`read_pvd`], ParaView's time-series index;
//! - [`rigid_frames`]: [`RigidBodyFrame`], the rigid bodies at their pose in every
//!   frame, a second series `rigid.pvd`;
//! - [`read_frame`]: [`read_frame()`] and [`read_rigid_frame`], those frames read back,
//!   and [`run_frame_at`], a run's frame nearest a time;
//! - [`frame_picture`] (with the feature `plot`): [`stage_frame_picture`], a PNG of a
//!   frame's deformed parts coloured by a cell value, with the bones in grey;
//! - [`history`]: [`HistoryColumns`] and [`HistoryWriter`], CSV histories of the explicit
//!   and implicit solvers;
//! - [`run_directory`]: [`RunDirectory`], which lays all of these out in one directory
//!   and keeps `result.pvd` listing complete frames only, and [`RunLog`];
//! - [`lock`]: [`OutputLock`], one writer per output directory;
//! - [`checkpoint`]: [`RunCheckpoint`], `checkpoint.bin`, what a stopped run resumes from;
//! - [`frame_schedule`]: [`FrameSchedule`], which recorded instants get a frame;
//! - [`run_writer`]: [`RunWriter`], the observer that writes all of these as a run goes,
//!   checkpoints after every frame, and resumes a stopped run.

pub mod checkpoint;
pub mod element_fields;
pub mod frame;
#[cfg(feature = "plot")]
pub mod frame_picture;
pub mod frame_schedule;
pub mod history;
pub mod lock;
pub mod pvd;
pub mod read_frame;
pub mod rigid_frames;
pub mod run_directory;
pub mod run_writer;
pub mod stress_percentile;
pub mod vtu;

pub use checkpoint::{CHECKPOINT_FILE, RunCheckpoint};
pub use element_fields::ElementFieldArrays;
pub use frame::{Field, FieldValues, Frame, voigt_to_vtk_symmetric, von_mises};
#[cfg(feature = "plot")]
pub use frame_picture::{FramePicture, FramePictureSummary, stage_frame_picture};
pub use frame_schedule::{FrameInstants, FrameSchedule};
pub use history::{HistoryColumns, HistoryWriter, write_explicit_history, write_implicit_history};
pub use lock::OutputLock;
pub use pvd::{PvdEntry, read_pvd, write_pvd};
pub use read_frame::{
    FrameData, RigidFrameData, RunFrame, frame_time, nearest_entry, read_frame, read_rigid_frame,
    run_frame_at,
};
pub use rigid_frames::{RigidBodyFrame, encode_rigid_vtu};
pub use run_directory::{ExistingResults, HISTORY_FILE, RunDirectory, RunLog, state_frame};
pub use run_writer::{
    ABORT_AFTER_CHECKPOINT, RunProgress, RunStart, RunWriter, StudyRunWriter, WrittenRun,
};
pub use vtu::{encode_vtu, stage_vtu, vtk_cell_type, write_vtu};
