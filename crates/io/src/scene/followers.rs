//! Registered follower kinds: a rigid tie or body whose pose the run sets as it goes
//! (`motion = { follower = "KIND", ... }` in a scene file), built by a kind that a crate
//! registers with `inventory`, as materials are registered.
//!
//! A kind declares its parameters (TOML values: numbers, strings, lists) and builds a
//! [`PoseFollower`] from them ([`FollowerParameters`] reads them, resolving files
//! relative to the scene and naming the file, line and key in every error). Entries with
//! the same `motion` table (the same kind and the same parameters) share one follower: a
//! follower that listens to the run (e.g. a patella pulled by the ties it moves) hears
//! every tie it moves, once per recorded instant.
//!
//! The kinds are those of the crates linked into the program: the knee's
//! (`knee-closed-chain`, `knee-patella`) are registered by `musclefem-studies`; a
//! program that reads scenes with the `io` crate alone knows none.

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::PathBuf;
use std::sync::Arc;

use toml::Spanned;

use musclefem_core::solver::PoseFollower;

use super::error::{Locator, SceneError, suggestion};

/// The `motion` table of a rigid tie or body, each value with its place in the file.
pub type MotionTable = BTreeMap<String, Spanned<toml::Value>>;

/// The key of a `motion` table that names the kind.
pub const FOLLOWER_KEY: &str = "follower";

/// One parameter a follower kind reads from its `motion` table.
#[derive(Debug, Clone, Copy)]
pub struct FollowerParameter {
    pub name: &'static str,
    /// What it is, with its unit and default.
    pub description: &'static str,
}

/// A follower kind's entry in the registry (submitted with `inventory::submit!`).
pub struct FollowerRegistration {
    /// What `follower = "..."` names.
    pub kind: &'static str,
    /// One line: what the follower moves and how.
    pub description: &'static str,
    /// Every parameter the kind accepts (any other key is refused).
    pub parameters: &'static [FollowerParameter],
    /// Build the follower from its parameters.
    pub build: fn(&FollowerParameters<'_>) -> Result<Arc<dyn PoseFollower>, SceneError>,
}

inventory::collect!(FollowerRegistration);

/// The follower kinds registered by the crates linked into the program, sorted by kind.
pub fn follower_kinds() -> Vec<&'static FollowerRegistration> {
    let mut kinds: Vec<&'static FollowerRegistration> = inventory::iter::<FollowerRegistration>
        .into_iter()
        .collect();
    kinds.sort_by_key(|k| k.kind);
    kinds
}

/// The parameters of one `motion` table, as a kind's `build` reads them.
pub struct FollowerParameters<'a> {
    kind: &'a str,
    table: &'a Spanned<MotionTable>,
    locator: &'a Locator,
    tie_names: &'a [String],
    followed_by: &'a [usize],
}

impl<'a> FollowerParameters<'a> {
    /// The kind being built.
    pub fn kind(&self) -> &str {
        self.kind
    }

    /// The rigid ties (indices in the problem's `Loads::rigid_ties`) that this follower
    /// moves (none for a follower of rigid bodies only).
    pub fn followed_by(&self) -> &[usize] {
        self.followed_by
    }

    /// An error about parameter `key` (at its value, or at the table without one),
    /// naming the file, the line and the key.
    pub fn error(&self, key: &str, message: impl std::fmt::Display) -> SceneError {
        let span = self
            .table
            .get_ref()
            .get(key)
            .map_or(self.table.span(), Spanned::span);
        self.locator.error(
            span,
            format!("follower '{}', `{key}`: {message}", self.kind),
        )
    }

    /// An error about the follower as a whole (at its `motion` table).
    pub fn whole_error(&self, message: impl std::fmt::Display) -> SceneError {
        self.locator.error(
            self.table.span(),
            format!("follower '{}': {message}", self.kind),
        )
    }

