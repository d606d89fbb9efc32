//! Which Abaqus user subroutine a build wraps — Abaqus/Explicit's `VUMAT` or
//! Abaqus/Standard's `UMAT` — and, for a UMAT, where the plugin's tangent comes from.
//! Each has its adapter (`plugins/abaqus_vumat/adapter.c`, `umat_adapter.c`) on the shared
//! kinematics and Abaqus utilities.

use std::fmt;
use std::str::FromStr;

use crate::error::VumatError;

/// The user subroutine a Fortran file is built as.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Subroutine {
    /// Abaqus/Explicit's `SUBROUTINE VUMAT`: blocks of points, co-rotational stress, no
    /// tangent (the host differentiates the stress).
    #[default]
    Vumat,
    /// Abaqus/Standard's `SUBROUTINE UMAT`: one point per call, Cauchy stress in the
    /// global basis, and the Jacobian DDSDDE (converted to ∂P/∂F by the adapter).
    Umat,
}

impl Subroutine {
    /// The name as Abaqus writes it (`VUMAT`, `UMAT`).
    pub fn name(self) -> &'static str {
        match self {
            Subroutine::Vumat => "VUMAT",
            Subroutine::Umat => "UMAT",
        }
    }

    /// The symbol gfortran gives the subroutine.
    pub fn symbol(self) -> &'static str {
        match self {
            Subroutine::Vumat => "vumat_",
            Subroutine::Umat => "umat_",
        }
    }

    /// The Abaqus solver the subroutine is written for.
    pub fn solver(self) -> &'static str {
        match self {
            Subroutine::Vumat => "Abaqus/Explicit",
            Subroutine::Umat => "Abaqus/Standard",
        }
    }

    /// The adapter's C files compiled for this subroutine.
    pub fn c_files(self) -> &'static [&'static str] {
        match self {
            Subroutine::Vumat => &["adapter.c", "kinematics.c", "abaqus_utilities.c"],
            Subroutine::Umat => &[
                "umat_adapter.c",
                "umat_tangent.c",
                "kinematics.c",
                "abaqus_utilities.c",
            ],
        }
    }

    /// The Abaqus utility routines a subroutine of this kind usually calls that the adapter
    /// defines (it defines all four for both kinds).
    pub fn provided_routines(self) -> &'static str {
        match self {
            Subroutine::Vumat => "XPLB_ABQERR and XPLB_EXIT",
            Subroutine::Umat => "STDB_ABQERR and XIT",
        }
    }

    /// The parameters the adapter declares after the props, as a list for messages.
    pub fn adapter_parameters(self) -> &'static str {
        match self {
            Subroutine::Vumat => "vumat_density, vumat_char_length, vumat_temperature",
            Subroutine::Umat => "umat_char_length, umat_temperature",
        }
    }
}

impl fmt::Display for Subroutine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Where a UMAT plugin's tangent ∂P/∂F comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TangentSource {
    /// The UMAT's DDSDDE, converted (docs/vumat.md, "The tangent"); central differences in
    /// the adapter at the points where the UMAT leaves DDSDDE unset.
    #[default]
    Ddsdde,
    /// Central differences of the stress by the host; DDSDDE is ignored.
    FiniteDifference,
}

impl TangentSource {
    /// The value of `UMAT_TANGENT` in `vumat_config.h` (the plugin's `provides_tangent`).
    pub fn c_value(self) -> u8 {
        match self {
            TangentSource::Ddsdde => 1,
            TangentSource::FiniteDifference => 0,
        }
    }
}

impl fmt::Display for TangentSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            TangentSource::Ddsdde => "ddsdde",
            TangentSource::FiniteDifference => "finite-difference",
        })
    }
}

impl FromStr for TangentSource {
    type Err = VumatError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text.trim() {
            "ddsdde" => Ok(TangentSource::Ddsdde),
            "finite-difference" => Ok(TangentSource::FiniteDifference),
            other => Err(VumatError::Option(format!(
                "--tangent '{other}': expected ddsdde or finite-difference"
            ))),
        }
    }
}
