//! `musclefem sweep merge SHARD_DIR... --out DIR`: the tables of a sweep's shards
//! (`sweep --shard K/N`, one job of a job array each) joined into one `sweep.csv`, with the
//! sensitivities of the whole sweep.
//!
//! The shards must be of one sweep: the same columns and the same base (`sweep_base.txt`,
//! the base's fingerprint). A run found in two shards must have the same parameter values
//! in both (the first shard's row is kept). Runs missing from every shard are named: rerun
//! their shard (it resumes) and merge again.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

use musclefem_io::PendingFile;

use super::report::{
    DESIGN_SIZE, SENSITIVITY_CSV, SENSITIVITY_PNG, SWEEP_BASE, report, write_sensitivities,
};
use super::study::Output;
use super::table::{self, Columns, Record, SWEEP_CSV};

#[derive(Debug, clap::Args)]
pub struct MergeArgs {
    /// The output directories of the shards (each holds a sweep.csv and sweep_base.txt).
    #[arg(value_name = "SHARD_DIR", required = true)]
    pub shards: Vec<PathBuf>,
    /// Where the merged sweep.csv and the sensitivities go.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Replace a sweep.csv already in --out.
    #[arg(long)]
    pub force: bool,
}

/// One shard's table.
struct ShardTable {
    base: String,
    columns: Columns,
    records: Vec<Record>,
}

fn read_shard(dir: &Path) -> Result<ShardTable> {
    let path = dir.join(SWEEP_CSV);
    let text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let header = text.lines().next().unwrap_or_default();
    let Some(columns) = table::columns_of(header) else {
        bail!(
            "{}: not a sweep table (its header is '{header}')",
            path.display()
        );
    };
    let records = table::parse_table(&text, &path, &columns)?;
    let base_path = dir.join(SWEEP_BASE);
    let base = std::fs::read_to_string(&base_path).with_context(|| {
        format!(
            "reading {} (what the rows were made from)",
            base_path.display()
        )
    })?;
    Ok(ShardTable {
        base,
        columns,
        records,
    })
}

pub fn merge(args: &MergeArgs) -> Result<()> {
    let mut shards = args
        .shards
        .iter()
        .map(|dir| -> Result<(&PathBuf, ShardTable)> { Ok((dir, read_shard(dir)?)) });
    let (first_dir, first) = shards.next().expect("clap requires a shard")?;
    let mut runs: BTreeMap<usize, (Record, &PathBuf)> = BTreeMap::new();
    let mut all = vec![(first_dir, first.records)];
    for shard in shards {
        let (dir, shard): (&PathBuf, ShardTable) = shard?;
        if shard.columns != first.columns {
            bail!(
                "{}: its columns are not those of {} (another sweep)",
                dir.join(SWEEP_CSV).display(),
                first_dir.join(SWEEP_CSV).display()
            );
        }
        if shard.base != first.base {
            bail!(
                "{}: its rows were made from another base ({}) than those of {} ({})",
                dir.display(),
                shard.base.trim(),
                first_dir.display(),
                first.base.trim()
            );
        }
        all.push((dir, shard.records));
    }
    for (dir, records) in all {
        for record in records {
            match runs.get(&record.run) {
                Some((kept, kept_dir)) if kept.values != record.values => bail!(
                    "run {} has parameters {:?} in {} and {:?} in {}: the shards are of \
                     different designs",
                    record.run,
                    kept.values,
                    kept_dir.display(),
                    record.values,
                    dir.display()
                ),
                Some(_) => {}
                None => {
                    runs.insert(record.run, (record, dir));
                }
            }
        }
    }
    let records: Vec<Record> = runs.into_values().map(|(record, _)| record).collect();

    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let _lock = musclefem_io::output::OutputLock::acquire(&args.out)?;
    let table_path = args.out.join(SWEEP_CSV);
    if table_path.exists() && !args.force {
        bail!(
            "{}: a sweep table is already there (use --force to replace it)",
            table_path.display()
        );
    }
    for stale in [SENSITIVITY_CSV, SENSITIVITY_PNG] {
        let _ = std::fs::remove_file(args.out.join(stale));
    }
    let text = table::format_table(&first.columns, &records);
    PendingFile::stage_bytes(&args.out.join(SWEEP_BASE), first.base.as_bytes())?.commit()?;
    PendingFile::stage_bytes(&table_path, text.as_bytes())?.commit()?;

    let design_size = first
        .base
        .lines()
        .find_map(|line| line.strip_prefix(DESIGN_SIZE)?.trim().parse::<usize>().ok())
        .unwrap_or_else(|| records.iter().map(|r| r.run + 1).max().unwrap_or(0));
    let missing: Vec<String> = (0..design_size)
        .filter(|run| !records.iter().any(|r| r.run == *run))
        .map(|run| run.to_string())
        .collect();
    println!(
        "merged {} of the {design_size} runs from {} shards into {}",
        records.len(),
        args.shards.len(),
        table_path.display()
    );
    if !missing.is_empty() {
        println!(
            "  missing runs (rerun their shards, which resume, and merge again): {}",
            missing.join(", ")
        );
    }
    report(&records, &table_path);
    let outputs = first
        .columns
        .outputs
        .iter()
        .map(|column| Output {
            column: column.clone(),
            description: column.clone(),
        })
        .collect();
    let title = first.base.lines().next().unwrap_or("sweep").to_string();
    write_sensitivities(
        &args.out,
        &title,
        &first.columns.parameters,
        outputs,
        &records,
    )
}
