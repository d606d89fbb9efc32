//! `musclefem fit`: least-squares calibration of material parameters to a measured curve:
//! the engineering stress–strain curve of the elongation test (Hill parameters; seed
//! §2.2: the paper calibrated D, b, c, d, k_c and k_e by hand-run parametric studies), or
//! one history column of a scene against another (`--scene FILE --x COLUMN --y COLUMN`,
//! the parameters of the scene's materials). Writes `fit.csv` (fitted values, standard
//! errors and 95 % confidence intervals from the Jacobian), `fit_curve.csv` (measured and
//! fitted values at the measured abscissae), `fit.png` (data against the start and fitted
//! curves) and `fit.txt` (the residual and how the solver stopped).
//!
//! - [`data`]: reading the measured curve;
//! - [`model`]: the elongation test or the scene as a function of the fitted parameters;
//! - `view`, `report`: how the curve is named and drawn, and the fitted numbers;
//! - [`levenberg_marquardt`]: the bounded least-squares solver;
//! - `unknowns`, [`outputs`]: the fitted parameters' starts and bounds, and the files;
//! - `multi_start`: the starting points of `--design FILE.csv`, one fit from each, the
//!   best kept.
//!
//! [`fit_curve`] is the fit without printing or files (the Python module's
//! `musclefem.fit`); [`fit`] is the command around it.

pub mod data;
pub mod levenberg_marquardt;
pub mod model;
mod multi_start;
pub mod outputs;
mod report;
mod unknowns;
mod view;

use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use nalgebra::DVector;

use musclefem_io::csv::{format_number, format_table};
use musclefem_io::plot::{Figure, LegendPosition, Panel, Series, SeriesStyle};

use crate::elongation::options::TestOptions;
use musclefem_core::mesh::generate::SpecimenShape;

use crate::elongation::protocol::{Activation, PULL_ELONGATION};
use crate::scene_study::SceneStudy;
use data::{Columns, MeasuredCurve, Range, parse_curve, read_curve};
use levenberg_marquardt::{Settings, Stop, minimise};
use model::{ElongationModel, FitModel, SceneModel};
use outputs::Outputs;
use report::Report;
use unknowns::unknowns;
use view::View;

/// Two-sided 95 % quantile of the normal distribution: the confidence intervals are the
/// asymptotic ones, fitted value ± 1.96 standard errors.
pub const Z_95: f64 = 1.959963984540054;

#[derive(Debug, clap::Args)]
pub struct FitArgs {
    /// The measured curve: a CSV file with a header line (see --strain-column and
    /// --stress-column).
    #[arg(long, value_name = "CURVE.csv")]
    pub data: PathBuf,
    /// The elongation test the data come from.
    #[arg(long, value_enum, default_value = "passive", conflicts_with = "scene")]
    pub test: Activation,
    /// A scene instead of an elongation test: the fit runs it with trial values of the
    /// parameters of its materials and compares its history column --y against --x with
    /// the data (the specimen and solver options below do not apply).
    #[arg(long, value_name = "SCENE.toml")]
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub trust: crate::scene_study::SceneTrustArgs,
    /// With --scene: the history column of the abscissa (it must increase along the run).
    #[arg(
        long,
        value_name = "COLUMN",
        default_value = "time_s",
        requires = "scene"
    )]
    pub x: String,
    /// With --scene: the history column fitted to the data, e.g. reaction_block.x1.x_n.
    #[arg(long, value_name = "COLUMN", requires = "scene")]
    pub y: Option<String>,
    /// The parameters to fit, comma-separated (e.g. c,A): Hill parameters for an
    /// elongation test (the others keep Table 1); for a scene, parameters of its one
    /// material or MATERIAL.NAME (the others keep the scene's values).
    #[arg(
        long,
        value_name = "NAME,...",
        value_delimiter = ',',
        required_unless_present = "design"
    )]
    pub params: Vec<String>,
    /// Start value of a fitted parameter [default: the scene's value, else Table 1 or the
    /// model's default]; repeatable.
    #[arg(long = "start", value_name = "NAME=VALUE")]
    pub starts: Vec<String>,
    /// A multi-start fit: a CSV file whose header names the fitted parameters (as
    /// --params does; without --params they are its columns) and whose every row is a
    /// set of start values. The fit runs from each row and keeps the one with the
    /// smallest residual; fit.txt lists every start's ending residual (`,`, `;` or tab
    /// separated; a byte-order mark and decimal commas are read).
    #[arg(long, value_name = "FILE.csv", conflicts_with = "starts")]
    pub design: Option<PathBuf>,
    /// Bounds of a fitted parameter [default: its valid range]; repeatable.
    #[arg(long = "bound", value_name = "NAME=LO:HI")]
    pub bounds: Vec<String>,
    /// Header of the data's strain column [default: engineering_strain; with --scene the
    /// --x name].
    #[arg(long, value_name = "NAME")]
    pub strain_column: Option<String>,
    /// Header of the data's stress column [default: engineering_stress_pa; with --scene the
    /// --y name].
    #[arg(long, value_name = "NAME")]
    pub stress_column: Option<String>,
    /// Engineering strain [1] (with --scene: the --x column's unit) = strain column × this
    /// (0.01 for percent).
    #[arg(long, value_name = "FACTOR", default_value_t = 1.0)]
    pub strain_scale: f64,
    /// Engineering stress [Pa] (with --scene: the --y column's unit) = stress column × this
    /// (e.g. 7000 for percent of a 700 kPa maximum isometric stress).
    #[arg(long, value_name = "FACTOR", default_value_t = 1.0)]
    pub stress_scale: f64,
    #[command(flatten)]
    pub options: TestOptions,
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "out/fit")]
    pub out: PathBuf,
    /// Replace the results of a previous fit in the output directory.
    #[arg(long)]
    pub force: bool,
}

