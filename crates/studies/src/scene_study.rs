//! A scene file as the base of a study (`musclefem sweep --scene FILE`, `musclefem fit
//! --scene FILE`): each run is the scene with some of its material parameters changed,
//! run in this process without output files, and read through the history it would
//! have written.
//!
//! - A varied parameter is `KEY` when the scene has one material, `MATERIAL.KEY`
//!   otherwise (`MATERIAL` the scene's local name of the material, `KEY` a parameter of
//!   its model as `musclefem materials` lists it).
//! - A sweep's output ([`HistoryOutput`]) is a column of the scene's `history.csv`, read
//!   at the end of the run (`COLUMN`) or at a time between two recorded rows, linearly
//!   (`COLUMN@TIME`, TIME in seconds). Without `--output`, every reaction column at the
//!   end.
//! - A fit reads one history column against another ([`SceneHistory::column`]).

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

use musclefem_core::solver::{Observer, Record, Snapshot};
use musclefem_io::scene::{Locator, PluginPolicy, SceneFile, Trust, build_model, read_scene_file};
use musclefem_materials::{MaterialLibrary, ParameterSpec};

/// A column of the scene's history, at the end of the run or at a time.
#[derive(Debug, Clone, PartialEq)]
pub struct HistoryOutput {
    /// The history column, e.g. `reaction_block.x1.x_n`.
    pub column: String,
    /// When [s]; `None`: the last recorded row.
    pub at: Option<f64>,
}

impl HistoryOutput {
    /// `COLUMN` or `COLUMN@TIME` (TIME in seconds, finite and not negative).
    pub fn parse(token: &str) -> Result<Self> {
        let (column, at) = match token.split_once('@') {
            None => (token.trim(), None),
            Some((column, time)) => {
                let at = match time.trim().parse::<f64>() {
                    Ok(t) if t.is_finite() && t >= 0.0 => t,
                    _ => bail!(
                        "--output '{token}': the time after '@' must be a number of seconds ≥ 0, \
                         e.g. reaction_block.x1.x_n@0.1"
                    ),
                };
                (column.trim(), Some(at))
            }
        };
        if column.is_empty() {
            bail!("--output '{token}': the column name is empty");
        }
        Ok(Self {
            column: column.to_string(),
            at,
        })
    }

    /// The output's column in `sweep.csv`: the history column, with `_at_<TIME>s` when
    /// read at a time.
    pub fn name(&self) -> String {
        match self.at {
            None => self.column.clone(),
            Some(t) => format!("{}_at_{t}s", self.column),
        }
    }

    /// Its value from a history (`times` ascending, `values` the column): the last
    /// value, or the linear interpolation at `at` (`None` if the run did not reach it).
    pub fn value(&self, times: &[f64], values: &[f64]) -> Option<f64> {
        let Some(at) = self.at else {
            return values.last().copied();
        };
        let after = times.iter().position(|&t| t >= at)?;
        if after == 0 || times[after] == at {
            return (times[after] == at).then_some(values[after]);
        }
        let (t0, t1) = (times[after - 1], times[after]);
        let w = (at - t0) / (t1 - t0);
        Some(values[after - 1] + w * (values[after] - values[after - 1]))
    }
}

/// The scene a study varies, and the outputs a sweep reads from its runs.
pub struct SceneStudy {
    path: PathBuf,
    scene: SceneFile,
    locator: Locator,
    /// The header of the scene's history, split.
    columns: Vec<String>,
    end_time: f64,
    outputs: Vec<HistoryOutput>,
}

/// What the commands that read a scene let it reach (`docs/scene-format.md`): its
/// plugins loaded, files outside its folder read.
#[derive(Debug, Clone, Copy, Default, clap::Args)]
pub struct SceneTrustArgs {
    /// Load the shared libraries the scene's materials name as `plugin` (loading one runs
    /// its code: only for plugins you trust).
    #[arg(long)]
    pub allow_plugins: bool,
    /// Let the scene name files (meshes, fibers, surfaces, plugins) outside its own folder.
    #[arg(long)]
    pub allow_outside_paths: bool,
}

