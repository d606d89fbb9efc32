//! `musclefem check SCENE` and `musclefem run SCENE`: read a scene, check it, run it with
//! a progress bar, and write the run directory (frames, PVD, history, scene copy, log).

use std::io::IsTerminal;
use std::ops::ControlFlow;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use indicatif::ProgressBar;

use musclefem_core::solver::explicit::ExplicitSettings;
use musclefem_core::solver::implicit::ImplicitSettings;
use musclefem_core::solver::{Outcome, Record, SolverError};
use musclefem_io::OutputError;
use musclefem_io::output::run_directory::HISTORY_FILE;
use musclefem_io::output::{
    CHECKPOINT_FILE, ExistingResults, FrameSchedule, HistoryWriter, RunLog, RunProgress, RunStart,
    RunWriter,
};
use musclefem_io::scene::{Analysis, Model, PluginPolicy, Trust, load_scene_trusting};
use musclefem_materials::MaterialLibrary;

use crate::commands::Interrupted;
use crate::{CheckArgs, RunArgs};
use musclefem_studies::bench::scene::{SceneProblem, scene_name};
use musclefem_studies::progress::{LINE_EVERY, progress_line, show_time, simulated_time_bar};
use musclefem_studies::scene_check::{check_report, refuse_free_body};
use musclefem_studies::solver::Solver;
use musclefem_studies::threads::worker_threads;

