//! Errors of the material library. Every variant names what it concerns (material,
//! parameter, point index, plugin path) so that the caller can report it as is.

use std::fmt;
use std::path::PathBuf;

/// Everything that can go wrong when building or updating a material.
#[derive(Debug, Clone, PartialEq)]
pub enum MaterialError {
    /// No material of that name is registered (built-in or loaded plugin).
    UnknownMaterial { name: String, valid: Vec<String> },
    /// The material has no parameter of that name.
    UnknownParameter {
        material: String,
        name: String,
        valid: Vec<String>,
    },
    /// A parameter without default was not given.
    MissingParameter { material: String, name: String },
    /// A parameter value is NaN, infinite where that is not allowed, or outside its range.
    ParameterOutOfRange {
        material: String,
        name: String,
        value: f64,
        range: String,
    },
    /// Two parameters that are valid on their own are inconsistent together (e.g. t1 < t0).
    InconsistentParameters { material: String, reason: String },
    /// The arrays of a point block do not have matching lengths.
    BlockShape {
        what: &'static str,
        expected: usize,
        found: usize,
    },
    /// The step's time or Δt is not finite, or Δt < 0.
    InvalidStep { time: f64, dt: f64 },
    /// A point's input is unusable: non-finite entries, det F ≤ 0, zero fiber direction, bad dt.
    InvalidPoint { point: usize, reason: String },
    /// The material returned a non-finite stress, state or tangent at a point.
    NonFiniteResult {
        material: String,
        point: usize,
        what: &'static str,
    },
    /// A plugin could not be loaded or reported a failure.
    Plugin { path: PathBuf, message: String },
    /// A material defined by the host program (e.g. in Python) failed, or could not be
    /// registered.
    Host { material: String, message: String },
}

impl fmt::Display for MaterialError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MaterialError::UnknownMaterial { name, valid } => write!(
                f,
                "unknown material '{name}'{}; valid materials: {}",
                suggestion(name, valid),
                valid.join(", ")
            ),
            MaterialError::UnknownParameter {
                material,
                name,
                valid,
            } => write!(
                f,
                "material '{material}' has no parameter '{name}'{}; valid parameters: {}",
                suggestion(name, valid),
                valid.join(", ")
            ),
            MaterialError::MissingParameter { material, name } => {
                write!(
                    f,
                    "material '{material}': parameter '{name}' has no default and must be given"
                )
            }
            MaterialError::ParameterOutOfRange {
                material,
                name,
                value,
                range,
            } => write!(
                f,
                "material '{material}': parameter '{name}' = {value} is outside its valid range {range}"
            ),
            MaterialError::InconsistentParameters { material, reason } => {
                write!(f, "material '{material}': {reason}")
            }
            MaterialError::BlockShape {
                what,
                expected,
                found,
            } => write!(
                f,
                "point block: '{what}' has {found} entries, expected {expected}"
            ),
            MaterialError::InvalidStep { time, dt } => write!(
                f,
                "step ending at time {time} s with dt = {dt} s: both must be finite and dt >= 0"
            ),
            MaterialError::InvalidPoint { point, reason } => {
                write!(f, "material point {point}: {reason}")
            }
            MaterialError::NonFiniteResult {
                material,
                point,
                what,
            } => write!(
                f,
                "material '{material}' returned a non-finite {what} at point {point}"
            ),
            MaterialError::Plugin { path, message } => {
                write!(f, "material plugin {}: {message}", path.display())
            }
            MaterialError::Host { material, message } => {
                write!(f, "material '{material}': {message}")
            }
        }
    }
}

impl std::error::Error for MaterialError {}

/// " (did you mean 'x'?)" when one valid name is close to the given one, else "".
fn suggestion(given: &str, valid: &[String]) -> String {
    let best = valid
        .iter()
        .map(|v| (edit_distance(&given.to_lowercase(), &v.to_lowercase()), v))
        .min_by_key(|(d, _)| *d);
    match best {
        Some((d, v)) if d <= 2.max(given.len() / 3) => format!(" (did you mean '{v}'?)"),
        _ => String::new(),
    }
}

/// Levenshtein distance between two strings (counted in chars).
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    let mut current = vec![0; b.len() + 1];
    for (i, ca) in a.chars().enumerate() {
        current[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitution = previous[j] + usize::from(ca != *cb);
            current[j + 1] = substitution.min(previous[j + 1] + 1).min(current[j] + 1);
        }
        std::mem::swap(&mut previous, &mut current);
    }
    previous[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestion_finds_close_names() {
        let valid = vec!["lambda_opt".to_string(), "sigma0".to_string()];
        assert_eq!(
            suggestion("lamda_opt", &valid),
            " (did you mean 'lambda_opt'?)"
        );
        assert_eq!(suggestion("zzz", &valid), "");
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }
}
