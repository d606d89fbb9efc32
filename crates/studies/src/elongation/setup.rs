//! What an elongation test hands the solvers: the specimen mesh, the Hill muscle part,
//! the grips as prescribed displacements, and the solver settings.

use std::collections::BTreeMap;

use anyhow::{Context, Result, bail};

use musclefem_core::mesh::Mesh;
use musclefem_core::solver::explicit::ExplicitSettings;
use musclefem_core::solver::implicit::{self, ImplicitSettings};
use musclefem_core::solver::{Loads, Part, PrescribedDisplacement};
use musclefem_io::csv::format_number;
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

use super::curve::CurveScale;
use super::protocol::{Activation, Grips};
use super::specimen::{Shape, SpecimenMesh, specimen_mesh};
use super::{ElongationTest, Solver};

/// Density of muscle [kg/m³].
pub const MUSCLE_DENSITY: f64 = 1060.0;

/// Everything one run needs.
pub struct Setup {
    pub specimen: SpecimenMesh,
    pub parts: Vec<Part>,
    /// The pulled end's axial condition comes first: its reaction is the test's force.
    pub loads: Loads,
    /// A name for each displacement condition, in order (`insertion.z`, `origin.z`, ...):
    /// the reaction columns of `history.csv`.
    pub displacement_names: Vec<String>,
    pub material: std::sync::Arc<dyn Material>,
}

impl Setup {
    /// What turns `test`'s rows into its curve (see [`CurveScale`]).
    pub fn curve_scale(&self, test: &ElongationTest) -> CurveScale {
        self.specimen.curve_scale(test.mode)
    }
}

/// The Hill muscle of `test`: its parameters, then the mode's activation.
pub fn muscle_material(test: &ElongationTest) -> Result<std::sync::Arc<dyn Material>> {
    let mut given: BTreeMap<String, f64> = test.parameters.clone();
    for (name, value) in test.mode.activation_parameters() {
        given.insert(name.to_string(), value);
    }
    MaterialLibrary::with_builtins()
        .create("hill", &given)
        .context("the Hill muscle's parameters")
}

/// Build the mesh, part and loads of `test`.
pub fn setup(test: &ElongationTest) -> Result<Setup> {
    if !(test.mesh_size.is_finite() && test.mesh_size > 0.0) {
        bail!("--mesh-size {} mm must be positive", 1e3 * test.mesh_size);
    }
    check_time_step(test)?;
    let specimen = specimen_mesh(test.shape, test.element, test.mesh_size)?;
    let material = muscle_material(test)?;
    let technology = test.element.technology(material.as_ref())?;
    let parts = vec![Part {
        block: 0,
        technology,
        material: material.clone(),
        density: MUSCLE_DENSITY,
    }];
    let (loads, displacement_names) = grips(&specimen.mesh, test.mode, test.grips)?;
    Ok(Setup {
        specimen,
        parts,
        displacement_names,
        loads,
        material,
    })
}

/// The end conditions: node set `insertion` pulled along z by the protocol, `origin` held.
/// Fixed grips hold every other component of both ends; sliding grips only the axial ones,
/// plus the lateral rigid-body motions: x and y of the origin node nearest the axis, and y
/// of the origin node farthest along +x (no rotation about the axis). With a name for each
/// condition: `<set>.<component>` (`origin_axis` and `origin_edge` for the two nodes of
/// the sliding grips).
fn grips(mesh: &Mesh, mode: Activation, grips: Grips) -> Result<(Loads, Vec<String>)> {
    let set = |name: &str| -> Result<Vec<u32>> {
        Ok(mesh
            .node_set(name)
            .with_context(|| format!("the specimen mesh has no node set '{name}'"))?
            .to_vec())
    };
    let held = || Amplitude::new(vec![(0.0, 0.0)]).expect("one knot");
    let mut names = Vec::new();
    let mut condition = |name: &str, nodes: Vec<u32>, dof: usize, amplitude: Amplitude| {
        names.push(format!("{name}.{}", ["x", "y", "z"][dof]));
        PrescribedDisplacement {
            nodes,
            dof,
            amplitude,
        }
    };
    let (origin, insertion) = (set("origin")?, set("insertion")?);
    let mut conditions = vec![
        condition("insertion", insertion.clone(), 2, mode.pulled_end()),
        condition("origin", origin.clone(), 2, held()),
    ];
    match grips {
        Grips::Fixed => {
            for dof in 0..2 {
                conditions.push(condition("origin", origin.clone(), dof, held()));
                conditions.push(condition("insertion", insertion.clone(), dof, held()));
            }
        }
        Grips::Sliding => {
            let (centre, on_x) = sliding_grip_nodes(mesh)?;
            conditions.push(condition("origin_axis", vec![centre], 0, held()));
            conditions.push(condition("origin_axis", vec![centre], 1, held()));
            conditions.push(condition("origin_edge", vec![on_x], 1, held()));
        }
    }
    Ok((Loads::from(conditions), names))
}

