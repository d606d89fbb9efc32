//! The neo-Hookean cube: a 1 cm cube (μ = 10 kPa, K = 2/D = 100 kPa, ρ = 1000 kg/m³)
//! clamped on its face x = 0, its face x = 1 cm clamped laterally and pulled 5 mm along x
//! in 1 s (stretch 1.5). The clamps make the deformation non-homogeneous (the faces
//! cannot contract), so the reaction force depends on the mesh and the element.
//!
//! Response: the reaction force on the pulled face at t = 0.25, 0.5, 0.75, 1 s [N],
//! linear between the solver's recorded instants.

use std::ops::ControlFlow;
use std::path::Path;

use anyhow::{Context, Result, bail};

use musclefem_core::solver::explicit::ExplicitSettings;
use musclefem_core::solver::implicit::ImplicitSettings;
use musclefem_core::solver::{Analysis, Observer, Problem, Record, Snapshot, run};
use musclefem_io::scene::{Model, build_model, parse_scene};
use musclefem_materials::MaterialLibrary;

use super::Response;
use super::method::{Method, StepSetting};
use super::reference::sample_at;
use crate::inertia::{inertia_warning, largest_kinetic_to_internal};

/// Edge of the cube [m].
pub const CUBE_EDGE: f64 = 0.01;
/// Duration of the pull [s].
pub const PULL_DURATION: f64 = 1.0;
/// Instants at which the reaction force is compared [s].
pub const SAMPLE_TIMES: [f64; 4] = [0.25, 0.5, 0.75, 1.0];
/// The `error_metric` column.
pub const ERROR_METRIC: &str = "max_relative_reaction_force_error_at_t_0.25_0.5_0.75_1s";

/// Compressibility D = 2/K of the cube's neo-Hookean material [1/Pa] (K = 100 kPa,
/// μ = 10 kPa: ν = 0.43).
pub const CUBE_COMPRESSIBILITY: f64 = 2e-5;

/// Pull of the face x = 1 cm along x [m] (stretch 1.5).
pub const CUBE_PULL: f64 = 0.005;

/// A clamped neo-Hookean cube (μ = 10 kPa, ρ = 1000 kg/m³, edge [`CUBE_EDGE`]): the bench's,
/// or a variant for the stability tests.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubeScene<'a> {
    /// Scene-file element name, e.g. "hex8-fbar".
    pub element: &'a str,
    /// Elements per edge.
    pub divisions: usize,
    /// Compressibility D = 2/K [1/Pa].
    pub compressibility: f64,
    /// Displacement of the face x = 1 cm along x at the end [m] (negative compresses).
    pub pull: f64,
    /// Duration of the linear ramp of the pull [s].
    pub duration: f64,
}

impl<'a> CubeScene<'a> {
    /// The bench's cube: [`CUBE_COMPRESSIBILITY`], [`CUBE_PULL`] in [`PULL_DURATION`].
    pub fn bench(element: &'a str, divisions: usize) -> Self {
        CubeScene {
            element,
            divisions,
            compressibility: CUBE_COMPRESSIBILITY,
            pull: CUBE_PULL,
            duration: PULL_DURATION,
        }
    }

    /// Its model (quasi-static implicit analysis over the duration; a run picks its own
    /// settings).
    pub fn model(&self) -> Result<Model> {
        let text = cube_scene(self);
        let (scene, locator) =
            parse_scene(&text, Path::new("bench-cube.toml")).context("the cube's scene")?;
        build_model(&scene, &locator, &mut MaterialLibrary::with_builtins())
            .context("the cube's model")
    }
}

