//! The `musclefem` command: argument parsing, progress bars and printing. The physics is
//! in the library crates; the studies behind `knee`, `elongate`, `sweep`, `fit` and `bench`
//! are in `musclefem-studies` (`crates/studies`).
//!
//! - `musclefem materials`: list every material with its parameters;
//! - `musclefem point`: one material point in uniaxial stress along the fiber
//!   (CSV + PNG of the stress history);
//! - `musclefem demo` (also `musclefem` alone): the passive and active Hill muscle on the
//!   default protocol;
//! - `musclefem check SCENE.toml`: read and check a scene file without running it;
//! - `musclefem run SCENE.toml`: run a scene, writing frames, history and log;
//! - `musclefem mesh`: a closed surface (STL/OBJ) to a tet4/tet10 Gmsh mesh with origin
//!   and insertion surfaces, through Gmsh's Python package (`scripts/musclefem_mesh.py`);
//! - `musclefem fibers`: fiber directions from a flow through a mesh file;
//! - `musclefem picture`: a PNG of a run's frame, deformed and coloured by von Mises
//!   stress (or another cell array), bones in grey;
//! - `musclefem elongate`: the paper's passive and active elongation tests of the
//!   fusiform muscle (see the library's `elongation` module);
//! - `musclefem vumat build`, `musclefem umat build`: an Abaqus/Explicit VUMAT or an
//!   Abaqus/Standard UMAT compiled into a material plugin (`musclefem-vumat`).

// Every crate that registers materials with `inventory` (today: materials) must be named
// here, or the linker may drop its registrations (see docs/design.md, "Two traps").
use musclefem_materials as _;

mod bench_command;
mod commands;
mod elongate_command;
mod fibers_command;
mod mesh_command;
mod picture_command;
mod scene_run;
mod summary;
mod vumat_command;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use musclefem_studies::solver::Solver;

