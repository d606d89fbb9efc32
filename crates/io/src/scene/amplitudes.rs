//! The scene's `[[amplitudes]]` by name: each checked once (knots of two numbers, times
//! increasing, a name defined once), then looked up by the loads, motions and
//! activations that name one.

use std::collections::BTreeMap;

use toml::Spanned;

use musclefem_materials::Amplitude;

use super::error::{Locator, SceneError, suggestion};
use super::format::{AmplitudeEntry, SceneFile};

/// The amplitudes of a scene by name.
pub(super) struct Amplitudes<'a> {
    entries: BTreeMap<String, &'a AmplitudeEntry>,
}

impl<'a> Amplitudes<'a> {
    /// Every amplitude of `scene`, checked.
    pub fn new(scene: &'a SceneFile, locator: &Locator) -> Result<Self, SceneError> {
        let mut entries: BTreeMap<String, &AmplitudeEntry> = BTreeMap::new();
        for entry in &scene.amplitudes {
            let name = entry.name.get_ref();
            let points = entry.points.get_ref();
            if let Some(k) = points.iter().position(|p| p.len() != 2) {
                return Err(locator.error(
                    entry.points.span(),
                    format!(
                        "amplitude '{name}': knot {} has {} values; a knot is [time, value]",
                        k + 1,
                        points[k].len()
                    ),
                ));
            }
            Amplitude::new(points.iter().map(|p| (p[0], p[1])).collect()).map_err(|e| {
                locator.error(entry.points.span(), format!("amplitude '{name}': {}", e.0))
            })?;
            if entries.insert(name.clone(), entry).is_some() {
                return Err(locator.error(
                    entry.name.span(),
                    format!("amplitude '{name}' is defined twice"),
                ));
            }
        }
        Ok(Amplitudes { entries })
    }

    /// The knots (time [s], value) of the amplitude `name` names, or an error at its
    /// place suggesting the nearest name.
    pub fn knots(
        &self,
        name: &Spanned<String>,
        locator: &Locator,
    ) -> Result<Vec<(f64, f64)>, SceneError> {
        let entry = self.entries.get(name.get_ref()).ok_or_else(|| {
            locator.error(
                name.span(),
                format!(
                    "unknown amplitude '{}'{}",
                    name.get_ref(),
                    suggestion(name.get_ref(), self.entries.keys().map(String::as_str))
                ),
            )
        })?;
        Ok(entry
            .points
            .get_ref()
            .iter()
            .map(|p| (p[0], p[1]))
            .collect())
    }
}
