//! What one squat of the knee study writes as it goes (through the run writer: frames,
//! history, a checkpoint after every frame) and its progress bar.

use std::ops::ControlFlow;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};

use musclefem_core::mesh::Mesh;
use musclefem_core::solver::RigidMotion;
use musclefem_core::solver::element_fields::PartFields;
use musclefem_core::solver::observer::Snapshot;
use musclefem_io::output::{
    FrameSchedule, HistoryColumns, HistoryWriter, RigidBodyFrame, RunLog, RunProgress, RunStart,
    RunWriter, StudyRunWriter,
};

use crate::elongation::Solver;
use crate::knee::simulation::{
    Activation, KneeGeometry, SquatResume, SquatStart, SquatWatcher, StressSample,
};

/// The progress bar of one squat, and the flag that stops it (Ctrl-C, or the other squat
/// failed).
pub(super) struct SquatProgress<'a> {
    pub(super) bar: &'a ProgressBar,
    pub(super) stop: &'a AtomicBool,
    /// Whether the flag stopped the run.
    pub(super) stopped: bool,
}

impl RunProgress for SquatProgress<'_> {
    fn reached(&mut self, time: f64) -> ControlFlow<()> {
        self.bar.set_position((1e3 * time) as u64);
        if self.stop.load(Ordering::Relaxed) {
            self.stopped = true;
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }
}

/// The run directory of one squat: opened by the run writer when the model is built
/// (fresh, or cut back to its checkpoint to resume), written as the run goes.
pub(super) struct Outputs<'a> {
    pub(super) root: PathBuf,
    pub(super) start: RunStart,
    /// The muscles' mesh with fibers (what the frames show).
    pub(super) mesh: &'a Mesh,
    /// The bones (the frames show them too, in `rigid.pvd`).
    pub(super) geometry: &'a KneeGeometry,
    /// Frames every `--frame-interval`, at the table's angles and at the end.
    pub(super) frames: FrameSchedule,
    /// `--frame-interval` [s], for the squat's scene.
    pub(super) frame_interval: f64,
    /// What makes a checkpoint this squat's: its settings and activation (the mesh is
    /// added).
    pub(super) identity: String,
    /// The first lines of `run.log` while the squat runs.
    pub(super) log_head: String,
    /// Handed to the writer at the start.
    pub(super) progress: Option<&'a mut dyn RunProgress>,
    pub(super) writer: Option<RunWriter<'a>>,
}

impl SquatWatcher for Outputs<'_> {
    fn start(&mut self, start: &SquatStart) -> Result<Option<SquatResume>> {
        let columns = HistoryColumns::new(Vec::new(), start.rigid_ties.clone())
            .with_interactions(start.interactions.clone());
        let path = self.root.join(musclefem_io::output::HISTORY_FILE);
        let history = match start.solver {
            Solver::Implicit => HistoryWriter::implicit(&path, &columns)?,
            Solver::Explicit => HistoryWriter::explicit(&path, &columns)?,
        };
        let progress = self
            .progress
            .take()
            .context("a squat's outputs were started twice")?;
        let fingerprint = musclefem_io::fingerprint::model_fingerprint(&self.identity, self.mesh);
        let (writer, resumed) = RunWriter::open(
            &self.root,
            self.start,
            self.mesh,
            history,
            (self.frames.clone(), true),
            fingerprint,
            progress,
        )
        .map_err(|e| match self.start {
            RunStart::Resume => anyhow::Error::from(e),
            RunStart::Fresh(_) => anyhow::anyhow!("{e} (use --force to replace a previous run)"),
        })?;
        let writer = writer.with_rigid_bodies(bone_frames(self.geometry, start.patella.clone()));
        // The squat as a scene that `musclefem run` reruns.
        start.scene.write_files(&self.root)?;
        writer
            .directory()
            .write_scene(&start.scene.text(self.frame_interval)?)?;
        let study = writer.resumed_study().to_vec();
        // A log from the start: a squat killed before its end leaves one that says so.
        let resumed_line = resumed.as_ref().map_or(String::new(), |checkpoint| {
            format!(
                "resumed = from the checkpoint at t = {:e} s\n",
                checkpoint.time
            )
        });
        writer.directory().write_run_log(&RunLog::new(format!(
            "{}{resumed_line}end = running (a squat that ended rewrites this line; this one was \
             stopped without being able to: --resume goes on from its last frame)\n",
            self.log_head
        )))?;
        self.writer = Some(writer);
        Ok(resumed.map(|solver| SquatResume { solver, study }))
    }

    fn recorded(&mut self, _: &StressSample, _: &Snapshot, _: &[PartFields]) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }

    fn run_writer(&mut self) -> Option<&mut dyn StudyRunWriter> {
        self.writer
            .as_mut()
            .map(|writer| writer as &mut dyn StudyRunWriter)
    }
}

/// The knee's bones as the frames show them (`rigid.pvd`, body_id 0, 1, 2): the femur
/// and the tibia on the squat's motions, the patella on `patella`, the run's pose.
fn bone_frames(geometry: &KneeGeometry, patella: RigidMotion) -> Vec<RigidBodyFrame<'_>> {
    let motions = &geometry.motions;
    [
        ("femur", &geometry.femur, motions.femur.clone()),
        ("tibia", &geometry.tibia, motions.tibia.clone()),
        ("patella", &geometry.patella, patella),
    ]
    .into_iter()
    .map(|(name, surface, motion)| RigidBodyFrame {
        name,
        vertices: &surface.vertices,
        triangles: &surface.triangles,
        motion,
    })
    .collect()
}

/// The bar of one squat of `duration` [s], in simulated milliseconds.
pub(super) fn progress_bar(duration: f64, activation: Activation) -> ProgressBar {
    let bar = ProgressBar::new((1e3 * duration) as u64);
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{:<7} {{bar:40}} {{pos}} / {{len}} ms of squat [{{elapsed_precise}}, ETA {{eta}}]",
            activation.name()
        ))
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}