/// What the fit runs and how its curve is named and drawn.
enum Base {
    Elongation(Box<crate::elongation::ElongationTest>),
    Scene(Box<SceneStudy>),
}

/// What a fit found, with the texts and the chart of its files.
pub struct Fitted {
    /// The fitted parameters, in the order of `--params`.
    pub names: Vec<String>,
    pub start: Vec<f64>,
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
    /// The fitted values.
    pub values: Vec<f64>,
    /// Standard error of each value (`None` for one on its bound, and for all when the
    /// parameters are not identifiable together: JᵀJ singular).
    pub standard_errors: Vec<Option<f64>>,
    pub at_bound: Vec<bool>,
    /// The data used, in SI units (engineering strain [1] and stress [Pa], or the scene's
    /// history columns), and the points left out.
    pub measured: MeasuredCurve,
    /// The fitted model at the measured abscissae.
    pub fitted_at_data: Vec<f64>,
    /// The model's whole curve (x, y) with the start and with the fitted values.
    pub start_curve: Vec<(f64, f64)>,
    pub fitted_curve: Vec<(f64, f64)>,
    /// RMS residual (in the data's unit) and R².
    pub rms: f64,
    pub r_squared: f64,
    /// Accepted steps, runs of the model, and why the solver stopped.
    pub iterations: usize,
    pub evaluations: usize,
    pub stop: Stop,
    /// fit.txt, fit.csv, fit_curve.csv (whose header names the curve's columns) and
    /// fit.png's chart.
    pub summary: String,
    pub table: String,
    pub curve_table: String,
    pub figure: Figure,
}

/// What a caller sees of a fit as it goes.
pub trait FitWatch {
    /// The data are read and the parameters checked; `announcement` is the line `fit`
    /// prints. An error here ends the fit before its first run (the command checks its
    /// output directory here).
    fn starting(&mut self, announcement: &str) -> Result<()>;
    /// An accepted step: its number and the RMS residual, in `unit`.
    fn iteration(&mut self, iteration: usize, rms: f64, unit: &str);
    /// The least-squares solver ended (the curves for the chart are computed next).
    fn solved(&mut self) {}
}

/// Why a fit stopped before its end: its `stop` flag was set.
#[derive(Debug)]
pub struct FitStopped;

impl std::fmt::Display for FitStopped {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("the fit was stopped on request")
    }
}

impl std::error::Error for FitStopped {}

/// `musclefem fit`: the fit, printed and written to `--out`.
pub fn fit(args: &FitArgs) -> Result<()> {
    let mut terminal = Terminal {
        args,
        outputs: None,
        bar: ProgressBar::hidden(),
    };
    let fitted = fit_curve(args, None, &mut terminal, &AtomicBool::new(false))?;
    print!("{}", fitted.summary);
    let outputs = terminal
        .outputs
        .context("the output directory was not opened")?;
    outputs.write(&fitted)?;
    println!(
        "results: {}/{{{}}}",
        outputs.dir().display(),
        outputs::FILES.join(",")
    );
    Ok(())
}

/// The command's view of a fit: its output directory, opened before the first run, and
/// a spinner with the residual.
struct Terminal<'a> {
    args: &'a FitArgs,
    outputs: Option<Outputs>,
    bar: ProgressBar,
}