/// musclefem: 3D finite-element simulation of active skeletal muscle (Hill-type and
/// neo-Hookean materials and plugins, explicit and implicit solvers, flow-based fibers,
/// contact and cohesive interfaces, the single-muscle tests and the knee squat). Without a
/// subcommand, runs `demo`.
#[derive(Debug, Parser)]
#[command(name = "musclefem", version)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// List every material (built-in and plugins) with its parameters, units, defaults
    /// and valid ranges.
    Materials(MaterialsArgs),
    /// Drive one material point in uniaxial stress along its fiber through a stretch
    /// history; write the history as CSV and a PNG chart.
    Point(PointArgs),
    /// The default job: the Hill muscle, passive and active (n2 = 1 after a 0.5 s
    /// isometric hold), stretched to 1.2; writes CSV and PNG files.
    Demo(DemoArgs),
    /// Read and check a scene file (TOML) without running it; print what it holds.
    Check(CheckArgs),
    /// The paper's single-muscle tests: uniaxial elongation of the 50 mm fusiform muscle,
    /// passive and/or active after a 0.5 s isometric hold, pulled at 5 mm/s to 20 % strain;
    /// writes curve.csv (engineering stress vs strain), curve.png and VTU/PVD frames.
    Elongate(elongate_command::ElongateArgs),
    /// A closed muscle surface (STL or OBJ) to a tet4/tet10 volume mesh through Gmsh
    /// (Python package gmsh: scripts/setup-gmsh.sh), with the surfaces origin and
    /// insertion chosen by planes, boxes or points, and outer; writes Gmsh .msh 4.1 in
    /// metres and prints elements, nodes, volume and each surface's faces and area.
    Mesh(mesh_command::MeshArgs),
    /// Fiber directions of a muscle mesh from a potential flow between its origin (inlet)
    /// and insertion (outlet): writes fibers.csv (element,cx,cy,cz,fx,fy,fz), fibers.vtu
    /// and fibers.png (arrows in the plane of the centroids' two principal axes); prints
    /// the flux through each inlet and outlet.
    Fibers(fibers_command::FibersArgs),
    /// A PNG of one frame of a run: its parts deformed, coloured by a cell array (von
    /// Mises stress by default), seen along a view (lateral, anterior, ... or a
    /// direction), with the rigid bodies of the same instant in grey; `--run DIR --time T`
    /// picks the frame nearest T.
    Picture(picture_command::PictureArgs),
    /// Run a scene file: VTU frames + PVD series (ParaView), history.csv, a copy of the
    /// scene and run.log in the output directory. Ctrl-C stops cleanly after the last
    /// complete frame.
    Run(RunArgs),
    /// The knee squat (seed §2.4): knee flexion 0° → 90° → 0° with the four quadriceps
    /// (VI, VL, VM, RF) tied to femur, pelvis and patella, bonded to each other and the
    /// femur; passive and/or active (50 % from 35° of flexion). Writes peak_stress.csv
    /// (vm95 per muscle at 30°, 45°, 60°, 90°), peak_stress.png, frames and histories.
    Knee(musclefem_studies::knee::command::KneeArgs),
    /// Parametric study of the elongation tests: every combination (or a Latin-hypercube
    /// sample) of varied Hill parameters, several runs at a time; writes sweep.csv (one row
    /// per run, resumable) and the normalised sensitivities (sensitivity.csv, .png).
    /// `sweep merge` joins the tables of shards (`--shard K/N`).
    #[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
    Sweep(musclefem_studies::sweep::SweepArgs),
    /// Least-squares fit of Hill parameters to a measured stress-strain curve through the
    /// elongation test; writes fit.csv (values, 95 % confidence intervals), fit_curve.csv,
    /// fit.txt (residual) and fit.png (data against the fit).
    Fit(musclefem_studies::fit::FitArgs),
    /// Speed against accuracy: run a matrix of solvers, elements, mesh sizes and steps on
    /// the cube and the elongation test, time each run and measure its error against a
    /// converged reference; writes work_precision.csv, work_precision.png (log–log, Pareto
    /// front marked) and bench.log. `--problem scaling` instead times the implicit cube at
    /// growing sizes (and through felupe): scaling.csv, scaling.png and scaling.log.
    Bench(bench_command::BenchArgs),
    /// One case of `bench --problem scaling`, in a process of its own (so that its peak
    /// memory is its own); prints one line of key=value.
    #[command(hide = true)]
    ScalingCase(bench_command::scaling::ScalingCaseArgs),
    /// Abaqus/Explicit VUMATs as materials: `vumat build FILE.f --name NAME --props ...
    /// --nstatev N --out LIB.so` compiles a user's Fortran VUMAT, unchanged, into a
    /// material plugin (docs/vumat.md).
    Vumat(vumat_command::VumatArgs),
    /// Abaqus/Standard UMATs as materials: `umat build FILE.f --name NAME --props ...
    /// --out LIB.so` compiles a user's Fortran UMAT, unchanged, into a material plugin whose
    /// tangent is its DDSDDE (docs/vumat.md, "UMAT").
    Umat(vumat_command::UmatArgs),
}

#[derive(Debug, Args)]
pub struct CheckArgs {
    /// The scene file (see docs/scene-format.md). A material's plugin is never loaded
    /// here: the rest of the scene is checked and the plugin's materials are named.
    pub scene: PathBuf,
    /// Let the scene name files outside its own folder.
    #[arg(long)]
    pub allow_outside_paths: bool,
}