impl SceneTrustArgs {
    /// The scene's permissions.
    pub fn trust(&self) -> Trust {
        Trust {
            plugins: if self.allow_plugins {
                PluginPolicy::Load
            } else {
                PluginPolicy::Refuse
            },
            outside_paths: self.allow_outside_paths,
        }
    }
}

impl SceneStudy {
    /// Read and check the scene at `path` (as `musclefem check` does) with the
    /// permissions `trust`, with every reaction column at the end as its outputs (none if
    /// it has no reaction).
    pub fn load(path: &Path, trust: Trust) -> Result<Self> {
        let (scene, locator) = read_scene_file(path)?;
        let locator = locator.with_trust(trust);
        let model = build_model(&scene, &locator, &mut MaterialLibrary::with_builtins())?;
        let header = model.history_columns().header(&model.analysis);
        let columns: Vec<String> = header.split(',').map(str::to_string).collect();
        let outputs = columns
            .iter()
            .filter(|c| c.starts_with("reaction_"))
            .map(|c| HistoryOutput {
                column: c.clone(),
                at: None,
            })
            .collect();
        Ok(Self {
            path: path.to_path_buf(),
            scene,
            locator,
            columns,
            end_time: model.analysis.end_time(),
            outputs,
        })
    }

    /// The study with the outputs `tokens` (`--output` values; none: the default of
    /// [`load`](Self::load)), each checked against the history's columns and the run's end.
    pub fn with_outputs(mut self, tokens: &[String]) -> Result<Self> {
        if !tokens.is_empty() {
            self.outputs = tokens
                .iter()
                .map(|t| HistoryOutput::parse(t))
                .collect::<Result<_>>()?;
        }
        if self.outputs.is_empty() {
            bail!(
                "{}: the scene has no reaction to report; name a history column with --output \
                 (its columns: {})",
                self.path.display(),
                self.columns.join(", ")
            );
        }
        for output in &self.outputs {
            self.check_column(&output.column, "--output")?;
            if let Some(at) = output.at
                && at > self.end_time
            {
                bail!(
                    "--output {}: the scene ends at {} s, before {at} s",
                    output.column,
                    self.end_time
                );
            }
        }
        Ok(self)
    }

    /// An error unless the scene's history has the column `name` (`flag` names the option
    /// that asked for it).
    pub fn check_column(&self, name: &str, flag: &str) -> Result<()> {
        if !self.columns.iter().any(|c| c == name) {
            bail!(
                "{flag} {name}: {} writes no history column '{name}' (its columns: {})",
                self.path.display(),
                self.columns.join(", ")
            );
        }
        Ok(())
    }

    /// The sweep's outputs, in the order of their columns in `sweep.csv`.
    pub fn outputs(&self) -> &[HistoryOutput] {
        &self.outputs
    }

    /// The scene's file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// When the scene's step ends [s].
    pub fn end_time(&self) -> f64 {
        self.end_time
    }

