//! `musclefem vumat build` and `musclefem umat build`: a user's Abaqus/Explicit VUMAT or
//! Abaqus/Standard UMAT compiled into a material plugin. Two commands rather than a
//! `--kind` option: Abaqus users know them as two different subroutines with their own
//! conventions, and the command then says which one the file must define. The build is in
//! `musclefem-vumat` (crates/vumat); this is its command line and its report.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args, Subcommand, ValueEnum};
use musclefem_vumat::options::parse_initial_values;
use musclefem_vumat::{FiberConvention, Prop, Subroutine, TangentSource, VumatBuild, build_plugin};

use crate::commands::parameter_table;

#[derive(Debug, Args)]
pub struct VumatArgs {
    #[command(subcommand)]
    pub command: VumatCommand,
}

#[derive(Debug, Subcommand)]
pub enum VumatCommand {
    /// Compile a Fortran file with SUBROUTINE VUMAT (Abaqus/Explicit's interface, unchanged)
    /// with gfortran and link it with musclefem's adapter into a material plugin for scenes
    /// (`plugin = "LIB.so"`, `run --allow-plugins`); see docs/vumat.md.
    Build(VumatBuildArgs),
}

/// Where the VUMAT finds the reference fiber direction.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum Fiber {
    /// Every tensor in the fiber's basis: the fiber is local direction 1 (*ORIENTATION).
    Orientation,
    /// Global basis, the unit fiber in state variables 1-3 at the first increment
    /// (*INITIAL CONDITIONS, TYPE=SOLUTION); needs --nstatev 3 or more.
    State,
    /// Global basis, no fiber direction (isotropic VUMATs).
    None,
}

#[derive(Debug, Args)]
pub struct UmatArgs {
    #[command(subcommand)]
    pub command: UmatCommand,
}

#[derive(Debug, Subcommand)]
pub enum UmatCommand {
    /// Compile a Fortran file with SUBROUTINE UMAT (Abaqus/Standard's interface, unchanged)
    /// with gfortran and link it with musclefem's adapter into a material plugin whose
    /// tangent is the UMAT's DDSDDE converted to dP/dF; see docs/vumat.md, "UMAT".
    Build(UmatBuildArgs),
}

/// Where a UMAT plugin's tangent comes from.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum Tangent {
    /// The UMAT's DDSDDE, converted to dP/dF (finite differences by the adapter where the
    /// UMAT leaves DDSDDE unset).
    Ddsdde,
    /// Central differences of the stress by musclefem; DDSDDE is ignored.
    FiniteDifference,
}

#[derive(Debug, Args)]
pub struct UmatBuildArgs {
    #[command(flatten)]
    pub build: VumatBuildArgs,
    /// Where the tangent the implicit solver uses comes from.
    #[arg(long, value_enum, default_value = "ddsdde")]
    pub tangent: Tangent,
}

#[derive(Debug, Args)]
pub struct VumatBuildArgs {
    /// The Fortran file with SUBROUTINE VUMAT (`umat build`: SUBROUTINE UMAT), .f, .for,
    /// .f90, ...
    pub source: PathBuf,
    /// Material name for scene files (`model = "NAME"`).
    #[arg(long, value_name = "NAME")]
    pub name: String,
    /// The subroutine's props in order, as named parameters with defaults and SI units
    /// (unit "1" when left out; no default: the scene must give it), e.g.
    /// mu=11370:Pa,D=5e-9:1/Pa.
    #[arg(long, value_name = "NAME[=DEFAULT[:UNIT]],...", default_value = "")]
    pub props: String,
    /// The subroutine's number of state variables (nstatev).
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub nstatev: usize,
    /// Initial values of the first state variables, V1,V2,... (the others start at 0), as
    /// *INITIAL CONDITIONS, TYPE=SOLUTION gives them.
    #[arg(long, value_name = "V1,V2,...", default_value = "")]
    pub statev_initial: String,
    /// Where the subroutine finds the fiber direction [default: orientation for a VUMAT,
    /// none for a UMAT, which works in the global basis and takes none or state].
    #[arg(long, value_enum)]
    pub fiber: Option<Fiber>,
    /// cmname passed to the subroutine [default: NAME in upper case].
    #[arg(long, value_name = "CMNAME")]
    pub cmname: Option<String>,
    /// The plugin library to write (e.g. libmy_vumat.so).
    #[arg(long, value_name = "LIB")]
    pub out: PathBuf,
    /// Replace an existing library.
    #[arg(long)]
    pub force: bool,
}

/// `musclefem vumat ...`.
pub fn vumat(args: &VumatArgs) -> Result<()> {
    match &args.command {
        VumatCommand::Build(build) => {
            build_command(build, Subroutine::Vumat, TangentSource::Ddsdde)
        }
    }
}

/// `musclefem umat ...`.
pub fn umat(args: &UmatArgs) -> Result<()> {
    match &args.command {
        UmatCommand::Build(umat) => {
            let tangent = match umat.tangent {
                Tangent::Ddsdde => TangentSource::Ddsdde,
                Tangent::FiniteDifference => TangentSource::FiniteDifference,
            };
            build_command(&umat.build, Subroutine::Umat, tangent)
        }
    }
}

fn build_command(
    args: &VumatBuildArgs,
    subroutine: Subroutine,
    tangent: TangentSource,
) -> Result<()> {
    let fiber = args.fiber.unwrap_or(match subroutine {
        Subroutine::Vumat => Fiber::Orientation,
        Subroutine::Umat => Fiber::None,
    });
    let build = VumatBuild {
        subroutine,
        tangent,
        source: args.source.clone(),
        name: args.name.clone(),
        cmname: args.cmname.clone(),
        props: Prop::parse_list(&args.props)?,
        nstatev: args.nstatev,
        statev_initial: parse_initial_values(&args.statev_initial)?,
        fiber: match fiber {
            Fiber::Orientation => FiberConvention::Orientation,
            Fiber::State => FiberConvention::State,
            Fiber::None => FiberConvention::None,
        },
        out: args.out.clone(),
        replace: args.force,
    };
    let built = build_plugin(&build)
        .with_context(|| format!("building a plugin from {}", args.source.display()))?;
    if !built.warnings.trim().is_empty() {
        eprintln!("gfortran's warnings:\n{}", built.warnings.trim_end());
    }
    let library = built.library.display();
    let tangent = match subroutine {
        Subroutine::Vumat => String::new(),
        Subroutine::Umat => format!(", tangent {tangent}"),
    };
    println!(
        "built {library}: material '{}' from {} ({subroutine}, cmname {}, {} props, nstatev \
         {}, fiber convention {}{tangent})",
        built.info.name,
        args.source.display(),
        build.cmname(),
        build.props.len(),
        build.nstatev,
        build.fiber
    );
    print!("{}", parameter_table(&built.info.parameters));
    let file_name = built
        .library
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    println!(
        "\nIn a scene, run with `musclefem run SCENE --allow-plugins`:\n\n[[materials]]\n\
         name = \"...\"\nmodel = \"{}\"\nplugin = \"{file_name}\"   # relative to the scene file",
        built.info.name
    );
    Ok(())
}
