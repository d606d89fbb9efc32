//! An elongation test as a scene file: `musclefem elongate` writes `scene.toml` and the
//! specimen's mesh (`specimen.inp`) into its run directory and runs that scene, so
//! `musclefem run DIR/scene.toml` reproduces its `history.csv` byte for byte, and the
//! scene can be edited, swept or fitted like any other.
//!
//! The scene says what [`super::setup::setup`] builds in memory: one part `specimen` of
//! the Hill muscle (the test's parameters and the mode's activation), fibers along the
//! axis z, the grips as displacement conditions on the node sets `origin` and
//! `insertion` (and, for sliding grips, the single nodes `origin_axis` and
//! `origin_edge`), the pulled end's amplitude `pull` in metres, and the solver settings;
//! The tests below run both from a scene read back from its files and in memory: the
//! reactions agree bit for bit, so `elongate`, `sweep` and `fit` give the same numbers.

use std::fmt::Write as _;
use std::time::Duration;

use anyhow::{Context, Result};

use musclefem_core::solver::Outcome;

use musclefem_io::mesh_export::abaqus_text;

use super::ElongationTest;
use super::protocol::Grips;
use super::run::ElongationRun;
use super::setup::{
    DEFAULT_IMPLICIT_INCREMENT, DEFAULT_MASS_SCALING_STEP, MUSCLE_DENSITY, check_time_step,
    sliding_grip_nodes,
};
use super::specimen::{SpecimenMesh, specimen_mesh};
use crate::solver::Solver;

/// File name of the specimen mesh beside the scene.
pub const SPECIMEN_MESH_FILE: &str = "specimen.inp";
/// The scene's part (its reaction columns are `reaction_specimen.<set>.<c>_n`).
pub const SPECIMEN_PART: &str = "specimen";

/// The scene of one test: its text, the mesh file's text, and the specimen (its length
/// and reference area turn the history into the curve).
pub struct ElongationScene {
    /// `scene.toml`.
    pub scene: String,
    /// [`SPECIMEN_MESH_FILE`]: the specimen mesh as Abaqus text.
    pub mesh: String,
    pub specimen: SpecimenMesh,
}

/// The scene of `test` (frames every `test.frame_interval`; none for 0).
pub fn elongation_scene(test: &ElongationTest) -> Result<ElongationScene> {
    check_time_step(test)?;
    let mut specimen = specimen_mesh(test.shape, test.element, test.mesh_size)?;
    if test.grips == Grips::Sliding {
        let (axis, edge) = sliding_grip_nodes(&specimen.mesh)?;
        let sets = &mut specimen.mesh.node_sets;
        sets.insert("origin_axis".to_string(), vec![axis]);
        sets.insert("origin_edge".to_string(), vec![edge]);
    }
    let description = format!("musclefem elongate: {}", test.label());
    let mesh = abaqus_text(&specimen.mesh, &description);
    let mut scene = format!(
        "# {description}\n# Written by `musclefem elongate`; `musclefem run` reruns it.\n\
         schema_version = 1\ndescription = {}\n",
        quoted(&description)
    );
    write_material(&mut scene, test);
    let _ = write!(
        scene,
        "\n[[parts]]\nname = \"{SPECIMEN_PART}\"\nmaterial = \"muscle\"\nelement = \"{}\"\n\
         density = {}\nmesh = {{ file = \"{SPECIMEN_MESH_FILE}\", block = \"{}\" }}\n\
         fibers = {{ direction = [0.0, 0.0, 1.0] }}\n",
        test.element.name(),
        number(MUSCLE_DENSITY),
        specimen.mesh.blocks[0].name,
    );
    let knots: Vec<String> = test
        .mode
        .pulled_end_knots()
        .iter()
        .map(|&(t, u)| format!("[{}, {}]", number(t), number(u)))
        .collect();
    let _ = write!(
        scene,
        "\n# The pulled end's displacement [m] against time [s] (seed §2.2).\n\
         [[amplitudes]]\nname = \"pull\"\npoints = [{}]\n",
        knots.join(", ")
    );
    write_grips(&mut scene, test.grips);
    write_step(&mut scene, test);
    Ok(ElongationScene {
        scene,
        mesh,
        specimen,
    })
}

/// `[[materials]]`: the Hill muscle with the test's parameters and the mode's activation.
fn write_material(scene: &mut String, test: &ElongationTest) {
    let mut parameters = test.parameters.clone();
    for (name, value) in test.mode.activation_parameters() {
        parameters.insert(name.to_string(), value);
    }
    let entries: Vec<String> = parameters
        .iter()
        .map(|(name, value)| format!("{name} = {}", number(*value)))
        .collect();
    let _ = write!(
        scene,
        "\n[[materials]]\nname = \"muscle\"\nmodel = \"hill\"\nparameters = {{ {} }}\n",
        entries.join(", ")
    );
}

