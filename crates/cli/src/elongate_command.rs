//! `musclefem elongate`: the paper's passive and active elongation tests of the fusiform
//! muscle. Each test is written as a scene (`scene.toml`, `specimen.inp`) into its
//! directory and run through the scene runner (frames, history, checkpoints, run.log);
//! curve.csv and curve.png come from the history, and the stress at 10 % and 20 % strain
//! is printed.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};

use musclefem_core::solver::SolverError;
use musclefem_io::csv::read_columns;
use musclefem_io::output::run_directory::{HISTORY_FILE, SCENE_FILE};
use musclefem_io::output::{CHECKPOINT_FILE, ExistingResults, RunStart};
use musclefem_io::plot::{Figure, LegendPosition, Panel, Series, stage_png};
use musclefem_io::scene::{Model, load_scene};
use musclefem_materials::MaterialLibrary;
use musclefem_studies::bench::{Problem, select};
use musclefem_studies::elongation::options::TestOptions;
use musclefem_studies::elongation::scene::{
    ElongationScene, SPECIMEN_MESH_FILE, elongation_scene, run_from_history,
};
use musclefem_studies::elongation::setup::check_time_step;
use musclefem_studies::elongation::{
    Activation, Curve, DEFAULT_FRAME_INTERVAL, DEFAULT_MESH_SIZE, DEFAULT_SETTING_RATIONALE,
    ElementChoice, ElongationRun, ElongationTest, Shape, Solver,
};

use crate::commands::Interrupted;
use crate::scene_run::interrupt_flag;
use musclefem_studies::run_directory::{DirectoryRun, run_into_directory};

/// Which tests to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ModeChoice {
    Passive,
    Active,
    /// Both, into DIR/passive and DIR/active, with one chart of both curves.
    Both,
}

#[derive(Debug, Args)]
pub struct ElongateArgs {
    /// Passive (pulled at 5 mm/s to 10 mm, 20 % strain), active (held 0.5 s while fully
    /// activating, then pulled the same way) or both.
    #[arg(long, value_enum, default_value = "both")]
    pub mode: ModeChoice,
    /// Solver, element, mesh size, specimen, grips and step.
    #[command(flatten)]
    pub test: TestOptions,
    /// Hill parameter overriding Table 1, e.g. --param sigma0=3e5 (units as in
    /// `musclefem materials`); repeatable. n2 and t0 are set by the mode.
    #[arg(long = "param", value_name = "KEY=VALUE")]
    pub params: Vec<String>,
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "out/elongate")]
    pub out: PathBuf,
    /// Time between frames [s] (0: no frames; a negative value is refused).
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = DEFAULT_FRAME_INTERVAL,
        allow_negative_numbers = true
    )]
    pub frame_interval: f64,
    /// Replace the results of a previous run in the output directory.
    #[arg(long)]
    pub force: bool,
    /// Go on with a stopped run from its last checkpoint (a test that completed is read
    /// back, not rerun); the other options must be those of the stopped run.
    #[arg(long, conflicts_with = "force")]
    pub resume: bool,
    /// Choose solver, element, mesh size and step as the cheapest setting whose measured
    /// error (passive elongation, `musclefem bench`) is at most this [%]; overrides
    /// --solver, --element, --mesh-size and --time-step.
    #[arg(long, value_name = "PERCENT")]
    pub tolerance: Option<f64>,
    #[command(flatten)]
    pub bench_table: crate::BenchTable,
}

/// The cheapest measured setting of the passive elongation within `percent` (see
/// [`musclefem_studies::bench::select`]), with the reason printed.
fn setting_within(percent: f64, table: &Path) -> Result<(Solver, ElementChoice, f64, f64)> {
    if !(percent.is_finite() && percent > 0.0) {
        bail!("--tolerance {percent} must be a positive percentage");
    }
    let text = std::fs::read_to_string(table).with_context(|| {
        format!(
            "--tolerance needs the measured work–precision table {} (write it with \
             `musclefem bench --problem elongate`)",
            table.display()
        )
    })?;
    let rows = select::read_table(&text).with_context(|| format!("reading {}", table.display()))?;
    let Some(row) = select::cheapest_within(&rows, Problem::Elongate.name(), 1e-2 * percent) else {
        let best = rows
            .iter()
            .filter(|r| r.problem == "elongate" && r.error.is_finite())
            .map(|r| r.error)
            .fold(f64::INFINITY, f64::min);
        bail!(
            "no setting in {} meets {percent} % (the most accurate measured elongation run is \
             off by {:.2} %); run musclefem bench on finer settings or loosen --tolerance",
            table.display(),
            100.0 * best
        );
    };
    let method = select::method_of(row)?;
    let test = musclefem_studies::bench::elongate::elongation_test(&method)?;
    println!(
        "--tolerance {percent} %: {} ({:.2} % error in {:.1} s, the cheapest within the \
         tolerance of the {} passive-elongation runs in {})",
        method.describe(),
        100.0 * row.error,
        row.wall_s,
        rows.iter().filter(|r| r.problem == "elongate").count(),
        table.display()
    );
    let step = test.time_step.context("the chosen setting has a step")?;
    Ok((test.solver, test.element, test.mesh_size, step))
}

