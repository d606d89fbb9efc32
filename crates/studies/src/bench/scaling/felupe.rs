//! The same cube through felupe (a Python FE package): `scripts/felupe_cube.py`, built
//! into the binary, run by a Python that imports felupe. That Python is
//! `$MUSCLEFEM_FELUPE_PYTHON`, else `.venv-felupe/bin/python` in the current directory or
//! at the root of the source tree (`scripts/setup-felupe` creates it with pip). Without
//! one the benchmark says why and goes on without felupe.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::case::ScalingRun;

/// The environment variable naming a Python that imports felupe.
pub const PYTHON_VARIABLE: &str = "MUSCLEFEM_FELUPE_PYTHON";
/// The virtual environment's Python that `scripts/setup-felupe` creates.
pub const VENV_PYTHON: &str = ".venv-felupe/bin/python";
/// felupe's linear solver in the `solver` column (its default, SciPy's `spsolve`).
pub const FELUPE_SOLVER: &str = "spsolve";

/// `scripts/felupe_cube.py`, run with `python -c`.
const SCRIPT: &str = include_str!("../../../../../scripts/felupe_cube.py");

/// A Python that imports felupe.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FelupePython {
    pub path: PathBuf,
    /// felupe's version, e.g. "11.3.0".
    pub version: String,
}

/// The Python to run felupe with, or why there is none (in words, with how to get one).
pub fn find_felupe() -> Result<FelupePython, String> {
    let python = match std::env::var_os(PYTHON_VARIABLE) {
        Some(path) => PathBuf::from(path),
        None => {
            let source_root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
            let candidates = [PathBuf::from(VENV_PYTHON), source_root.join(VENV_PYTHON)];
            match candidates.into_iter().find(|p| p.is_file()) {
                Some(path) => path,
                None => {
                    return Err(format!(
                        "felupe not found: no {PYTHON_VARIABLE} and no {VENV_PYTHON} \
                         (scripts/setup-felupe installs it with pip)"
                    ));
                }
            }
        }
    };
    let output = Command::new(&python)
        .args(["-c", "import felupe; print(felupe.__version__)"])
        .output()
        .map_err(|e| format!("felupe not run: {} could not start: {e}", python.display()))?;
    if !output.status.success() {
        return Err(format!(
            "felupe not importable by {}: {}",
            python.display(),
            last_line(&String::from_utf8_lossy(&output.stderr))
        ));
    }
    Ok(FelupePython {
        path: python,
        version: String::from_utf8_lossy(&output.stdout).trim().to_string(),
    })
}

/// Run the cube of `divisions`³ at Poisson's ratio `poisson` through felupe; a failure
/// is a failed run with the reason (the benchmark goes on).
pub fn run_felupe_cube(python: &FelupePython, divisions: usize, poisson: f64) -> ScalingRun {
    let unknowns =
        musclefem_core::verification::uniaxial_cube::UniaxialCube::with_poisson(divisions, poisson)
            .unknowns();
    let failed = |reason: String| {
        ScalingRun::failed(
            "felupe",
            FELUPE_SOLVER,
            divisions,
            poisson,
            unknowns,
            reason,
        )
    };
    let output = match Command::new(&python.path)
        .arg("-c")
        .arg(SCRIPT)
        .arg(divisions.to_string())
        .arg(poisson.to_string())
        .output()
    {
        Ok(output) => output,
        Err(e) => return failed(format!("{} could not start: {e}", python.path.display())),
    };
    let stdout = String::from_utf8_lossy(&output.stdout);
    if !output.status.success() {
        return failed(format!(
            "felupe_cube.py failed: {}",
            last_line(&String::from_utf8_lossy(&output.stderr))
        ));
    }
    match stdout
        .lines()
        .rev()
        .find(|l| l.trim_start().starts_with('{'))
    {
        Some(line) => parse_felupe_line(line).unwrap_or_else(failed),
        None => failed(format!("felupe_cube.py printed no result: {stdout}")),
    }
}

/// The run of felupe_cube.py's JSON line (a flat object of numbers and one string).
pub fn parse_felupe_line(line: &str) -> Result<ScalingRun, String> {
    let number = |key: &str| -> Result<f64, String> {
        json_value(line, key)
            .and_then(|v| v.parse().ok())
            .ok_or_else(|| format!("no number {key} in felupe_cube.py's line '{line}'"))
    };
    Ok(ScalingRun {
        code: "felupe".to_string(),
        solver: FELUPE_SOLVER.to_string(),
        divisions: number("divisions")? as usize,
        poisson: number("poisson")?,
        unknowns: number("unknowns")? as usize,
        wall_s: number("seconds")?,
        newton_iterations: number("newton_iterations")? as usize,
        end_force_n: number("force")?,
        peak_memory_bytes: number("peak_memory_bytes").ok().map(|b| b as u64),
        failure: None,
    })
}

/// The text of the value of `"key":` in a flat JSON object, up to the next comma or the
/// closing brace.
fn json_value<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    let quoted = format!("\"{key}\":");
    let start = line.find(&quoted)? + quoted.len();
    let rest = &line[start..];
    let end = rest.find([',', '}']).unwrap_or(rest.len());
    Some(rest[..end].trim())
}

fn last_line(text: &str) -> String {
    text.lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("(no message)")
        .trim()
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn felupe_cubes_line_is_read() {
        let line = r#"{"divisions": 2, "poisson": 0.3, "unknowns": 45, "seconds": 0.439, "newton_iterations": 30, "force": 0.8798326322150337, "peak_memory_bytes": 89157632, "felupe": "11.3.0"}"#;
        let run = parse_felupe_line(line).unwrap();
        assert_eq!(
            (run.divisions, run.unknowns, run.newton_iterations),
            (2, 45, 30)
        );
        assert_eq!(run.poisson, 0.3);
        assert_eq!(run.wall_s, 0.439);
        assert_eq!(run.end_force_n, 0.8798326322150337);
        assert_eq!(run.peak_memory_bytes, Some(89157632));
        assert_eq!(run.series_name(), "felupe spsolve");
        assert!(parse_felupe_line(r#"{"divisions": 2}"#).is_err());
    }
}
