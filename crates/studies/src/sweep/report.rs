//! What a finished sweep reports: the count of runs and failures on the terminal
//! ([`report`]) and the sensitivities of every output to every varied parameter
//! (`sensitivity.csv`, `sensitivity.png`, [`write_sensitivities`]), from the rows of
//! `sweep.csv` alone (so a merged table of shards reports the same).

use std::path::Path;

use anyhow::Result;

use musclefem_io::PendingFile;
use musclefem_io::csv::format_number;
use musclefem_io::plot::stage_bar_png;

use super::run::Outcome;
use super::sensitivity::{normalised_sensitivities, sensitivity_chart};
use super::study::Output;
use super::table::Record;

/// `sensitivity.csv` (parameter, output, sensitivity) and `sensitivity.png` from the
/// finished runs, and the ranking on the terminal.
pub(super) fn write_sensitivities(
    out: &Path,
    title: &str,
    names: &[String],
    study_outputs: Vec<Output>,
    records: &[Record],
) -> Result<()> {
    let varied = |j: usize| {
        let first = records.first().map(|r| r.values[j]);
        records.iter().any(|r| Some(r.values[j]) != first)
    };
    if !(0..names.len()).any(varied) {
        println!("  no parameter takes two values: no sensitivities");
        return Ok(());
    }
    // In run order, so that the regression's sums (and sensitivity.csv) do not depend on
    // which run finished first.
    let mut records: Vec<&Record> = records.iter().collect();
    records.sort_by_key(|r| r.run);
    let mut outputs = Vec::new();
    let largest = |k: usize| {
        records
            .iter()
            .filter_map(|r| match &r.outcome {
                Outcome::Finished { outputs, .. } => outputs[k],
                Outcome::Failed { .. } => None,
            })
            .fold(0.0, |m: f64, y| m.max(y.abs()))
    };
    let scale = (0..study_outputs.len()).map(largest).fold(0.0, f64::max);
    for (k, output) in study_outputs.into_iter().enumerate() {
        // A reaction on a symmetry plane is zero up to round-off: its relative changes are
        // noise, not a sensitivity.
        if largest(k) <= NEGLIGIBLE_OUTPUT * scale {
            println!(
                "  {}: at most {:.3e} in every run, below {NEGLIGIBLE_OUTPUT:e} of the largest \
                 output ({scale:.3e}): no sensitivity reported",
                output.description,
                largest(k)
            );
            continue;
        }
        let runs: Vec<(Vec<f64>, f64)> = records
            .iter()
            .filter_map(|r| match &r.outcome {
                Outcome::Finished { outputs, .. } => outputs[k].map(|y| (r.values.clone(), y)),
                Outcome::Failed { .. } => None,
            })
            .collect();
        match normalised_sensitivities(&runs) {
            Some(s) => outputs.push((output.column, output.description, s)),
            None => println!(
                "  {}: {} finished runs cannot determine the sensitivities of {} parameters",
                output.description,
                runs.len(),
                names.len()
            ),
        }
    }
    if outputs.is_empty() {
        return Ok(());
    }
    let mut csv = String::from("parameter,output,sensitivity\n");
    for (column, output, values) in &outputs {
        let mut ranked: Vec<(&String, f64)> = names
            .iter()
            .zip(values)
            .filter_map(|(n, s)| s.map(|s| (n, s)))
            .collect();
        ranked.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
        let text: Vec<String> = ranked.iter().map(|(n, s)| format!("{n} {s:+.3}")).collect();
        println!("  sensitivity of the {output}: {}", text.join(", "));
        for (name, s) in &ranked {
            csv.push_str(&format!("{name},{column},{}\n", format_number(*s)));
        }
    }
    let finished = records.iter().filter(|r| r.outcome.is_finished()).count();
    let title = format!("{title}, {finished} finished runs");
    let series: Vec<(&str, Vec<Option<f64>>)> = outputs
        .iter()
        .map(|(_, name, s)| (name.as_str(), s.clone()))
        .collect();
    let chart = sensitivity_chart(&title, names, &series);
    let csv_path = out.join(SENSITIVITY_CSV);
    let png_path = out.join(SENSITIVITY_PNG);
    let staged = [
        PendingFile::stage_bytes(&csv_path, csv.as_bytes())?,
        stage_bar_png(&png_path, &chart)?,
    ];
    for file in staged {
        file.commit()?;
    }
    println!(
        "sensitivities: {} and {}",
        csv_path.display(),
        png_path.display()
    );
    Ok(())
}

/// The count of runs and failures, and each failure's error, on the terminal.
pub(super) fn report(records: &[Record], table_path: &Path) {
    let mut records: Vec<&Record> = records.iter().collect();
    records.sort_by_key(|r| r.run);
    let failed = records.iter().filter(|r| !r.outcome.is_finished()).count();
    let wall: f64 = records.iter().map(|r| r.outcome.wall_time()).sum();
    println!(
        "{} runs ({} failed; {:.1} s of run time in all): {}",
        records.len(),
        failed,
        wall,
        table_path.display()
    );
    for record in records.iter().filter(|r| !r.outcome.is_finished()) {
        if let Outcome::Failed { error, .. } = &record.outcome {
            println!("  run {} failed: {error}", record.run);
        }
    }
}

/// Outputs whose magnitude stays below this fraction of the largest output's get no
/// sensitivity (see `write_sensitivities`).
const NEGLIGIBLE_OUTPUT: f64 = 1e-4;

pub(super) const SENSITIVITY_CSV: &str = "sensitivity.csv";
/// What the rows of `sweep.csv` were made from ([`Study::fingerprint`]): a resumed sweep
/// must have the same.
pub(super) const SWEEP_BASE: &str = "sweep_base.txt";
/// The line of `sweep_base.txt` that gives the number of runs in the design.
pub(super) const DESIGN_SIZE: &str = "runs in the design = ";
pub(super) const SENSITIVITY_PNG: &str = "sensitivity.png";