/// The scene file (see docs/scene-format.md) of `cube`.
pub fn cube_scene(cube: &CubeScene) -> String {
    let CubeScene {
        element,
        divisions,
        compressibility: d,
        pull,
        duration,
    } = *cube;
    format!(
        r#"schema_version = 1
description = "clamped neo-Hookean cube pulled to stretch 1.5 (bench)"

[[materials]]
name = "rubber"
model = "neo-hookean"
parameters = {{ mu = 1e4, D = {d:e} }}

[[parts]]
name = "cube"
material = "rubber"
element = "{element}"
density = 1000.0
mesh = {{ generator = "box", size = [{CUBE_EDGE}, {CUBE_EDGE}, {CUBE_EDGE}], divisions = [{divisions}, {divisions}, {divisions}] }}

[[amplitudes]]
name = "ramp"
points = [[0.0, 0.0], [{duration:e}, 1.0]]

[[displacements]]
part = "cube"
nodes = "x1"
components = ["x"]
value = {pull:e}
amplitude = "ramp"

[[displacements]]
part = "cube"
nodes = "x1"
components = ["y", "z"]

[[displacements]]
part = "cube"
nodes = "x0"
components = ["x", "y", "z"]

[step]
solver = "implicit"
duration = {duration:e}
"#
    )
}

/// Elements per edge for a target size `mesh_size` [m] (at least 1).
pub fn divisions(mesh_size: f64) -> usize {
    ((CUBE_EDGE / mesh_size).round() as usize).max(1)
}

/// Run `method` on the cube and return its reaction force at [`SAMPLE_TIMES`].
pub fn run_cube(method: &Method) -> Result<Response> {
    if !(method.mesh_size.is_finite() && method.mesh_size > 0.0) {
        bail!(
            "the cube's mesh size {} m must be positive",
            method.mesh_size
        );
    }
    let model = CubeScene::bench(method.element.name(), divisions(method.mesh_size)).model()?;
    let mut history = ReactionHistory {
        points: vec![(0.0, 0.0)],
        kinetic_to_internal: 0.0,
    };
    let analysis = match method.step {
        StepSetting::Implicit { increment } => {
            let increments = (PULL_DURATION / increment).round().max(1.0) as usize;
            Analysis::Implicit(ImplicitSettings::new(PULL_DURATION, increments).with_cutting())
        }
        StepSetting::Explicit {
            mass_scaling,
            safety,
        } => {
            let mut settings = ExplicitSettings::new(PULL_DURATION);
            settings.safety_factor = safety;
            settings.mass_scaling_time_step = mass_scaling;
            settings.history_interval = PULL_DURATION / 200.0;
            Analysis::Explicit(settings)
        }
    };
    let problem = Problem {
        mesh: &model.mesh,
        parts: &model.parts,
        loads: &model.loads,
        interactions: &mut [],
    };
    run(problem, &analysis, &mut history)?;
    Ok(Response {
        warning: inertia_warning(history.kinetic_to_internal),
        samples: SAMPLE_TIMES
            .iter()
            .map(|&t| sample_at(&history.points, t))
            .collect::<Option<_>>()
            .context("the run did not reach the end of the pull")?,
    })
}

/// (time [s], reaction force on the pulled face along x [N]) of each recorded instant, and
/// (explicit) the largest kinetic/internal energy from a tenth of the pull on.
struct ReactionHistory {
    points: Vec<(f64, f64)>,
    kinetic_to_internal: f64,
}

impl Observer for ReactionHistory {
    fn record(&mut self, record: &Record, _snapshot: &Snapshot) -> ControlFlow<()> {
        self.points.push((record.time(), record.reactions()[0]));
        if let Record::Explicit(row) = record {
            let ratio =
                largest_kinetic_to_internal(std::slice::from_ref(*row), 0.1 * PULL_DURATION);
            self.kinetic_to_internal = self.kinetic_to_internal.max(ratio);
        }
        ControlFlow::Continue(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elongation::ElementChoice;

    #[test]
    fn a_coarse_implicit_cube_pulls_back_with_a_growing_force() {
        let method = Method {
            element: ElementChoice::Hex8Fbar,
            mesh_size: 0.005,
            step: StepSetting::Implicit { increment: 0.25 },
        };
        let response = run_cube(&method).unwrap();
        assert_eq!(response.samples.len(), 4);
        assert!(response.samples.windows(2).all(|w| w[1] > w[0]));
        // Uniaxial stress of the free cube gives 1.00 N at stretch 1.5; the clamps stiffen
        // it, the coarse mesh cannot be far above.
        let end = response.samples[3];
        assert!(end > 1.0 && end < 2.0, "{end} N");
    }
}
