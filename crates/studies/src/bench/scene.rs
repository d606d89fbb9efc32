//! A scene of the user's own (`musclefem bench --scene FILE`): its step settings measured
//! against a reference run of the same scene, so that `musclefem run SCENE --tolerance`
//! can pick the cheapest. The mesh and the elements are the scene's: only the solver and
//! the step change.
//!
//! - **Scene run implicitly** (N increments, or duration / output interval): the matrix
//!   is implicit with N and 2N increments (the scene's dynamics kept), and explicit at
//!   safety 0.9 with mass scaling to T/1000 and T/100 and, when it takes at most
//!   [`MAX_EXPLICIT_STEPS`] steps by the estimate below, the physical mass. The reference
//!   is implicit with 4N increments.
//! - **Scene run explicitly** (a fast motion: inertia is the physics): the matrix is
//!   explicit at safety 0.9 with the physical mass, and implicit with Newmark's inertia at
//!   N and 2N increments (N = duration / output interval). The reference is explicit at
//!   safety 0.45.
//!
//! Response: every nodal displacement at the end [m]; the error is
//! max_i |u_i − u_i^ref| / max_i |u_i^ref| (see [`super::reference`]).
//!
//! The explicit step count is estimated as T c / (0.9 h) with c the fastest small-strain
//! dilatational wave speed of the parts and h the smallest element's V^(1/3): the runs too
//! long by it are left out, and named in the log.

use std::ops::ControlFlow;
use std::path::Path;

use anyhow::{Context, Result, bail};
use nalgebra::Vector3;

use musclefem_core::mesh::ElementRef;
use musclefem_core::solver::explicit::ExplicitSettings;
use musclefem_core::solver::implicit::ImplicitSettings;
use musclefem_core::solver::{Analysis, Observer, Record, Snapshot};
use musclefem_io::scene::{Model, Trust, fastest_wave_speed, load_scene_trusting};
use musclefem_materials::MaterialLibrary;

use super::Response;
use super::method::StepSetting;
use crate::inertia::{inertia_warning, largest_kinetic_to_internal};

/// The `error_metric` column.
pub const ERROR_METRIC: &str = "max_nodal_displacement_error_at_the_end";

/// Explicit runs estimated to take more steps than this are left out of the matrix.
pub const MAX_EXPLICIT_STEPS: f64 = 1e5;

/// The safety factor of the explicit runs of the matrix (the reference of an explicit
/// scene takes half of it).
pub const SCENE_SAFETY: f64 = 0.9;

/// A scene and its name (the file's stem: the `problem` column).
pub struct SceneProblem {
    pub name: String,
    pub model: Model,
}

impl SceneProblem {
    /// The scene at `path`, checked as `musclefem run` checks it, with the permissions
    /// `trust`.
    pub fn load(path: &Path, trust: Trust) -> Result<Self> {
        let name = scene_name(path)?;
        let model = load_scene_trusting(path, &mut MaterialLibrary::with_builtins(), trust)?;
        Ok(SceneProblem { name, model })
    }

    /// Duration of the scene's step [s].
    pub fn duration(&self) -> f64 {
        match &self.model.analysis {
            Analysis::Explicit(s) => s.end_time,
            Analysis::Implicit(s) => s.end_time,
        }
    }

    /// N: the scene's implicit increments, or duration / output interval.
    fn base_increments(&self) -> usize {
        match &self.model.analysis {
            Analysis::Implicit(s) => s.increments.max(1),
            Analysis::Explicit(_) => {
                ((self.duration() / self.model.output_interval).round() as usize).max(1)
            }
        }
    }

    fn implicit(&self, multiple: usize) -> StepSetting {
        StepSetting::Implicit {
            increment: self.duration() / (multiple * self.base_increments()) as f64,
        }
    }

