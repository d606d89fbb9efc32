//! What a sweep varies and measures: one of the elongation tests (`--base passive|active`,
//! the Hill parameters of its specimen, the stress at 10 % and 20 % strain) or a scene
//! file (`--scene FILE`, its materials' parameters, columns of its history).

use anyhow::{Context, Result, bail};

use musclefem_io::fingerprint::fnv1a;
use musclefem_materials::MaterialLibrary;

use super::run::{Outcome, run_elongation_sample, timed};
use super::vary::Axis;
use crate::elongation::{Activation, ElongationTest};
use crate::scene_study::{HistoryOutput, SceneStudy};

/// The base of a sweep.
pub enum Study {
    /// An elongation test of `musclefem elongate`.
    Elongation {
        mode: Activation,
        test: Box<ElongationTest>,
        /// The test's options, as `TestOptions::describe` gives them.
        options: String,
    },
    /// A scene file.
    Scene(Box<SceneStudy>),
}

/// One summary output of every run: its column in `sweep.csv` and what it is.
#[derive(Debug, Clone, PartialEq)]
pub struct Output {
    pub column: String,
    pub description: String,
}

impl Study {
    /// The summary outputs of every run, in the order of their `sweep.csv` columns.
    pub fn outputs(&self) -> Vec<Output> {
        match self {
            Study::Elongation { .. } => vec![
                Output {
                    column: "stress_10pct_pa".into(),
                    description: "stress at 10 % strain".into(),
                },
                Output {
                    column: "stress_20pct_pa".into(),
                    description: "stress at 20 % strain".into(),
                },
            ],
            Study::Scene(scene) => scene
                .outputs()
                .iter()
                .map(|o| Output {
                    column: o.name(),
                    description: describe(o),
                })
                .collect(),
        }
    }

    /// "passive elongation (implicit, …)" or "scene examples/x.toml".
    pub fn title(&self) -> String {
        match self {
            Study::Elongation { mode, options, .. } => {
                format!("{} elongation ({options})", mode.name())
            }
            Study::Scene(scene) => format!("scene {}", scene.path().display()),
        }
    }

    /// What the runs are made from, as one line per item: the base and its settings (for
    /// a scene its file's size and FNV-1a hash). Rows made from another base are not
    /// resumed.
    pub fn fingerprint(&self) -> Result<String> {
        Ok(match self {
            Study::Elongation { test, .. } => format!(
                "{}\ntime step = {}\n",
                self.title(),
                test.time_step
                    .map_or("default".to_string(), |t| format!("{t} s"))
            ),
            Study::Scene(scene) => {
                let bytes = std::fs::read(scene.path())
                    .with_context(|| format!("reading {}", scene.path().display()))?;
                format!(
                    "{}\n{} bytes, FNV-1a {:016x}\n",
                    self.title(),
                    bytes.len(),
                    fnv1a(&bytes)
                )
            }
        })
    }

    /// Every varied name must be a parameter the base lets a sweep set.
    pub fn check_names(&self, axes: &[Axis]) -> Result<()> {
        match self {
            Study::Elongation { .. } => check_hill_names(axes),
            Study::Scene(scene) => scene
                .check_names(axes.iter().map(|a| a.name.as_str()))
                .context("--vary"),
        }
    }

    /// One run with `names[i] = values[i]`.
    pub fn run(&self, names: &[String], values: &[f64]) -> Outcome {
        match self {
            Study::Elongation { test, .. } => timed(|| run_elongation_sample(test, names, values)),
            Study::Scene(scene) => timed(|| scene.run(names, values)),
        }
    }
}

fn describe(output: &HistoryOutput) -> String {
    match output.at {
        None => format!("{} at the end", output.column),
        Some(t) => format!("{} at {t} s", output.column),
    }
}

/// Every varied name must be a Hill parameter, and not one the mode sets.
fn check_hill_names(axes: &[Axis]) -> Result<()> {
    let hill = MaterialLibrary::with_builtins().info("hill")?;
    for axis in axes {
        if axis.name == "n2" || axis.name == "t0" {
            bail!(
                "--vary {}: the mode sets the activation (passive n2 = 0, active n2 = 1 from t0 = 0)",
                axis.name
            );
        }
        if !hill.parameters.iter().any(|p| p.name == axis.name) {
            let known: Vec<&str> = hill.parameters.iter().map(|p| p.name.as_ref()).collect();
            bail!(
                "--vary {}: the Hill muscle has no parameter '{}' (it has {})",
                axis.name,
                axis.name,
                known.join(", ")
            );
        }
    }
    Ok(())
}
