//! `musclefem sweep`: a parametric study of the elongation tests (seed §2.2, §3.1) or of
//! any scene. Every combination of the varied material parameters (or a Latin-hypercube
//! sample of their ranges, or the parameter sets of a user's design CSV) runs, several at a time, and each run's summary goes to
//! `DIR/sweep.csv`; then the normalised sensitivity of each summary output (the stress at
//! 10 % and 20 % strain, or the scene's history columns) to each parameter goes to
//! `DIR/sensitivity.csv` and `DIR/sensitivity.png`.
//!
//! - [`study`]: what is varied and measured (a scene through [`crate::scene_study`]);
//! - [`vary`]: the `--vary` axes;
//! - [`grid`], [`latin_hypercube`]: the two designs (lists of runs), and
//!   [`design_file`] a user's (`--design FILE.csv`, also `fit`'s starting points);
//! - [`run`]: one run and its [`run::Outcome`] (a failure is an outcome, not an abort);
//! - [`table`]: `sweep.csv`, rewritten after every run, read back to resume;
//! - [`sensitivity`]: the sensitivities and their chart;
//! - `distributed` (cargo feature `mpi`): the runs shared among MPI ranks under `mpirun`.

pub mod design_file;
pub mod grid;
pub mod latin_hypercube;
pub mod merge;
mod report;
pub mod run;
pub mod sensitivity;
pub mod study;
pub mod table;
pub mod vary;

#[cfg(feature = "mpi")]
pub mod distributed;

use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Context, Result, anyhow, bail};
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use musclefem_io::PendingFile;
use musclefem_io::output::OutputLock;

use crate::elongation::Activation;
use crate::elongation::options::TestOptions;
use crate::scene_study::SceneStudy;
use report::{
    DESIGN_SIZE, SENSITIVITY_CSV, SENSITIVITY_PNG, SWEEP_BASE, report, write_sensitivities,
};
use study::Study;
use table::{Columns, Record, SWEEP_CSV};

#[derive(Debug, clap::Args)]
pub struct SweepArgs {
    /// An elongation test of `musclefem elongate` as the base: `passive` or `active`
    /// (with the specimen and solver options below); its outputs are the engineering
    /// stress at 10 % and 20 % strain.
    #[arg(
        long,
        value_name = "TEST",
        required_unless_present = "scene",
        conflicts_with = "scene"
    )]
    pub base: Option<String>,
    /// A scene file as the base: each run is the scene with the varied parameters of its
    /// materials changed (the specimen and solver options below do not apply).
    #[arg(long, value_name = "SCENE.toml")]
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub trust: crate::scene_study::SceneTrustArgs,
    /// A summary output of a scene run: a column of its history.csv at the end of the
    /// run (COLUMN) or at a time (COLUMN@SECONDS, linear between rows); repeatable
    /// [default: every reaction column at the end].
    #[arg(long = "output", value_name = "COLUMN[@TIME]", requires = "scene")]
    pub outputs: Vec<String>,
    /// A varied parameter: NAME=V1,V2,... or NAME=LO:HI:N (N evenly spaced values);
    /// repeatable. NAME is a Hill parameter for an elongation test (see `musclefem
    /// materials`); for a scene it is a parameter of its one material, or MATERIAL.NAME
    /// when it has several. Every combination runs, unless --samples is given.
    #[arg(
        long = "vary",
        value_name = "NAME=VALUES",
        required_unless_present = "design"
    )]
    pub vary: Vec<String>,
    /// Run N points of a Latin hypercube over each parameter's range [smallest, largest
    /// value] instead of every combination.
    #[arg(long, value_name = "N")]
    pub samples: Option<usize>,
    /// Run exactly the parameter sets of this CSV file instead of --vary's: a header of
    /// parameter names (as --vary takes them), then one row of values per run, in order
    /// (`,`, `;` or tab separated; a byte-order mark and decimal commas are read).
    #[arg(
        long,
        value_name = "FILE.csv",
        conflicts_with_all = ["vary", "samples"]
    )]
    pub design: Option<PathBuf>,
    /// Seed of the Latin hypercube (the same seed gives the same runs).
    #[arg(long, value_name = "SEED", default_value_t = 1)]
    pub seed: u64,
    /// Runs at a time; the runs' solvers share these threads [default: one per core].
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    #[command(flatten)]
    pub options: TestOptions,
    /// Output directory. A sweep.csv already there from the same sweep is resumed: its
    /// runs (finished or failed) are not run again.
    #[arg(long, value_name = "DIR", default_value = "out/sweep")]
    pub out: PathBuf,
    /// Start afresh: discard the results of a previous sweep in the output directory.
    #[arg(long)]
    pub force: bool,
    /// Run only shard K of N (K from 1): the runs whose number is K − 1 modulo N, for a
    /// job array without MPI (each shard with its own --out); `musclefem sweep merge`
    /// joins the shards' tables and computes the sensitivities.
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    pub shard: Option<Shard>,
    #[command(subcommand)]
    pub command: Option<SweepCommand>,
}