    /// The runs of the matrix, and the ones left out with the reason.
    pub fn matrix(&self) -> (Vec<StepSetting>, Vec<String>) {
        let explicit = |mass_scaling| StepSetting::Explicit {
            mass_scaling,
            safety: SCENE_SAFETY,
        };
        let mut left_out = Vec::new();
        let mut methods = vec![self.implicit(1), self.implicit(2)];
        if let Analysis::Implicit(_) = self.model.analysis {
            let duration = self.duration();
            methods.extend([
                explicit(Some(duration / 1000.0)),
                explicit(Some(duration / 100.0)),
            ]);
            match self.explicit_steps() {
                Some(steps) if steps <= MAX_EXPLICIT_STEPS => methods.push(explicit(None)),
                Some(steps) => left_out.push(format!(
                    "explicit with the physical mass: about {steps:.1e} steps (more than \
                     {MAX_EXPLICIT_STEPS:.0e})"
                )),
                None => left_out.push(
                    "explicit with the physical mass: no part's material has a small-strain \
                     stiffness to estimate its step by"
                        .to_string(),
                ),
            }
        } else {
            methods.insert(0, explicit(None));
        }
        (methods, left_out)
    }

    /// The reference run (see the module's documentation).
    pub fn reference(&self) -> StepSetting {
        match self.model.analysis {
            Analysis::Implicit(_) => self.implicit(4),
            Analysis::Explicit(_) => StepSetting::Explicit {
                mass_scaling: None,
                safety: 0.5 * SCENE_SAFETY,
            },
        }
    }

    /// T c / (0.9 h): the explicit steps with the physical mass, estimated.
    fn explicit_steps(&self) -> Option<f64> {
        let speed = fastest_wave_speed(&self.model.parts)?;
        let smallest = self.element_volumes().fold(f64::INFINITY, f64::min).cbrt();
        (smallest > 0.0).then(|| self.duration() * speed / (SCENE_SAFETY * smallest))
    }

    fn element_volumes(&self) -> impl Iterator<Item = f64> + '_ {
        let mesh = &self.model.mesh;
        mesh.blocks.iter().enumerate().flat_map(move |(b, block)| {
            (0..block.len()).map(move |e| {
                let element = ElementRef {
                    block: b as u32,
                    element: e as u32,
                };
                mesh.element_volume(element).unwrap_or(0.0)
            })
        })
    }

    /// The mean element size (V / N)^(1/3) [m].
    pub fn mean_element_size(&self) -> f64 {
        let (volume, count) = self
            .element_volumes()
            .fold((0.0, 0usize), |(v, n), x| (v + x, n + 1));
        (volume / count.max(1) as f64).cbrt()
    }

    /// The parts' elements as named in scene files, `+`-joined when they differ.
    pub fn element(&self) -> String {
        let mut names: Vec<&str> = self
            .model
            .parts
            .iter()
            .map(|p| p.technology.name())
            .collect();
        names.dedup();
        names.join("+")
    }

    /// The scene's analysis with the step setting `step` (the duration, output interval
    /// and, implicitly, the scene's dynamics kept; an explicit scene's implicit runs keep
    /// its inertia with Newmark's rule).
    pub fn analysis(&self, step: StepSetting) -> Analysis {
        let duration = self.duration();
        match step {
            StepSetting::Implicit { increment } => {
                let increments = (duration / increment).round().max(1.0) as usize;
                let mut settings = ImplicitSettings::new(duration, increments).with_cutting();
                settings.dynamics = match &self.model.analysis {
                    Analysis::Implicit(s) => s.dynamics.clone(),
                    Analysis::Explicit(_) => Some(Default::default()),
                };
                Analysis::Implicit(settings)
            }
            StepSetting::Explicit {
                mass_scaling,
                safety,
            } => {
                let mut settings = match &self.model.analysis {
                    Analysis::Explicit(s) => s.clone(),
                    Analysis::Implicit(_) => ExplicitSettings::new(duration),
                };
                settings.safety_factor = safety;
                settings.mass_scaling_time_step = mass_scaling;
                settings.history_interval = self.model.output_interval;
                Analysis::Explicit(settings)
            }
        }
    }

    /// Run the scene with `step`: its displacements at the end.
    pub fn run(&self, step: StepSetting) -> Result<Response> {
        let model = &self.model;
        let mut end = EndState {
            from_time: 0.1 * self.duration(),
            time: 0.0,
            displacement: Vec::new(),
            kinetic_to_internal: 0.0,
        };
        let quasi_static = matches!(&model.analysis, Analysis::Implicit(s) if s.dynamics.is_none());
        model.run_with(&self.analysis(step), &mut end)?;
        let duration = self.duration();
        if (end.time - duration).abs() > 1e-9 * duration.max(1.0) {
            bail!(
                "the run ended at t = {} s, not at the scene's {duration} s",
                end.time
            );
        }
        Ok(Response {
            samples: end
                .displacement
                .iter()
                .flat_map(|u| [u.x, u.y, u.z])
                .collect(),
            // Inertia pollutes the answer only where the scene is quasi-static.
            warning: if quasi_static {
                inertia_warning(end.kinetic_to_internal)
            } else {
                None
            },
        })
    }
}

