//! `musclefem bench --problem scaling`: the implicit cube of issue #36 timed at each size,
//! Poisson's ratio and linear solver (see the library's `bench::scaling`), each case in a
//! child process of this binary (`musclefem scaling-case`, hidden) so that its peak
//! memory is its own; then the same cubes through felupe when a Python with felupe is
//! found. Writes DIR/scaling.csv, DIR/scaling.png and DIR/scaling.log and prints the
//! table, the fitted slopes, the time ratios and the end-force differences.

use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result, bail};
use clap::Args;

use musclefem_io::PendingFile;
use musclefem_io::plot::stage_png;
use musclefem_studies::bench::scaling::case::MUSCLEFEM;
use musclefem_studies::bench::scaling::chart::scaling_figure;
use musclefem_studies::bench::scaling::csv::scaling_csv;
use musclefem_studies::bench::scaling::felupe::{find_felupe, run_felupe_cube};
use musclefem_studies::bench::scaling::report::scaling_report;
use musclefem_studies::bench::scaling::{ScalingCase, ScalingRun, ScalingSolver};

use super::{BenchArgs, machine, progress_bar, say};

/// The outputs of a scaling benchmark in its directory.
pub const SCALING_FILES: [&str; 3] = ["scaling.csv", "scaling.png", "scaling.log"];

/// `musclefem scaling-case` (hidden): one case of the scaling benchmark, run in this
/// process; prints its measurement as one line of `key=value`.
#[derive(Debug, Args)]
pub struct ScalingCaseArgs {
    /// Elements per edge n.
    #[arg(long)]
    pub divisions: usize,
    /// Poisson's ratio ν.
    #[arg(long)]
    pub poisson: f64,
    #[arg(long, value_enum)]
    pub solver: ScalingSolver,
}

/// Run one case and print its line (the child's side).
pub fn scaling_case(args: &ScalingCaseArgs) -> Result<()> {
    let case = ScalingCase {
        divisions: args.divisions,
        poisson: args.poisson,
        solver: args.solver,
    };
    println!("{}", case.run()?.to_line());
    Ok(())
}

/// The benchmark (the parent's side).
pub fn bench_scaling(args: &BenchArgs) -> Result<()> {
    if args.quick {
        bail!("--problem scaling has no --quick: choose small cubes with --sizes");
    }
    if args.sizes.contains(&0) {
        bail!("--sizes: every cube needs at least one element per edge");
    }
    if let Some(nu) = args.poisson.iter().find(|nu| !(**nu > -1.0 && **nu < 0.5)) {
        bail!("--poisson {nu}: Poisson's ratio must lie in (−1, 0.5)");
    }
    crate::commands::refuse_existing(&SCALING_FILES.map(|f| args.out.join(f)), args.force)?;
    let _lock = musclefem_io::output::OutputLock::acquire(&args.out)?;
    let mut cases = Vec::new();
    for &divisions in &args.sizes {
        for &poisson in &args.poisson {
            for &solver in &args.solvers {
                cases.push(ScalingCase {
                    divisions,
                    poisson,
                    solver,
                });
            }
        }
    }
    let felupe = if args.no_felupe {
        Err("felupe not run (--no-felupe)".to_string())
    } else {
        find_felupe()
    };
    let felupe_sizes: Vec<usize> = match &args.felupe_sizes {
        Some(sizes) => sizes.clone(),
        None => args.sizes.clone(),
    };
    let felupe_cases = if felupe.is_ok() {
        felupe_sizes.len() * args.poisson.len()
    } else {
        0
    };
    let mut log = format!(
        "musclefem bench --problem scaling\nmachine: {}\ncubes: n = {:?}, ν = {:?}, \
         solvers {:?}; each case in a child process (peak memory is its own)\n",
        machine(),
        args.sizes,
        args.poisson,
        args.solvers.iter().map(|s| s.name()).collect::<Vec<_>>()
    );
    match &felupe {
        Ok(python) => {
            log += &format!(
                "felupe {} ({}): n = {felupe_sizes:?}\n",
                python.version,
                python.path.display()
            )
        }
        Err(reason) => log += &format!("{reason}\n"),
    }
    let bar = progress_bar((cases.len() + felupe_cases) as u64);
    let mut runs = Vec::new();
    for case in &cases {
        bar.set_message(case.describe());
        let run = run_in_child(case);
        bar.inc(1);
        let line = describe_run(&run);
        say(&bar, &line);
        log += &line;
        log.push('\n');
        runs.push(run);
    }
    if let Ok(python) = &felupe {
        for &divisions in &felupe_sizes {
            for &poisson in &args.poisson {
                bar.set_message(format!("felupe {divisions}³ ν = {poisson}"));
                let run = run_felupe_cube(python, divisions, poisson);
                bar.inc(1);
                let line = describe_run(&run);
                say(&bar, &line);
                log += &line;
                log.push('\n');
                runs.push(run);
            }
        }
    }
    bar.finish_and_clear();
    let report = scaling_report(&runs);
    log += &report;
    write_outputs(&args.out, &runs, &log)?;
    print!("{report}");
    for file in SCALING_FILES {
        println!("{}", args.out.join(file).display());
    }
    Ok(())
}

