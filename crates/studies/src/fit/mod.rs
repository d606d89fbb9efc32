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
//! - [`levenberg_marquardt`]: the bounded least-squares solver.

pub mod data;
pub mod levenberg_marquardt;
pub mod model;
mod report;
mod view;

use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use nalgebra::DVector;

use musclefem_io::PendingFile;
use musclefem_io::csv::{format_number, format_table};
use musclefem_io::output::OutputLock;
use musclefem_io::plot::{Figure, LegendPosition, Panel, Series, SeriesStyle, stage_png};
use musclefem_materials::MaterialLibrary;
use musclefem_materials::{Bound, ParameterSpec};

use crate::elongation::options::TestOptions;
use musclefem_core::mesh::generate::SpecimenShape;

use crate::elongation::protocol::{Activation, PULL_ELONGATION};
use crate::scene_study::SceneStudy;
use data::{Columns, Range, read_curve};
use levenberg_marquardt::{Settings, minimise};
use model::{ElongationModel, FitModel, SceneModel};
use report::Report;
use view::View;

/// Two-sided 95 % quantile of the normal distribution: the confidence intervals are the
/// asymptotic ones, fitted value ± 1.96 standard errors.
const Z_95: f64 = 1.959963984540054;

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
    #[arg(long, value_name = "NAME,...", value_delimiter = ',', required = true)]
    pub params: Vec<String>,
    /// Start value of a fitted parameter [default: the scene's value, else Table 1 or the
    /// model's default]; repeatable.
    #[arg(long = "start", value_name = "NAME=VALUE")]
    pub starts: Vec<String>,
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

/// One fitted parameter: name, start and bounds.
struct Unknown {
    name: String,
    start: f64,
    lower: f64,
    upper: f64,
}

/// What the fit runs and how its curve is named and drawn.
enum Base {
    Elongation(Box<crate::elongation::ElongationTest>),
    Scene(Box<SceneStudy>),
}

pub fn fit(args: &FitArgs) -> Result<()> {
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
    let unknowns = unknowns(args, &base)?;
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
    let start: Vec<f64> = unknowns.iter().map(|u| u.start).collect();
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
            let curve = model.curve(&start).context("the start values' run")?;
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
    let measured = read_curve(&args.data, &columns, range)?;
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
    let outputs = Outputs::new(args)?;
    println!(
        "fitting {} to {} points of {} ({} outside {within} left out), {}",
        names.join(", "),
        measured.strain.len(),
        args.data.display(),
        measured.left_out,
        view.what,
    );
    let data = DVector::from_vec(measured.stress.clone());
    let residuals = |x: &[f64]| -> Result<DVector<f64>> {
        Ok(DVector::from_vec(model.predict(x, &measured.strain)?) - &data)
    };
    let lower: Vec<f64> = unknowns.iter().map(|u| u.lower).collect();
    let upper: Vec<f64> = unknowns.iter().map(|u| u.upper).collect();
    let bar = spinner();
    let points = measured.strain.len() as f64;
    let started = Instant::now();
    let solution = minimise(
        &residuals,
        &start,
        &lower,
        &upper,
        &Settings::default(),
        &mut |iteration, cost| {
            bar.set_message(format!(
                "iteration {iteration}: RMS residual {:.4e} {}",
                (2.0 * cost / points).sqrt(),
                view.y_unit
            ));
        },
    )?;
    bar.finish_and_clear();
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
        "data = {}\npoints = {} (left out: {} outside {within})\n{}\n{}time = {:.1} s\n",
        args.data.display(),
        measured.strain.len(),
        measured.left_out,
        view.summary_line,
        report.text(),
        elapsed.as_secs_f64()
    );
    print!("{summary}");
    let fitted_stress: Vec<f64> = measured
        .stress
        .iter()
        .zip(solution.residuals.iter())
        .map(|(y, r)| y + r)
        .collect();
    let curve_csv = format_table(
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
    for (label, curve) in [("fitted", fitted_curve), ("start", start_curve)] {
        let curve = curve.with_context(|| format!("the {label} curve for fit.png"))?;
        panel = panel.with_series(Series::new(
            label,
            curve
                .iter()
                .map(|&(x, y)| (view.x_scale * x, view.y_scale * y)),
        ));
    }
    let figure = Figure::new("musclefem fit").with_panel(panel);
    outputs.write(report.csv(), curve_csv, summary, &figure)
}