    fn value(&self, key: &str) -> Option<&'a Spanned<toml::Value>> {
        self.table.get_ref().get(key)
    }

    fn required(&self, key: &str) -> Result<&'a Spanned<toml::Value>, SceneError> {
        self.value(key)
            .ok_or_else(|| self.whole_error(format!("`{key}` is missing")))
    }

    fn as_number(&self, key: &str, value: &toml::Value) -> Result<f64, SceneError> {
        let number = match value {
            toml::Value::Float(x) => *x,
            toml::Value::Integer(i) => *i as f64,
            other => {
                return Err(self.error(key, format!("expected a number, found {other}")));
            }
        };
        if number.is_finite() {
            Ok(number)
        } else {
            Err(self.error(key, format!("{number} is not a finite number")))
        }
    }

    /// Number `key` (an integer is read as a float).
    pub fn number(&self, key: &str) -> Result<f64, SceneError> {
        self.as_number(key, self.required(key)?.get_ref())
    }

    /// Number `key`, or `default` without one.
    pub fn number_or(&self, key: &str, default: f64) -> Result<f64, SceneError> {
        match self.value(key) {
            Some(value) => self.as_number(key, value.get_ref()),
            None => Ok(default),
        }
    }

    /// A list of three numbers `key` (a point or a direction).
    pub fn vector(&self, key: &str) -> Result<[f64; 3], SceneError> {
        self.as_vector(key, self.required(key)?.get_ref())
    }

    /// A list of three numbers `key`, or `default` without one.
    pub fn vector_or(&self, key: &str, default: [f64; 3]) -> Result<[f64; 3], SceneError> {
        match self.value(key) {
            Some(value) => self.as_vector(key, value.get_ref()),
            None => Ok(default),
        }
    }

    fn as_vector(&self, key: &str, value: &toml::Value) -> Result<[f64; 3], SceneError> {
        let items = match value {
            toml::Value::Array(items) if items.len() == 3 => items,
            other => {
                return Err(self.error(key, format!("expected [x, y, z], found {other}")));
            }
        };
        let mut vector = [0.0; 3];
        for (component, item) in vector.iter_mut().zip(items) {
            *component = self.as_number(key, item)?;
        }
        Ok(vector)
    }

    /// Text `key`.
    pub fn text(&self, key: &str) -> Result<&'a str, SceneError> {
        match self.required(key)?.get_ref() {
            toml::Value::String(text) => Ok(text),
            other => Err(self.error(key, format!("expected a string, found {other}"))),
        }
    }

    /// Whether the table gives `key`.
    pub fn has(&self, key: &str) -> bool {
        self.value(key).is_some()
    }

    /// The file `key` names, relative to the scene's folder (and confined to it unless
    /// the scene is trusted, as every file a scene names).
    pub fn file(&self, key: &str) -> Result<PathBuf, SceneError> {
        let name = self.text(key)?;
        self.locator.resolve(self.required(key)?.span(), name)
    }

    /// The rigid ties a list of names `key` names (indices in the problem's ties), or
    /// `None` without the key.
    pub fn ties(&self, key: &str) -> Result<Option<Vec<usize>>, SceneError> {
        let Some(value) = self.value(key) else {
            return Ok(None);
        };
        let toml::Value::Array(items) = value.get_ref() else {
            return Err(self.error(key, "expected a list of rigid tie names"));
        };
        let names = self.tie_names.iter().map(String::as_str);
        items
            .iter()
            .map(|item| {
                let name = item
                    .as_str()
                    .ok_or_else(|| self.error(key, format!("{item} is not a tie's name")))?;
                self.tie_names
                    .iter()
                    .position(|n| n == name)
                    .ok_or_else(|| {
                        self.error(
                            key,
                            format!("no rigid tie '{name}'{}", suggestion(name, names.clone())),
                        )
                    })
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    }
}

/// The follower of each rigid tie (`None`: a prescribed motion).
pub type TieFollowers = Vec<Option<Arc<dyn PoseFollower>>>;

/// The followers of a scene's `motion` tables: one per distinct table.
#[derive(Default)]
pub struct Followers {
    built: Vec<(BTreeMap<String, toml::Value>, Arc<dyn PoseFollower>)>,
}

/// A table without its spans (what makes two tables the same follower).
fn plain(table: &MotionTable) -> BTreeMap<String, toml::Value> {
    table
        .iter()
        .map(|(k, v)| (k.clone(), v.get_ref().clone()))
        .collect()
}

impl Followers {
    /// Build the followers of the rigid ties' `motion` tables (`tables[i]` is tie i's,
    /// `None` for a tie with a prescribed motion; `tie_names` in the same order): one per
    /// distinct table, told which ties it moves.
    pub fn of_ties(
        tables: &[Option<&Spanned<MotionTable>>],
        tie_names: &[String],
        locator: &Locator,
    ) -> Result<(Self, TieFollowers), SceneError> {
        let mut followers = Followers::default();
        let mut of_tie = vec![None; tables.len()];
        for (index, table) in tables.iter().enumerate() {
            let Some(table) = table else { continue };
            let key = plain(table.get_ref());
            if let Some((_, built)) = followers.built.iter().find(|(k, _)| *k == key) {
                of_tie[index] = Some(built.clone());
                continue;
            }
            let followed_by: Vec<usize> = tables
                .iter()
                .enumerate()
                .filter(|(_, t)| t.is_some_and(|t| plain(t.get_ref()) == key))
                .map(|(i, _)| i)
                .collect();
            let built = build(table, locator, tie_names, &followed_by)?;
            followers.built.push((key, built.clone()));
            of_tie[index] = Some(built);
        }
        Ok((followers, of_tie))
    }

    /// The follower of a rigid body's `motion` table: the ties' follower of the same
    /// table if there is one (the body moves with those ties), else a new one.
    pub fn of_body(
        &mut self,
        table: &Spanned<MotionTable>,
        tie_names: &[String],
        locator: &Locator,
    ) -> Result<Arc<dyn PoseFollower>, SceneError> {
        let key = plain(table.get_ref());
        if let Some((_, built)) = self.built.iter().find(|(k, _)| *k == key) {
            return Ok(built.clone());
        }
        let built = build(table, locator, tie_names, &[])?;
        self.built.push((key, built.clone()));
        Ok(built)
    }
}

/// The follower of one `motion` table: its kind looked up, its keys checked against the
/// kind's parameters, then built.
fn build(
    table: &Spanned<MotionTable>,
    locator: &Locator,
    tie_names: &[String],
    followed_by: &[usize],
) -> Result<Arc<dyn PoseFollower>, SceneError> {
    let Some(kind_value) = table.get_ref().get(FOLLOWER_KEY) else {
        return Err(locator.error(
            table.span(),
            format!("`motion` needs `{FOLLOWER_KEY} = \"KIND\"` (the follower's kind)"),
        ));
    };
    let kinds = follower_kinds();
    let known = || {
        if kinds.is_empty() {
            "none (the program registers no follower kind)".to_string()
        } else {
            kinds.iter().map(|k| k.kind).collect::<Vec<_>>().join(", ")
        }
    };
    let at = |span: Range<usize>, message: String| locator.error(span, message);
    let Some(kind) = kind_value.get_ref().as_str() else {
        return Err(at(
            kind_value.span(),
            format!("`{FOLLOWER_KEY}` must name a kind; known: {}", known()),
        ));
    };
    let Some(registration) = kinds.iter().find(|k| k.kind == kind) else {
        return Err(at(
            kind_value.span(),
            format!(
                "`{FOLLOWER_KEY}`: unknown follower kind '{kind}'{}; known: {}",
                suggestion(kind, kinds.iter().map(|k| k.kind)),
                known()
            ),
        ));
    };
    let accepted = registration.parameters.iter().map(|p| p.name);
    for (key, value) in table.get_ref() {
        if key != FOLLOWER_KEY && !accepted.clone().any(|name| name == key) {
            return Err(at(
                value.span(),
                format!(
                    "follower '{kind}' has no parameter `{key}`{}; it takes: {}",
                    suggestion(key, accepted.clone()),
                    accepted.clone().collect::<Vec<_>>().join(", ")
                ),
            ));
        }
    }
    (registration.build)(&FollowerParameters {
        kind: registration.kind,
        table,
        locator,
        tie_names,
        followed_by,
    })
}

/// A rigid tie's or body's prescribed motion as written: `translation`,
/// `translation_amplitude` and `rotation`.
pub type PrescribedMotion<'a> = (
    &'a [f64; 3],
    &'a Option<Spanned<String>>,
    &'a Option<super::format::RotationEntry>,
);

/// Refuse a prescribed motion beside a follower's `motion` table.
pub fn followed_alone(
    table: &Spanned<MotionTable>,
    (translation, translation_amplitude, rotation): PrescribedMotion<'_>,
    locator: &Locator,
) -> Result<(), SceneError> {
    if *translation != [0.0; 3] || translation_amplitude.is_some() || rotation.is_some() {
        return Err(locator.error(
            table.span(),
            "`motion` sets the whole pose: remove `translation`, `translation_amplitude` and \
             `rotation` (or the `motion`)",
        ));
    }
    Ok(())
}
