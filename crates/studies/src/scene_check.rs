//! What `musclefem check` says of a scene, and the check `musclefem run` makes before it
//! writes anything: the one implementation for the command and the Python module.

use std::path::Path;

use anyhow::{Context, Result};

use musclefem_core::solver::free_motion::refuse_free_motion;
use musclefem_io::scene::Model;

/// An error naming the scene (`name`, its file) if a body of a quasi-static model can
/// move freely (see `musclefem_core::solver::free_motion`).
pub fn refuse_free_body(model: &Model, name: &Path) -> Result<()> {
    refuse_free_motion(
        &model.mesh,
        &model.loads,
        &model.analysis,
        model.interactions.len(),
    )
    .with_context(|| format!("{}", name.display()))
}

/// The report of `musclefem check` on the scene `name` built into `model` (read with
/// `PluginPolicy::SkipForCheck`): "NAME: ok", the materials whose plugin was not loaded,
/// then what the scene holds (parts, nodes and loads, interactions, analysis). An error
/// if a body can move freely.
pub fn check_report(model: &Model, name: &Path) -> Result<String> {
    refuse_free_body(model, name)?;
    let mut report = format!("{}: ok\n", name.display());
    for material in &model.unchecked_plugins {
        report.push_str(&format!(
            "  material {material}: plugin not loaded (check runs no foreign code), its \
             parameters unchecked; `run --allow-plugins` loads it\n"
        ));
    }
    report.push_str(&model.describe());
    Ok(report)
}
