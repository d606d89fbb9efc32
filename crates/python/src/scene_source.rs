//! Where a `musclefem.Scene` comes from: a scene file, or a dict written out as TOML
//! ([`crate::toml_text`]). Either way the scene is its text, read once, and a path: the
//! file's, or for a dict a name in its base directory, against which the files the scene
//! names (meshes, fibers, surfaces) are found.

use std::path::{Path, PathBuf};

use musclefem_io::scene::{Model, SceneError, Trust, build_model, parse_scene};

use crate::toml_text::TomlText;

/// The file name a dict scene is given in its base directory (in messages, the run
/// directory's `scene.toml` is its text).
pub(crate) const DICT_SCENE_NAME: &str = "<dict>.toml";

/// A scene's text and where it was read from.
#[derive(Debug, Clone)]
pub(crate) struct SceneSource {
    /// The scene file, or `BASE_DIR/<dict>.toml` for a dict.
    pub path: PathBuf,
    pub text: String,
    /// For a dict: the key of every line of `text`, to name it in errors.
    pub dict: Option<TomlText>,
}

impl SceneSource {
    /// The scene file at `path`, read now.
    pub fn file(path: &Path) -> anyhow::Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Ok(SceneSource {
            path: path.to_path_buf(),
            text,
            dict: None,
        })
    }

    /// The scene of a dict written as `toml`, its files relative to `base_dir`.
    pub fn dict(toml: TomlText, base_dir: &Path) -> Self {
        SceneSource {
            path: base_dir.join(DICT_SCENE_NAME),
            text: toml.text.clone(),
            dict: Some(toml),
        }
    }

    /// What messages call the scene: its file, or `Scene.from_dict`.
    pub fn name(&self) -> String {
        match self.dict {
            None => self.path.display().to_string(),
            Some(_) => "Scene.from_dict".to_string(),
        }
    }

    /// Read, check and build the model with the permissions `trust`, with the materials
    /// of `library` (the built-in ones and those registered from Python).
    pub fn load(&self, trust: Trust) -> anyhow::Result<Model> {
        let mut library = crate::library::material_library();
        parse_scene(&self.text, &self.path)
            .and_then(|(scene, locator)| {
                build_model(&scene, &locator.with_trust(trust), &mut library)
            })
            .map_err(|error| self.explain(error))
    }

    /// An error of the scene reader; for a dict, with the key of its line instead of the
    /// line of the generated text.
    pub fn explain(&self, error: SceneError) -> anyhow::Error {
        let Some(dict) = &self.dict else {
            return error.into();
        };
        match error {
            SceneError::At { line, message, .. } => match dict.key_at(line) {
                Some(key) => anyhow::anyhow!("Scene.from_dict: {key}: {message}"),
                None => anyhow::anyhow!("Scene.from_dict: {message}"),
            },
            SceneError::Whole { message, .. } => anyhow::anyhow!("Scene.from_dict: {message}"),
            error => error.into(),
        }
    }
}