pub fn elongate(args: &ElongateArgs) -> Result<()> {
    let modes: &[Activation] = match args.mode {
        ModeChoice::Passive => &[Activation::Passive],
        ModeChoice::Active => &[Activation::Active],
        ModeChoice::Both => &[Activation::Passive, Activation::Active],
    };
    musclefem_studies::frame_interval::check_frame_interval(args.frame_interval)?;
    let parameters = crate::commands::parse_params(&args.params)?;
    if parameters.contains_key("n2") || parameters.contains_key("t0") {
        bail!("--param n2 / t0: the mode sets the activation (passive n2 = 0, active n2 = 1)");
    }
    let (solver, element, mesh_size, time_step) = match args.tolerance {
        Some(percent) => {
            let (solver, element, size, step) = setting_within(percent, &args.bench_table.path)?;
            (solver, element, size, Some(step))
        }
        None => (
            args.test.solver,
            args.test.element,
            1e-3 * args.test.mesh_size,
            args.test.time_step,
        ),
    };
    if args.tolerance.is_none()
        && (solver, element) == (Solver::Implicit, ElementChoice::Hex8Fbar)
        && (mesh_size - DEFAULT_MESH_SIZE).abs() < 1e-12
    {
        println!("{DEFAULT_SETTING_RATIONALE}");
    }
    // Ctrl-C stops the running test after its last frame; a second one kills the process.
    let interrupted = interrupt_flag();
    let mut runs = Vec::new();
    for &mode in modes {
        let test = ElongationTest {
            mode,
            solver,
            element,
            mesh_size,
            shape: args.test.shape,
            grips: args.test.grips,
            parameters: parameters.clone(),
            time_step,
            frame_interval: args.frame_interval,
            ..ElongationTest::recommended(mode)
        };
        // Refused before any directory is made (the run's own checks come later).
        check_time_step(&test)?;
        let directory = if modes.len() == 1 {
            args.out.clone()
        } else {
            args.out.join(mode.name())
        };
        let run = run_one(&test, &directory, args, &interrupted)?;
        runs.push((mode, run));
    }
    let chart = args.out.join("curve.png");
    let figure = curve_figure(args.test.shape, (solver, element, mesh_size), &runs);
    stage_png(&chart, &figure)?.commit()?;
    println!("chart: {}", chart.display());
    Ok(())
}

/// Run one test into `directory` as a scene: `scene.toml` and `specimen.inp` (what
/// `musclefem run` reruns), frames, `history.csv`, `run.log` (through the scene runner),
/// then `curve.csv` from the history; print its summary. With `--resume`, a test whose
/// run completed earlier is read back from its history instead of rerun.
fn run_one(
    test: &ElongationTest,
    directory: &Path,
    args: &ElongateArgs,
    interrupted: &Arc<AtomicBool>,
) -> Result<ElongationRun> {
    let label = test.label();
    println!("{label}");
    let started = Instant::now();
    let scene = elongation_scene(test)?;
    let scene_path = directory.join(SCENE_FILE);
    let history_path = directory.join(HISTORY_FILE);
    let completed = args.resume
        && !directory.join(CHECKPOINT_FILE).exists()
        && history_path.exists()
        && std::fs::read_to_string(directory.join(SCENE_FILE)).ok() == Some(scene.scene.clone());
    if completed {
        let run = run_from_history(
            test,
            &scene.specimen,
            columns(&read_columns(&history_path)?),
            None,
            Duration::ZERO,
        )?;
        println!(
            "  complete in an earlier run: read back from {}",
            history_path.display()
        );
        print_summary(&run);
        return Ok(run);
    }
    let model = load_staged(&scene, test.mode)?;
    let start = match (args.resume, args.force) {
        (true, _) => RunStart::Resume,
        (false, true) => RunStart::Fresh(ExistingResults::Replace),
        (false, false) => RunStart::Fresh(ExistingResults::Refuse),
    };
    let report = run_into_directory(
        &model,
        DirectoryRun {
            scene: &scene_path,
            scene_text: &scene.scene,
            beside: &[(SPECIMEN_MESH_FILE, &scene.mesh)],
            out: directory,
            start,
            frame_instants: &[],
            log_header: format!(
                "test = {label}\nelements = {}\nnodes = {}\n",
                scene.specimen.mesh.element_count(),
                scene.specimen.mesh.node_count()
            ),
            setup_time: started.elapsed(),
            keep_checkpoint: false,
            interrupted,
            bar: None,
            companion: None,
        },
    )?;
    if let Some(time) = report.resumed_from {
        println!("  resumed from the checkpoint at t = {time:e} s");
    }
    // The curve from the history as written (a resumed run's rows before the checkpoint
    // included), committed whatever the outcome: up to the stop if stopped.
    let run = run_from_history(
        test,
        &scene.specimen,
        columns(&read_columns(&history_path)?),
        report.outcome.as_ref().ok(),
        report.solve_time,
    )?;
    run.curve
        .stage_csv(&directory.join("curve.csv"))?
        .commit()?;
    match report.outcome {
        Ok(_) => {
            print_summary(&run);
            Ok(run)
        }
        Err(SolverError::Interrupted { time }) => Err(Interrupted(format!(
            "stopped at t = {time:.6e} s on request; the curve up to there is in {} (run.log \
             says so); the same command with --resume goes on from the last frame",
            directory.join("curve.csv").display()
        ))
        .into()),
        Err(error) => Err(anyhow::Error::from(error).context(format!(
            "{label} (the frames, history and curve up to the failure are in {})",
            directory.display()
        ))),
    }
}

