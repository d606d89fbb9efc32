//! A part's recorded activation (`[parts.activation]`): the scene's words turned into a
//! [`ActivationHistory`] the part's material takes as a typed input
//! ([`musclefem_materials::Material::with_activation_history`]).
//!
//! Sources: an amplitude of the scene, a column of a CSV file (read with
//! [`crate::delimited`]: byte-order mark, `,` `;` or tab, decimal commas), or a column of
//! an OpenSim storage file (`.sto`, `.mot`). The values are activations in [0, 1], or
//! with `excitation = true` excitations that first-order activation dynamics turn into
//! activation (time constants `activation_time_constant`, `deactivation_time_constant`).

use std::path::Path;
use std::sync::Arc;

use toml::Spanned;

use musclefem_materials::{ActivationDynamics, ActivationHistory, Material};

use super::amplitudes::Amplitudes;
use super::error::{Locator, SceneError, suggestion};
use super::format::ActivationEntry;
use crate::delimited::parse_delimited;
use crate::opensim_storage::parse_storage;

/// The history `entry` of part `part` describes.
pub fn activation_history(
    entry: &Spanned<ActivationEntry>,
    part: &str,
    amplitudes: &Amplitudes,
    locator: &Locator,
) -> Result<ActivationHistory, SceneError> {
    let span = entry.span();
    let entry = entry.get_ref();
    let at = |span: std::ops::Range<usize>, message: String| {
        locator.error(span, format!("part '{part}' activation: {message}"))
    };
    let (source, mut samples) = match (&entry.amplitude, &entry.file) {
        (Some(name), None) => {
            for (key, given) in [
                ("column", entry.column.as_ref().map(Spanned::span)),
                ("time_column", entry.time_column.as_ref().map(Spanned::span)),
            ] {
                if let Some(key_span) = given {
                    return Err(at(
                        key_span,
                        format!("`{key}` is for a file, not an amplitude"),
                    ));
                }
            }
            let samples = amplitudes.knots(name, locator)?;
            (format!("amplitude '{}'", name.get_ref()), samples)
        }
        (None, Some(file)) => {
            let column = entry.column.as_ref().ok_or_else(|| {
                at(
                    span.clone(),
                    "a file needs the `column` of this part".into(),
                )
            })?;
            let time = entry
                .time_column
                .as_ref()
                .map_or("time", |t| t.get_ref().as_str());
            let path = locator.resolve(file.span(), file.get_ref())?;
            let samples = file_column(&path, time, column.get_ref())
                .map_err(|message| at(file.span(), message))?;
            (
                format!("column '{}' of {}", column.get_ref(), file.get_ref()),
                samples,
            )
        }
        _ => {
            return Err(at(
                span,
                "give either `amplitude` or `file` (with `column`)".into(),
            ));
        }
    };
    if let Some(offset) = &entry.time_offset {
        let offset_value = *offset.get_ref();
        if !offset_value.is_finite() {
            return Err(at(
                offset.span(),
                format!("time_offset {offset_value} s is not finite"),
            ));
        }
        for sample in &mut samples {
            sample.0 -= offset_value;
        }
    }
    let constant =
        |value: &Option<Spanned<f64>>, default: f64, key: &str| match (value, entry.excitation) {
            (Some(v), false) => Err(at(
                v.span(),
                format!("`{key}` applies to excitations: add `excitation = true`"),
            )),
            (Some(v), true) => Ok(*v.get_ref()),
            (None, _) => Ok(default),
        };
    let defaults = ActivationDynamics::default();
    let dynamics = ActivationDynamics {
        activation_time_constant: constant(
            &entry.activation_time_constant,
            defaults.activation_time_constant,
            "activation_time_constant",
        )?,
        deactivation_time_constant: constant(
            &entry.deactivation_time_constant,
            defaults.deactivation_time_constant,
            "deactivation_time_constant",
        )?,
    };
    let history = if entry.excitation {
        ActivationHistory::from_excitation(format!("excitation {source}"), samples, dynamics)
    } else {
        ActivationHistory::from_levels(format!("activation {source}"), samples)
    };
    history.map_err(|e| at(span, e.0))
}

/// `material` driven by `history`, or an error naming the part when the material has no
/// activation to drive.
pub fn driven_material(
    material: &Arc<dyn Material>,
    history: Arc<ActivationHistory>,
    part: &str,
    entry: &Spanned<ActivationEntry>,
    locator: &Locator,
) -> Result<Arc<dyn Material>, SceneError> {
    material.with_activation_history(history).ok_or_else(|| {
        locator.error(
            entry.span(),
            format!(
                "part '{part}' activation: its material '{}' has no activation to drive \
                     (use the Hill muscle, model \"hill\")",
                material.name()
            ),
        )
    })
}

/// (time, value) of `column` against `time` in a CSV or OpenSim storage file (`.sto`,
/// `.mot`, or any file with an `endheader` line).
fn file_column(path: &Path, time: &str, column: &str) -> Result<Vec<(f64, f64)>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let storage = text
        .lines()
        .any(|l| l.trim().eq_ignore_ascii_case("endheader"));
    if storage {
        return parse_storage(&text)
            .map_err(|e| format!("{}:{}: {}", path.display(), e.line, e.message))?
            .column(time, column)
            .map_err(|e| format!("{}: {e}", path.display()));
    }
    let table = parse_delimited(&text).map_err(|e| format!("{}:{e}", path.display()))?;
    let index = |wanted: &str| {
        table.names.iter().position(|n| n == wanted).ok_or_else(|| {
            format!(
                "{}: no column '{wanted}'{}; the columns are: {}",
                path.display(),
                suggestion(wanted, table.names.iter().map(String::as_str)),
                table.names.join(", ")
            )
        })
    };
    let (t, v) = (index(time)?, index(column)?);
    table
        .rows
        .iter()
        .map(|row| {
            Ok((
                table
                    .number(row, t)
                    .map_err(|e| format!("{}:{e}", path.display()))?,
                table
                    .number(row, v)
                    .map_err(|e| format!("{}:{e}", path.display()))?,
            ))
        })
        .collect()
}