#[derive(Debug, Args)]
pub struct RunArgs {
    /// The scene file (see docs/scene-format.md).
    pub scene: PathBuf,
    /// Output directory [default: out/<scene name>].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Use this solver instead of the scene's, with its default settings for the scene's
    /// duration and output interval.
    #[arg(long, value_enum)]
    pub solver: Option<Solver>,
    /// Run the cheapest solver and step setting whose measured error (`musclefem bench
    /// --scene SCENE`: displacements at the end against its reference run) is at most
    /// this [%].
    #[arg(long, value_name = "PERCENT", conflicts_with = "solver")]
    pub tolerance: Option<f64>,
    #[command(flatten)]
    pub bench_table: crate::BenchTable,
    /// Worker threads [default: one per core].
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Replace the results of a previous run in the output directory.
    #[arg(long, conflicts_with = "resume")]
    pub force: bool,
    /// Go on with the stopped run in the output directory from its last checkpoint
    /// (written at every frame); the files end as an uninterrupted run's would.
    #[arg(long)]
    pub resume: bool,
    #[command(flatten)]
    pub trust: musclefem_studies::scene_study::SceneTrustArgs,
}

/// The work–precision table that `--tolerance` reads (written by `musclefem bench`).
pub use musclefem_studies::bench::BenchTable;

#[derive(Debug, Args)]
pub struct MaterialsArgs {
    /// Load a material plugin (shared library) first; repeatable.
    #[arg(long = "plugin", value_name = "PATH")]
    pub plugins: Vec<PathBuf>,
}

#[derive(Debug, Args)]
pub struct PointArgs {
    /// Material name (see `musclefem materials`).
    #[arg(long, value_name = "NAME")]
    pub material: String,
    /// Material parameter, overriding its default; repeatable (e.g. --param n2=1).
    #[arg(long = "param", value_name = "KEY=VALUE")]
    pub params: Vec<String>,
    /// Load a material plugin (shared library) first; repeatable.
    #[arg(long = "plugin", value_name = "PATH")]
    pub plugins: Vec<PathBuf>,
    /// Piecewise-linear fiber stretch history TIME:STRETCH,... in s and 1
    /// (e.g. 0:1,0.5:1,2.5:1.2).
    #[arg(long, value_name = "T:L,T:L,...")]
    pub stretch: String,
    /// Time step [s].
    #[arg(long, value_name = "SECONDS", default_value_t = 1e-3)]
    pub dt: f64,
    /// Output CSV file; the chart goes next to it with the extension .png.
    #[arg(long, value_name = "FILE.csv")]
    pub out: PathBuf,
    /// Do not write the PNG chart.
    #[arg(long)]
    pub no_plot: bool,
    /// Replace the results of an earlier run in the output place.
    #[arg(long)]
    pub force: bool,
}

#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "out/demo")]
    pub out: PathBuf,
    /// Replace the results of an earlier run in the output place.
    #[arg(long)]
    pub force: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Materials(args)) => commands::materials(&args),
        Some(Command::Point(args)) => commands::point(&args),
        Some(Command::Demo(args)) => commands::demo(&args),
        Some(Command::Check(args)) => scene_run::check(&args),
        Some(Command::Run(args)) => scene_run::run(&args),
        Some(Command::Elongate(args)) => elongate_command::elongate(&args),
        Some(Command::Mesh(args)) => mesh_command::mesh(&args),
        Some(Command::Fibers(args)) => fibers_command::fibers(&args),
        Some(Command::Picture(args)) => picture_command::picture(&args),
        Some(Command::Knee(args)) => commands::knee(&args),
        Some(Command::Sweep(args)) => musclefem_studies::sweep::sweep(&args),
        Some(Command::Fit(args)) => musclefem_studies::fit::fit(&args),
        Some(Command::Bench(args)) => bench_command::bench(&args),
        Some(Command::ScalingCase(args)) => bench_command::scaling::scaling_case(&args),
        Some(Command::Vumat(args)) => vumat_command::vumat(&args),
        Some(Command::Umat(args)) => vumat_command::umat(&args),
        None => commands::demo(&DemoArgs {
            out: PathBuf::from("out/demo"),
            force: false,
        }),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) if error.downcast_ref::<commands::Interrupted>().is_some() => {
            eprintln!("interrupted: {error}");
            ExitCode::from(130)
        }
        Err(error) => {
            // `{:#}` prints the whole chain: what was being done, then each cause.
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
