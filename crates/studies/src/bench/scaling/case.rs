//! One case of the scaling benchmark: the cube at n³ elements, Poisson's ratio ν, one
//! linear solver; its measurement ([`ScalingRun`]); and the line of `key=value` in which
//! a child process (`musclefem scaling-case`) hands it to the benchmark.

use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};

use musclefem_core::solver::amg_cg::LinearSolver;
use musclefem_core::solver::implicit::run_quasi_static;
use musclefem_core::verification::uniaxial_cube::UniaxialCube;

use super::memory::peak_resident_memory;

/// The code of musclefem's runs in the `code` column (felupe's: "felupe").
pub const MUSCLEFEM: &str = "musclefem";

/// musclefem's linear solver for the implicit tangents.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, clap::ValueEnum)]
pub enum ScalingSolver {
    /// Sparse Cholesky factorization (faer).
    #[value(name = "direct")]
    Direct,
    /// Conjugate gradients preconditioned with smoothed-aggregation multigrid.
    #[value(name = "amg_cg")]
    AmgCg,
}

impl ScalingSolver {
    pub fn name(self) -> &'static str {
        match self {
            ScalingSolver::Direct => "direct",
            ScalingSolver::AmgCg => "amg_cg",
        }
    }

    /// The solver of `name` ([`ScalingSolver::name`]).
    pub fn from_name(name: &str) -> Option<Self> {
        [ScalingSolver::Direct, ScalingSolver::AmgCg]
            .into_iter()
            .find(|s| s.name() == name)
    }

    fn linear_solver(self) -> LinearSolver {
        match self {
            ScalingSolver::Direct => LinearSolver::Direct,
            ScalingSolver::AmgCg => LinearSolver::AmgCg,
        }
    }
}

/// One cube to time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScalingCase {
    /// Elements per edge n.
    pub divisions: usize,
    /// Poisson's ratio ν [1].
    pub poisson: f64,
    pub solver: ScalingSolver,
}

impl ScalingCase {
    /// The cube of this case.
    pub fn cube(&self) -> UniaxialCube {
        UniaxialCube::with_poisson(self.divisions, self.poisson)
    }

    /// E.g. "20³ ν = 0.49 amg_cg".
    pub fn describe(&self) -> String {
        format!(
            "{}³ ν = {} {}",
            self.divisions,
            self.poisson,
            self.solver.name()
        )
    }

    /// Build and solve the cube in this process and time it (mesh, model and solve). The
    /// peak memory is this process's high-water mark, whatever ran in it before.
    pub fn run(&self) -> Result<ScalingRun> {
        let cube = self.cube();
        let started = Instant::now();
        let model = cube.model();
        let mut settings = cube.settings();
        settings.linear_solver = self.solver.linear_solver();
        let result = run_quasi_static(&model.mesh, &model.parts, &model.loads, &settings)
            .with_context(|| format!("the cube {}", self.describe()))?;
        let wall_s = started.elapsed().as_secs_f64();
        let end = result
            .history
            .last()
            .context("the implicit run recorded no step")?;
        Ok(ScalingRun {
            code: MUSCLEFEM.to_string(),
            solver: self.solver.name().to_string(),
            divisions: self.divisions,
            poisson: self.poisson,
            unknowns: result.equations,
            wall_s,
            newton_iterations: result.steps.iter().map(|s| s.iterations).sum(),
            // The pull of x1 is the cube's first prescribed displacement.
            end_force_n: end.reactions[0],
            peak_memory_bytes: peak_resident_memory(),
            failure: None,
        })
    }
}

/// One timed cube, of musclefem or of felupe.
#[derive(Debug, Clone, PartialEq)]
pub struct ScalingRun {
    /// "musclefem" or "felupe".
    pub code: String,
    /// musclefem's linear solver ([`ScalingSolver::name`]), or felupe's ("spsolve").
    pub solver: String,
    /// Elements per edge n.
    pub divisions: usize,
    /// Poisson's ratio ν [1].
    pub poisson: f64,
    /// Free degrees of freedom.
    pub unknowns: usize,
    /// Wall time of mesh, model and solve [s] (NaN when the run failed).
    pub wall_s: f64,
    /// Newton iterations over the 10 steps.
    pub newton_iterations: usize,
    /// Reaction force on the face x1 along x at the end [N] (NaN when the run failed).
    pub end_force_n: f64,
    /// Peak resident memory of the process that ran it [bytes], where known.
    pub peak_memory_bytes: Option<u64>,
    /// Why the run failed, if it did.
    pub failure: Option<String>,
}