/// What `sweep` does besides running one.
#[derive(Debug, clap::Subcommand)]
pub enum SweepCommand {
    /// Join the sweep.csv of shards (`sweep --shard K/N`) of one sweep into one table in
    /// --out, and compute its sensitivities.
    Merge(merge::MergeArgs),
}

/// Shard K of N of a sweep's runs (1 <= K <= N).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Shard {
    /// Whether run number `run` (from 0) belongs to this shard.
    pub fn holds(&self, run: usize) -> bool {
        run % self.count == self.index - 1
    }
}

fn parse_shard(text: &str) -> Result<Shard, String> {
    let (k, n) = text
        .split_once('/')
        .ok_or_else(|| format!("'{text}': expected K/N, e.g. 2/8"))?;
    let number = |s: &str| {
        s.trim()
            .parse::<usize>()
            .map_err(|_| format!("'{text}': '{s}' is not a whole number"))
    };
    let (index, count) = (number(k)?, number(n)?);
    if count == 0 || index == 0 || index > count {
        return Err(format!("'{text}': K/N needs 1 <= K <= N"));
    }
    Ok(Shard { index, count })
}

pub fn sweep(args: &SweepArgs) -> Result<()> {
    if let Some(SweepCommand::Merge(merge)) = &args.command {
        return merge::merge(merge);
    }
    let plan = Plan::new(args)?;
    #[cfg(feature = "mpi")]
    if let Some(universe) = distributed::start()? {
        return distributed::sweep(args, &plan, &universe);
    }
    let _lock = plan.lock_output()?;
    let done = plan.previous_records(args.force)?;
    let done_runs: Vec<usize> = done.iter().map(|r| r.run).collect();
    let pending = plan.pending(&done_runs);
    plan.announce(done.len(), pending.len(), "");
    let records = plan.run_share(&pending, done, true)?;
    plan.finish(args, &records)
}

/// What a sweep runs: the base study, the varied parameters and the list of runs.
pub struct Plan {
    study: Study,
    names: Vec<String>,
    /// Parameter values of each run, in run order.
    design: Vec<Vec<f64>>,
    /// Runs at a time (in each process).
    jobs: usize,
    columns: Columns,
    table_path: PathBuf,
    /// The shard this process runs (`--shard`), or all runs.
    shard: Option<Shard>,
}