/// `[[displacements]]`: the pulled end first (its reaction is the test's force), then
/// what holds the ends (see [`super::setup`]).
fn write_grips(scene: &mut String, grips: Grips) {
    let mut condition = |nodes: &str, components: &str, pulled: bool| {
        let pull = if pulled {
            "value = 1.0\namplitude = \"pull\"\n"
        } else {
            ""
        };
        let _ = write!(
            scene,
            "\n[[displacements]]\npart = \"{SPECIMEN_PART}\"\nnodes = \"{nodes}\"\n\
             components = [{components}]\n{pull}"
        );
    };
    condition("insertion", "\"z\"", true);
    condition("origin", "\"z\"", false);
    match grips {
        Grips::Fixed => {
            condition("origin", "\"x\", \"y\"", false);
            condition("insertion", "\"x\", \"y\"", false);
        }
        Grips::Sliding => {
            condition("origin_axis", "\"x\", \"y\"", false);
            condition("origin_edge", "\"y\"", false);
        }
    }
}

/// `[step]` and `[output]`: the solver's settings as [`super::setup`] makes them.
fn write_step(scene: &mut String, test: &ElongationTest) {
    let duration = test.mode.duration();
    let _ = write!(
        scene,
        "\n[step]\nsolver = \"{}\"\nduration = {}\noutput_interval = {}\n",
        test.solver.name(),
        number(duration),
        number(test.output_interval)
    );
    match test.solver {
        Solver::Implicit => {
            let increment = test.time_step.unwrap_or(DEFAULT_IMPLICIT_INCREMENT);
            let increments = (duration / increment).round().max(1.0) as usize;
            let _ = write!(
                scene,
                "\n[step.implicit]\nincrements = {increments}\nstep_cutting = true\n"
            );
        }
        Solver::Explicit => {
            let step = test.time_step.unwrap_or(DEFAULT_MASS_SCALING_STEP);
            let _ = write!(
                scene,
                "\n[step.explicit]\nmass_scaling_time_step = {}\n",
                number(step)
            );
        }
    }
    let _ = write!(
        scene,
        "\n[output]\nframes = {}\nframe_interval = {}\n",
        test.frame_interval > 0.0,
        number(test.checkpoint_interval())
    );
}

/// A test's result from the `history.csv` its scene run wrote (`names` and `columns` as
/// [`musclefem_io::csv::read_columns`] reads them): the curve from the time and the
/// pulled end's reaction, the steps, the Newton iterations (implicit) or the largest
/// kinetic / internal energy during the pull (explicit), and the added mass fraction
/// when the run's `outcome` is at hand (not for a test completed by an earlier process).
pub fn run_from_history(
    test: &ElongationTest,
    specimen: &SpecimenMesh,
    (names, columns): (&[String], &[Vec<f64>]),
    outcome: Option<&Outcome>,
    solve_time: Duration,
) -> Result<ElongationRun> {
    let column = |name: &str| -> Result<&[f64]> {
        names
            .iter()
            .position(|n| n == name)
            .map(|i| columns[i].as_slice())
            .with_context(|| format!("the test's history has no column '{name}'"))
    };
    let time = column("time_s")?;
    let force = column(&format!("reaction_{SPECIMEN_PART}.insertion.z_n"))?;
    let curve = specimen
        .curve_scale(test.mode)
        .curve(time.iter().copied().zip(force.iter().copied()));
    let hold = test.mode.hold();
    let (newton_iterations, kinetic_to_internal) = match test.solver {
        Solver::Implicit => {
            let iterations = column("newton_iterations")?.iter().sum::<f64>() as usize;
            (Some(iterations), None)
        }
        Solver::Explicit => {
            let kinetic = column("kinetic_energy_j")?;
            let internal = column("internal_energy_j")?;
            let ratio = (0..time.len())
                .filter(|&i| time[i] > hold && internal[i] > 0.0)
                .map(|i| kinetic[i] / internal[i])
                .fold(0.0, f64::max);
            (None, Some(ratio))
        }
    };
    let (steps, added_mass_fraction) = match outcome {
        Some(Outcome::Explicit(result)) => (result.steps, Some(result.added_mass_fraction)),
        Some(outcome) => (outcome.steps(), None),
        None => (time.len(), None),
    };
    Ok(ElongationRun {
        curve,
        elements: specimen.mesh.element_count(),
        nodes: specimen.mesh.node_count(),
        solve_time,
        steps,
        newton_iterations,
        kinetic_to_internal,
        added_mass_fraction,
    })
}

/// A TOML float that reads back to the same `f64` (`{:?}` is Rust's shortest round-trip
/// form; an integral value keeps its `.0`).
fn number(value: f64) -> String {
    format!("{value:?}")
}