impl FitWatch for Terminal<'_> {
    fn starting(&mut self, announcement: &str) -> Result<()> {
        self.outputs = Some(Outputs::new(&self.args.out, self.args.force)?);
        println!("{announcement}");
        self.bar = spinner();
        Ok(())
    }

    fn iteration(&mut self, iteration: usize, rms: f64, unit: &str) {
        self.bar.set_message(format!(
            "iteration {iteration}: RMS residual {rms:.4e} {unit}"
        ));
    }

    fn solved(&mut self) {
        self.bar.finish_and_clear();
    }
}

/// The fit `args` asks for, to the data of `args.data` or, when given, to the CSV text
/// `data` (`args.data` then only names it in messages); `stop` stops it between two runs
/// of the model (the error is then [`FitStopped`]).
pub fn fit_curve(
    args: &FitArgs,
    data: Option<&str>,
    watch: &mut dyn FitWatch,
    stop: &AtomicBool,
) -> Result<Fitted> {
    let base = match &args.scene {
        Some(path) => {
            crate::sweep::check_no_test_options(&args.options)?;
            let study = SceneStudy::load(path, args.trust.trust())?;
            let y = args.y.as_deref().context(
                "--scene: name the history column to fit with --y, e.g. --y reaction_block.x1.x_n",
            )?;
            study.check_column(&args.x, "--x")?;
            study.check_column(y, "--y")?;
            Base::Scene(Box::new(study))
        }
        None => {
            let test = args.options.test(args.test, BTreeMap::new());
            crate::elongation::setup::check_time_step(&test)?;
            Base::Elongation(Box::new(test))
        }
    };
    let design = multi_start::design_starts(args)?;
    let params = match &design {
        Some(design) => design.names.clone(),
        None => args.params.iter().map(|p| p.trim().to_string()).collect(),
    };
    let start_tokens = match &design {
        Some(design) => design.start_tokens(0),
        None => args.starts.clone(),
    };
    let mut unknowns = unknowns(args, &base, &params, &start_tokens)?;
    if let Some(design) = &design {
        design.check_bounds(&unknowns)?;
    }
    let names: Vec<String> = unknowns.iter().map(|u| u.name.clone()).collect();
    for (flag, scale) in [
        ("--strain-scale", args.strain_scale),
        ("--stress-scale", args.stress_scale),
    ] {
        if !(scale.is_finite() && scale != 0.0) {
            bail!("{flag} {scale}: must be a finite, non-zero factor");
        }
    }
    let y_column = args.y.clone().unwrap_or_default();
    let (default_x, default_y) = match &base {
        Base::Elongation(_) => ("engineering_strain", "engineering_stress_pa"),
        Base::Scene(_) => (args.x.as_str(), y_column.as_str()),
    };
    let columns = Columns {
        strain: args.strain_column.clone().unwrap_or(default_x.to_string()),
        stress: args.stress_column.clone().unwrap_or(default_y.to_string()),
        strain_scale: args.strain_scale,
        stress_scale: args.stress_scale,
    };
    let model = match &base {
        Base::Elongation(test) => FitModel::Elongation(ElongationModel {
            base: test,
            names: &names,
        }),
        Base::Scene(study) => FitModel::Scene(SceneModel {
            study,
            names: &names,
            x: &args.x,
            y: &y_column,
        }),
    };
    let starts: Vec<Vec<f64>> = match &design {
        Some(design) => design.rows.clone(),
        None => vec![unknowns.iter().map(|u| u.start).collect()],
    };
    let (view, range) = match &base {
        // Both specimens are 50 mm long: the pull ends at 20 % strain.
        Base::Elongation(_) => (
            View::elongation(args.test, &args.options),
            Range {
                low: 0.0,
                high: PULL_ELONGATION / SpecimenShape::paper_fusiform().length(),
                low_inclusive: false,
            },
        ),
        // The data within the start run's abscissae.
        Base::Scene(study) => {
            let curve = model.curve(&starts[0]).context("the start values' run")?;
            let first = curve.first().map_or(0.0, |p| p.0);
            let last = curve.last().map_or(0.0, |p| p.0);
            let range = Range {
                low: first,
                high: last,
                low_inclusive: true,
            };
            (View::scene(study, &args.x, &y_column), range)
        }
    };
    let measured = match data {
        None => read_curve(&args.data, &columns, range)?,
        Some(text) => parse_curve(text, &args.data, &columns, range)?,
    };
    let within = view.range_text(range);
    if measured.strain.len() <= unknowns.len() {
        bail!(
            "{}: {} points within {within} ({} left out), not more than the {} fitted parameters",
            args.data.display(),
            measured.strain.len(),
            measured.left_out,
            unknowns.len()
        );
    }
    watch.starting(&format!(
        "fitting {} to {} points of {} ({} outside {within} left out), {}{}",
        names.join(", "),
        measured.strain.len(),
        args.data.display(),
        measured.left_out,
        view.what,
        design.as_ref().map_or(String::new(), |d| format!(
            ", from each of the {} starts of {}",
            d.rows.len(),
            d.path.display()
        )),
    ))?;
    let data = DVector::from_vec(measured.stress.clone());
    let residuals = |x: &[f64]| -> Result<DVector<f64>> {
        if stop.load(Ordering::SeqCst) {
            return Err(FitStopped.into());
        }
        Ok(DVector::from_vec(model.predict(x, &measured.strain)?) - &data)
    };
    let lower: Vec<f64> = unknowns.iter().map(|u| u.lower).collect();
    let upper: Vec<f64> = unknowns.iter().map(|u| u.upper).collect();
    let points = measured.strain.len() as f64;
    let started = Instant::now();
    let mut ends = Vec::with_capacity(starts.len());
    for start in &starts {
        let solution = minimise(
            &residuals,
            start,
            &lower,
            &upper,
            &Settings::default(),
            &mut |iteration, cost| {
                watch.iteration(iteration, (2.0 * cost / points).sqrt(), view.y_unit)
            },
        );
        if solution.is_err() && stop.load(Ordering::SeqCst) {
            return Err(FitStopped.into());
        }
        ends.push(solution);
    }
    watch.solved();
    let (best, solution, starts_text) =
        multi_start::best_end(ends, design.as_ref(), points, view.y_unit)?;
    let start = starts[best].clone();
    for (unknown, &x) in unknowns.iter_mut().zip(&start) {
        unknown.start = x;
    }
    let elapsed = started.elapsed();

    let (start_curve, fitted_curve) =
        rayon::join(|| model.curve(&start), || model.curve(&solution.x));
    let report = Report {
        unknowns: &unknowns,
        solution: &solution,
        measured_stress: &measured.stress,
        unit: view.y_unit,
        quantity: &view.y_quantity,
    };
    let summary = format!(
        "data = {}\npoints = {} (left out: {} outside {within})\n{}\n{starts_text}{}time = {:.1} s\n",
        args.data.display(),
        measured.strain.len(),
        measured.left_out,
        view.summary_line,
        report.text(),
        elapsed.as_secs_f64()
    );
    let fitted_stress: Vec<f64> = measured
        .stress
        .iter()
        .zip(solution.residuals.iter())
        .map(|(y, r)| y + r)
        .collect();
    let curve_table = format_table(
        &view.curve_header,
        (0..measured.strain.len())
            .map(|i| [measured.strain[i], measured.stress[i], fitted_stress[i]]),
    );
    let mut panel = Panel::new(
        format!(
            "{}: {}",
            view.title,
            names
                .iter()
                .zip(&solution.x)
                .map(|(n, &x)| format!("{n} = {}", significant(x, 4)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        &view.x_label,
        &view.y_label,
    )
    .with_legend(LegendPosition::UpperLeft)
    .with_series(
        Series::new(
            "measured",
            measured
                .strain
                .iter()
                .zip(&measured.stress)
                .map(|(e, s)| (view.x_scale * e, view.y_scale * s)),
        )
        .with_style(SeriesStyle::Dots),
    );
    let fitted_curve = fitted_curve.context("the fitted curve for fit.png")?;
    let start_curve = start_curve.context("the start curve for fit.png")?;
    for (label, curve) in [("fitted", &fitted_curve), ("start", &start_curve)] {
        panel = panel.with_series(Series::new(
            label,
            curve
                .iter()
                .map(|&(x, y)| (view.x_scale * x, view.y_scale * y)),
        ));
    }
    let (rms, r_squared) = report.residual();
    let standard_errors = report
        .standard_errors()
        .unwrap_or_else(|| vec![None; unknowns.len()]);
    Ok(Fitted {
        at_bound: (0..unknowns.len()).map(|j| report.at_bound(j)).collect(),
        table: report.csv(),
        names,
        start,
        lower,
        upper,
        values: solution.x.clone(),
        standard_errors,
        fitted_at_data: fitted_stress,
        start_curve,
        fitted_curve,
        rms,
        r_squared,
        iterations: solution.iterations,
        evaluations: solution.evaluations,
        stop: solution.stop,
        summary,
        curve_table,
        figure: Figure::new("musclefem fit").with_panel(panel),
        measured,
    })
}

/// `x` rounded to `digits` significant digits, as text.
fn significant(x: f64, digits: i32) -> String {
    if x == 0.0 || !x.is_finite() {
        return format_number(x);
    }
    let factor = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
    format_number((x * factor).round() / factor)
}

fn spinner() -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new_spinner();
    bar.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    bar.set_message("iteration 0");
    bar
}
