//! What `musclefem vumat build` is asked to build: the user's Fortran file, the material
//! name, the VUMAT's props (names, defaults, units), its number of state variables and the
//! fiber-direction convention, each checked before any compiler runs.

use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;

use crate::error::VumatError;
use crate::kind::{Subroutine, TangentSource};

/// Fortran source extensions gfortran recognises (fixed form: f, for, ftn, f77; free form:
/// f90, f95, f03, f08; upper case: run through the preprocessor, which is on anyway).
pub const FORTRAN_EXTENSIONS: [&str; 8] = ["f", "for", "ftn", "f77", "f90", "f95", "f03", "f08"];

/// Longest material name and cmname (Abaqus's cmname is CHARACTER*80).
pub const MAX_NAME_LENGTH: usize = 80;

/// Prefixes of the parameters the adapters declare after the user's props (the VUMAT's,
/// the UMAT's), refused as prop names for both.
pub const ADAPTER_PARAMETER_PREFIXES: [&str; 2] = ["vumat_", "umat_"];

/// Where the VUMAT finds the reference fiber direction (docs/vumat.md, "Fiber direction").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FiberConvention {
    /// Every tensor in the material basis (a, b, c) of the point, a the unit reference
    /// fiber: the fiber is local direction 1, as with Abaqus's `*ORIENTATION`.
    #[default]
    Orientation,
    /// Global basis; the unit reference fiber (global components) is in the first three
    /// user state variables at the first increment, as with `*INITIAL CONDITIONS,
    /// TYPE=SOLUTION`. Needs nstatev ≥ 3.
    State,
    /// Global basis; the fiber direction is not passed (isotropic VUMATs).
    None,
}

impl FiberConvention {
    /// The value of `VUMAT_FIBER` in `vumat_config.h`.
    pub fn c_macro(self) -> &'static str {
        match self {
            FiberConvention::Orientation => "VUMAT_FIBER_ORIENTATION",
            FiberConvention::State => "VUMAT_FIBER_STATE",
            FiberConvention::None => "VUMAT_FIBER_NONE",
        }
    }
}

impl fmt::Display for FiberConvention {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            FiberConvention::Orientation => "orientation",
            FiberConvention::State => "state",
            FiberConvention::None => "none",
        })
    }
}

impl FromStr for FiberConvention {
    type Err = VumatError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text.trim() {
            "orientation" => Ok(FiberConvention::Orientation),
            "state" => Ok(FiberConvention::State),
            "none" => Ok(FiberConvention::None),
            other => Err(VumatError::Option(format!(
                "--fiber '{other}': expected orientation, state or none"
            ))),
        }
    }
}

/// One VUMAT prop, `props(i)`, as a named material parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Prop {
    /// Parameter name in scene files: a letter, then letters, digits or '_'.
    pub name: String,
    /// Default value; `None`: the scene must give it.
    pub default: Option<f64>,
    /// SI unit, "1" when dimensionless.
    pub unit: String,
}

impl Prop {
    /// Parse `--props` text: `NAME[=DEFAULT[:UNIT]],...` (e.g. `mu=11370:Pa,D=5e-9:1/Pa`),
    /// in the order of the VUMAT's props. Empty text: no props. Errors quote the token.
    pub fn parse_list(text: &str) -> Result<Vec<Prop>, VumatError> {
        let mut props: Vec<Prop> = Vec::new();
        if text.trim().is_empty() {
            return Ok(props);
        }
        for token in text.split(',') {
            let token = token.trim();
            let bad = |why: String| VumatError::Option(format!("--props '{token}': {why}"));
            let (name, rest) = match token.split_once('=') {
                Some((name, rest)) => (name.trim(), Some(rest)),
                None => (token, None),
            };
            check_prop_name(name).map_err(bad)?;
            let (default, unit) = match rest {
                None => (None, "1".to_string()),
                Some(rest) => {
                    let (value, unit) = match rest.split_once(':') {
                        Some((value, unit)) => (value.trim(), unit.trim()),
                        None => (rest.trim(), "1"),
                    };
                    let value: f64 = value
                        .parse()
                        .map_err(|_| bad(format!("'{value}' is not a number")))?;
                    if !value.is_finite() {
                        return Err(bad(format!("the default {value} is not finite")));
                    }
                    check_text("the unit", unit).map_err(bad)?;
                    (Some(value), unit.to_string())
                }
            };
            if props.iter().any(|p| p.name == name) {
                return Err(bad(format!("'{name}' is given more than once")));
            }
            props.push(Prop {
                name: name.to_string(),
                default,
                unit,
            });
        }
        Ok(props)
    }
}