    /// Every name must name one parameter of one of the scene's materials.
    pub fn check_names<'a>(&self, names: impl IntoIterator<Item = &'a str>) -> Result<()> {
        for name in names {
            self.parameter(name)?;
        }
        Ok(())
    }

    /// The parameter a name stands for (see the module documentation): its table entry,
    /// and the value the scene gives it (`None`: the model's default).
    pub fn parameter(&self, name: &str) -> Result<(ParameterSpec, Option<f64>)> {
        let (index, key) = self.resolve(name)?;
        let entry = &self.scene.materials[index];
        let mut library = MaterialLibrary::with_builtins();
        if let Some(plugin) = &entry.plugin {
            let directory = self.path.parent().unwrap_or(Path::new("."));
            library.load_plugin(&directory.join(plugin.get_ref()))?;
        }
        let info = library.info(entry.model.get_ref())?;
        let Some(spec) = info.parameters.iter().find(|p| p.name == key).cloned() else {
            let known: Vec<&str> = info.parameters.iter().map(|p| p.name.as_ref()).collect();
            bail!(
                "{name}: material '{}' ({}) has no parameter '{key}' (it has {})",
                entry.name.get_ref(),
                info.name,
                known.join(", ")
            );
        };
        let given = entry
            .parameters
            .as_ref()
            .and_then(|p| p.get_ref().get(&key).copied());
        Ok((spec, given))
    }

    /// (index of the material entry, parameter key) of a name.
    fn resolve(&self, name: &str) -> Result<(usize, String)> {
        let materials = &self.scene.materials;
        let local_names: Vec<&str> = materials
            .iter()
            .map(|m| m.name.get_ref().as_str())
            .collect();
        match name.split_once('.') {
            Some((material, key)) => {
                let index = local_names
                    .iter()
                    .position(|&n| n == material)
                    .with_context(|| {
                        format!(
                            "{name}: {} has no material '{material}' (it has {})",
                            self.path.display(),
                            local_names.join(", ")
                        )
                    })?;
                Ok((index, key.to_string()))
            }
            None if materials.len() == 1 => Ok((0, name.to_string())),
            None => bail!(
                "{name}: {} has {} materials ({}); name the one meant as MATERIAL.{name}",
                self.path.display(),
                materials.len(),
                local_names.join(", ")
            ),
        }
    }

    /// The scene with `names[i] = values[i]`, run to its end: its history.
    pub fn history(&self, names: &[String], values: &[f64]) -> Result<SceneHistory> {
        let mut scene = self.scene.clone();
        for (name, &value) in names.iter().zip(values) {
            let (index, key) = self.resolve(name)?;
            scene.materials[index].set_parameter(&key, value);
        }
        let model = build_model(&scene, &self.locator, &mut MaterialLibrary::with_builtins())?;
        let columns = model.history_columns();
        let mut history = History {
            columns: &columns,
            path: &self.path,
            rows: Vec::new(),
            error: None,
        };
        let outcome = model.run(&mut history)?;
        if let Some(error) = history.error {
            return Err(error.into());
        }
        Ok(SceneHistory {
            header: columns
                .header(&model.analysis)
                .split(',')
                .map(str::to_string)
                .collect(),
            rows: history.rows,
            steps: outcome.steps(),
        })
    }

    /// The scene with `names[i] = values[i]`, run to its end: the run's steps and the
    /// value of each output.
    pub fn run(&self, names: &[String], values: &[f64]) -> Result<(usize, Vec<Option<f64>>)> {
        let history = self.history(names, values)?;
        let times = history.column("time_s")?;
        let outputs = self
            .outputs
            .iter()
            .map(|o| Ok(o.value(&times, &history.column(&o.column)?)))
            .collect::<Result<_>>()?;
        Ok((history.steps, outputs))
    }
}

/// The history of one run of a scene.
pub struct SceneHistory {
    pub header: Vec<String>,
    pub rows: Vec<Vec<f64>>,
    /// Solver steps or increments.
    pub steps: usize,
}

impl SceneHistory {
    /// The values of column `name`, row by row.
    pub fn column(&self, name: &str) -> Result<Vec<f64>> {
        let k = self
            .header
            .iter()
            .position(|c| c == name)
            .with_context(|| format!("the history has no column '{name}'"))?;
        Ok(self.rows.iter().map(|row| row[k]).collect())
    }
}

/// The rows of the history a run would write.
struct History<'a> {
    columns: &'a musclefem_io::output::HistoryColumns,
    path: &'a Path,
    rows: Vec<Vec<f64>>,
    error: Option<musclefem_io::OutputError>,
}