/// The two origin nodes that hold the sliding grips' lateral rigid-body motion: the one
/// nearest the axis (x and y held) and the one farthest along +x (y held).
pub fn sliding_grip_nodes(mesh: &Mesh) -> Result<(u32, u32)> {
    let origin = mesh
        .node_set("origin")
        .context("the specimen mesh has no node set 'origin'")?;
    let position = |n: &u32| mesh.nodes.position(*n as usize);
    let radius = |n: &u32| position(n).xy().norm();
    let along_x = |n: &u32| position(n).x - position(n).y.abs();
    let centre = *origin
        .iter()
        .min_by(|a, b| radius(a).total_cmp(&radius(b)))
        .context("the origin set is empty")?;
    let on_x = *origin
        .iter()
        .max_by(|a, b| along_x(a).total_cmp(&along_x(b)))
        .context("the origin set is empty")?;
    Ok((centre, on_x))
}

/// Default implicit increment [s]: resolves the activation rise (time constant 1/S =
/// 20 ms) during the hold and the pull's strain rate.
pub const DEFAULT_IMPLICIT_INCREMENT: f64 = 0.025;

/// Default target step of the explicit solver's mass scaling [s]. On the 4 mm fusiform it
/// adds 26 times the mass (the physical stable step is ≈ 2 µs), and the passive curve stays
/// within 0.7 % of the peak stress of the quasi-static implicit one; at 2e-5 s (107 times
/// the mass) the soft passive muscle rings by ±3 kPa (4 %).
pub const DEFAULT_MASS_SCALING_STEP: f64 = 1e-5;

/// Quasi-static implicit settings for `test`, with automatic step cutting.
pub fn implicit_settings(test: &ElongationTest) -> ImplicitSettings {
    let duration = test.mode.duration();
    let increment = test.time_step.unwrap_or(DEFAULT_IMPLICIT_INCREMENT);
    let increments = (duration / increment).round().max(1.0) as usize;
    ImplicitSettings::new(duration, increments).with_cutting()
}

/// The fewest increments (implicit) or mass-scaled steps (explicit) an elongation test
/// may take: the curve is read at 10 % and 20 % strain, so it needs a point at least every
/// 4 % of the passive pull's 20 % (one 2 s increment printed 63 kPa at 10 % for the
/// converged 29.5; the work–precision chart's coarsest setting, 0.4 s, takes 5).
pub const MIN_TEST_STEPS: f64 = 5.0;

/// Refuses a `--time-step` that is not a positive, finite number at most a tenth of the
/// test's duration, before anything runs (0 or 1e-300 ran forever, −0.1 or 1e9 took one
/// step and printed a wrong stress).
pub fn check_time_step(test: &ElongationTest) -> Result<()> {
    let Some(step) = test.time_step else {
        return Ok(());
    };
    let duration = test.mode.duration();
    if !(step.is_finite() && step > 0.0) {
        bail!(
            "--time-step {} s must be a positive number of seconds",
            format_number(step)
        );
    }
    if step > duration / MIN_TEST_STEPS {
        bail!(
            "--time-step {} s is more than a fifth of the {} test's {duration} s: the \
             curve needs at least {MIN_TEST_STEPS} steps",
            format_number(step),
            test.mode.name()
        );
    }
    if duration / step > implicit::MAX_INCREMENTS as f64 {
        bail!(
            "--time-step {} s would take {:.3e} steps over the {duration} s test, more \
             than the {} allowed",
            format_number(step),
            duration / step,
            implicit::MAX_INCREMENTS
        );
    }
    Ok(())
}

/// Explicit settings for `test`: mass scaling to the target step, a curve point every
/// `output_interval`.
pub fn explicit_settings(test: &ElongationTest) -> ExplicitSettings {
    let mut settings = ExplicitSettings::new(test.mode.duration());
    settings.mass_scaling_time_step = Some(test.time_step.unwrap_or(DEFAULT_MASS_SCALING_STEP));
    settings.history_interval = test.output_interval;
    settings
}

impl Solver {
    pub fn name(self) -> &'static str {
        match self {
            Solver::Explicit => "explicit",
            Solver::Implicit => "implicit",
        }
    }
}

impl Shape {
    pub fn name(self) -> &'static str {
        match self {
            Shape::Fusiform => "fusiform",
            Shape::Cylinder => "cylinder",
        }
    }
}
