//! `musclefem knee`: the squat with the four quadriceps, passive and active, and their
//! peak stresses (seed §2.4, Fig. 6).
//!
//! Writes, under `--out DIR`:
//! - `peak_stress.csv` (`muscle,knee_angle_deg,phase,activation,vm95_pa`) and
//!   `peak_stress.png` (one panel per muscle, bars per knee angle: passive and active,
//!   in flexion and in extension);
//! - per run, `passive/` and `active/`: VTU frames and `result.pvd` (stress, von Mises,
//!   fibers, activation), the bones at their pose in every frame (`rigid.pvd`: femur,
//!   tibia, patella as body_id 0, 1, 2), `history.csv` (the solver's convergence and energies, forces
//!   on every tie and interaction, each part's vm95), `vm95.csv` (each muscle's vm95 at every recorded
//!   instant), `newton.csv` (implicit: every increment's Newton residuals), `cuts.csv`
//!   (implicit: every failed attempt that was cut, and why), `tendon.csv` (the
//!   quadriceps' pull, the patellar tendon's force and strain, the patella's pose),
//!   `plausibility.csv` (at 30°, 45°, 60°, 90° in both phases: each muscle's pull, the
//!   patellar tendon's force, the knee extensor moment, the fiber stretch, the forces on
//!   the femur, the tendons' peak stress), `run.log`, and `scene.toml` with the files it
//!   names (`muscles.inp`, `fibers.csv`, `patella_table.csv`, the bones' OBJ files): the
//!   squat as a scene that `musclefem run` reruns;
//! - `kinematics.csv`: the closed chain's hip flexion, knee flexion, tibia angle and
//!   pelvis height over the squat;
//! - `patella_tracking.csv` (Visible Human knee): every 5°, the trochlear groove's floor,
//!   depth and crests under the patella, and how far lateral of the floor
//!   the planar mechanism's patella rides
//!   ([`crate::knee::anatomy::visible_human::tracking`]);
//! - `anatomy/` (procedural knee): its bones and muscles at 0°, 30°, 45°, 60° and 90°.
//!
//! [`knee`] is the command; [`run_knee`] the same study with its lines, bars and stop in
//! the caller's hands and its tables returned (the Python module's `musclefem.knee`).

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget};

use crate::elongation::Solver;
use crate::interrupted::Interrupted;
use crate::knee::anatomy::export::write_anatomy;
use crate::knee::simulation::patella::write_tendon_csv;
use crate::knee::simulation::peak_stress::{
    TABLE_ANGLES_DEGREES, peak_stress_from_history, stage_peak_stress_csv,
};
use crate::knee::simulation::plausibility::write_plausibility_csv;
use crate::knee::simulation::resolution::resolution_rationale;
use crate::knee::simulation::visible_human::visible_human_geometry;
use crate::knee::simulation::{
    Activation, KneeGeometry, PeakStressRow, SquatDirectory, SquatRun, SquatSettings,
    run_squat_scene,
};
use crate::knee::{Anatomy, Quadriceps};
use musclefem_io::output::{CHECKPOINT_FILE, ExistingResults, RunLog, RunStart};
use musclefem_io::plot::stage_bar_png;

/// What a caller sees of the knee study as it goes.
pub struct KneeView<'a> {
    /// Where the command's lines go (each ends with a newline): stdout for the command.
    pub say: &'a (dyn Fn(&str) + Sync),
    /// Whether the squats' progress bars are drawn (on stderr).
    pub bars: bool,
    /// Stops both squats at their next recorded instant once set: by the caller (Ctrl-C in
    /// Python), or by a squat that failed, for the other.
    pub stop: &'a AtomicBool,
}

/// What the knee study found (its files are under `--out`).
pub struct KneeOutcome {
    /// `peak_stress.csv`'s rows: vm95 per muscle, angle, phase and activation.
    pub rows: Vec<PeakStressRow>,
    /// The squats, in the order of `activations`.
    pub activations: Vec<Activation>,
    pub runs: Vec<SquatRun>,
    /// The muscles, in the order of every per-muscle column.
    pub muscles: Vec<Quadriceps>,
}

/// `musclefem knee`; `stop` (set by Ctrl-C) stops both squats at their next recorded
/// instant, and the study then ends with [`Interrupted`].
pub fn knee(args: &KneeArgs, stop: &AtomicBool) -> Result<()> {
    let say = |text: &str| print!("{text}");
    let view = KneeView {
        say: &say,
        bars: std::io::stderr().is_terminal(),
        stop,
    };
    run_knee(args, &view).map(drop)
}

