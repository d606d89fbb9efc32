//! `musclefem bench --scene FILE`: the step settings of a scene of the user's own against
//! its reference run (see the library's `bench::scene`), written like the problems'.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};

use musclefem_studies::bench::csv::WorkPrecisionRow;
use musclefem_studies::bench::reference::relative_error;
use musclefem_studies::bench::scene::{ERROR_METRIC, SceneProblem};

use super::{machine, pareto_log, progress_bar, say, write_outputs};

pub fn bench_scene(scene_path: &Path, trust: musclefem_io::scene::Trust, out: &Path) -> Result<()> {
    let scene = SceneProblem::load(scene_path, trust)?;
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let (methods, left_out) = scene.matrix();
    let bar = progress_bar(methods.len() as u64 + 1);
    let name = &scene.name;
    let mut log = format!(
        "musclefem bench --scene {}\nmachine: {}\n{name}: {} elements of {}, mean size {:.3} mm\n",
        scene_path.display(),
        machine(),
        scene.model.mesh.element_count(),
        scene.element(),
        1e3 * scene.mean_element_size()
    );
    let reference_step = scene.reference();
    bar.set_message(format!("{name} reference: {}", reference_step.label()));
    let started = Instant::now();
    let reference = scene.run(reference_step).with_context(|| {
        format!(
            "the reference run of {} ({} {}) failed",
            scene_path.display(),
            reference_step.solver().name(),
            reference_step.label()
        )
    })?;
    bar.inc(1);
    let line = format!(
        "{name} reference: {} {} in {:.2} s ({ERROR_METRIC})",
        reference_step.solver().name(),
        reference_step.label(),
        started.elapsed().as_secs_f64()
    );
    say(&bar, &line);
    log += &line;
    log.push('\n');
    let mut rows = Vec::new();
    for step in methods {
        bar.set_message(format!("{name}: {} {}", step.solver().name(), step.label()));
        let started = Instant::now();
        let outcome = scene.run(step);
        let wall_s = started.elapsed().as_secs_f64();
        bar.inc(1);
        let error = outcome
            .as_ref()
            .map_or(f64::NAN, |r| relative_error(r, &reference));
        let line = match &outcome {
            Ok(response) => format!(
                "{name}: {} {}: {wall_s:.3} s, error {error:.3e}{}",
                step.solver().name(),
                step.label(),
                response
                    .warning
                    .as_ref()
                    .map_or(String::new(), |w| format!(" (warning: {w})"))
            ),
            Err(e) => format!(
                "{name}: {} {}: FAILED after {wall_s:.2} s: {e:#}",
                step.solver().name(),
                step.label()
            ),
        };
        say(&bar, &line);
        log += &line;
        log.push('\n');
        rows.push(WorkPrecisionRow {
            problem: name.clone(),
            solver: step.solver().name().to_string(),
            element: scene.element(),
            mesh_size_mm: 1e3 * scene.mean_element_size(),
            step_setting: step.label(),
            wall_s,
            error,
            error_metric: ERROR_METRIC.to_string(),
        });
    }
    bar.finish_and_clear();
    for reason in left_out {
        log += &format!("{name}: left out: {reason}\n");
    }
    log += &pareto_log(name, &rows);
    write_outputs(out, &rows, &log)
}
