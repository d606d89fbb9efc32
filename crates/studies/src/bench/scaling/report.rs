//! The scaling benchmark's results in words: the table of runs, each series' fitted
//! slope, the time ratios (musclefem / felupe and AMG-CG / direct, per cube) and the
//! relative differences of the end forces (AMG-CG and felupe against the direct solver).

use super::case::{MUSCLEFEM, ScalingRun};
use super::slope::{FittedSlope, fitted_slope};

/// The relative end-force difference AMG-CG must stay within against the direct solver
/// (issue #36).
pub const SOLVER_FORCE_TOLERANCE: f64 = 1e-8;

/// The runs of one code and solver at one Poisson's ratio, in the order run.
#[derive(Debug, Clone)]
pub struct RunSeries<'a> {
    /// E.g. "musclefem direct".
    pub name: String,
    pub poisson: f64,
    pub runs: Vec<&'a ScalingRun>,
}

impl RunSeries<'_> {
    /// E.g. "musclefem direct, ν = 0.3".
    pub fn label(&self) -> String {
        format!("{}, ν = {}", self.name, self.poisson)
    }

    /// Its slope of time against unknowns (see [`fitted_slope`]), failed runs left out.
    pub fn slope(&self) -> Option<FittedSlope> {
        let points: Vec<(usize, f64, f64)> = self
            .runs
            .iter()
            .filter(|r| r.failure.is_none())
            .map(|r| (r.divisions, r.unknowns as f64, r.wall_s))
            .collect();
        fitted_slope(&points)
    }
}

/// `runs` grouped by code, solver and Poisson's ratio, in order of first appearance.
pub fn run_series(runs: &[ScalingRun]) -> Vec<RunSeries<'_>> {
    let mut series: Vec<RunSeries> = Vec::new();
    for run in runs {
        let name = run.series_name();
        match series
            .iter_mut()
            .find(|s| s.name == name && s.poisson == run.poisson)
        {
            Some(s) => s.runs.push(run),
            None => series.push(RunSeries {
                name,
                poisson: run.poisson,
                runs: vec![run],
            }),
        }
    }
    series
}

/// The table, slopes, ratios and force differences of `runs`, one finding a line.
pub fn scaling_report(runs: &[ScalingRun]) -> String {
    let mut text = String::from(
        "code      solver   n    unknowns  ν      wall [s]  Newton  end force [N]          peak [MiB]\n",
    );
    for run in runs {
        let memory = run
            .peak_memory_bytes
            .map_or("-".to_string(), |b| format!("{:.0}", b as f64 / 1048576.0));
        text += &format!(
            "{:<9} {:<8} {:<4} {:<9} {:<6} {:<9.3} {:<7} {:<22.15e} {}\n",
            run.code,
            run.solver,
            run.divisions,
            run.unknowns,
            run.poisson,
            run.wall_s,
            run.newton_iterations,
            run.end_force_n,
            memory
        );
        if let Some(reason) = &run.failure {
            text += &format!("  FAILED: {reason}\n");
        }
    }
    text += "slope of log wall time against log unknowns:\n";
    for series in run_series(runs) {
        let slope = series
            .slope()
            .map_or("fewer than two sizes".to_string(), |s| s.describe());
        text += &format!("  {}: {slope}\n", series.label());
    }
    let cubes = cubes(runs);
    let ours: Vec<String> = solvers_of(runs, MUSCLEFEM);
    let felupe = |n: usize, nu: f64| successful(runs, "felupe", None, n, nu);
    if cubes.iter().any(|&(n, nu)| felupe(n, nu).is_some()) {
        text += "wall time ratio musclefem / felupe:\n";
        for &(n, nu) in &cubes {
            let Some(theirs) = felupe(n, nu) else {
                continue;
            };
            for solver in &ours {
                if let Some(our) = successful(runs, MUSCLEFEM, Some(solver), n, nu) {
                    text += &format!(
                        "  {n}³ ν = {nu} {solver}: {:.3} ({:.3} s / {:.3} s)\n",
                        our.wall_s / theirs.wall_s,
                        our.wall_s,
                        theirs.wall_s
                    );
                }
            }
        }
    }
    let pairs = |solver: &str| -> Vec<(usize, f64, &ScalingRun, &ScalingRun)> {
        cubes
            .iter()
            .filter_map(|&(n, nu)| {
                let direct = successful(runs, MUSCLEFEM, Some("direct"), n, nu)?;
                let other = successful(runs, MUSCLEFEM, Some(solver), n, nu)?;
                Some((n, nu, direct, other))
            })
            .collect()
    };
    let amg_pairs = pairs("amg_cg");
    if !amg_pairs.is_empty() {
        text += "wall time ratio amg_cg / direct:\n";
        for &(n, nu, direct, amg) in &amg_pairs {
            text += &format!("  {n}³ ν = {nu}: {:.3}\n", amg.wall_s / direct.wall_s);
        }
        text += &format!(
            "end force, relative difference amg_cg against direct (issue #36: ≤ {SOLVER_FORCE_TOLERANCE:e}):\n"
        );
        for &(n, nu, direct, amg) in &amg_pairs {
            let difference = relative_difference(amg.end_force_n, direct.end_force_n);
            let verdict = if difference <= SOLVER_FORCE_TOLERANCE {
                "within"
            } else {
                "ABOVE"
            };
            text += &format!("  {n}³ ν = {nu}: {difference:.2e} ({verdict})\n");
        }
    }
    let felupe_pairs: Vec<(usize, f64, &ScalingRun, &ScalingRun)> = cubes
        .iter()
        .filter_map(|&(n, nu)| {
            let ours = ours
                .iter()
                .find_map(|s| successful(runs, MUSCLEFEM, Some(s), n, nu))?;
            Some((n, nu, ours, felupe(n, nu)?))
        })
        .collect();
    if !felupe_pairs.is_empty() {
        text += "end force, relative difference felupe against musclefem (different \
                 elements: reported, not asserted):\n";
        for (n, nu, ours, theirs) in felupe_pairs {
            text += &format!(
                "  {n}³ ν = {nu}: {:.2e} (musclefem {}: {:.9} N, felupe: {:.9} N)\n",
                relative_difference(theirs.end_force_n, ours.end_force_n),
                ours.solver,
                ours.end_force_n,
                theirs.end_force_n
            );
        }
    }
    text
}