/// Run `case` in a child process of this binary; a failure is a failed run with its
/// reason.
fn run_in_child(case: &ScalingCase) -> ScalingRun {
    let failed = |reason: String| {
        ScalingRun::failed(
            MUSCLEFEM,
            case.solver.name(),
            case.divisions,
            case.poisson,
            case.cube().unknowns(),
            reason,
        )
    };
    let output = std::env::current_exe()
        .context("this program's path")
        .and_then(|exe| {
            Command::new(exe)
                .arg("scaling-case")
                .args(["--divisions", &case.divisions.to_string()])
                .args(["--poisson", &case.poisson.to_string()])
                .args(["--solver", case.solver.name()])
                .output()
                .context("the case's child process could not start")
        });
    let output = match output {
        Ok(output) => output,
        Err(e) => return failed(format!("{e:#}")),
    };
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        return failed(stderr.trim().to_string());
    }
    let stdout = String::from_utf8_lossy(&output.stdout);
    match stdout.lines().last().map(ScalingRun::from_line) {
        Some(Ok(run)) => run,
        Some(Err(e)) => failed(format!("{e:#}")),
        None => failed("the case's child process printed nothing".to_string()),
    }
}

/// One line for the log and the terminal.
fn describe_run(run: &ScalingRun) -> String {
    let what = format!(
        "{} {}³ ν = {} ({} unknowns)",
        run.series_name(),
        run.divisions,
        run.poisson,
        run.unknowns
    );
    match &run.failure {
        Some(reason) => format!("{what}: FAILED: {reason}"),
        None => format!(
            "{what}: {:.3} s, {} Newton iterations, end force {:.12} N{}",
            run.wall_s,
            run.newton_iterations,
            run.end_force_n,
            run.peak_memory_bytes.map_or(String::new(), |b| format!(
                ", peak memory {:.0} MiB",
                b as f64 / 1048576.0
            ))
        ),
    }
}

/// DIR/scaling.csv, DIR/scaling.png and DIR/scaling.log, all staged first.
fn write_outputs(out: &Path, runs: &[ScalingRun], log: &str) -> Result<()> {
    let csv = PendingFile::stage_bytes(&out.join("scaling.csv"), scaling_csv(runs).as_bytes())?;
    let png = stage_png(&out.join("scaling.png"), &scaling_figure(runs))?;
    let log_file = PendingFile::stage_bytes(&out.join("scaling.log"), log.as_bytes())?;
    csv.commit()?;
    png.commit()?;
    log_file.commit()?;
    Ok(())
}
