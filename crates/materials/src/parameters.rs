//! Material parameters: their declaration (name, unit, default, valid range) and their
//! resolution from a user's name → value map into a checked, ordered set of values.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fmt;

use crate::MaterialError;

/// One end of a parameter's valid range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bound {
    /// No limit on this side.
    Unbounded,
    /// The limit itself is allowed.
    Inclusive(f64),
    /// The limit itself is not allowed (e.g. D > 0).
    Exclusive(f64),
}

/// Declaration of one material parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct ParameterSpec {
    /// Name as written in scene files and on the command line (case-sensitive).
    pub name: Cow<'static, str>,
    /// SI unit, "1" for dimensionless.
    pub unit: Cow<'static, str>,
    /// Value used when the user gives none; `None` makes the parameter required.
    pub default: Option<f64>,
    pub lower: Bound,
    pub upper: Bound,
    /// Whether +∞ / −∞ are acceptable values (e.g. a deactivation time "never").
    pub allow_infinite: bool,
    /// One line: what the parameter means.
    pub description: Cow<'static, str>,
}

impl ParameterSpec {
    /// A finite-valued parameter with a default, for the built-in materials' static tables.
    pub const fn new(
        name: &'static str,
        unit: &'static str,
        default: f64,
        lower: Bound,
        upper: Bound,
        description: &'static str,
    ) -> Self {
        ParameterSpec {
            name: Cow::Borrowed(name),
            unit: Cow::Borrowed(unit),
            default: Some(default),
            lower,
            upper,
            allow_infinite: false,
            description: Cow::Borrowed(description),
        }
    }

    /// The same parameter, allowed to be ±∞ (within its bounds).
    pub const fn allowing_infinity(mut self) -> Self {
        self.allow_infinite = true;
        self
    }

    /// Whether `value` is acceptable for this parameter.
    pub fn accepts(&self, value: f64) -> bool {
        if value.is_nan() || (value.is_infinite() && !self.allow_infinite) {
            return false;
        }
        let above_lower = match self.lower {
            Bound::Unbounded => true,
            Bound::Inclusive(l) => value >= l,
            Bound::Exclusive(l) => value > l,
        };
        let below_upper = match self.upper {
            Bound::Unbounded => true,
            Bound::Inclusive(u) => value <= u,
            Bound::Exclusive(u) => value < u,
        };
        above_lower && below_upper
    }

    /// The valid range in interval notation, e.g. "(0, inf)" or "[0, 1]".
    pub fn range_text(&self) -> String {
        let lower = match self.lower {
            Bound::Unbounded => "(-inf".to_string(),
            Bound::Inclusive(l) => format!("[{l}"),
            Bound::Exclusive(l) => format!("({l}"),
        };
        let upper = match self.upper {
            Bound::Unbounded => "inf)".to_string(),
            Bound::Inclusive(u) => format!("{u}]"),
            Bound::Exclusive(u) => format!("{u})"),
        };
        let finite = if self.allow_infinite { "" } else { ", finite" };
        format!("{lower}, {upper}{finite}")
    }
}

impl fmt::Display for ParameterSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let default = match self.default {
            Some(d) => format!("{d:e}"),
            None => "required".to_string(),
        };
        write!(
            f,
            "{:<16} {:<8} default {:<12} range {:<22} {}",
            self.name,
            format!("[{}]", self.unit),
            default,
            self.range_text(),
            self.description
        )
    }
}

/// Checked parameter values of one material, in the order of its declaration.
#[derive(Debug, Clone, PartialEq)]
pub struct ParameterSet {
    material: String,
    names: Vec<String>,
    values: Vec<f64>,
}

impl ParameterSet {
    /// Resolve `given` against `specs`: unknown names, missing required values, NaN and
    /// out-of-range values are errors that name the parameter and list the valid ones.
    pub fn resolve(
        material: &str,
        specs: &[ParameterSpec],
        given: &BTreeMap<String, f64>,
    ) -> Result<Self, MaterialError> {
        let valid: Vec<String> = specs.iter().map(|s| s.name.to_string()).collect();
        if let Some(unknown) = given.keys().find(|k| !valid.contains(k)) {
            return Err(MaterialError::UnknownParameter {
                material: material.to_string(),
                name: unknown.clone(),
                valid,
            });
        }
        let mut values = Vec::with_capacity(specs.len());
        for spec in specs {
            let value = match (given.get(spec.name.as_ref()), spec.default) {
                (Some(v), _) => *v,
                (None, Some(d)) => d,
                (None, None) => {
                    return Err(MaterialError::MissingParameter {
                        material: material.to_string(),
                        name: spec.name.to_string(),
                    });
                }
            };
            if !spec.accepts(value) {
                return Err(MaterialError::ParameterOutOfRange {
                    material: material.to_string(),
                    name: spec.name.to_string(),
                    value,
                    range: spec.range_text(),
                });
            }
            values.push(value);
        }
        Ok(ParameterSet {
            material: material.to_string(),
            names: valid,
            values,
        })
    }

    /// The value of a declared parameter.
    pub fn get(&self, name: &str) -> Result<f64, MaterialError> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|i| self.values[i])
            .ok_or_else(|| MaterialError::UnknownParameter {
                material: self.material.clone(),
                name: name.to_string(),
                valid: self.names.clone(),
            })
    }

    /// All values in declaration order (what a plugin receives as its property array).
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Parameter names in declaration order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Name of the material these values belong to.
    pub fn material(&self) -> &str {
        &self.material
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPECS: [ParameterSpec; 2] = [
        ParameterSpec::new(
            "D",
            "1/Pa",
            5e-9,
            Bound::Exclusive(0.0),
            Bound::Unbounded,
            "compressibility",
        ),
        ParameterSpec::new(
            "n2",
            "1",
            0.0,
            Bound::Inclusive(0.0),
            Bound::Inclusive(1.0),
            "activation",
        ),
    ];

    fn given(pairs: &[(&str, f64)]) -> BTreeMap<String, f64> {
        pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect()
    }

    #[test]
    fn defaults_fill_missing_values() {
        let set = ParameterSet::resolve("m", &SPECS, &given(&[("n2", 1.0)])).unwrap();
        assert_eq!(set.values(), &[5e-9, 1.0]);
        assert_eq!(set.get("D").unwrap(), 5e-9);
    }

    #[test]
    fn bad_values_name_the_parameter_and_range() {
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let err = ParameterSet::resolve("m", &SPECS, &given(&[("D", bad)])).unwrap_err();
            let text = err.to_string();
            assert!(text.contains("'D'") && text.contains("(0, inf)"), "{text}");
        }
        let err = ParameterSet::resolve("m", &SPECS, &given(&[("n2", 1.5)])).unwrap_err();
        assert!(err.to_string().contains("[0, 1]"), "{err}");
    }

    #[test]
    fn unknown_parameter_lists_valid_ones() {
        let err = ParameterSet::resolve("m", &SPECS, &given(&[("n3", 1.0)])).unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("'n3'") && text.contains("D, n2") && text.contains("did you mean 'n2'")
        );
    }

    #[test]
    fn required_parameter_must_be_given() {
        let mut spec = SPECS[0].clone();
        spec.default = None;
        let err = ParameterSet::resolve("m", &[spec], &given(&[])).unwrap_err();
        assert!(matches!(err, MaterialError::MissingParameter { .. }));
    }
}