/// |a − b| / |b|.
pub fn relative_difference(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The (n, ν) of `runs`, in order of first appearance.
fn cubes(runs: &[ScalingRun]) -> Vec<(usize, f64)> {
    let mut cubes: Vec<(usize, f64)> = Vec::new();
    for run in runs {
        if !cubes.contains(&(run.divisions, run.poisson)) {
            cubes.push((run.divisions, run.poisson));
        }
    }
    cubes
}

/// The solvers of `code` in `runs`, in order of first appearance.
fn solvers_of(runs: &[ScalingRun], code: &str) -> Vec<String> {
    let mut solvers: Vec<String> = Vec::new();
    for run in runs.iter().filter(|r| r.code == code) {
        if !solvers.contains(&run.solver) {
            solvers.push(run.solver.clone());
        }
    }
    solvers
}

/// The successful run of `code` (and `solver`, if given) on n³ at ν.
fn successful<'a>(
    runs: &'a [ScalingRun],
    code: &str,
    solver: Option<&str>,
    divisions: usize,
    poisson: f64,
) -> Option<&'a ScalingRun> {
    runs.iter().find(|r| {
        r.code == code
            && solver.is_none_or(|s| r.solver == s)
            && r.divisions == divisions
            && r.poisson == poisson
            && r.failure.is_none()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(code: &str, solver: &str, n: usize, wall_s: f64, force: f64) -> ScalingRun {
        ScalingRun {
            code: code.into(),
            solver: solver.into(),
            divisions: n,
            poisson: 0.3,
            unknowns: 3 * (n + 1).pow(3) - 4 * (n + 1).pow(2),
            wall_s,
            newton_iterations: 31,
            end_force_n: force,
            peak_memory_bytes: None,
            failure: None,
        }
    }

    #[test]
    fn the_report_gives_ratios_slopes_and_force_differences() {
        let runs = [
            run("musclefem", "direct", 10, 1.0, 1.0),
            run("musclefem", "amg_cg", 10, 1.5, 1.0 + 2e-15),
            run("musclefem", "direct", 20, 10.0, 1.0),
            run("musclefem", "amg_cg", 20, 10.0, 1.0 + 1e-6),
            run("felupe", "spsolve", 10, 4.0, 1.001),
        ];
        let text = scaling_report(&runs);
        assert!(
            text.contains("  10³ ν = 0.3 direct: 0.250 (1.000 s / 4.000 s)"),
            "{text}"
        );
        assert!(text.contains("  10³ ν = 0.3 amg_cg: 0.375"), "{text}");
        assert!(
            text.contains(
                "wall time ratio amg_cg / direct:\n  10³ ν = 0.3: 1.500\n  20³ ν = 0.3: 1.000"
            ),
            "{text}"
        );
        assert!(text.contains("  20³ ν = 0.3: 1.00e-6 (ABOVE)"), "{text}");
        assert!(text.contains("  10³ ν = 0.3: 2.00e-15 (within)"), "{text}");
        assert!(
            text.contains("  10³ ν = 0.3: 1.00e-3 (musclefem direct"),
            "{text}"
        );
        assert!(text.contains("musclefem direct, ν = 0.3: slope"), "{text}");
        assert!(
            text.contains("felupe spsolve, ν = 0.3: fewer than two sizes"),
            "{text}"
        );
        assert_eq!(run_series(&runs).len(), 3);
    }
}
