//! A squat run as its scene (issue 30, step 4): what `musclefem knee` runs. The squat's
//! model is built in code for its scene ([`super::scene::SquatScene`]) and for the knee's
//! observer ([`Recorder`]); the scene, read back from a staging folder, runs through the
//! directory runner of `musclefem run` ([`crate::run_directory`]: frames, history,
//! checkpoints, progress, Ctrl-C) with the observer beside the writer, so that `musclefem
//! run DIR/scene.toml` computes the same `history.csv`. The observer's patella is the
//! knee's own, told the same pull as the scene's ([`Recorder::observes_patella`]).

use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use anyhow::{Context, Result};
use indicatif::ProgressBar;

use musclefem_core::solver::SolverError;
use musclefem_fibers::FiberField;
use musclefem_io::output::run_directory::SCENE_FILE;
use musclefem_io::output::{ExistingResults, RunDirectory, RunStart};
use musclefem_io::scene::{Model, load_scene};
use musclefem_materials::MaterialLibrary;

use super::model::{Activation, KneeGeometry};
use super::peak_stress::table_instants;
use super::recorder::{Recorder, finish};
use super::run::{SquatRun, SquatSettings, element_regions, squat_model, squat_result};
use super::scene::SquatScene;
use crate::run_directory::{DirectoryRun, run_into_directory};

/// Where and how a squat's scene runs.
pub struct SquatDirectory<'a> {
    /// The squat's run directory (`scene.toml` and its files are written there).
    pub out: &'a Path,
    pub start: RunStart,
    /// Frames every this [s] (none for 0), and at the table's angles.
    pub frame_interval: f64,
    /// The first lines of `run.log`.
    pub log_header: String,
    /// Stops the squat after its last complete frame once set.
    pub interrupted: &'a AtomicBool,
    /// The squat's progress bar (`None`: the runner's own).
    pub bar: Option<ProgressBar>,
}

/// How a squat run as its scene went.
pub struct SceneSquat {
    /// The squat's result, or why it failed (its recorder's error before the solver's).
    pub run: Result<SquatRun>,
    /// Whether it was stopped on request (`interrupted`) rather than failing.
    pub stopped: bool,
    pub directory: RunDirectory,
}

/// Run the squat of `activation` with `settings` on `geometry` with `fibers` as its
/// scene, into `job.out`. Errors are those before the run and in writing its outputs;
/// how the run went is in the result. A completed squat keeps its last checkpoint: the
/// study removes it once complete.
pub fn run_squat_scene(
    geometry: &KneeGeometry,
    fibers: &FiberField,
    activation: Activation,
    settings: &SquatSettings,
    job: SquatDirectory<'_>,
) -> Result<SceneSquat> {
    let started = Instant::now();
    let (knee, built) = squat_model(geometry, fibers, activation, settings)?;
    let scene = SquatScene::new(geometry, &knee.mesh, &built, activation, settings)?;
    let text = scene.text(job.frame_interval)?;
    let files = scene.files();
    let model = load_staged(&text, &files, activation)?;
    let regions = element_regions(geometry, &knee.mesh, fibers, &built);
    let mut recorder = Recorder::new(geometry, &knee, &built, &regions, &settings.squat)?;
    let beside: Vec<(&str, &str)> = (files.iter())
        .map(|(name, text)| (*name, text.as_str()))
        .collect();
    let instants: Vec<f64> = (table_instants(&settings.squat).into_iter())
        .map(|(_, _, time)| time)
        .collect();
    let report = run_into_directory(
        &model,
        DirectoryRun {
            scene: &job.out.join(SCENE_FILE),
            scene_text: &text,
            beside: &beside,
            out: job.out,
            start: job.start,
            frame_instants: &instants,
            log_header: job.log_header,
            setup_time: started.elapsed(),
            keep_checkpoint: true,
            interrupted: job.interrupted,
            bar: job.bar,
            companion: Some(&mut recorder),
        },
    )?;
    let context = || {
        format!(
            "{} {} squat ({} elements)",
            settings.solver.name(),
            activation.name(),
            knee.mesh.element_count()
        )
    };
    let stopped =
        recorder.error.is_none() && matches!(report.outcome, Err(SolverError::Interrupted { .. }));
    let run = finish(report.outcome.map_err(anyhow::Error::from), &mut recorder)
        .with_context(context)
        .and_then(|outcome| {
            squat_result(
                &mut recorder,
                outcome,
                (activation, settings, &geometry.muscles),
                built.summaries.clone(),
                report.solve_time,
                report.resumed_from,
            )
        });
    Ok(SceneSquat {
        run,
        stopped,
        directory: report.directory,
    })
}

/// Run the squat of `activation` as its scene into `out`, replacing what it holds, with
/// frames only at the table's angles, no progress bar and no stop but an error: the
/// squat of the benchmark and the tests.
pub fn run_squat_in(
    geometry: &KneeGeometry,
    fibers: &FiberField,
    activation: Activation,
    settings: &SquatSettings,
    out: &Path,
) -> Result<SquatRun> {
    let never = AtomicBool::new(false);
    let squat = run_squat_scene(
        geometry,
        fibers,
        activation,
        settings,
        SquatDirectory {
            out,
            start: RunStart::Fresh(ExistingResults::Replace),
            frame_interval: 0.0,
            log_header: format!("activation = {}\n", activation.name()),
            interrupted: &never,
            bar: Some(ProgressBar::hidden()),
        },
    )?;
    squat.run
}

/// The squat's scene read back from a private staging folder (the run directory is not
/// touched before the runner refuses or replaces what it holds).
fn load_staged(text: &str, files: &[(&str, String)], activation: Activation) -> Result<Model> {
    let staging = std::env::temp_dir().join(format!(
        "musclefem-knee-{}-{}",
        std::process::id(),
        activation.name()
    ));
    std::fs::create_dir_all(&staging).with_context(|| format!("creating {}", staging.display()))?;
    let loaded = (|| -> Result<Model> {
        std::fs::write(staging.join(SCENE_FILE), text)?;
        for (name, text) in files {
            std::fs::write(staging.join(name), text)?;
        }
        Ok(load_scene(
            &staging.join(SCENE_FILE),
            &mut MaterialLibrary::with_builtins(),
        )?)
    })();
    let _ = std::fs::remove_dir_all(&staging);
    loaded.context("the squat's scene")
}
