//! `musclefem elongate`: the paper's passive and active elongation tests of the fusiform
//! muscle, with curve.csv, curve.png, VTU/PVD frames and the stress at 10 % and 20 %
//! strain.

use std::io::IsTerminal;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context, Result, bail};

use crate::commands::Interrupted;
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};

use musclefem_core::solver::observer::{Record, Snapshot};
use musclefem_io::output::{ExistingResults, HistoryColumns, HistoryWriter, RunDirectory, RunLog};
use musclefem_io::plot::{Figure, LegendPosition, Panel, Series, stage_png};
use musclefem_studies::bench::{Problem, select};
use musclefem_studies::elongation::options::TestOptions;
use musclefem_studies::elongation::run::run_on;
use musclefem_studies::elongation::setup::{check_time_step, setup};
use musclefem_studies::elongation::{
    Activation, Curve, CurvePoint, DEFAULT_MESH_SIZE, DEFAULT_SETTING_RATIONALE, ElementChoice,
    ElongationRun, ElongationTest, ElongationWatcher, Grips, Shape, Solver,
};

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
        default_value_t = 0.25,
        allow_negative_numbers = true
    )]
    pub frame_interval: f64,
    /// Replace the results of a previous run in the output directory.
    #[arg(long)]
    pub force: bool,
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
    // Ctrl-C stops the running test after its last point; a second one kills the process.
    let interrupted = Arc::new(AtomicBool::new(false));
    {
        let flag = interrupted.clone();
        let _ = ctrlc::set_handler(move || {
            if flag.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
        });
    }
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

/// Run one test into `directory`: frames, curve.csv, run.log (and curve.png for a single
/// mode), and print its summary.
fn run_one(
    test: &ElongationTest,
    directory: &Path,
    args: &ElongateArgs,
    interrupted: &Arc<AtomicBool>,
) -> Result<ElongationRun> {
    let existing = if args.force {
        ExistingResults::Replace
    } else {
        ExistingResults::Refuse
    };
    let mut output = RunDirectory::create(directory, existing)
        .map_err(|e| anyhow::anyhow!("{e} (use --force to replace a previous run)"))?;
    let label = format!(
        "{} {} elongation, {} {}, {} mm, {} grips",
        test.solver.name(),
        test.mode.name(),
        test.shape.name(),
        test.element.name(),
        musclefem_io::csv::format_number(1e3 * test.mesh_size),
        grips_name(test.grips),
    );
    println!("{label}");
    let setup = setup(test)?;
    // The solver's history beside the curve, from the first row on (the reactions of
    // every end condition, energies, Newton iterations).
    let columns = HistoryColumns::new(setup.displacement_names.clone(), Vec::new());
    let history = match test.solver {
        Solver::Implicit => output.implicit_history(&columns)?,
        Solver::Explicit => output.explicit_history(&columns)?,
    };
    let mut watcher = FrameWriter {
        history: Some(history),
        directory: &mut output,
        interval: args.frame_interval,
        next: 0.0,
        end_time: test.mode.duration(),
        mesh: &setup.specimen.mesh,
        error: None,
        bar: progress_bar(test.mode.duration()),
        interrupted: interrupted.clone(),
        points: Vec::new(),
    };
    let result = run_on(test, &setup, &mut watcher);
    watcher.bar.finish_and_clear();
    if let Some(history) = watcher.history.take() {
        history.finish()?;
    }
    if let Some(error) = watcher.error.take() {
        return Err(error).context("writing a frame or the history failed");
    }
    if interrupted.load(Ordering::SeqCst) {
        // The curve up to the last point, and a log that says where the test stopped.
        let time = watcher.points.last().map_or(0.0, |p| p.time);
        let mut points = std::mem::take(&mut watcher.points);
        if points.first().is_none_or(|p| p.time > 0.0) {
            // As a finished run's curve: the implicit solver records converged increments
            // only, and the test starts stress-free.
            points.insert(
                0,
                CurvePoint {
                    time: 0.0,
                    strain: 0.0,
                    force: 0.0,
                    stress: 0.0,
                },
            );
        }
        let curve = Curve { points };
        curve.stage_csv(&directory.join("curve.csv"))?.commit()?;
        let log = RunLog::new(format!(
            "test = {label}\nend = interrupted at t = {time:e} s (Ctrl-C)\n"
        ));
        output.write_run_log(&log)?;
        return Err(Interrupted(format!(
            "stopped at t = {time:.6e} s on request; the curve up to there is in {} (run.log \
             says so)",
            directory.join("curve.csv").display()
        ))
        .into());
    }
    let run = result?;
    run.curve
        .stage_csv(&directory.join("curve.csv"))?
        .commit()?;
    let log = RunLog::new(format!(
        "test = {label}\nelements = {}\nnodes = {}\nsteps = {}\nend = complete\n",
        run.elements, run.nodes, run.steps
    ))
    .timing("solve", run.solve_time);
    output.write_run_log(&log)?;
    print_summary(&run);
    Ok(run)
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

/// Writes the history, and a frame with the element fields every `interval` of simulated
/// time.
struct FrameWriter<'a> {
    history: Option<HistoryWriter>,
    directory: &'a mut RunDirectory,
    interval: f64,
    next: f64,
    /// The last point always gets a frame [s].
    end_time: f64,
    mesh: &'a musclefem_core::mesh::Mesh,
    error: Option<anyhow::Error>,
    bar: ProgressBar,
    /// Set by Ctrl-C: stop after the current point.
    interrupted: Arc<AtomicBool>,
    /// The curve so far (written whole if the test is interrupted).
    points: Vec<CurvePoint>,
}

impl ElongationWatcher for FrameWriter<'_> {
    fn history_row(&mut self, record: &Record) {
        if let Some(history) = &mut self.history
            && let Err(e) = history.push_record(record)
        {
            self.error.get_or_insert(e.into());
        }
    }

    fn point(&mut self, point: &CurvePoint, snapshot: &Snapshot) -> ControlFlow<()> {
        self.bar.set_position((1e3 * point.time) as u64);
        self.points.push(*point);
        if self.interrupted.load(Ordering::SeqCst) {
            return ControlFlow::Break(());
        }
        let at_end = point.time >= self.end_time - 1e-9;
        if self.interval <= 0.0 || (point.time < self.next - 1e-12 && !at_end) {
            return ControlFlow::Continue(());
        }
        self.next = point.time + self.interval;
        let mesh = self.mesh;
        let written = snapshot
            .element_fields()
            .map_err(anyhow::Error::from)
            .and_then(|parts| {
                self.directory
                    .write_state_frame(mesh, point.time, snapshot.displacement, &parts, &[])
                    .map_err(anyhow::Error::from)
            });
        match written {
            Ok(_) => ControlFlow::Continue(()),
            Err(e) => {
                self.error = Some(e);
                ControlFlow::Break(())
            }
        }
    }

    fn progress(&mut self, time: f64) -> ControlFlow<()> {
        self.bar.set_position((1e3 * time) as u64);
        if self.interrupted.load(Ordering::SeqCst) {
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }
}

fn progress_bar(duration: f64) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new((1e3 * duration) as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos} / {len} ms [{elapsed_precise}, ETA {eta}]")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
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

fn grips_name(grips: Grips) -> &'static str {
    match grips {
        Grips::Fixed => "fixed",
        Grips::Sliding => "sliding",
    }
}
