//! `musclefem run SCENE --tolerance PERCENT`: the cheapest step setting of the scene that
//! `musclefem bench --scene SCENE` measured within the tolerance.

use std::path::Path;

use anyhow::{Context, Result, bail};

use musclefem_io::scene::Analysis;
use musclefem_studies::bench::method::millimetres;
use musclefem_studies::bench::scene::SceneProblem;
use musclefem_studies::bench::select;

/// The analysis of the cheapest measured run of `scene` within `percent` [%] in the
/// work–precision table `table`, and why (one sentence). Errors when the table is
/// missing, has no run of the scene or none measured on its mesh and elements, or none
/// within the tolerance.
pub fn analysis_within(
    scene: &SceneProblem,
    scene_path: &Path,
    percent: f64,
    table: &Path,
) -> Result<(Analysis, String)> {
    if !(percent.is_finite() && percent > 0.0) {
        bail!("--tolerance {percent} must be a positive percentage");
    }
    let measure = format!(
        "musclefem bench --scene {} --out {}",
        scene_path.display(),
        table.parent().unwrap_or(Path::new(".")).display()
    );
    let text = std::fs::read_to_string(table).with_context(|| {
        format!(
            "--tolerance needs the measured work–precision table {} (write it with `{measure}`)",
            table.display()
        )
    })?;
    let rows: Vec<_> = select::read_table(&text)
        .with_context(|| format!("reading {}", table.display()))?
        .into_iter()
        .filter(|r| r.problem == scene.name)
        .collect();
    if rows.is_empty() {
        bail!(
            "{} has no runs of the scene '{}' (write them with `{measure}`)",
            table.display(),
            scene.name
        );
    }
    // The table holds sizes in millimetres to three decimals: compare them as written.
    let (element, size_mm) = (scene.element(), millimetres(scene.mean_element_size()));
    let rows: Vec<_> = rows
        .into_iter()
        .filter(|r| r.element == element && millimetres(1e-3 * r.mesh_size_mm) == size_mm)
        .collect();
    if rows.is_empty() {
        bail!(
            "the runs of '{}' in {} were measured on another mesh or other elements than the \
             scene's ({element}, {size_mm} mm): measure them again with `{measure}`",
            scene.name,
            table.display()
        );
    }
    let Some(row) = select::cheapest_within(&rows, &scene.name, 1e-2 * percent) else {
        let best = rows
            .iter()
            .filter(|r| r.error.is_finite())
            .map(|r| r.error)
            .fold(f64::INFINITY, f64::min);
        bail!(
            "no run of '{}' in {} meets {percent} % (the most accurate is off by {:.2e} %): \
             loosen --tolerance, or run the scene as it is",
            scene.name,
            table.display(),
            100.0 * best
        );
    };
    let step = select::step_of(row)?;
    let why = format!(
        "--tolerance {percent} %: {} {} ({:.2e} % error in {:.2} s), the cheapest within it of \
         the {} measured runs of '{}' in {}",
        step.solver().name(),
        step.label(),
        100.0 * row.error,
        row.wall_s,
        rows.len(),
        scene.name,
        table.display()
    );
    Ok((scene.analysis(step), why))
}