/// A TOML basic string.
fn quoted(text: &str) -> String {
    format!("\"{}\"", text.replace('\\', "\\\\").replace('"', "\\\""))
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;
    use std::ops::ControlFlow;

    use musclefem_core::solver::{Observer, Record, Snapshot};
    use musclefem_io::output::{FrameInstants, FrameSchedule};
    use musclefem_io::scene::load_scene;
    use musclefem_materials::MaterialLibrary;

    use super::*;
    use crate::elongation::run::{ElongationWatcher, run_elongation};
    use crate::elongation::{Activation, CurvePoint, ElementChoice, Shape};

    /// (time [s], pulled end's reaction [N]) of every recorded row.
    #[derive(Default)]
    struct Rows(Vec<(f64, f64)>);

    /// [`Rows`] of a scene run that asks for a checkpoint where `musclefem run` takes
    /// one (at the frame instants), as the in-memory test does.
    struct SceneRows {
        rows: Rows,
        frames: FrameInstants,
    }

    impl Observer for SceneRows {
        fn start(&mut self, snapshot: &Snapshot) -> ControlFlow<()> {
            self.frames.reached(snapshot.time);
            ControlFlow::Continue(())
        }

        fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
            self.frames.reached(snapshot.time);
            self.rows.0.push((record.time(), record.reactions()[0]));
            ControlFlow::Continue(())
        }

        fn wants_checkpoint(&mut self) -> bool {
            self.frames.take_due()
        }
    }

    impl ElongationWatcher for Rows {
        fn point(&mut self, _point: &CurvePoint, _snapshot: &Snapshot) -> ControlFlow<()> {
            ControlFlow::Continue(())
        }
        fn history_row(&mut self, record: &Record) {
            self.0.push((record.time(), record.reactions()[0]));
        }
    }

    /// The scene of `test`, written to a folder of its own and read back, runs to the
    /// same reactions as the in-memory test, bit for bit.
    fn assert_scene_runs_as_the_test(test: &ElongationTest, name: &str) {
        let directory = std::env::temp_dir().join(format!(
            "musclefem-elongation-scene-{name}-{}",
            std::process::id()
        ));
        std::fs::create_dir_all(&directory).unwrap();
        let scene = elongation_scene(test).unwrap();
        std::fs::write(directory.join("scene.toml"), &scene.scene).unwrap();
        std::fs::write(directory.join(SPECIMEN_MESH_FILE), &scene.mesh).unwrap();
        let model = load_scene(
            &directory.join("scene.toml"),
            &mut MaterialLibrary::with_builtins(),
        )
        .unwrap_or_else(|e| panic!("{e}\n{}", scene.scene));
        std::fs::remove_dir_all(&directory).unwrap();
        let mut from_scene = SceneRows {
            rows: Rows::default(),
            frames: FrameInstants::new(FrameSchedule::new(
                model.frame_interval,
                model.analysis.end_time(),
                &[],
            )),
        };
        model.run(&mut from_scene).unwrap();
        let from_scene = from_scene.rows;
        let mut in_memory = Rows::default();
        run_elongation(test, &mut in_memory).unwrap();
        assert!(
            from_scene.0.len() > 4,
            "{name}: {} rows",
            from_scene.0.len()
        );
        assert_eq!(from_scene.0, in_memory.0, "{name}");
    }

    #[test]
    fn a_passive_implicit_test_with_sliding_grips_runs_the_same_from_its_scene() {
        let test = ElongationTest {
            shape: Shape::Cylinder,
            grips: Grips::Sliding,
            mesh_size: 0.00875,
            time_step: Some(0.41),
            frame_interval: 0.5,
            parameters: BTreeMap::from([("sigma0".to_string(), 3e5), ("b".to_string(), 12.5)]),
            ..ElongationTest::recommended(Activation::Passive)
        };
        assert_scene_runs_as_the_test(&test, "implicit-sliding");
    }

    #[test]
    fn an_active_explicit_test_with_fixed_grips_runs_the_same_from_its_scene() {
        let test = ElongationTest {
            solver: Solver::Explicit,
            element: ElementChoice::Hex8OnePoint,
            shape: Shape::Cylinder,
            mesh_size: 0.00875,
            time_step: Some(2e-4),
            output_interval: 0.1,
            ..ElongationTest::recommended(Activation::Active)
        };
        assert_scene_runs_as_the_test(&test, "explicit-fixed");
    }

    #[test]
    fn numbers_read_back_to_the_same_bits() {
        for value in [0.1, 1.0 / 3.0, 5e-9, 7e5, 1060.0, -0.0, 2.05, 1e-300] {
            let read: f64 = number(value).parse().unwrap();
            assert_eq!(read.to_bits(), value.to_bits(), "{value}");
        }
        assert_eq!(quoted("a \"b\" \\c"), "\"a \\\"b\\\" \\\\c\"");
    }
}