impl Plan {
    fn new(args: &SweepArgs) -> Result<Plan> {
        let study = match (&args.base, &args.scene) {
            (_, Some(scene)) => {
                check_no_test_options(&args.options)?;
                Study::Scene(Box::new(
                    SceneStudy::load(scene, args.trust.trust())?.with_outputs(&args.outputs)?,
                ))
            }
            (Some(base), None) if !args.outputs.is_empty() => bail!(
                "--base {base} --output {}: the elongation tests report the stress at 10 % and \
                 20 % strain; --output names history columns of a --scene",
                args.outputs.join(" --output ")
            ),
            (Some(base), None) => {
                let mode = base_mode(base)?;
                let test = args.options.test(mode, BTreeMap::new());
                // Every run shares the step: refuse it once, not in every row.
                crate::elongation::setup::check_time_step(&test)?;
                Study::Elongation {
                    mode,
                    test: Box::new(test),
                    options: args.options.describe(),
                }
            }
            (None, None) => bail!("name the base: --base passive|active or --scene FILE"),
        };
        let (axes, design) = match &args.design {
            Some(path) => {
                let file = design_file::DesignFile::read(path)?;
                // Each parameter's values, for the names' check and the sensitivities.
                let axes: Vec<vary::Axis> = (file.names.iter().enumerate())
                    .map(|(c, name)| vary::Axis {
                        name: name.clone(),
                        values: file.rows.iter().map(|row| row[c]).collect(),
                    })
                    .collect();
                study
                    .check_names(&axes)
                    .with_context(|| format!("the header of {}", path.display()))?;
                (axes, file.rows)
            }
            None => {
                let axes = vary::parse_axes(&args.vary)?;
                study.check_names(&axes)?;
                let design = match args.samples {
                    Some(0) => bail!("--samples 0: a Latin hypercube needs at least one run"),
                    Some(n) => latin_hypercube::latin_hypercube(&axes, n, args.seed),
                    None => grid::full_factorial(&axes),
                };
                (axes, design)
            }
        };
        let jobs = match args.jobs {
            Some(0) => bail!("--jobs 0: at least one run must run at a time"),
            Some(n) => {
                let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
                if n > cores {
                    eprintln!("warning: --jobs {n} is more than the {cores} cores; using {cores}");
                }
                n.min(cores)
            }
            None => std::thread::available_parallelism().map_or(1, |n| n.get()),
        };
        let names: Vec<String> = axes.iter().map(|a| a.name.clone()).collect();
        let columns = Columns {
            parameters: names.clone(),
            outputs: study.outputs().into_iter().map(|o| o.column).collect(),
        };
        Ok(Plan {
            study,
            names,
            design,
            jobs,
            columns,
            table_path: args.out.join(SWEEP_CSV),
            shard: args.shard,
        })
    }

    /// Lock the output directory (created if missing) for this sweep: a second sweep
    /// aimed at it stops before it reads or writes a row.
    pub(crate) fn lock_output(&self) -> Result<OutputLock> {
        let dir = match self.table_path.parent() {
            Some(dir) if !dir.as_os_str().is_empty() => dir,
            _ => Path::new("."),
        };
        Ok(OutputLock::acquire(dir)?)
    }

    /// Create the output directory and read the rows of a previous run of this sweep;
    /// then record this sweep's base in `sweep_base.txt`.
    fn previous_records(&self, force: bool) -> Result<Vec<Record>> {
        if let Some(dir) = self.table_path.parent() {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("creating the output directory {}", dir.display()))?;
        }
        let base = format!(
            "{}{DESIGN_SIZE}{}\n",
            self.study.fingerprint()?,
            self.design.len()
        );
        let records = previous_records(&self.table_path, &self.columns, &self.design, force)?;
        let base_path = self.table_path.with_file_name(SWEEP_BASE);
        if !records.is_empty() {
            let previous = std::fs::read_to_string(&base_path).unwrap_or_default();
            if previous != base {
                bail!(
                    "{}: its rows were made from another base ({}) than this sweep's ({}); use \
                     another --out, or --force to start afresh",
                    self.table_path.display(),
                    if previous.is_empty() {
                        format!("{} is missing", base_path.display())
                    } else {
                        previous.trim().to_string()
                    },
                    base.trim()
                );
            }
        }
        PendingFile::stage_bytes(&base_path, base.as_bytes())?.commit()?;
        Ok(records)
    }

    /// The runs not in `done` (run numbers) and in this process's shard, in run order.
    fn pending(&self, done: &[usize]) -> Vec<usize> {
        (0..self.design.len())
            .filter(|run| !done.contains(run))
            .filter(|&run| self.shard.is_none_or(|shard| shard.holds(run)))
            .collect()
    }

    fn announce(&self, done: usize, pending: usize, processes: &str) {
        let shard = self
            .shard
            .map_or(String::new(), |s| format!(" in shard {s}"));
        println!(
            "{}: {} runs, {done} already in {}, {pending} to run{shard}{processes}, {} at a time",
            self.study.title(),
            self.design.len(),
            self.table_path.display(),
            self.jobs
        );
    }

    /// The threads the runs share: `jobs` of them.
    fn worker_pool(&self) -> Result<rayon::ThreadPool> {
        rayon::ThreadPoolBuilder::new()
            .num_threads(self.jobs)
            .build()
            .context("starting the worker threads")
    }

    /// Run number `run` of the design (a failure is an outcome, not an error).
    fn run_one(&self, run: usize) -> Record {
        Record {
            run,
            values: self.design[run].clone(),
            outcome: self.study.run(&self.names, &self.design[run]),
        }
    }

    /// Run `runs`, `jobs` at a time, adding their records to `records`; with `write`,
    /// rewrite sweep.csv after each.
    fn run_share(&self, runs: &[usize], records: Vec<Record>, write: bool) -> Result<Vec<Record>> {
        let records = Mutex::new(records);
        let bar = progress_bar(runs.len());
        let pool = self.worker_pool()?;
        pool.install(|| {
            runs.par_iter()
                .with_max_len(1)
                .try_for_each(|&run| -> Result<()> {
                    let record = self.run_one(run);
                    let mut records = records.lock().map_err(|_| anyhow!("a run panicked"))?;
                    records.push(record);
                    if write {
                        self.write_table(&records)?;
                    }
                    bar.inc(1);
                    Ok(())
                })
        })?;
        bar.finish_and_clear();
        records.into_inner().map_err(|_| anyhow!("a run panicked"))
    }

    fn write_table(&self, records: &[Record]) -> Result<()> {
        let text = table::format_table(&self.columns, records);
        PendingFile::stage_bytes(&self.table_path, text.as_bytes())?.commit()?;
        Ok(())
    }

    /// The summary on the terminal and the sensitivities.
    fn finish(&self, args: &SweepArgs, records: &[Record]) -> Result<()> {
        report(records, &self.table_path);
        if let Some(shard) = &args.shard {
            println!(
                "  shard {shard} of the sweep: no sensitivities until the shards are merged \
                 (`musclefem sweep merge SHARD_DIR... --out DIR`)"
            );
            return Ok(());
        }
        write_sensitivities(
            &args.out,
            &self.study.title(),
            &self.names,
            self.study.outputs(),
            records,
        )
    }
}

