//! `musclefem bench`: the work–precision matrix of each problem (see the library's `bench`
//! module), written as DIR/work_precision.csv, DIR/work_precision.png and DIR/bench.log;
//! or, with `--problem scaling`, the implicit cube timed at growing sizes
//! ([`scaling`]: DIR/scaling.csv, DIR/scaling.png, DIR/scaling.log).

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};

use musclefem_io::PendingFile;
use musclefem_io::plot::stage_png;
use musclefem_studies::bench::chart::work_precision_figure;
use musclefem_studies::bench::csv::{WorkPrecisionRow, to_csv};
use musclefem_studies::bench::method::millimetres;
use musclefem_studies::bench::pareto::pareto_front;
use musclefem_studies::bench::scaling::ScalingSolver;
use musclefem_studies::bench::{Measurement, Problem, matrix, reference_method};

/// Which problems to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ProblemChoice {
    /// The clamped neo-Hookean cube pulled to stretch 1.5.
    Cube,
    /// The passive elongation of the fusiform Hill muscle.
    Elongate,
    /// The passive knee squat, coarse against medium (no --quick; its medium reference
    /// takes about 5 minutes).
    Knee,
    /// Cube, elongate and (without --quick) knee.
    All,
    /// Not a work–precision matrix: the implicit cube of issue #36 (symmetry planes,
    /// pulled to stretch 1.5 in 10 steps) timed at each of --sizes, --poisson and
    /// --solvers (and through felupe when installed), with the fitted growth of the time;
    /// writes scaling.csv, scaling.png and scaling.log.
    Scaling,
}

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// A small matrix that finishes in about two minutes (fewer meshes and steps).
    #[arg(long)]
    pub quick: bool,
    /// Which problem to benchmark.
    #[arg(long, value_enum, default_value = "all")]
    pub problem: ProblemChoice,
    /// Instead of the problems: this scene file's step settings (implicit increments,
    /// explicit mass scaling) against its reference run, on its own mesh and elements;
    /// `musclefem run SCENE --tolerance` reads the rows.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["problem", "quick"])]
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub trust: musclefem_studies::scene_study::SceneTrustArgs,
    /// --problem scaling: elements per edge n of the cubes.
    #[arg(
        long,
        value_name = "N,N,...",
        value_delimiter = ',',
        default_value = "10,20,30,40"
    )]
    pub sizes: Vec<usize>,
    /// --problem scaling: Poisson's ratios ν of the cubes (μ = 10 kPa; bulk modulus
    /// K = 2μ(1 + ν)/(3(1 − 2ν))).
    #[arg(
        long,
        value_name = "NU,NU,...",
        value_delimiter = ',',
        default_value = "0.3,0.49"
    )]
    pub poisson: Vec<f64>,
    /// --problem scaling: musclefem's linear solvers.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "direct,amg_cg"
    )]
    pub solvers: Vec<ScalingSolver>,
    /// --problem scaling: run the same cubes through felupe when a Python with felupe is
    /// found ($MUSCLEFEM_FELUPE_PYTHON or .venv-felupe/bin/python, made by
    /// scripts/setup-felupe); without one, the log says so and the bench goes on (the
    /// default).
    #[arg(long, overrides_with = "no_felupe")]
    pub felupe: bool,
    /// --problem scaling: do not run felupe.
    #[arg(long, overrides_with = "felupe")]
    pub no_felupe: bool,
    /// --problem scaling: the sizes felupe runs [default: --sizes] (felupe took 450 s at
    /// 20³ on 2 cores).
    #[arg(long, value_name = "N,N,...", value_delimiter = ',')]
    pub felupe_sizes: Option<Vec<usize>>,
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "out/bench")]
    pub out: PathBuf,
    /// Replace the results of an earlier run in the output place.
    #[arg(long)]
    pub force: bool,
}

pub mod scaling;
mod scene;

