//! Errors of reading a scene: always the file, and where known the line, column and key.

use std::ops::Range;
use std::path::{Path, PathBuf};

use super::trust::Trust;

/// Why a scene cannot be read or built. Displays as `FILE:LINE:COLUMN: message`.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{}: cannot read the scene: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}:{line}:{column}: {message}", path.display())]
    At {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },
    #[error("{}: {message}", path.display())]
    Whole { path: PathBuf, message: String },
}

/// Maps byte offsets of a scene text to 1-based lines and columns.
#[derive(Debug, Clone)]
pub struct Locator {
    path: PathBuf,
    line_starts: Vec<usize>,
    /// What the scene may reach beyond its text (plugins, files outside its folder).
    trust: Trust,
}

impl Locator {
    pub fn new(path: &Path, text: &str) -> Self {
        let line_starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Locator {
            path: path.to_path_buf(),
            line_starts,
            trust: Trust::default(),
        }
    }

    /// The same file with the permissions `trust` (default: none, see [`Trust`]).
    pub fn with_trust(mut self, trust: Trust) -> Self {
        self.trust = trust;
        self
    }

    /// The scene's permissions.
    pub fn trust(&self) -> Trust {
        self.trust
    }

    /// The file `name` the scene names at `span`, relative to the scene's folder and
    /// confined to it unless the trust allows otherwise ([`Trust::resolve`]).
    pub fn resolve(&self, span: Range<usize>, name: &str) -> Result<PathBuf, SceneError> {
        self.trust.resolve(self, span, name)
    }

    /// The file name as given.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// An error at the start of `span` (a byte range of the text).
    pub fn error(&self, span: Range<usize>, message: impl Into<String>) -> SceneError {
        let line = self.line_starts.partition_point(|&s| s <= span.start);
        let column = span.start - self.line_starts[line.max(1) - 1] + 1;
        SceneError::At {
            path: self.path.clone(),
            line: line.max(1),
            column,
            message: message.into(),
        }
    }

    /// An error about the scene as a whole.
    pub fn whole(&self, message: impl Into<String>) -> SceneError {
        SceneError::Whole {
            path: self.path.clone(),
            message: message.into(),
        }
    }
}

/// Levenshtein distance between two strings (characters).
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut current = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            current[j + 1] = (previous[j] + usize::from(ca != *cb))
                .min(previous[j + 1] + 1)
                .min(current[j] + 1);
        }
        previous = current;
    }
    previous[b.len()]
}

/// The candidate nearest to `given` if it is close enough to be a likely typo
/// (at most a third of the characters differ).
pub fn nearest<'a>(given: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    candidates
        .into_iter()
        .map(|c| (edit_distance(&given.to_lowercase(), &c.to_lowercase()), c))
        .filter(|(d, c)| *d <= c.chars().count().max(given.chars().count()).div_ceil(3))
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// " (did you mean `x`?)" for the nearest candidate, or "".
pub fn suggestion<'a>(given: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    nearest(given, candidates)
        .map(|c| format!(" (did you mean `{c}`?)"))
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_and_columns_are_one_based() {
        let locator = Locator::new(Path::new("s.toml"), "a = 1\nbb = 2\n");
        let message = locator.error(9..10, "here").to_string();
        assert_eq!(message, "s.toml:2:4: here");
        assert_eq!(locator.error(0..1, "x").to_string(), "s.toml:1:1: x");
    }

    #[test]
    fn the_nearest_key_is_suggested_only_when_close() {
        assert_eq!(nearest("sise", ["size", "divisions"]), Some("size"));
        assert_eq!(nearest("density", ["size", "divisions"]), None);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }
}
