//! The parameters a fit varies: their names checked against the parameter table of the
//! Hill material (elongation) or of the scene's material, their starts (`--start`, else
//! the scene's value, Table 1 or the model's default) and bounds (`--bound`, else the
//! parameter's valid range).

use std::collections::BTreeMap;

use anyhow::{Context, Result, bail};

use musclefem_materials::{Bound, MaterialLibrary, ParameterSpec};

use super::{Base, FitArgs};

/// One fitted parameter: name, start and bounds.
pub(super) struct Unknown {
    pub(super) name: String,
    pub(super) start: f64,
    pub(super) lower: f64,
    pub(super) upper: f64,
}

/// The fitted parameters `params` with their starts (`starts`, NAME=VALUE tokens as
/// `--start` gives them) and bounds, checked against the parameter table of the Hill
/// material (elongation) or of the scene's material.
pub(super) fn unknowns(
    args: &FitArgs,
    base: &Base,
    params: &[String],
    starts: &[String],
) -> Result<Vec<Unknown>> {
    let hill = MaterialLibrary::with_builtins().info("hill")?;
    // The table entry of a fitted name and the start it has unless --start says otherwise.
    let lookup = |name: &str| -> Result<(ParameterSpec, Option<f64>)> {
        match base {
            Base::Elongation(_) => {
                if name == "n2" || name == "t0" {
                    bail!(
                        "--params {name}: the test sets the activation (passive n2 = 0, active n2 = 1)"
                    );
                }
                let Some(spec) = hill.parameters.iter().find(|p| p.name == name) else {
                    let known: Vec<&str> =
                        hill.parameters.iter().map(|p| p.name.as_ref()).collect();
                    bail!(
                        "--params {name}: the Hill muscle has no parameter '{name}' (it has {})",
                        known.join(", ")
                    );
                };
                Ok((spec.clone(), spec.default))
            }
            Base::Scene(study) => {
                let (spec, given) = study.parameter(name).context("--params")?;
                let start = given.or(spec.default);
                Ok((spec, start))
            }
        }
    };
    let mut starts = name_values(starts, "--start")?;
    let mut bounds = name_values(&args.bounds, "--bound")?;
    let mut unknowns: Vec<Unknown> = Vec::new();
    for name in params {
        let name = name.trim();
        let (spec, default_start) = lookup(name)?;
        let spec = &spec;
        if unknowns.iter().any(|u| u.name == name) {
            bail!("--params: '{name}' is given more than once");
        }
        let start = match starts.remove(name) {
            Some(text) => parse_number(&text, "--start", name)?,
            None => default_start
                .with_context(|| format!("--params {name}: give --start {name}=VALUE"))?,
        };
        let (lower, upper) = match bounds.remove(name) {
            Some(text) => {
                let (lo, hi) = text
                    .split_once(':')
                    .with_context(|| format!("--bound {name}={text}: expected NAME=LO:HI"))?;
                let (lo, hi) = (
                    parse_number(lo, "--bound", name)?,
                    parse_number(hi, "--bound", name)?,
                );
                if lo >= hi {
                    bail!("--bound {name}={text}: LO must be below HI");
                }
                (lo, hi)
            }
            None => valid_range(spec, start),
        };
        let acceptable = |bound: f64| bound.is_infinite() || spec.accepts(bound);
        if !(lower..=upper).contains(&start) || !acceptable(lower) || !acceptable(upper) {
            bail!(
                "--params {name}: the start {start} and bounds [{lower}, {upper}] must lie in \
                 the valid range of '{name}' with the start between the bounds"
            );
        }
        unknowns.push(Unknown {
            name: name.to_string(),
            start,
            lower,
            upper,
        });
    }
    for (flag, left) in [("--start", starts), ("--bound", bounds)] {
        if let Some(name) = left.keys().next() {
            bail!("{flag} {name}: '{name}' is not among --params");
        }
    }
    Ok(unknowns)
}

/// NAME=TEXT tokens of `flag` by name.
fn name_values(tokens: &[String], flag: &str) -> Result<BTreeMap<String, String>> {
    let mut map = BTreeMap::new();
    for token in tokens {
        let (name, value) = token
            .split_once('=')
            .with_context(|| format!("{flag} '{token}': expected NAME=..."))?;
        if map
            .insert(name.trim().to_string(), value.trim().to_string())
            .is_some()
        {
            bail!(
                "{flag} '{token}': '{}' is given more than once",
                name.trim()
            );
        }
    }
    Ok(map)
}

fn parse_number(text: &str, flag: &str, name: &str) -> Result<f64> {
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .with_context(|| format!("{flag} {name}: '{}' is not a finite number", text.trim()))
}

/// The parameter's valid range as closed bounds: an open end at l is moved inside by
/// 10⁻⁶ of the start value; an unbounded side stays infinite.
fn valid_range(spec: &ParameterSpec, start: f64) -> (f64, f64) {
    let inset = 1e-6 * start.abs().max(f64::MIN_POSITIVE);
    let lower = match spec.lower {
        Bound::Unbounded => f64::NEG_INFINITY,
        Bound::Inclusive(l) => l,
        Bound::Exclusive(l) => l + inset,
    };
    let upper = match spec.upper {
        Bound::Unbounded => f64::INFINITY,
        Bound::Inclusive(u) => u,
        Bound::Exclusive(u) => u - inset,
    };
    (lower, upper)
}