fn check_prop_name(name: &str) -> Result<(), String> {
    let mut chars = name.chars();
    let first_ok = chars.next().is_some_and(|c| c.is_ascii_alphabetic());
    if !first_ok || !chars.all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(format!(
            "'{name}' is not a parameter name (a letter, then letters, digits or '_')"
        ));
    }
    if let Some(prefix) = ADAPTER_PARAMETER_PREFIXES
        .iter()
        .find(|prefix| name.starts_with(**prefix))
    {
        return Err(format!(
            "'{name}': names starting with '{prefix}' are the adapters' (vumat_density, \
             vumat_char_length, vumat_temperature; umat_char_length, umat_temperature)"
        ));
    }
    Ok(())
}

/// Text that goes into a C string literal and a scene: printable ASCII, no quote or
/// backslash, not empty.
fn check_text(what: &str, text: &str) -> Result<(), String> {
    if text.is_empty() {
        return Err(format!("{what} is empty"));
    }
    if let Some(c) = text
        .chars()
        .find(|c| !(c.is_ascii_graphic() || *c == ' ') || *c == '"' || *c == '\\')
    {
        return Err(format!("{what} '{text}' holds the character {c:?}"));
    }
    Ok(())
}

/// Parse `--statev-initial` text: `V1,V2,...`, finite numbers. Errors quote the token.
pub fn parse_initial_values(text: &str) -> Result<Vec<f64>, VumatError> {
    if text.trim().is_empty() {
        return Ok(Vec::new());
    }
    text.split(',')
        .map(|token| {
            let token = token.trim();
            match token.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(VumatError::Option(format!(
                    "--statev-initial '{token}' is not a finite number"
                ))),
            }
        })
        .collect()
}

/// Everything a build needs.
#[derive(Debug, Clone, PartialEq)]
pub struct VumatBuild {
    /// Which subroutine the file defines and the plugin runs (VUMAT or UMAT).
    pub subroutine: Subroutine,
    /// The user's Fortran file with `SUBROUTINE VUMAT` (or `UMAT`).
    pub source: PathBuf,
    /// Registry name of the material (scene files' `model`).
    pub name: String,
    /// cmname passed to the VUMAT [default: the name in upper case, as Abaqus passes
    /// material names].
    pub cmname: Option<String>,
    /// The VUMAT's props, in order.
    pub props: Vec<Prop>,
    /// The VUMAT's number of state variables.
    pub nstatev: usize,
    /// Initial values of the first state variables (the others start at 0), as Abaqus's
    /// `*INITIAL CONDITIONS, TYPE=SOLUTION` gives them.
    pub statev_initial: Vec<f64>,
    /// Where the VUMAT finds the fiber direction.
    pub fiber: FiberConvention,
    /// The plugin library to write.
    pub out: PathBuf,
    /// Replace an existing `out`.
    pub replace: bool,
    /// Where a UMAT plugin's tangent comes from (ignored for a VUMAT, whose tangent the
    /// host always differentiates).
    pub tangent: TangentSource,
}

/// Most state variables a VUMAT may declare (per point; a bound against typos).
pub const MAX_NSTATEV: usize = 10_000;

impl VumatBuild {
    /// The cmname passed to the VUMAT.
    pub fn cmname(&self) -> String {
        self.cmname
            .clone()
            .unwrap_or_else(|| self.name.to_ascii_uppercase())
    }

