//! The subcommands: argument checking, composition of the library crates, output.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use musclefem_io::PendingFile;
use musclefem_io::csv::{format_number, stage_uniaxial_csv};
use musclefem_io::plot::{stage_png, uniaxial_figure};
use musclefem_materials::{MaterialLibrary, MaterialOrigin, ParameterSpec};
use musclefem_studies::material_point::{PointRun, run_point};

use crate::summary::summarize;
use crate::{DemoArgs, MaterialsArgs, PointArgs};

/// The built-in materials plus the plugins at `paths`, loaded in order.
fn library_with_plugins(paths: &[PathBuf]) -> Result<MaterialLibrary> {
    let mut library = MaterialLibrary::with_builtins();
    for path in paths {
        // The error names the plugin path and the reason.
        library.load_plugin(path)?;
    }
    Ok(library)
}

/// `musclefem materials`.
pub fn materials(args: &MaterialsArgs) -> Result<()> {
    let library = library_with_plugins(&args.plugins)?;
    let all = library.materials();
    println!("{} materials\n", all.len());
    for info in &all {
        let origin = match &info.origin {
            MaterialOrigin::BuiltIn => "built-in".to_string(),
            MaterialOrigin::Plugin(path) => format!("plugin {}", path.display()),
            MaterialOrigin::Host(host) => format!("defined in {host}"),
        };
        println!("{}  ({origin})", info.name);
        println!("  {}", info.description);
        print!("{}", parameter_table(&info.parameters));
        println!();
    }
    Ok(())
}

/// Parameters as an aligned table, indented by four spaces.
pub fn parameter_table(specs: &[ParameterSpec]) -> String {
    if specs.is_empty() {
        return "    (no parameters)\n".to_string();
    }
    let header = ["parameter", "unit", "default", "valid range", "description"];
    let rows: Vec<[String; 5]> = specs
        .iter()
        .map(|s| {
            [
                s.name.to_string(),
                s.unit.to_string(),
                s.default
                    .map(format_number)
                    .unwrap_or_else(|| "required".to_string()),
                s.range_text(),
                s.description.to_string(),
            ]
        })
        .collect();
    let mut widths = header.map(|h| h.chars().count());
    for row in &rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let line = |cells: [&str; 5]| {
        let mut text = String::from("   ");
        for (i, cell) in cells.iter().enumerate() {
            if i + 1 == cells.len() {
                text.push(' ');
                text.push_str(cell);
            } else {
                text.push_str(&format!(" {cell:<width$} ", width = widths[i]));
            }
        }
        text.trim_end().to_string() + "\n"
    };
    let mut table = line(header);
    for row in &rows {
        table.push_str(&line([&row[0], &row[1], &row[2], &row[3], &row[4]]));
    }
    table
}

/// Parse `--param KEY=VALUE` tokens. Errors quote the token.
pub fn parse_params(tokens: &[String]) -> Result<BTreeMap<String, f64>> {
    let mut params = BTreeMap::new();
    for token in tokens {
        let Some((key, value)) = token.split_once('=') else {
            bail!("--param '{token}': expected KEY=VALUE, e.g. --param n2=1");
        };
        let key = key.trim();
        if key.is_empty() {
            bail!("--param '{token}': the parameter name before '=' is empty");
        }
        let value: f64 = value
            .trim()
            .parse()
            .map_err(|_| anyhow!("--param '{token}': '{}' is not a number", value.trim()))?;
        if params.insert(key.to_string(), value).is_some() {
            bail!("--param '{token}': parameter '{key}' is given more than once");
        }
    }
    Ok(params)
}

/// The chart's path for a CSV path: same stem, extension .png.
fn png_path(csv: &Path) -> PathBuf {
    csv.with_extension("png")
}

/// Stage the CSV (and the chart titled `title`, unless `plot` is false) of `run` for `csv`.
fn stage_outputs(csv: &Path, run: &PointRun, plot: bool, title: &str) -> Result<Vec<PendingFile>> {
    let mut staged = vec![stage_uniaxial_csv(csv, &run.rows)?];
    if plot {
        let figure = uniaxial_figure(title, &[(&run.label, &run.rows)]);
        staged.push(stage_png(&png_path(csv), &figure)?);
    }
    Ok(staged)
}

/// Commit staged files (each by one rename in its own directory); returns their paths.
/// Each file is replaced whole. The set is not one transaction: should a later rename fail
/// (the files are already complete on the same file system, so only an I/O fault can do
/// that), the files renamed before it are new and the rest old.
fn commit_all(staged: Vec<PendingFile>) -> Result<Vec<PathBuf>> {
    let mut written = Vec::with_capacity(staged.len());
    for file in staged {
        let path = file.target().to_path_buf();
        file.commit()?;
        written.push(path);
    }
    Ok(written)
}

/// Create the directory that will hold `path`, if any.
fn create_parent(path: &Path) -> Result<()> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create the directory '{}'", dir.display())),
        _ => Ok(()),
    }
}

fn paths_text(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// `musclefem point`.
pub fn point(args: &PointArgs) -> Result<()> {
    let params = parse_params(&args.params)?;
    let is_png = args
        .out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if is_png || args.out.file_name().is_none() {
        bail!(
            "--out '{}': expected the CSV file name (the chart goes next to it as .png)",
            args.out.display()
        );
    }
    let mut outputs = vec![args.out.clone()];
    if !args.no_plot {
        outputs.push(png_path(&args.out));
    }
    refuse_existing(&outputs, args.force)?;
    let library = library_with_plugins(&args.plugins)?;
    let run = run_point(&library, &args.material, &params, &args.stretch, args.dt)?;
    create_parent(&args.out)?;
    let title = format!("Uniaxial stress along the fiber: {}", run.label);
    let written = commit_all(stage_outputs(&args.out, &run, !args.no_plot, &title)?)?;
    println!(
        "{}: uniaxial stress along the fiber, --stretch {} --dt {}",
        run.label, args.stretch, args.dt
    );
    print!("{}", summarize(&run.rows));
    println!("wrote {}", paths_text(&written));
    Ok(())
}

/// One run of the default job.
struct DemoCase {
    /// File stem in the output directory.
    stem: &'static str,
    what: &'static str,
    params: &'static [(&'static str, f64)],
    stretch: &'static str,
}