/// The specimen and solver options shape an elongation test: with a scene, whose file
/// says all that, they are refused rather than ignored.
pub(crate) fn check_no_test_options(options: &TestOptions) -> Result<()> {
    if !options.are_defaults() {
        bail!(
            "--scene: the elongation test's options (--solver, --element, --mesh-size, --shape, \
             --grips, --time-step) do not apply to a scene; set them in the scene file"
        );
    }
    Ok(())
}

/// The elongation mode named by `--base`.
fn base_mode(base: &str) -> Result<Activation> {
    match base {
        "passive" => Ok(Activation::Passive),
        "active" => Ok(Activation::Active),
        other if Path::new(other).extension().is_some_and(|e| e == "toml") => bail!(
            "--base {other}: a scene file is given with --scene {other}; the bases are the \
             elongation tests 'passive' and 'active'"
        ),
        other => bail!("--base '{other}': expected 'passive' or 'active' (the elongation tests)"),
    }
}

/// The rows of a previous run of this sweep (none with `force`, which removes its files).
/// Each row must hold the parameter values this design gives its run.
fn previous_records(
    path: &Path,
    columns: &Columns,
    design: &[Vec<f64>],
    force: bool,
) -> Result<Vec<Record>> {
    if force {
        for file in [SWEEP_CSV, SWEEP_BASE, SENSITIVITY_CSV, SENSITIVITY_PNG] {
            let stale = path.with_file_name(file);
            if stale.exists() {
                std::fs::remove_file(&stale)
                    .with_context(|| format!("removing {}", stale.display()))?;
            }
        }
        return Ok(Vec::new());
    }
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(e).with_context(|| format!("reading {}", path.display())),
    };
    let records = table::parse_table(&text, path, columns)?;
    for record in &records {
        if design.get(record.run) != Some(&record.values) {
            bail!(
                "{}: run {} has parameters {:?}, which is not this sweep's run {} (another \
                 design, --samples or --seed?); use another --out, or --force to start afresh",
                path.display(),
                record.run,
                record.values,
                record.run
            );
        }
    }
    Ok(records)
}

fn progress_bar(runs: usize) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(runs as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos} / {len} runs [{elapsed_precise}, ETA {eta}]")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}
