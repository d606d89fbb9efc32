//! Scene files: a model (parts, materials, loads, step) in TOML that a user can read,
//! write and rerun. [`load_scene`] reads, checks and builds one; every error names the
//! file and, where it concerns an entry, its line, column and key, with the nearest valid
//! name suggested for a misspelt one. The format is documented in `docs/scene-format.md`.

mod activation;
mod amplitudes;
mod build;
mod describe;
mod error;
mod followers;
mod format;
mod interaction_surfaces;
mod interactions;
mod locking;
pub mod memory;
mod model_run;
mod parse;
mod part_mesh;
mod solver_choice;
mod step;
mod strands;
mod trust;

use std::path::Path;

use musclefem_materials::MaterialLibrary;

pub use build::{Analysis, ELEMENT_NAMES, Model, build_model, element_technology};
pub use error::{Locator, SceneError};
pub use followers::{
    FOLLOWER_KEY, FollowerParameter, FollowerParameters, FollowerRegistration, MotionTable,
    follower_kinds,
};
pub use format::{SCHEMA_VERSION, SceneFile};
pub use interactions::InteractionModel;
pub use locking::{
    LOCKING_BULK_TO_SHEAR, locking_warning, small_strain_bulk_modulus, small_strain_shear_modulus,
};
pub use parse::{parse_scene, read_scene_file};
pub use solver_choice::{AutoSolver, SLOW_MOTION_RATIO, choose_solver, fastest_wave_speed};
pub use step::dissipative_newmark;
pub use trust::{PluginPolicy, Trust};

/// Read the scene at `path` and build its model, with no permissions beyond reading
/// files in its folder (a `plugin` is refused: see [`Trust`]).
pub fn load_scene(path: &Path, library: &mut MaterialLibrary) -> Result<Model, SceneError> {
    load_scene_trusting(path, library, Trust::default())
}

/// [`load_scene`] with the permissions `trust` (plugins loaded into `library` when it
/// allows them).
pub fn load_scene_trusting(
    path: &Path,
    library: &mut MaterialLibrary,
    trust: Trust,
) -> Result<Model, SceneError> {
    let (scene, locator) = read_scene_file(path)?;
    build_model(&scene, &locator.with_trust(trust), library)
}
