//! Why a VUMAT plugin could not be built. Messages name the file and pass the compilers'
//! own output through (gfortran's `FILE:LINE:COLUMN:` lines included).

use std::fmt;
use std::path::PathBuf;

use musclefem_materials::MaterialError;

use crate::kind::Subroutine;

/// A failed `musclefem vumat build`.
#[derive(Debug)]
pub enum VumatError {
    /// A command-line option is malformed or inconsistent.
    Option(String),
    /// A compiler is not installed.
    ToolMissing {
        /// The program looked for (e.g. `gfortran`).
        tool: String,
        /// The environment variable that names another one.
        variable: &'static str,
    },
    /// The user's Fortran file did not compile: gfortran's messages.
    Compile { source: PathBuf, output: String },
    /// The Fortran file calls routines nobody defines (or does not define VUMAT / UMAT).
    Undefined {
        subroutine: Subroutine,
        source: PathBuf,
        routines: Vec<String>,
        output: String,
    },
    /// The adapter did not compile or the library did not link.
    Adapter { step: String, output: String },
    /// Reading or writing a file failed.
    Io {
        what: String,
        path: PathBuf,
        source: std::io::Error,
    },
    /// The output exists and replacing it was not asked for.
    OutputExists(PathBuf),
    /// The built library does not load as a material plugin.
    Load(MaterialError),
}

impl fmt::Display for VumatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VumatError::Option(text) => f.write_str(text),
            VumatError::ToolMissing { tool, variable } => write!(
                f,
                "the compiler '{tool}' was not found: install it (Debian/Ubuntu: \
                 scripts/setup-fortran.sh, or apt-get install gfortran) or name another \
                 one with the environment variable {variable}"
            ),
            VumatError::Compile { source, output } => write!(
                f,
                "gfortran could not compile {}:\n{}",
                source.display(),
                output.trim_end()
            ),
            VumatError::Undefined {
                subroutine,
                source,
                routines,
                output,
            } => {
                if routines.iter().any(|r| r == subroutine.symbol()) {
                    write!(
                        f,
                        "{} does not define SUBROUTINE {subroutine} (the linker found no \
                         symbol {})",
                        source.display(),
                        subroutine.symbol()
                    )?;
                } else {
                    write!(
                        f,
                        "{} calls routines that neither it nor musclefem defines: {} \
                         (musclefem provides the Abaqus utilities {})",
                        source.display(),
                        routines
                            .iter()
                            .map(|r| r.trim_end_matches('_').to_ascii_uppercase())
                            .collect::<Vec<_>>()
                            .join(", "),
                        subroutine.provided_routines()
                    )?;
                }
                write!(f, "\nlinker output:\n{}", output.trim_end())
            }
            VumatError::Adapter { step, output } => {
                write!(f, "{step} failed:\n{}", output.trim_end())
            }
            VumatError::Io { what, path, source } => {
                write!(f, "cannot {what} {}: {source}", path.display())
            }
            VumatError::OutputExists(path) => {
                write!(f, "{} exists; give --force to replace it", path.display())
            }
            VumatError::Load(error) => write!(f, "the built plugin does not load: {error}"),
        }
    }
}

impl std::error::Error for VumatError {}