impl ScalingRun {
    /// A run of `code` and `solver` on `divisions`³ at `poisson` that failed for `reason`.
    pub fn failed(
        code: &str,
        solver: &str,
        divisions: usize,
        poisson: f64,
        unknowns: usize,
        reason: String,
    ) -> Self {
        ScalingRun {
            code: code.to_string(),
            solver: solver.to_string(),
            divisions,
            poisson,
            unknowns,
            wall_s: f64::NAN,
            newton_iterations: 0,
            end_force_n: f64::NAN,
            peak_memory_bytes: None,
            failure: Some(reason),
        }
    }

    /// E.g. "musclefem direct" or "felupe spsolve".
    pub fn series_name(&self) -> String {
        format!("{} {}", self.code, self.solver)
    }

    /// The line a child process prints for a successful musclefem run: `key=value`
    /// separated by spaces, floating-point values in full precision.
    pub fn to_line(&self) -> String {
        format!(
            "solver={} divisions={} poisson={:e} unknowns={} wall_s={:e} \
             newton_iterations={} end_force_n={:e} peak_memory_bytes={}",
            self.solver,
            self.divisions,
            self.poisson,
            self.unknowns,
            self.wall_s,
            self.newton_iterations,
            self.end_force_n,
            self.peak_memory_bytes
                .map_or("unknown".to_string(), |b| b.to_string()),
        )
    }

    /// The musclefem run of a [`ScalingRun::to_line`] line.
    pub fn from_line(line: &str) -> Result<Self> {
        let value = |key: &str| -> Result<&str> {
            line.split_whitespace()
                .find_map(|pair| pair.strip_prefix(key)?.strip_prefix('='))
                .ok_or_else(|| anyhow!("no {key}= in the case's line '{line}'"))
        };
        let number = |key: &str| -> Result<f64> {
            value(key)?
                .parse()
                .with_context(|| format!("{key} in the case's line '{line}'"))
        };
        let count = |key: &str| -> Result<usize> {
            value(key)?
                .parse()
                .with_context(|| format!("{key} in the case's line '{line}'"))
        };
        let solver = value("solver")?;
        if ScalingSolver::from_name(solver).is_none() {
            bail!("unknown solver '{solver}' in the case's line '{line}'");
        }
        Ok(ScalingRun {
            code: MUSCLEFEM.to_string(),
            solver: solver.to_string(),
            divisions: count("divisions")?,
            poisson: number("poisson")?,
            unknowns: count("unknowns")?,
            wall_s: number("wall_s")?,
            newton_iterations: count("newton_iterations")?,
            end_force_n: number("end_force_n")?,
            peak_memory_bytes: value("peak_memory_bytes")?.parse().ok(),
            failure: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn direct_and_amg_cg_pull_the_small_cube_with_the_same_force() {
        for poisson in [0.3, 0.49] {
            let run = |solver| {
                ScalingCase {
                    divisions: 3,
                    poisson,
                    solver,
                }
                .run()
                .unwrap()
            };
            let direct = run(ScalingSolver::Direct);
            let amg_cg = run(ScalingSolver::AmgCg);
            assert_eq!(direct.unknowns, 3 * 64 - 4 * 16);
            assert_eq!(amg_cg.unknowns, direct.unknowns);
            let difference = (amg_cg.end_force_n - direct.end_force_n).abs();
            assert!(
                difference <= 1e-8 * direct.end_force_n.abs(),
                "ν = {poisson}: {} N against {} N",
                amg_cg.end_force_n,
                direct.end_force_n
            );
            // Uniaxial stress of μ = 10 kPa over 1 cm² at stretch 1.5: about 1 N.
            assert!(
                direct.end_force_n > 0.5 && direct.end_force_n < 1.5,
                "{direct:?}"
            );
            assert!(direct.newton_iterations >= 10, "{direct:?}");
        }
    }

    #[test]
    fn a_run_survives_its_line() {
        let run = ScalingRun {
            code: MUSCLEFEM.to_string(),
            solver: "amg_cg".to_string(),
            divisions: 20,
            poisson: 0.49,
            unknowns: 26019,
            wall_s: 12.345678901234567,
            newton_iterations: 31,
            end_force_n: 0.987_654_321_012_345_6,
            peak_memory_bytes: Some(252 << 20),
            failure: None,
        };
        assert_eq!(ScalingRun::from_line(&run.to_line()).unwrap(), run);
        let unknown_memory = ScalingRun {
            peak_memory_bytes: None,
            ..run
        };
        assert_eq!(
            ScalingRun::from_line(&unknown_memory.to_line()).unwrap(),
            unknown_memory
        );
        assert!(ScalingRun::from_line("solver=direct divisions=2").is_err());
    }
}