/// Material of the default job.
const DEMO_MATERIAL: &str = "hill";
/// Time step of the default job [s].
const DEMO_DT: f64 = 1e-3;
const DEMO_CASES: [DemoCase; 2] = [
    DemoCase {
        stem: "passive",
        what: "passive muscle stretched to 1.2 in 2 s",
        params: &[],
        stretch: "0:1,2:1.2",
    },
    DemoCase {
        stem: "active",
        what: "fully activated muscle (n2 = 1), held isometric for 0.5 s, then stretched to \
               1.2 in 2 s",
        params: &[("n2", 1.0)],
        stretch: "0:1,0.5:1,2.5:1.2",
    },
];

/// `musclefem demo` and `musclefem` alone.
pub fn demo(args: &DemoArgs) -> Result<()> {
    let outputs: Vec<PathBuf> = DEMO_CASES
        .iter()
        .flat_map(|case| ["csv", "png"].map(|e| args.out.join(format!("{}.{e}", case.stem))))
        .collect();
    refuse_existing(&outputs, args.force)?;
    let library = MaterialLibrary::with_builtins();
    println!(
        "musclefem demo: material point of the '{DEMO_MATERIAL}' muscle in uniaxial stress \
         along the fiber, dt = {DEMO_DT} s"
    );
    let mut runs = Vec::new();
    for case in &DEMO_CASES {
        let params = case
            .params
            .iter()
            .map(|(k, v)| (k.to_string(), *v))
            .collect();
        let run = run_point(&library, DEMO_MATERIAL, &params, case.stretch, DEMO_DT)
            .with_context(|| format!("demo case '{}'", case.stem))?;
        runs.push(run);
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create the directory '{}'", args.out.display()))?;
    let mut staged = Vec::new();
    for (case, run) in DEMO_CASES.iter().zip(&runs) {
        staged.extend(stage_outputs(
            &args.out.join(format!("{}.csv", case.stem)),
            run,
            true,
            &format!(
                "{}: {DEMO_MATERIAL} muscle, --stretch {}",
                case.stem, case.stretch
            ),
        )?);
    }
    let written = commit_all(staged)?;
    for (case, run) in DEMO_CASES.iter().zip(&runs) {
        println!(
            "\n{}: {} (--stretch {})",
            case.stem, case.what, case.stretch
        );
        print!("{}", summarize(&run.rows));
    }
    println!("\nwrote {}", paths_text(&written));
    Ok(())
}

/// `musclefem knee`, which Ctrl-C stops cleanly at each squat's next recorded instant
/// (exit 130; `--resume` goes on from the last frames).
pub fn knee(args: &musclefem_studies::knee::command::KneeArgs) -> Result<()> {
    let interrupted = crate::scene_run::interrupt_flag();
    musclefem_studies::knee::command::knee(args, &interrupted)
}

pub use musclefem_studies::interrupted::Interrupted;

/// The one overwrite policy of the commands that write: an earlier result is replaced only
/// with `--force`. Checked before any work, so a long run does not end in a refusal.
pub fn refuse_existing(paths: &[PathBuf], force: bool) -> Result<()> {
    if force {
        return Ok(());
    }
    if let Some(existing) = paths.iter().find(|p| p.exists()) {
        bail!(
            "{} exists: an earlier result is there (use --force to replace it, or another \
             --out)",
            existing.display()
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_parse_and_bad_tokens_are_quoted() {
        let tokens = ["n2=1".to_string(), " mu = 1e4 ".to_string()];
        let params = parse_params(&tokens).unwrap();
        assert_eq!(params["n2"], 1.0);
        assert_eq!(params["mu"], 1e4);
        for bad in ["mu", "mu=", "=3", "mu=ten", "n2=1,n1=0"] {
            let err = parse_params(&[bad.to_string()]).unwrap_err().to_string();
            assert!(err.contains(&format!("'{bad}'")), "{bad}: {err}");
        }
        let twice = ["n2=1".to_string(), "n2=0.5".to_string()];
        let err = parse_params(&twice).unwrap_err().to_string();
        assert!(err.contains("more than once"), "{err}");
    }

    #[test]
    fn parameter_table_is_aligned() {
        let specs = musclefem_materials::neo_hookean::NEO_HOOKEAN_PARAMETERS;
        let table = parameter_table(&specs);
        let lines: Vec<&str> = table.lines().collect();
        assert_eq!(lines.len(), 3, "{table}");
        let column = |line: &str, word: &str| line.find(word).unwrap();
        assert_eq!(column(lines[0], "default"), column(lines[1], "11370"));
        assert_eq!(column(lines[0], "default"), column(lines[2], "5e-9"));
        assert_eq!(
            column(lines[0], "description"),
            column(lines[2], "compressibility")
        );
    }

    #[test]
    fn demo_cases_name_real_parameters() {
        let info = MaterialLibrary::with_builtins()
            .info(DEMO_MATERIAL)
            .unwrap();
        for case in &DEMO_CASES {
            for (name, _) in case.params {
                assert!(info.parameters.iter().any(|p| p.name == *name), "{name}");
            }
            musclefem_materials::driver::StretchHistory::parse(case.stretch).unwrap();
        }
    }
}
