//! What a scene file may make the program do beyond reading it: [`Trust`].
//!
//! A scene is data, but two of its keys reach further. A material's `plugin` names a
//! shared library, and loading one runs its code (its constructors run on load, before
//! any function is called). Mesh, fiber and surface file names are opened and, on a
//! parse error, quoted. So by default a scene may not load plugins, and every file it
//! names must lie in the scene's own folder or below it; the user lifts either with
//! `--allow-plugins` / `--allow-outside-paths`. `check` never loads a plugin: it checks
//! the rest of the scene and says which materials it could not check.

use std::ops::Range;
use std::path::{Path, PathBuf};

use super::error::{Locator, SceneError};

/// What to do with a material's `plugin`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PluginPolicy {
    /// Refuse the scene, naming the plugin and `--allow-plugins` (the default).
    #[default]
    Refuse,
    /// Load the library (the user trusts it).
    Load,
    /// Do not load it and check the rest (`check`): the material is stood in for by a
    /// neo-Hookean one, reported in [`super::Model::unchecked_plugins`].
    SkipForCheck,
}

/// The scene's permissions (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Trust {
    pub plugins: PluginPolicy,
    /// Files named by the scene may lie outside its folder.
    pub outside_paths: bool,
}

impl Trust {
    /// The file `name` (from the scene at `locator`, at `span`) as a path relative to the
    /// scene's folder, refused if it leads outside that folder (unless allowed). The check
    /// follows symbolic links and `..`; a file that does not exist is left to the reader.
    pub fn resolve(
        &self,
        locator: &Locator,
        span: Range<usize>,
        name: &str,
    ) -> Result<PathBuf, SceneError> {
        let directory = locator.path().parent().unwrap_or(Path::new("."));
        let path = directory.join(name);
        if self.outside_paths {
            return Ok(path);
        }
        if crate::paths::lies_in_folder(&path, directory) {
            Ok(path)
        } else {
            Err(locator.error(
                span,
                format!(
                    "'{name}' lies outside the scene's folder {}: files a scene names must be \
                     in its folder or below it (pass --allow-outside-paths if you trust this \
                     scene)",
                    directory.display()
                ),
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_outside_the_scene_folder_are_refused_unless_allowed() {
        let root = std::env::temp_dir().join(format!("musclefem-trust-{}", std::process::id()));
        let inner = root.join("scene");
        std::fs::create_dir_all(inner.join("meshes")).unwrap();
        std::fs::write(inner.join("meshes/a.inp"), "").unwrap();
        std::fs::write(root.join("secret.txt"), "").unwrap();
        let locator = Locator::new(&inner.join("model.toml"), "mesh = 1\n");
        let trust = Trust::default();
        assert!(trust.resolve(&locator, 0..4, "meshes/a.inp").is_ok());
        let error = trust
            .resolve(&locator, 0..4, "../secret.txt")
            .unwrap_err()
            .to_string();
        assert!(error.contains("outside the scene's folder"), "{error}");
        assert!(error.contains("model.toml:1:1"), "{error}");
        let open = Trust {
            outside_paths: true,
            ..Trust::default()
        };
        assert!(open.resolve(&locator, 0..4, "../secret.txt").is_ok());
        // A missing file is the reader's error to report.
        assert!(trust.resolve(&locator, 0..4, "../missing.inp").is_ok());
        std::fs::remove_dir_all(&root).unwrap();
    }
}
