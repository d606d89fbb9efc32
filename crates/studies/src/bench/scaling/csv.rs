//! `scaling.csv`: one row per timed cube, with the header [`SCALING_HEADER`] exactly. A
//! failed run has `NaN` time and force; an unknown peak memory is empty.

use super::case::ScalingRun;

/// Header of `scaling.csv`, exactly: n is the elements per edge, wall_s the time of mesh,
/// model and solve [s], end_force_n the reaction on x1 at the end [N], peak_memory_mb the
/// peak resident memory of the process that ran the case [MiB].
pub const SCALING_HEADER: &str =
    "code,solver,n,unknowns,poisson,wall_s,newton_iterations,end_force_n,peak_memory_mb";

/// The CSV text of `runs`, header first.
pub fn scaling_csv(runs: &[ScalingRun]) -> String {
    let mut text = String::from(SCALING_HEADER);
    text.push('\n');
    for run in runs {
        let memory = run
            .peak_memory_bytes
            .map_or(String::new(), |b| format!("{:.1}", b as f64 / 1048576.0));
        text += &format!(
            "{},{},{},{},{},{:.4},{},{:.15e},{}\n",
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
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_have_as_many_fields_as_the_header() {
        let run = ScalingRun {
            code: "musclefem".into(),
            solver: "direct".into(),
            divisions: 10,
            poisson: 0.49,
            unknowns: 3509,
            wall_s: 1.03,
            newton_iterations: 31,
            end_force_n: 1.0,
            peak_memory_bytes: Some(36 << 20),
            failure: None,
        };
        let failed = ScalingRun::failed("felupe", "spsolve", 10, 0.3, 3509, "x".into());
        let text = scaling_csv(&[run, failed]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], SCALING_HEADER);
        assert_eq!(
            lines[1],
            "musclefem,direct,10,3509,0.49,1.0300,31,1.000000000000000e0,36.0"
        );
        assert_eq!(lines[2], "felupe,spsolve,10,3509,0.3,NaN,0,NaN,");
        assert_eq!(lines[2].split(',').count(), 9);
    }
}