/// The knee study of `args`: its files written under `args.out`, its lines said to
/// `view`, its tables returned.
pub fn run_knee(args: &KneeArgs, view: &KneeView<'_>) -> Result<KneeOutcome> {
    let started = Instant::now();
    let say = view.say;
    if !(args.duration.is_finite() && args.duration > 0.0) {
        bail!("--duration {} s must be positive", args.duration);
    }
    if !(5.0..=90.0).contains(&args.peak_flexion) {
        bail!(
            "--peak-flexion {}° must be from 5° to 90° (the anatomy's range)",
            args.peak_flexion
        );
    }
    crate::frame_interval::check_frame_interval(args.frame_interval)?;
    if let Some(step) = args.time_step
        && !(step.is_finite() && step > 0.0 && step < args.duration)
    {
        bail!("--time-step {step} s must be positive and below the duration");
    }
    let knee_anatomy = args.knee_anatomy();
    match (&knee_anatomy, args.element) {
        (KneeAnatomy::VisibleHuman, Some(element)) => bail!(
            "--element {}: the Visible Human knee's muscles are meshed with tet10-fbar; \
             --element chooses the hex8 of --anatomy procedural or of an anatomy directory",
            element.name()
        ),
        (_, Some(element)) if !element.is_hex() => bail!(
            "--element {}: the knee's muscles are meshed with hex8 (use hex8-fbar or \
             hex8-one-point)",
            element.name()
        ),
        _ => {}
    }
    let activations = args.activations();
    let (settings, resolution, why) = args.settings()?;
    if let Some(why) = why {
        say(&format!("{why}\n"));
    }
    let start = if args.resume {
        RunStart::Resume
    } else if args.force {
        RunStart::Fresh(ExistingResults::Replace)
    } else {
        RunStart::Fresh(ExistingResults::Refuse)
    };
    // Refuse before any work if earlier results are in the way (or, resuming, if the
    // study there completed).
    for file in ["peak_stress.csv", "peak_stress.png"] {
        let path = args.out.join(file);
        if path.exists() && args.resume {
            bail!(
                "{} exists: the study in {} completed, there is nothing to resume",
                path.display(),
                args.out.display()
            );
        }
        if path.exists() && !args.force {
            bail!(
                "{} exists: use --force to replace a previous run",
                path.display()
            );
        }
    }
    if args.resume {
        for activation in &activations {
            let path = args.out.join(activation.name()).join(CHECKPOINT_FILE);
            if !path.is_file() {
                bail!(
                    "{} does not exist: the {} squat has no checkpoint to resume from (it \
                     stopped before its first frame, or was not run with these options); \
                     start again without --resume",
                    path.display(),
                    activation.name()
                );
            }
        }
    }
    // The procedural anatomy, kept to be written out, and the squat's geometry.
    let procedural_knee = || Anatomy::procedural_knee(resolution).context("the procedural knee");
    let (geometry, procedural) = match &knee_anatomy {
        KneeAnatomy::VisibleHuman => (visible_human_geometry(resolution, &settings.squat)?, None),
        KneeAnatomy::Procedural => {
            let anatomy = procedural_knee()?;
            let geometry = KneeGeometry::procedural_knee(&anatomy, &settings.squat)?;
            (geometry, Some(anatomy))
        }
        KneeAnatomy::Files(directory) => {
            let geometry = crate::knee::simulation::files::geometry_from_directory(
                directory,
                &procedural_knee()?,
                &settings.squat,
            )?;
            (geometry, None)
        }
    };
    // Nothing is written before the output directory is this run's alone.
    let _lock = musclefem_io::output::OutputLock::acquire(&args.out)?;
    if let Some(anatomy) = &procedural {
        write_anatomy(anatomy, &args.out.join("anatomy"), &TABLE_ANGLES_DEGREES)
            .context("writing the anatomy")?;
    }
    musclefem_io::atomic::write_atomically(
        &args.out.join("kinematics.csv"),
        geometry.motions.kinematics_csv(200).as_bytes(),
    )
    .context("writing kinematics.csv")?;
    if let Some(tracking) = &geometry.patella_tracking {
        musclefem_io::atomic::write_atomically(
            &args.out.join("patella_tracking.csv"),
            tracking.csv().as_bytes(),
        )
        .context("writing patella_tracking.csv")?;
    }
    let fibers = geometry.fibers()?;
    let muscle_elements: usize = (0..geometry.muscles.len())
        .map(|b| geometry.mesh.blocks[b].len())
        .sum();
    say(&format!(
        "knee squat 0° → {}° → 0° in {} s (closed chain: tibia pinned at the ankle, pelvis \
         lowered), {}, {} solver{}, {} muscle and {} tendon elements of {} ({}), {} \
         interfaces, fibers in {:.2?}\n",
        args.peak_flexion,
        settings.squat.duration,
        match activations.as_slice() {
            [one] => one.name().to_string(),
            _ => "passive and active side by side".to_string(),
        },
        settings.solver.name(),
        match settings.solver {
            Solver::Implicit if settings.inertia => " with inertia (Newmark)",
            Solver::Implicit => " (quasi-static)",
            Solver::Explicit => " with mass scaling",
        },
        muscle_elements,
        geometry.mesh.element_count() - muscle_elements,
        match &knee_anatomy {
            KneeAnatomy::VisibleHuman => "tet10-fbar",
            _ => args.element().name(),
        },
        match &knee_anatomy {
            KneeAnatomy::VisibleHuman => {
                format!("Visible Human Female, {resolution:?} resolution").to_lowercase()
            }
            KneeAnatomy::Files(d) => format!("from {}", d.display()),
            KneeAnatomy::Procedural => {
                format!("procedural anatomy, {resolution:?} resolution").to_lowercase()
            }
        },
        settings.interfaces.name(),
        fibers.solve_time + fibers.setup_time,
    ));
    say(&format!(
        "  {} solver: {}\n",
        settings.solver.name(),
        crate::knee::simulation::run::solver_rationale(settings.solver, args.is_visible_human())
    ));
    if let Some(tracking) = &geometry.patella_tracking {
        say(&format!(
            "  {} (patella_tracking.csv)\n",
            tracking.summary()
        ));
    }
    if knee_anatomy == KneeAnatomy::Procedural {
        say(&format!(
            "  {} resolution: {}\n",
            format!("{resolution:?}").to_lowercase(),
            resolution_rationale(resolution)
        ));
    }
    // The runs go side by side, each on its own share of the cores in a pool of its own
    // (`squat_pool`): one squat's element loops then never wait for a thread that is busy
    // with the other's, and its sparse factorizations, serial, keep their core busy.
    let threads_per_squat = (rayon::current_num_threads() / activations.len()).max(1);
    let side_by_side = activations.len() > 1;
    let bars = MultiProgress::with_draw_target(if view.bars {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    });
    let stop = view.stop;
    let outcomes: Vec<Result<SquatRun>> = std::thread::scope(|scope| {
        let handles: Vec<_> = activations
            .iter()
            .map(|&activation| {
                let bar = bars.add(progress_bar(settings.squat.duration, activation));
                let (geometry, fibers, settings) = (&geometry, &fibers, &settings);
                scope.spawn(move || {
                    let squat = OneSquat {
                        geometry,
                        fibers,
                        activation,
                        settings,
                    };
                    let run = || run_one(args, &squat, start, &bar, stop, say);
                    let outcome = if side_by_side {
                        squat_pool(threads_per_squat).and_then(|pool| pool.install(run))
                    } else {
                        run()
                    };
                    if outcome.is_err() {
                        // The other run stops at its next recorded instant.
                        stop.store(true, Ordering::Relaxed);
                    }
                    bar.finish_and_clear();
                    outcome
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|handle| {
                handle
                    .join()
                    .unwrap_or_else(|_| Err(anyhow::anyhow!("a squat's thread panicked")))
            })
            .collect()
    });
    // The first error that is not the other run's stop on request.
    let mut runs = Vec::new();
    let mut errors = Vec::new();
    for outcome in outcomes {
        match outcome {
            Ok(run) => runs.push(run),
            Err(e) => errors.push(e),
        }
    }
    if let Some(index) = errors
        .iter()
        .position(|e| e.to_string() != STOPPED_ON_REQUEST)
    {
        return Err(errors.swap_remove(index));
    }
    if !errors.is_empty() {
        return Err(Interrupted(format!(
            "the knee study in {} was stopped; each squat's last frame is checkpointed: \
             run the same command with --resume to go on",
            args.out.display()
        ))
        .into());
    }
    let rows: Vec<PeakStressRow> = runs.iter().flat_map(|r| r.rows.clone()).collect();
    let csv = args.out.join("peak_stress.csv");
    let chart = args.out.join("peak_stress.png");
    stage_peak_stress_csv(&csv, &rows)?.commit()?;
    if rows.is_empty() {
        say(&format!(
            "the squat's peak ({}°) is below the table's first angle: no {}\n",
            args.peak_flexion,
            chart.display()
        ));
    } else {
        stage_bar_png(
            &chart,
            &peak_stress_chart(&rows, &geometry.muscles, &settings),
        )?
        .commit()?;
    }
    // The study is complete: nothing is left to resume.
    for activation in &activations {
        let path = args.out.join(activation.name()).join(CHECKPOINT_FILE);
        match std::fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(e).with_context(|| format!("removing {}", path.display()));
            }
            _ => {}
        }
    }
    say(&table_text(&rows, &geometry.muscles, &activations));
    let written = if rows.is_empty() {
        csv.display().to_string()
    } else {
        format!("{}, {}", csv.display(), chart.display())
    };
    say(&format!(
        "wrote {written} and the runs' frames and histories under {} in {:.1?}\n",
        args.out.display(),
        started.elapsed()
    ));
    Ok(KneeOutcome {
        rows,
        activations,
        runs,
        muscles: geometry.muscles.clone(),
    })
}

mod tolerance;

mod args;
pub use args::{KneeAnatomy, KneeArgs, PROCEDURAL};

mod run_files;
use run_files::{run_log, run_summary, write_cut_attempts, write_newton_steps, write_vm95};

mod tables;
use tables::{peak_stress_chart, table_text};

mod bar;
use bar::progress_bar;

/// The message of a run stopped on request: Ctrl-C, or the other squat failed.
const STOPPED_ON_REQUEST: &str = "stopped on request (Ctrl-C, or the other squat failed)";

/// What one squat of the study runs on.
struct OneSquat<'a> {
    geometry: &'a KneeGeometry,
    fibers: &'a musclefem_fibers::FiberField,
    activation: Activation,
    settings: &'a SquatSettings,
}

