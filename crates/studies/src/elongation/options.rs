//! The command-line choice of an elongation test's specimen, mesh, element and solver,
//! shared by `musclefem elongate` and the parametric commands (`musclefem sweep`,
//! `musclefem fit`).

use std::collections::BTreeMap;

use super::{Activation, DEFAULT_MESH_SIZE, ElementChoice, ElongationTest, Grips, Shape, Solver};

#[derive(Debug, Clone, clap::Args)]
pub struct TestOptions {
    /// Solver: implicit (quasi-static Newton, recommended for this slow motion) or
    /// explicit (central differences with mass scaling, the paper's method).
    #[arg(long, value_enum, default_value = "implicit")]
    pub solver: Solver,
    /// Element technology.
    #[arg(long, value_enum, default_value = "hex8-fbar")]
    pub element: ElementChoice,
    /// Target element edge length [mm].
    #[arg(long, value_name = "MM", default_value_t = 1e3 * DEFAULT_MESH_SIZE)]
    pub mesh_size: f64,
    /// Specimen: the 50 mm fusiform muscle (end diameter 9 mm, mid-belly 17.5 mm), or a
    /// cylinder of the mid-belly diameter (homogeneous deformation with sliding grips: a
    /// coarse mesh is then enough).
    #[arg(long, value_enum, default_value = "fusiform")]
    pub shape: Shape,
    /// Fixed grips clamp the end faces; sliding grips prescribe only their axial motion.
    #[arg(long, value_enum, default_value = "fixed")]
    pub grips: Grips,
    /// Implicit increment, or explicit mass-scaling target step [s] (defaults: 0.025 s
    /// implicit, 1e-5 s explicit). Checked before the run: positive, at most a fifth of
    /// the test (a negative value is read, then refused with the reason).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub time_step: Option<f64>,
}

impl TestOptions {
    /// The test of `mode` with these options and the Hill `parameters` overriding Table 1.
    pub fn test(&self, mode: Activation, parameters: BTreeMap<String, f64>) -> ElongationTest {
        ElongationTest {
            mode,
            solver: self.solver,
            element: self.element,
            mesh_size: 1e-3 * self.mesh_size,
            shape: self.shape,
            grips: self.grips,
            parameters,
            time_step: self.time_step,
            ..ElongationTest::recommended(mode)
        }
    }

    /// Whether every option has its default (none was given on the command line).
    pub fn are_defaults(&self) -> bool {
        #[derive(clap::Parser)]
        struct Defaults {
            #[command(flatten)]
            options: TestOptions,
        }
        let defaults = <Defaults as clap::Parser>::parse_from(["defaults"]).options;
        self.describe() == defaults.describe() && self.time_step.is_none()
    }

    /// One line for logs and chart titles, e.g. "fusiform, hex8-fbar, 4 mm, fixed grips,
    /// implicit".
    pub fn describe(&self) -> String {
        use clap::ValueEnum;
        let name = |v: Option<clap::builder::PossibleValue>| {
            v.map_or_else(String::new, |v| v.get_name().to_string())
        };
        format!(
            "{}, {}, {} mm, {} grips, {}",
            self.shape.name(),
            self.element.name(),
            musclefem_io::csv::format_number(self.mesh_size),
            name(self.grips.to_possible_value()),
            self.solver.name(),
        )
    }
}