/// The name of the scene at `path` in a work–precision table: its file's stem (without
/// commas, which the table separates its columns by).
pub fn scene_name(path: &Path) -> Result<String> {
    path.file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty() && !s.contains(','))
        .map(str::to_string)
        .with_context(|| {
            format!(
                "{}: the scene's file name names its rows, and must have no comma",
                path.display()
            )
        })
}

/// The last recorded state of a run, and (explicit) the largest kinetic/internal energy
/// from a tenth of the run on.
struct EndState {
    /// From when the kinetic/internal energy ratio counts [s].
    from_time: f64,
    time: f64,
    displacement: Vec<Vector3<f64>>,
    kinetic_to_internal: f64,
}

impl EndState {
    fn keep(&mut self, time: f64, snapshot: &Snapshot) {
        self.time = time;
        self.displacement.clear();
        self.displacement.extend_from_slice(snapshot.displacement);
    }
}

impl Observer for EndState {
    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        self.keep(record.time(), snapshot);
        if let Record::Explicit(row) = record {
            let ratio = largest_kinetic_to_internal(std::slice::from_ref(*row), self.from_time);
            self.kinetic_to_internal = self.kinetic_to_internal.max(ratio);
        }
        ControlFlow::Continue(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example(name: &str) -> SceneProblem {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples")
            .join(name);
        SceneProblem::load(&path, Trust::default()).unwrap()
    }

    #[test]
    fn an_implicit_scene_is_refined_implicitly_and_tried_explicitly() {
        // 10 increments in 1 s, quasi-static.
        let scene = example("neo_hookean_cube_stretch.toml");
        assert_eq!(scene.name, "neo_hookean_cube_stretch");
        assert_eq!(scene.element(), "hex8-fbar");
        assert!((scene.mean_element_size() - 0.0025).abs() < 1e-12);
        assert_eq!(
            scene.reference(),
            StepSetting::Implicit { increment: 0.025 }
        );
        let (methods, left_out) = scene.matrix();
        let labels: Vec<String> = methods.iter().map(|m| m.label()).collect();
        assert_eq!(
            labels,
            [
                "increment=0.1s",
                "increment=0.05s",
                "mass_scaling=1e-3s;safety=0.9",
                "mass_scaling=1e-2s;safety=0.9",
                "no_mass_scaling;safety=0.9"
            ]
        );
        assert!(left_out.is_empty(), "{left_out:?}");
        let Analysis::Implicit(settings) = scene.analysis(methods[1]) else {
            panic!("implicit expected");
        };
        assert_eq!((settings.increments, settings.dynamics), (20, None));
        // The homogeneous hyperelastic cube does not depend on the increment.
        let reference = scene.run(scene.reference()).unwrap();
        let coarse = scene.run(methods[0]).unwrap();
        assert_eq!(reference.samples.len(), 3 * scene.model.mesh.node_count());
        assert!(super::super::reference::relative_error(&coarse, &reference) < 1e-9);
    }

    #[test]
    fn an_explicit_scene_keeps_its_inertia_in_the_implicit_runs() {
        let scene = example("hill_block_isometric.toml");
        assert_eq!(
            scene.reference(),
            StepSetting::Explicit {
                mass_scaling: None,
                safety: 0.45
            }
        );
        let (methods, _) = scene.matrix();
        assert_eq!(methods[0].label(), "no_mass_scaling;safety=0.9");
        let Analysis::Implicit(settings) = scene.analysis(methods[1]) else {
            panic!("implicit expected");
        };
        assert!(settings.dynamics.is_some());
    }
}
