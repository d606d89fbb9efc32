//! Reading a scene file: TOML syntax and the shape of every table, with errors that name
//! the line, the column and the key, and suggest the nearest valid key.

use std::path::Path;

use super::error::{Locator, SceneError, suggestion};
use super::format::{SCHEMA_VERSION, SceneFile};

/// Read and parse the scene at `path`.
pub fn read_scene_file(path: &Path) -> Result<(SceneFile, Locator), SceneError> {
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_scene(&text, path)
}

/// Parse scene `text` read from `path` (used in messages only).
pub fn parse_scene(text: &str, path: &Path) -> Result<(SceneFile, Locator), SceneError> {
    let locator = Locator::new(path, text);
    let scene: SceneFile = toml::from_str(text).map_err(|error| {
        let message = explain(error.message());
        match error.span() {
            Some(span) => locator.error(span, message),
            None => locator.whole(message),
        }
    })?;
    if *scene.schema_version.get_ref() != SCHEMA_VERSION {
        return Err(locator.error(
            scene.schema_version.span(),
            format!(
                "schema_version {} is not supported: this program reads version {SCHEMA_VERSION}",
                scene.schema_version.get_ref()
            ),
        ));
    }
    Ok((scene, locator))
}

/// serde's message, with the nearest valid key suggested for an unknown one
/// ("unknown field `sise`, expected one of `generator`, `size`, `divisions`").
fn explain(message: &str) -> String {
    let message = message.trim();
    let unknown = ["unknown field `", "unknown variant `"]
        .iter()
        .find_map(|prefix| message.strip_prefix(prefix));
    let Some(rest) = unknown else {
        return message.to_string();
    };
    let Some((given, expected)) = rest.split_once('`') else {
        return message.to_string();
    };
    let candidates: Vec<&str> = expected
        .split(['`', ','])
        .map(str::trim)
        .filter(|s| !s.is_empty() && !s.starts_with("expected") && *s != "or")
        .collect();
    format!("{message}{}", suggestion(given, candidates))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unknown_key_gets_the_nearest_valid_one() {
        let explained =
            explain("unknown field `sise`, expected one of `generator`, `size`, `divisions`");
        assert!(explained.ends_with("(did you mean `size`?)"), "{explained}");
        let plain = explain("invalid type: string \"a\", expected f64");
        assert_eq!(plain, "invalid type: string \"a\", expected f64");
    }
}