pub fn bench(args: &BenchArgs) -> Result<()> {
    if args.problem == ProblemChoice::Scaling {
        return scaling::bench_scaling(args);
    }
    crate::commands::refuse_existing(
        &["work_precision.csv", "work_precision.png", "bench.log"].map(|f| args.out.join(f)),
        args.force,
    )?;
    if let Some(scene_path) = &args.scene {
        return scene::bench_scene(scene_path, args.trust.trust(), &args.out);
    }
    let problems: &[Problem] = match (args.problem, args.quick) {
        (ProblemChoice::Cube, _) => &[Problem::Cube],
        (ProblemChoice::Elongate, _) => &[Problem::Elongate],
        (ProblemChoice::Knee, false) => &[Problem::Knee],
        (ProblemChoice::All, false) => &[Problem::Cube, Problem::Elongate, Problem::Knee],
        (ProblemChoice::All, true) => &[Problem::Cube, Problem::Elongate],
        (ProblemChoice::Scaling, _) => unreachable!("--problem scaling returned above"),
        (ProblemChoice::Knee, true) => bail!(
            "--problem knee has no --quick matrix: its reference, the passive squat on the \
             medium mesh, takes about 5 minutes on 2 cores; run it without --quick"
        ),
    };
    // Creates the directory; a second bench into it is refused while this one runs.
    let _lock = musclefem_io::output::OutputLock::acquire(&args.out)?;
    let runs: usize = problems
        .iter()
        .map(|&p| matrix(p, args.quick).len() + 1)
        .sum();
    let bar = progress_bar(runs as u64);
    let mut rows = Vec::new();
    let mut log = format!(
        "musclefem bench{}\nmachine: {}\n",
        if args.quick { " --quick" } else { "" },
        machine()
    );
    for &problem in problems {
        let method = reference_method(problem, args.quick);
        bar.set_message(format!(
            "{} reference: {}",
            problem.name(),
            method.describe()
        ));
        let reference = Measurement::take(problem, &method);
        bar.inc(1);
        let reference_response = match &reference.outcome {
            Ok(response) => response.clone(),
            Err(reason) => bail!(
                "the {} reference run ({}) failed: {reason}",
                problem.name(),
                method.describe()
            ),
        };
        let line = format!(
            "{} reference: {} in {:.2} s, response {:?} ({})",
            problem.name(),
            method.describe(),
            reference.wall.as_secs_f64(),
            reference_response.samples,
            problem.error_metric()
        );
        say(&bar, &line);
        log += &line;
        log.push('\n');
        let first = rows.len();
        for method in matrix(problem, args.quick) {
            bar.set_message(format!("{}: {}", problem.name(), method.describe()));
            let measurement = Measurement::take(problem, &method);
            bar.inc(1);
            let error = measurement.error(&reference_response);
            let line = match &measurement.outcome {
                Ok(response) => format!(
                    "{}: {}: {:.3} s, error {:.3e}{}",
                    problem.name(),
                    method.describe(),
                    measurement.wall.as_secs_f64(),
                    error,
                    response
                        .warning
                        .as_ref()
                        .map_or(String::new(), |w| format!(" (warning: {w})"))
                ),
                Err(reason) => format!(
                    "{}: {}: FAILED after {:.2} s: {reason}",
                    problem.name(),
                    method.describe(),
                    measurement.wall.as_secs_f64()
                ),
            };
            say(&bar, &line);
            log += &line;
            log.push('\n');
            rows.push(WorkPrecisionRow::new(&measurement, error));
        }
        log += &pareto_log(problem.name(), &rows[first..]);
    }
    bar.finish_and_clear();
    if args.quick && args.problem == ProblemChoice::All {
        log += "knee: not run (no --quick matrix; run musclefem bench --problem knee)\n";
    } else if problems.len() < 3 {
        log += "(not all problems run)\n";
    }
    write_outputs(&args.out, &rows, &log)
}

/// The Pareto front of one problem's `rows` for the log (fastest first).
fn pareto_log(problem: &str, rows: &[WorkPrecisionRow]) -> String {
    let points: Vec<(f64, f64)> = rows.iter().map(|r| (r.wall_s, r.error)).collect();
    let mut log = format!("{problem} Pareto front (fastest first):\n");
    for i in pareto_front(&points) {
        let row = &rows[i];
        log += &format!(
            "  {} {} {} mm {}: {:.3} s, error {:.3e}\n",
            row.solver,
            row.element,
            millimetres(1e-3 * row.mesh_size_mm),
            row.step_setting,
            row.wall_s,
            row.error
        );
    }
    log
}

/// Writes DIR/work_precision.csv, DIR/work_precision.png and DIR/bench.log (all staged
/// first: nothing half-written) and prints the Pareto fronts and the paths.
fn write_outputs(out: &Path, rows: &[WorkPrecisionRow], log: &str) -> Result<()> {
    let csv_path = out.join("work_precision.csv");
    let png_path = out.join("work_precision.png");
    let log_path = out.join("bench.log");
    let csv = PendingFile::stage_bytes(&csv_path, to_csv(rows).as_bytes())?;
    let png = stage_png(&png_path, &work_precision_figure(rows))?;
    let log_file = PendingFile::stage_bytes(&log_path, log.as_bytes())?;
    csv.commit()?;
    png.commit()?;
    log_file.commit()?;
    for line in log
        .lines()
        .filter(|l| l.starts_with(' ') || l.contains("Pareto"))
    {
        println!("{line}");
    }
    println!("table: {}", csv_path.display());
    println!("chart: {}", png_path.display());
    println!("log: {}", log_path.display());
    Ok(())
}

/// The CPU model and core count, for the log (timings are only comparable on one machine).
fn machine() -> String {
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".to_string());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    format!("{model}, {cores} threads available")
}

/// Print `line` above the bar, or plainly when the bar is hidden.
fn say(bar: &ProgressBar, line: &str) {
    if bar.is_hidden() {
        println!("{line}");
    } else {
        bar.println(line);
    }
}

/// A bar over the runs on a terminal; hidden otherwise (each run's line is printed).
fn progress_bar(runs: u64) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(runs);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} runs [{elapsed_precise}] {msg}")
            .expect("a valid template"),
    );
    bar
}
