//! The arguments of `musclefem knee` and the squat settings they choose.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::tolerance::setting_within;
use crate::elongation::{ElementChoice, Solver};
use crate::knee::Resolution;
use crate::knee::simulation::interactions::InterfaceLaw;
use crate::knee::simulation::visible_human::VISIBLE_HUMAN;
use crate::knee::simulation::{Activation, SquatSettings};

/// `--anatomy procedural`: the swept-solid knee.
pub const PROCEDURAL: &str = "procedural";

/// The knee a squat runs on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum KneeAnatomy {
    /// The Visible Human Female's segmented quadriceps (the default).
    VisibleHuman,
    /// Swept elliptical bellies with tendon blocks (`crate::knee::anatomy::muscles`).
    Procedural,
    /// Muscles from the files of a directory, on the procedural knee's bones.
    Files(PathBuf),
}

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("activation").args(["passive", "active", "both"])))]
pub struct KneeArgs {
    /// Only the passive squat.
    #[arg(long)]
    pub passive: bool,
    /// Only the active squat (50 % activation from 35° of flexion on, held to the end).
    #[arg(long)]
    pub active: bool,
    /// Both, side by side on two threads (the default).
    #[arg(long)]
    pub both: bool,
    /// Solver: explicit (central differences with mass scaling, the paper's method; the
    /// default on the Visible Human knee, whose 78 k unknowns make each Newton iteration
    /// take about a minute on 2 cores) or implicit (Newton with step cutting and the
    /// muscles' inertia, Newmark's trapezoidal rule; the default on the procedural knee
    /// and anatomy directories, where it is the faster: see the README).
    #[arg(long, value_enum)]
    pub solver: Option<Solver>,
    /// The hexahedra of the procedural knee and of an anatomy directory: hex8-fbar (the
    /// default; 2×2×2 points, mean dilatation) or hex8-one-point (one point, hourglass
    /// control). The Visible Human knee is meshed with tet10-fbar and refuses it.
    #[arg(long, value_enum)]
    pub element: Option<ElementChoice>,
    /// Mesh resolution (coarse, the default). The Visible Human knee: coarse (13 447
    /// tet10 in its muscles) or medium. The procedural knee: coarse (384 hex8 per
    /// muscle belly), medium (2352) or fine (8960).
    #[arg(long, value_enum, default_value = "coarse")]
    pub resolution: Resolution,
    /// On the procedural knee (which it implies): choose solver, element, resolution and
    /// step as the cheapest whose measured vm95 error (passive squat, against the medium
    /// mesh) is at most this [%]: from the knee rows of --bench-table when it has some,
    /// else from the chart measured with the program; medium (the reference) when none is
    /// within it.
    #[arg(
        long,
        value_name = "PERCENT",
        conflicts_with_all = ["resolution", "anatomy", "solver", "element", "time_step"]
    )]
    pub tolerance: Option<f64>,
    #[command(flatten)]
    pub bench_table: crate::bench::BenchTable,
    /// `visible-human` (the default): the Visible Human Female's segmented quadriceps
    /// (tet10, coarse or medium), bones and landmarks, with tendon strands to the patella
    /// (shipped with the program). `procedural`: swept elliptical bellies sized to the
    /// Visible Human Male's volumes, with tendon blocks (hex8; a squat in minutes, but its
    /// active stresses exceed what muscle carries: see the README). Or muscles from files:
    /// DIR/muscles.msh or DIR/muscles.inp with one block per muscle (named VI, VL, VM, RF
    /// or vastus_intermedius, ...) and node sets <block>_origin and <block>_insertion,
    /// with the procedural knee's bones; DIR/femur.stl replaces its femur if present.
    #[arg(long, value_name = "visible-human|procedural|DIR")]
    pub anatomy: Option<PathBuf>,
    /// How the bonded muscle–muscle and muscle–femur interfaces resist a slide: sliding
    /// (the default: they resist opening and interpenetration, not a slide) or
    /// elastic-shear (the paper's K_ss = 0.05 N/mm³; the README compares the two).
    #[arg(long, value_enum, default_value = "sliding")]
    pub interfaces: InterfaceLaw,
    /// Peak knee flexion of the squat [°], from 5 to 90; the table's angles (30°, 45°,
    /// 60°, 90°) beyond it are left out: a shallow squat for a first look.
    #[arg(long, value_name = "DEGREES", default_value_t = 90.0)]
    pub peak_flexion: f64,
    /// Duration of the squat 0° → peak → 0° [s].
    #[arg(long, value_name = "SECONDS", default_value_t = crate::knee::simulation::run::DEFAULT_SQUAT_DURATION)]
    pub duration: f64,
    /// Implicit increment, or explicit mass-scaling target step [s] (defaults: 0.02 s
    /// implicit, 2e-5 s explicit).
    #[arg(long, value_name = "SECONDS")]
    pub time_step: Option<f64>,
    /// Time between frames [s] (0: no frames; a negative value is refused).
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = 0.1,
        allow_negative_numbers = true
    )]
    pub frame_interval: f64,
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "out/knee")]
    pub out: PathBuf,
    /// Replace the results of a previous run in the output directory.
    #[arg(long, conflicts_with = "resume")]
    pub force: bool,
    /// Go on with a stopped study in the output directory (Ctrl-C, a kill, a time
    /// limit) from each squat's last frame, with the same options: the results are
    /// those of an uninterrupted run, bit for bit (docs/checkpoint-restart.md).
    #[arg(long)]
    pub resume: bool,
}