/// One squat with its outputs under `--out DIR/<activation>`: its scene written there
/// and run through the directory runner of `musclefem run`, the knee's tables beside;
/// its summary printed.
fn run_one(
    args: &KneeArgs,
    squat: &OneSquat<'_>,
    start: RunStart,
    bar: &ProgressBar,
    stop: &AtomicBool,
    say: &(dyn Fn(&str) + Sync),
) -> Result<SquatRun> {
    let OneSquat {
        geometry,
        fibers,
        activation,
        settings,
    } = *squat;
    let directory = args.out.join(activation.name());
    let squat = run_squat_scene(
        geometry,
        fibers,
        activation,
        settings,
        SquatDirectory {
            out: &directory,
            start,
            frame_interval: args.frame_interval,
            log_header: format!(
                "activation = {}
solver = {}
duration_s = {}
peak_flexion_deg = {}
",
                activation.name(),
                settings.solver.name(),
                settings.squat.duration,
                args.peak_flexion
            ),
            interrupted: stop,
            bar: Some(bar.clone()),
        },
    )?;
    let output = squat.directory;
    let ended = |end: &str| {
        output.write_run_log(&RunLog::new(format!(
            "activation = {}\nend = {end}\n",
            activation.name()
        )))
    };
    if squat.stopped {
        ended("stopped on request (Ctrl-C, or the other squat failed); --resume goes on")?;
        bail!(STOPPED_ON_REQUEST);
    }
    let mut run = match squat.run {
        Ok(run) => run,
        Err(error) => {
            ended(&format!(
                "failed: {}",
                format!("{error:#}").replace('\n', "; ")
            ))?;
            return Err(error);
        }
    };
    // The table's vm95 from the history's columns (which `musclefem run` of the scene
    // writes too); the recorder's rows keep where the peaks lie.
    let bellies: Vec<&str> = (0..geometry.muscles.len())
        .map(|m| geometry.block_name(m))
        .collect();
    let from_history = peak_stress_from_history(
        &directory.join(musclefem_io::output::HISTORY_FILE),
        &bellies,
        &geometry.muscles,
        &settings.squat,
        activation,
    )?;
    for (row, history_row) in run.rows.iter_mut().zip(from_history) {
        row.vm95 = history_row.vm95;
    }
    write_vm95(&directory.join("vm95.csv"), &geometry.muscles, &run.samples)?;
    if !run.newton_steps.is_empty() {
        write_newton_steps(&directory.join("newton.csv"), &run.newton_steps)?;
        write_cut_attempts(&directory.join("cuts.csv"), &run.cut_attempts)?;
    }
    write_tendon_csv(&directory.join("tendon.csv"), &run.tendon)?;
    write_plausibility_csv(
        &directory.join("plausibility.csv"),
        &run.plausibility_rows,
        &geometry.muscles,
    )?;
    output.write_run_log(
        &run_log(&run, settings, &geometry.muscles).timing("solve", run.solve_time),
    )?;
    let summary = run_summary(&run, &geometry.muscles);
    bar.suspend(|| say(&summary));
    Ok(run)
}

/// A pool of `threads` worker threads for one of the squats that run side by side. The
/// results do not depend on it: every parallel loop gives the same bits on any number of
/// threads.
fn squat_pool(threads: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("squat-worker-{i}"))
        .build()
        .context("starting a squat's worker threads")
}