    /// Check the options (not the files): name, cmname, extension, nstatev against the
    /// fiber convention.
    pub fn check(&self) -> Result<(), VumatError> {
        let option = |text: String| Err(VumatError::Option(text));
        let name = &self.name;
        if name.is_empty()
            || name.len() > MAX_NAME_LENGTH
            || !name.starts_with(|c: char| c.is_ascii_alphabetic())
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        {
            return option(format!(
                "--name '{name}': a material name is a letter, then letters, digits, '-' or \
                 '_', at most {MAX_NAME_LENGTH} characters"
            ));
        }
        let cmname = self.cmname();
        if cmname.len() > MAX_NAME_LENGTH {
            return option(format!(
                "--cmname '{cmname}' is longer than {MAX_NAME_LENGTH} characters"
            ));
        }
        if let Err(why) = check_text("--cmname", &cmname) {
            return option(why);
        }
        let extension = self
            .source
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("");
        if !FORTRAN_EXTENSIONS.contains(&extension.to_ascii_lowercase().as_str()) {
            return option(format!(
                "{}: not a Fortran file name (expected the extension .{})",
                self.source.display(),
                FORTRAN_EXTENSIONS.join(", .")
            ));
        }
        if self.nstatev > MAX_NSTATEV {
            return option(format!(
                "--nstatev {} is more than {MAX_NSTATEV}",
                self.nstatev
            ));
        }
        if self.statev_initial.len() > self.nstatev {
            return option(format!(
                "--statev-initial gives {} values, more than --nstatev {}",
                self.statev_initial.len(),
                self.nstatev
            ));
        }
        if self.subroutine == Subroutine::Umat && self.fiber == FiberConvention::Orientation {
            return option(
                "--fiber orientation is for VUMATs: a UMAT works in the global basis here; \
                 give --fiber none, or --fiber state to find the fiber in state variables 1 \
                 to 3 (docs/vumat.md, \"UMAT\")"
                    .to_string(),
            );
        }
        if self.fiber == FiberConvention::State && self.nstatev < 3 {
            return option(format!(
                "--fiber state puts the fiber direction into state variables 1 to 3, but \
                 --nstatev is {}: give --nstatev 3 or more",
                self.nstatev
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn props_parse_with_defaults_units_and_required_values() {
        let props = Prop::parse_list(" mu=11370:Pa, D = 5e-9 : 1/Pa ,k=2,alpha").unwrap();
        let view: Vec<(&str, Option<f64>, &str)> = props
            .iter()
            .map(|p| (p.name.as_str(), p.default, p.unit.as_str()))
            .collect();
        assert_eq!(
            view,
            [
                ("mu", Some(11370.0), "Pa"),
                ("D", Some(5e-9), "1/Pa"),
                ("k", Some(2.0), "1"),
                ("alpha", None, "1"),
            ]
        );
        assert!(Prop::parse_list("").unwrap().is_empty());
    }

    #[test]
    fn initial_values_parse_and_bad_ones_are_quoted() {
        assert_eq!(parse_initial_values("1, 1,0").unwrap(), [1.0, 1.0, 0.0]);
        assert!(parse_initial_values(" ").unwrap().is_empty());
        let error = parse_initial_values("1,x").unwrap_err().to_string();
        assert!(
            error.contains("--statev-initial 'x' is not a finite number"),
            "{error}"
        );
    }

    #[test]
    fn bad_props_are_refused_quoting_the_token() {
        for (text, expected) in [
            ("mu=x", "--props 'mu=x': 'x' is not a number"),
            ("mu=1,mu=2", "--props 'mu=2': 'mu' is given more than once"),
            ("1mu=1", "'1mu' is not a parameter name"),
            (
                "vumat_density=1",
                "names starting with 'vumat_' are the adapters'",
            ),
            ("umat_x=1", "names starting with 'umat_' are the adapters'"),
            ("mu=inf", "the default inf is not finite"),
            ("mu=1:P\"a", "the unit 'P\"a' holds the character '\"'"),
            ("mu=1,", "'' is not a parameter name"),
        ] {
            let error = Prop::parse_list(text).unwrap_err().to_string();
            assert!(error.contains(expected), "{text}: {error}");
        }
    }

    fn build(name: &str, source: &str, nstatev: usize, fiber: FiberConvention) -> VumatBuild {
        VumatBuild {
            source: source.into(),
            name: name.into(),
            cmname: None,
            props: Vec::new(),
            nstatev,
            statev_initial: Vec::new(),
            fiber,
            out: "lib.so".into(),
            replace: false,
            subroutine: Subroutine::Vumat,
            tangent: TangentSource::Ddsdde,
        }
    }

    #[test]
    fn options_are_checked_before_compiling() {
        let ok = build("my-muscle", "muscle.for", 3, FiberConvention::State);
        ok.check().unwrap();
        assert_eq!(ok.cmname(), "MY-MUSCLE");
        for (b, expected) in [
            (
                build("my muscle", "m.f", 0, FiberConvention::None),
                "--name 'my muscle'",
            ),
            (
                build("m", "m.c", 0, FiberConvention::None),
                "m.c: not a Fortran file name",
            ),
            (
                build("m", "m.f", 2, FiberConvention::State),
                "--fiber state puts the fiber direction into state variables 1 to 3, but \
                 --nstatev is 2",
            ),
            (
                build("m", "m.f90", 20_000, FiberConvention::None),
                "--nstatev 20000",
            ),
            (
                VumatBuild {
                    subroutine: Subroutine::Umat,
                    ..build("m", "m.f", 0, FiberConvention::Orientation)
                },
                "--fiber orientation is for VUMATs",
            ),
            (
                VumatBuild {
                    statev_initial: vec![1.0, 1.0],
                    ..build("m", "m.f", 1, FiberConvention::None)
                },
                "--statev-initial gives 2 values, more than --nstatev 1",
            ),
        ] {
            let error = b.check().unwrap_err().to_string();
            assert!(error.contains(expected), "{error}");
        }
    }
}