impl KneeArgs {
    /// The settings of the runs and the resolution: those `--tolerance` chose (with its
    /// reason, printed), or the recommended ones of the solver with the element,
    /// resolution and time step given; the duration given.
    pub(super) fn settings(&self) -> Result<(SquatSettings, Resolution, Option<String>)> {
        let (mut settings, resolution, why) = match self.tolerance {
            Some(percent) => {
                let (settings, resolution, why) = setting_within(percent, &self.bench_table.path)?;
                (settings, resolution, Some(why))
            }
            None => {
                let mut settings = SquatSettings::recommended(self.solver());
                settings.element = self.element();
                if let Some(step) = self.time_step {
                    settings.time_step = step;
                }
                (settings, self.resolution, None)
            }
        };
        settings.squat.duration = self.duration;
        settings.squat.peak_flexion = self.peak_flexion.to_radians();
        settings.interfaces = self.interfaces;
        Ok((settings, resolution, why))
    }

    /// The knee the squat runs on: `--anatomy`, else the Visible Human's, or the
    /// procedural one that `--tolerance` chooses among.
    pub fn knee_anatomy(&self) -> KneeAnatomy {
        match self.anatomy.as_deref() {
            None if self.tolerance.is_some() => KneeAnatomy::Procedural,
            None => KneeAnatomy::VisibleHuman,
            Some(name) if name.as_os_str() == VISIBLE_HUMAN => KneeAnatomy::VisibleHuman,
            Some(name) if name.as_os_str() == PROCEDURAL => KneeAnatomy::Procedural,
            Some(directory) => KneeAnatomy::Files(directory.to_path_buf()),
        }
    }

    /// Whether the squat runs on the Visible Human knee.
    pub(super) fn is_visible_human(&self) -> bool {
        self.knee_anatomy() == KneeAnatomy::VisibleHuman
    }

    /// The hexahedron given, or hex8-fbar.
    pub(super) fn element(&self) -> ElementChoice {
        self.element.unwrap_or(ElementChoice::Hex8Fbar)
    }

    /// The solver given, or the anatomy's default: explicit on the Visible Human knee,
    /// implicit on the others ([`crate::knee::simulation::run::solver_rationale`] says why).
    pub(super) fn solver(&self) -> Solver {
        match self.solver {
            Some(solver) => solver,
            None if self.is_visible_human() => Solver::Explicit,
            None => Solver::Implicit,
        }
    }

    pub(super) fn activations(&self) -> Vec<Activation> {
        match (self.passive, self.active) {
            (true, _) => vec![Activation::Passive],
            (_, true) => vec![Activation::Active],
            _ => vec![Activation::Passive, Activation::Active],
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;

    #[derive(Parser)]
    struct Command {
        #[command(flatten)]
        knee: KneeArgs,
    }

    /// `musclefem knee` without options runs both squats explicitly on the Visible
    /// Human knee's coarse mesh: the anatomy whose stresses meet issue #29's bounds (see
    /// the README); its medium mesh has not been run to the end.
    #[test]
    fn the_default_run_is_both_squats_explicit_on_the_coarse_visible_human_knee() {
        let args = Command::try_parse_from(["knee"]).unwrap().knee;
        let (settings, resolution, why) = args.settings().unwrap();
        assert_eq!(why, None);
        assert_eq!(args.knee_anatomy(), KneeAnatomy::VisibleHuman);
        assert_eq!(resolution, Resolution::Coarse);
        assert_eq!(settings.solver, Solver::Explicit);
        assert_eq!(
            args.activations(),
            vec![Activation::Passive, Activation::Active]
        );
    }

    /// The procedural knee, named or implied by `--tolerance`, runs implicitly with
    /// hex8-fbar unless told otherwise; any other name is a directory of muscles.
    #[test]
    fn the_procedural_knee_runs_implicitly_and_a_directory_is_read_from_files() {
        let args = Command::try_parse_from(["knee", "--anatomy", "procedural"])
            .unwrap()
            .knee;
        assert_eq!(args.knee_anatomy(), KneeAnatomy::Procedural);
        let (settings, _, _) = args.settings().unwrap();
        assert_eq!(settings.solver, Solver::Implicit);
        assert_eq!(settings.element, ElementChoice::Hex8Fbar);
        let args = Command::try_parse_from(["knee", "--tolerance", "20"])
            .unwrap()
            .knee;
        assert_eq!(args.knee_anatomy(), KneeAnatomy::Procedural);
        let args = Command::try_parse_from(["knee", "--anatomy", "my/muscles"])
            .unwrap()
            .knee;
        assert_eq!(
            args.knee_anatomy(),
            KneeAnatomy::Files(PathBuf::from("my/muscles"))
        );
        assert_eq!(args.settings().unwrap().0.solver, Solver::Implicit);
    }

    /// On the Visible Human knee the default solver is the explicit one, and a solver
    /// given is kept.
    #[test]
    fn the_visible_human_knee_runs_explicitly_unless_told_otherwise() {
        let args = Command::try_parse_from(["knee", "--anatomy", "visible-human"])
            .unwrap()
            .knee;
        assert_eq!(args.settings().unwrap().0.solver, Solver::Explicit);
        let args =
            Command::try_parse_from(["knee", "--anatomy", "visible-human", "--solver", "implicit"])
                .unwrap()
                .knee;
        assert_eq!(args.settings().unwrap().0.solver, Solver::Implicit);
    }
}