/// The scene read back from a private staging folder (the run directory is not touched
/// before the run refuses or replaces what it holds).
fn load_staged(scene: &ElongationScene, mode: Activation) -> Result<Model> {
    let staging = std::env::temp_dir().join(format!(
        "musclefem-elongate-{}-{}",
        std::process::id(),
        mode.name()
    ));
    std::fs::create_dir_all(&staging).with_context(|| format!("creating {}", staging.display()))?;
    let loaded = (|| -> Result<Model> {
        std::fs::write(staging.join(SCENE_FILE), &scene.scene)?;
        std::fs::write(staging.join(SPECIMEN_MESH_FILE), &scene.mesh)?;
        Ok(load_scene(
            &staging.join(SCENE_FILE),
            &mut MaterialLibrary::with_builtins(),
        )?)
    })();
    let _ = std::fs::remove_dir_all(&staging);
    loaded.context("the elongation test's scene")
}

/// Borrowed names and columns of a read table.
fn columns(table: &(Vec<String>, Vec<Vec<f64>>)) -> (&[String], &[Vec<f64>]) {
    (&table.0, &table.1)
}

fn print_summary(run: &ElongationRun) {
    let iterations = run
        .newton_iterations
        .map_or(String::new(), |n| format!(" ({n} Newton iterations)"));
    println!(
        "  {} elements, {} nodes, {} steps{iterations} in {:.2?}",
        run.elements, run.nodes, run.steps, run.solve_time
    );
    if let (Some(ratio), Some(added)) = (run.kinetic_to_internal, run.added_mass_fraction) {
        println!(
            "  mass scaling added {:.3e} of the mass; largest kinetic/internal energy during \
             the pull {:.2e}",
            added, ratio
        );
    }
    for strain in [0.1, 0.2] {
        match run.curve.stress_at_strain(strain) {
            Some(stress) => println!(
                "  engineering stress at {:.0} % strain: {:.2} kPa",
                100.0 * strain,
                1e-3 * stress
            ),
            None => println!("  {:.0} % strain was not reached", 100.0 * strain),
        }
    }
}

/// Engineering stress [kPa] against strain [%] of every run on one chart.
fn curve_figure(
    shape: Shape,
    (solver, element, mesh_size): (Solver, ElementChoice, f64),
    runs: &[(Activation, ElongationRun)],
) -> Figure {
    let mut panel = Panel::new(
        format!(
            "{} elongation at 5 mm/s ({}, {}, {} mm)",
            match shape {
                Shape::Fusiform => "fusiform muscle",
                Shape::Cylinder => "cylinder",
            },
            solver.name(),
            element.name(),
            1e3 * mesh_size
        ),
        "engineering strain [%]",
        "engineering stress [kPa]",
    )
    .with_legend(LegendPosition::UpperLeft);
    for (mode, run) in runs {
        panel = panel.with_series(Series::new(mode.name(), curve_points(&run.curve)));
    }
    Figure::new("musclefem elongate").with_panel(panel)
}

fn curve_points(curve: &Curve) -> Vec<(f64, f64)> {
    curve
        .points
        .iter()
        .map(|p| (100.0 * p.strain, 1e-3 * p.stress))
        .collect()
}