impl Observer for History<'_> {
    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        match self.columns.record_row(record, snapshot, self.path) {
            Ok(row) => {
                self.rows.push(row);
                ControlFlow::Continue(())
            }
            Err(error) => {
                self.error = Some(error);
                ControlFlow::Break(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples")
            .join(name)
    }

    #[test]
    fn outputs_parse_and_interpolate() {
        let end = HistoryOutput::parse("reaction_a_n").unwrap();
        assert_eq!(end.at, None);
        assert_eq!(end.name(), "reaction_a_n");
        let times = [0.0, 0.1, 0.2];
        let values = [0.0, 10.0, 30.0];
        assert_eq!(end.value(&times, &values), Some(30.0));
        let mid = HistoryOutput::parse("reaction_a_n@0.15").unwrap();
        assert_eq!(mid.name(), "reaction_a_n_at_0.15s");
        approx::assert_relative_eq!(mid.value(&times, &values).unwrap(), 20.0);
        assert_eq!(
            HistoryOutput::parse("r@0.1")
                .unwrap()
                .value(&times, &values),
            Some(10.0)
        );
        assert_eq!(
            HistoryOutput::parse("r@0.3")
                .unwrap()
                .value(&times, &values),
            None
        );
        for (token, expected) in [("@1", "empty"), ("r@-1", "≥ 0"), ("r@x", "seconds")] {
            let error = HistoryOutput::parse(token).unwrap_err().to_string();
            assert!(error.contains(expected), "{error}");
        }
    }

    #[test]
    fn names_and_columns_are_checked_against_the_scene() {
        let path = example("hill_block_isometric.toml");
        let study = SceneStudy::load(&path, Trust::default()).unwrap();
        // Every reaction at the end by default: the four held faces.
        let names: Vec<String> = study.outputs().iter().map(HistoryOutput::name).collect();
        assert_eq!(names.len(), 4, "{names:?}");
        assert!(names.iter().all(|n| n.starts_with("reaction_block.")));
        study.check_names(["sigma0", "muscle.b"]).unwrap();
        let (spec, given) = study.parameter("n2").unwrap();
        assert_eq!((spec.name.as_ref(), given), ("n2", Some(1.0)));
        assert_eq!(study.parameter("b").unwrap().1, None);
        for (name, expected) in [
            ("sigm0", "no parameter 'sigm0'"),
            ("bone.b", "no material 'bone'"),
        ] {
            let error = study.check_names([name]).unwrap_err().to_string();
            assert!(error.contains(expected), "{error}");
        }
        let error = SceneStudy::load(&path, Trust::default())
            .unwrap()
            .with_outputs(&["reaction_nothing_n".into()])
            .err()
            .unwrap()
            .to_string();
        assert!(error.contains("no history column"), "{error}");
        assert!(error.contains("reaction_block.x1.x_n"), "{error}");
        let late = SceneStudy::load(&path, Trust::default())
            .unwrap()
            .with_outputs(&["reaction_block.x1.x_n@1".into()])
            .err()
            .unwrap()
            .to_string();
        assert!(late.contains("ends at 0.15 s"), "{late}");
    }

    #[test]
    fn the_isometric_force_scales_with_the_maximum_isometric_stress() {
        // The block of the example held isometric, activated fully: its reaction on x1 is
        // σ_iso × A, σ_iso ≈ σ0 f_L(λ_f) with the fiber a little shorter than optimal as
        // the series element stretches (the example's 692.8 kPa at σ0 = 700 kPa).
        let study = SceneStudy::load(&example("hill_block_isometric.toml"), Trust::default())
            .unwrap()
            .with_outputs(&["reaction_block.x1.x_n".into()])
            .unwrap();
        let area = 5e-3 * 5e-3;
        let names = ["sigma0".to_string()];
        let (_, at_700) = study.run(&names, &[7e5]).unwrap();
        let (steps, at_600) = study.run(&names, &[6e5]).unwrap();
        assert!(steps > 100, "{steps}");
        let (f700, f600) = (at_700[0].unwrap(), at_600[0].unwrap());
        approx::assert_relative_eq!(f700.abs() / area, 692.8e3, max_relative = 0.01);
        approx::assert_relative_eq!(f600 / f700, 6.0 / 7.0, max_relative = 0.01);
    }
}