mod tolerance;

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
    let fingerprint = model.fingerprint(&scene_text, &model.analysis);
    let start = match (args.resume, args.force) {
        (true, _) => RunStart::Resume,
        (false, true) => RunStart::Fresh(ExistingResults::Replace),
        (false, false) => RunStart::Fresh(ExistingResults::Refuse),
    };
    let interrupted = Arc::new(AtomicBool::new(false));
    {
        let flag = interrupted.clone();
        // A second Ctrl-C while the first is being honoured kills the process as usual.
        let _ = ctrlc::set_handler(move || {
            if flag.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
        });
    }
    let duration = model.analysis.end_time();
    let mut progress = Progress {
        model: &model,
        bar: progress_bar(duration),
        log_lines: !std::io::stderr().is_terminal(),
        next_log: 0.0,
        started: Instant::now(),
        interrupted,
        last_row: String::new(),
    };
    let history = HistoryWriter::for_analysis(
        &out.join(HISTORY_FILE),
        &model.history_columns(),
        &model.analysis,
    )?;
    let frames = FrameSchedule::new(model.output_interval, duration, &[]);
    let (mut writer, resumed) = RunWriter::open(
        &out,
        start,
        &model.mesh,
        history,
        (frames, model.write_frames),
        fingerprint,
        &mut progress,
    )
    .map_err(|e| match e {
        OutputError::Resume { .. } => anyhow::Error::from(e),
        e => anyhow::anyhow!("{e} (use --force to replace a previous run)"),
    })?;
    writer.directory().write_scene(&scene_text)?;
    // A log from the start: a run killed before its end leaves one that says so.
    let resumed_from = resumed.as_ref().map_or(String::new(), |c| {
        format!("resumed = from the checkpoint at t = {:e} s\n", c.time)
    });
    writer.directory().write_run_log(&RunLog::new(format!(
        "scene = {}\nsolver = {:?}\n{resumed_from}end = running (a run that ended rewrites \
         this line; this one was stopped without being able to)\n",
        args.scene.display(),
        model.analysis
    )))?;
    print!("{}", model.describe());
    let setup = started.elapsed();
    let solve_started = Instant::now();
    let result = match &resumed {
        Some(checkpoint) => model.resume_with(&model.analysis, checkpoint, &mut writer),
        None => model.run(&mut writer),
    };
    let steps = result.as_ref().map_or(0, Outcome::steps);
    let outcome = result.map(|_| ());
    let solve = solve_started.elapsed();
    let written = writer.finish()?;
    progress.bar.finish_and_clear();
    let directory = written.directory;
    // How the run ended, for whoever reads the directory later.
    let end = match (&outcome, &written.write_error, &written.fields_error) {
        (_, Some(error), _) => format!("failed writing the outputs: {error}"),
        (_, _, Some(error)) => format!("failed evaluating a frame's element fields: {error}"),
        (Ok(()), None, None) => format!("complete ({steps} steps)"),
        (Err(SolverError::Interrupted { time }), ..) => {
            format!("interrupted at t = {time:e} s (Ctrl-C)")
        }
        (Err(error), ..) => format!("failed: {error}"),
    };
    let checkpoints = match &written.no_checkpoints {
        Some(why) => format!("checkpoints = none: {}\n", why.replace('\n', "; ")),
        None => format!("checkpoints = at every frame, in {CHECKPOINT_FILE} until the end\n"),
    };
    let log = RunLog::new(format!(
        "scene = {}\nsolver = {:?}\n{resumed_from}{checkpoints}end = {}\n",
        args.scene.display(),
        model.analysis,
        end.replace('\n', "; ")
    ))
    .timing("setup", setup)
    .timing("solve", solve);
    directory.write_run_log(&log)?;
    if let Some(error) = written.write_error {
        return Err(error).context("writing the outputs failed; the run was stopped");
    }
    if let Some(error) = written.fields_error {
        bail!(
            "{}: evaluating the element fields of a frame failed: {error}\n(the frames and \
             history up to there are in {})",
            args.scene.display(),
            out.display()
        );
    }
    match outcome {
        Ok(()) => {
            directory.remove_checkpoint()?;
            println!(
                "done: {steps} steps in {:.2?}; {} frames, history and log in {}",
                solve,
                directory.frames().len(),
                out.display()
            );
            if !progress.last_row.is_empty() {
                println!("  at the end: {}", progress.last_row);
            }
            Ok(())
        }
        Err(SolverError::Interrupted { time }) => Err(Interrupted(format!(
            "stopped at t = {time:.6e} s on request; {} frames and the history up to there \
             are in {} (run.log says so); `musclefem run {} --out {} --resume` goes on from \
             the last frame",
            directory.frames().len(),
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

/// A bar over simulated time on a terminal; hidden otherwise (plain log lines are printed
/// instead, see [`Progress`]).
fn progress_bar(duration: f64) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    simulated_time_bar(duration)
}

/// Drives the bar (or plain log lines), keeps the last row's reactions for the summary,
/// honours Ctrl-C.
struct Progress<'a> {
    model: &'a Model,
    bar: ProgressBar,
    /// Without a terminal: a plain log line on stderr every tenth of the duration and at
    /// the end.
    log_lines: bool,
    next_log: f64,
    started: Instant,
    interrupted: Arc<AtomicBool>,
    last_row: String,
}

impl RunProgress for Progress<'_> {
    fn recorded(&mut self, record: &Record) -> ControlFlow<()> {
        let newton = match record {
            Record::Explicit(_) => String::new(),
            Record::Implicit(row) => format!(" ({} Newton iterations)", row.iterations),
        };
        let reactions: Vec<String> = (self.model.displacement_names.iter())
            .zip(record.reactions())
            .map(|(name, r)| format!("{name} {r:.6e} N"))
            .collect();
        self.last_row = format!(
            "t = {:.6e} s{newton}: {}",
            record.time(),
            reactions.join(", ")
        );
        ControlFlow::Continue(())
    }

    fn reached(&mut self, time: f64) -> ControlFlow<()> {
        let duration = self.model.analysis.end_time();
        show_time(&self.bar, time, duration);
        let at_end = time >= duration * (1.0 - 1e-12);
        if self.log_lines && (time >= self.next_log || at_end) {
            eprintln!("{}", progress_line(time, duration, self.started.elapsed()));
            self.next_log = time + LINE_EVERY * duration;
        }
        if self.interrupted.load(Ordering::SeqCst) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}
