//! `musclefem check SCENE` and `musclefem run SCENE`: read a scene, check it, run it with
//! a progress bar, and write the run directory (frames, PVD, history, scene copy, log).

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use anyhow::{Context, Result, bail};

use musclefem_core::solver::SolverError;
use musclefem_core::solver::explicit::ExplicitSettings;
use musclefem_core::solver::implicit::ImplicitSettings;
use musclefem_io::output::{ExistingResults, RunStart};
use musclefem_io::scene::{Analysis, Model, PluginPolicy, Trust, load_scene_trusting};
use musclefem_materials::MaterialLibrary;

use crate::commands::Interrupted;
use crate::{CheckArgs, RunArgs};
use musclefem_studies::bench::scene::{SceneProblem, scene_name};
use musclefem_studies::scene_check::{check_report, refuse_free_body};
use musclefem_studies::solver::Solver;
use musclefem_studies::threads::worker_threads;

mod tolerance;

use musclefem_studies::run_directory::{DirectoryRun, run_into_directory};

/// Print what the scene holds, or fail naming the file, line and key.
pub fn check(args: &CheckArgs) -> Result<()> {
    let trust = Trust {
        plugins: PluginPolicy::SkipForCheck,
        outside_paths: args.allow_outside_paths,
    };
    let model = load_scene_trusting(&args.scene, &mut MaterialLibrary::with_builtins(), trust)?;
    print!("{}", check_report(&model, &args.scene)?);
    Ok(())
}

/// Run the scene and write its run directory.
pub fn run(args: &RunArgs) -> Result<()> {
    if let Some(requested) = args.threads {
        let (threads, warning) = worker_threads(requested, "--threads")?;
        if let Some(warning) = warning {
            eprintln!("warning: {warning}");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build_global()
            .context("cannot set the number of threads")?;
    }
    let started = Instant::now();
    let mut model = load_scene_trusting(
        &args.scene,
        &mut MaterialLibrary::with_builtins(),
        args.trust.trust(),
    )?;
    if let Some(choice) = args.solver {
        model.analysis = switch_solver(&model, choice);
        model.solver_rationale = None;
    }
    if let Some(percent) = args.tolerance {
        let scene = SceneProblem {
            name: scene_name(&args.scene)?,
            model,
        };
        let (analysis, why) =
            tolerance::analysis_within(&scene, &args.scene, percent, &args.bench_table.path)?;
        model = scene.model;
        model.analysis = analysis;
        model.solver_rationale = Some(why);
    }
    // A body no condition holds is refused before anything is written.
    refuse_free_body(&model, &args.scene)?;
    let scene_text = std::fs::read_to_string(&args.scene)
        .with_context(|| format!("cannot read {}", args.scene.display()))?;
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = args.scene.file_stem().unwrap_or_default();
        PathBuf::from("out").join(stem)
    });
    let start = match (args.resume, args.force) {
        (true, _) => RunStart::Resume,
        (false, true) => RunStart::Fresh(ExistingResults::Replace),
        (false, false) => RunStart::Fresh(ExistingResults::Refuse),
    };
    print!("{}", model.describe());
    let report = run_into_directory(
        &model,
        DirectoryRun {
            scene: &args.scene,
            scene_text: &scene_text,
            beside: &[],
            out: &out,
            start,
            frame_instants: &[],
            log_header: String::new(),
            setup_time: started.elapsed(),
            keep_checkpoint: false,
            interrupted: &interrupt_flag(),
            bar: None,
            companion: None,
        },
    )?;
    let steps = report.steps();
    match report.outcome {
        Ok(_) => {
            println!(
                "done: {steps} steps in {:.2?}; {} frames, history and log in {}",
                report.solve_time,
                report.directory.frames().len(),
                out.display()
            );
            if !report.last_row.is_empty() {
                println!("  at the end: {}", report.last_row);
            }
            Ok(())
        }
        Err(SolverError::Interrupted { time }) => Err(Interrupted(format!(
            "stopped at t = {time:.6e} s on request; {} frames and the history up to there \
             are in {} (run.log says so); `musclefem run {} --out {} --resume` goes on from \
             the last frame",
            report.directory.frames().len(),
            out.display(),
            args.scene.display(),
            out.display()
        ))
        .into()),
        Err(error) => bail!(
            "{}: {error}\n(the frames and history up to the failure are in {})",
            args.scene.display(),
            out.display()
        ),
    }
}

/// The other solver's default settings for the scene's duration and output interval.
fn switch_solver(model: &Model, choice: Solver) -> Analysis {
    let duration = model.analysis.end_time();
    match (choice, &model.analysis) {
        (Solver::Explicit, Analysis::Explicit(_)) | (Solver::Implicit, Analysis::Implicit(_)) => {
            model.analysis.clone()
        }
        (Solver::Explicit, _) => {
            let mut settings = ExplicitSettings::new(duration);
            settings.history_interval = model.output_interval;
            Analysis::Explicit(settings)
        }
        (Solver::Implicit, _) => {
            let increments = ((duration / model.output_interval).round() as usize).max(1);
            Analysis::Implicit(ImplicitSettings::new(duration, increments).with_cutting())
        }
    }
}

/// A flag that Ctrl-C sets (the run then stops after its last complete frame); a second
/// Ctrl-C while the first is being honoured kills the process as usual. Install once per
/// process.
pub fn interrupt_flag() -> Arc<AtomicBool> {
    let interrupted = Arc::new(AtomicBool::new(false));
    let flag = interrupted.clone();
    let _ = ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    });
    interrupted
}