/// The fitted parameters with their starts and bounds, checked against the parameter
/// table of the Hill material (elongation) or of the scene's material.
fn unknowns(args: &FitArgs, base: &Base) -> Result<Vec<Unknown>> {
    let hill = MaterialLibrary::with_builtins().info("hill")?;
    // The table entry of a fitted name and the start it has unless --start says otherwise.
    let lookup = |name: &str| -> Result<(ParameterSpec, Option<f64>)> {
        match base {
            Base::Elongation(_) => {
                if name == "n2" || name == "t0" {
                    bail!(
                        "--params {name}: the test sets the activation (passive n2 = 0, active n2 = 1)"
                    );
                }
                let Some(spec) = hill.parameters.iter().find(|p| p.name == name) else {
                    let known: Vec<&str> =
                        hill.parameters.iter().map(|p| p.name.as_ref()).collect();
                    bail!(
                        "--params {name}: the Hill muscle has no parameter '{name}' (it has {})",
                        known.join(", ")
                    );
                };
                Ok((spec.clone(), spec.default))
            }
            Base::Scene(study) => {
                let (spec, given) = study.parameter(name).context("--params")?;
                let start = given.or(spec.default);
                Ok((spec, start))
            }
        }
    };
    let mut starts = name_values(&args.starts, "--start")?;
    let mut bounds = name_values(&args.bounds, "--bound")?;
    let mut unknowns: Vec<Unknown> = Vec::new();
    for name in &args.params {
        let name = name.trim();
        let (spec, default_start) = lookup(name)?;
        let spec = &spec;
        if unknowns.iter().any(|u| u.name == name) {
            bail!("--params: '{name}' is given more than once");
        }
        let start = match starts.remove(name) {
            Some(text) => parse_number(&text, "--start", name)?,
            None => default_start
                .with_context(|| format!("--params {name}: give --start {name}=VALUE"))?,
        };
        let (lower, upper) = match bounds.remove(name) {
            Some(text) => {
                let (lo, hi) = text
                    .split_once(':')
                    .with_context(|| format!("--bound {name}={text}: expected NAME=LO:HI"))?;
                let (lo, hi) = (
                    parse_number(lo, "--bound", name)?,
                    parse_number(hi, "--bound", name)?,
                );
                if lo >= hi {
                    bail!("--bound {name}={text}: LO must be below HI");
                }
                (lo, hi)
            }
            None => valid_range(spec, start),
        };
        let acceptable = |bound: f64| bound.is_infinite() || spec.accepts(bound);
        if !(lower..=upper).contains(&start) || !acceptable(lower) || !acceptable(upper) {
            bail!(
                "--params {name}: the start {start} and bounds [{lower}, {upper}] must lie in \
                 the valid range of '{name}' with the start between the bounds"
            );
        }
        unknowns.push(Unknown {
            name: name.to_string(),
            start,
            lower,
            upper,
        });
    }
    for (flag, left) in [("--start", starts), ("--bound", bounds)] {
        if let Some(name) = left.keys().next() {
            bail!("{flag} {name}: '{name}' is not among --params");
        }
    }
    Ok(unknowns)
}

/// NAME=TEXT tokens of `flag` by name.
fn name_values(tokens: &[String], flag: &str) -> Result<BTreeMap<String, String>> {
    let mut map = BTreeMap::new();
    for token in tokens {
        let (name, value) = token
            .split_once('=')
            .with_context(|| format!("{flag} '{token}': expected NAME=..."))?;
        if map
            .insert(name.trim().to_string(), value.trim().to_string())
            .is_some()
        {
            bail!(
                "{flag} '{token}': '{}' is given more than once",
                name.trim()
            );
        }
    }
    Ok(map)
}

fn parse_number(text: &str, flag: &str, name: &str) -> Result<f64> {
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .with_context(|| format!("{flag} {name}: '{}' is not a finite number", text.trim()))
}

/// The parameter's valid range as closed bounds: an open end at l is moved inside by
/// 10⁻⁶ of the start value; an unbounded side stays infinite.
fn valid_range(spec: &ParameterSpec, start: f64) -> (f64, f64) {
    let inset = 1e-6 * start.abs().max(f64::MIN_POSITIVE);
    let lower = match spec.lower {
        Bound::Unbounded => f64::NEG_INFINITY,
        Bound::Inclusive(l) => l,
        Bound::Exclusive(l) => l + inset,
    };
    let upper = match spec.upper {
        Bound::Unbounded => f64::INFINITY,
        Bound::Inclusive(u) => u,
        Bound::Exclusive(u) => u - inset,
    };
    (lower, upper)
}

/// The output files, checked before the fit starts (so a long fit does not end in a
/// refusal) and written together at its end.
struct Outputs {
    dir: PathBuf,
    /// Held while the fit runs: one writer per output directory.
    _lock: OutputLock,
}

const FILES: [&str; 4] = ["fit.csv", "fit_curve.csv", "fit.txt", "fit.png"];

impl Outputs {
    fn new(args: &FitArgs) -> Result<Self> {
        let dir = args.out.clone();
        let existing = FILES.iter().map(|f| dir.join(f)).find(|p| p.exists());
        if let (false, Some(existing)) = (args.force, existing) {
            bail!(
                "{} exists: a previous fit is in {} (use --force to replace it)",
                existing.display(),
                dir.display()
            );
        }
        // Creates the directory; a second fit into it is refused while this one runs.
        let lock = OutputLock::acquire(&dir)?;
        Ok(Outputs { dir, _lock: lock })
    }

    fn write(&self, csv: String, curve: String, summary: String, figure: &Figure) -> Result<()> {
        let staged = [
            PendingFile::stage_bytes(&self.dir.join(FILES[0]), csv.as_bytes())?,
            PendingFile::stage_bytes(&self.dir.join(FILES[1]), curve.as_bytes())?,
            PendingFile::stage_bytes(&self.dir.join(FILES[2]), summary.as_bytes())?,
            stage_png(&self.dir.join(FILES[3]), figure)?,
        ];
        for file in staged {
            file.commit()?;
        }
        println!("results: {}/{{{}}}", self.dir.display(), FILES.join(","));
        Ok(())
    }
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
