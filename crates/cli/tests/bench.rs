//! `musclefem bench`: the work–precision table and chart of the cube (the elongation's
//! quick matrix takes about a minute and the knee's half an hour; they are run by hand,
//! see README), of a scene of one's own, and the `--tolerance` choices read from them; and
//! the scaling benchmark on tiny cubes.

use std::process::Command;

use musclefem_studies::bench::csv::WORK_PRECISION_HEADER;
use musclefem_studies::bench::scaling::csv::SCALING_HEADER;
use musclefem_studies::bench::{Problem, matrix};

/// Runs `command` (the musclefem binary with its arguments) and returns its standard
/// output, failing the test with both streams unless it succeeds.
fn succeeding_stdout(command: &mut Command) -> String {
    let output = command.output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

#[test]
fn the_quick_cube_bench_writes_the_table_chart_and_log() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("musclefem-bench-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let stdout = succeeding_stdout(
        Command::new(env!("CARGO_BIN_EXE_musclefem"))
            .args(["bench", "--quick", "--problem", "cube", "--out"])
            .arg(&dir),
    );
    assert!(stdout.contains("cube Pareto front"), "{stdout}");

    let table = std::fs::read_to_string(dir.join("work_precision.csv")).unwrap();
    let mut lines = table.lines();
    assert_eq!(lines.next(), Some(WORK_PRECISION_HEADER));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), matrix(Problem::Cube, true).len());
    for row in &rows {
        assert_eq!(row.len(), 8, "{row:?}");
        assert_eq!(row[0], "cube");
        let wall: f64 = row[5].parse().unwrap();
        let error: f64 = row[6].parse().unwrap();
        assert!(wall > 0.0 && error.is_finite() && error >= 0.0, "{row:?}");
    }
    // The locking element is worse than the F-bar hex8 on the same mesh.
    let error_of = |solver: &str, element: &str, size: &str| -> f64 {
        rows.iter()
            .find(|r| r[1] == solver && r[2] == element && r[3] == size)
            .unwrap_or_else(|| panic!("{solver} {element} {size} mm"))[6]
            .parse()
            .unwrap()
    };
    assert!(error_of("implicit", "tet4", "2.5") > error_of("implicit", "hex8-fbar", "2.5"));

    let png = std::fs::read(dir.join("work_precision.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let log = std::fs::read_to_string(dir.join("bench.log")).unwrap();
    assert!(
        log.contains("cube reference: implicit hex8-fbar, 1 mm"),
        "{log}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The knee has no quick matrix: `--quick --problem knee` says why before any run.
#[test]
fn the_quick_knee_is_refused_with_the_reason() {
    let dir = std::env::temp_dir().join(format!(
        "musclefem-bench-knee-unused-{}",
        std::process::id()
    ));
    let output = Command::new(env!("CARGO_BIN_EXE_musclefem"))
        .args(["bench", "--quick", "--problem", "knee", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("--problem knee has no --quick matrix") && stderr.contains("medium mesh"),
        "{stderr}"
    );
    assert!(!dir.exists(), "nothing is written");
}

/// `musclefem elongate --tolerance`: the cheapest setting of a work–precision table within
/// the tolerance is run, with the reason printed; none within it, or no table, is an error.
#[test]
fn elongate_with_a_tolerance_runs_the_cheapest_measured_setting() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("musclefem-bench-tolerance-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let table = dir.join("work_precision.csv");
    // A table as `musclefem bench` writes it (values of a quick run, rounded).
    std::fs::write(
        &table,
        format!(
            "{WORK_PRECISION_HEADER}\n\
             elongate,implicit,hex8-fbar,4,increment=0.4s,3.9,1.1e-2,m\n\
             elongate,implicit,tet4,4,increment=0.2s,2.6,1.18e0,m\n\
             elongate,explicit,hex8-one-point,4,mass_scaling=1e-4s;safety=0.9,4.7,1.1e-1,m\n"
        ),
    )
    .unwrap();
    let elongate = |tolerance: &str, table: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_musclefem"))
            .args(["elongate", "--mode", "passive", "--frame-interval", "0"])
            .args(["--tolerance", tolerance, "--bench-table"])
            .arg(table)
            .arg("--out")
            .arg(dir.join(format!("run-{tolerance}")))
            .output()
            .unwrap()
    };
    let output = elongate("150", &table);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        stdout.contains("--tolerance 150 %: implicit tet4, 4 mm, increment=0.2s (118.00 % error"),
        "{stdout}"
    );
    assert!(
        stdout.contains("implicit passive elongation, fusiform tet4, 4 mm"),
        "{stdout}"
    );

    let output = elongate("0.5", &table);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("no setting in") && stderr.contains("off by 1.10 %"),
        "{stderr}"
    );

    let output = elongate("5", &dir.join("missing.csv"));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("musclefem bench --problem elongate"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `musclefem bench --scene`: a scene's step settings against its reference run, in the
/// same table and chart; the homogeneous hyperelastic cube does not depend on the
/// increment, and the heavily mass-scaled explicit run is flagged.
#[test]
fn a_scene_of_ones_own_is_benchmarked_against_its_reference() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("musclefem-bench-scene-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/neo_hookean_cube_stretch.toml");
    succeeding_stdout(
        Command::new(env!("CARGO_BIN_EXE_musclefem"))
            .args(["bench", "--scene"])
            .arg(&scene)
            .arg("--out")
            .arg(&dir),
    );
    let table = std::fs::read_to_string(dir.join("work_precision.csv")).unwrap();
    let mut lines = table.lines();
    assert_eq!(lines.next(), Some(WORK_PRECISION_HEADER));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 5);
    for row in &rows {
        assert_eq!(
            row[..4],
            ["neo_hookean_cube_stretch", row[1], "hex8-fbar", "2.5"]
        );
        assert_eq!(row[7], "max_nodal_displacement_error_at_the_end");
        let error: f64 = row[6].parse().unwrap();
        if row[1] == "implicit" {
            assert!(error < 1e-9, "{row:?}");
        } else {
            assert!(error > 0.0 && error < 0.1, "{row:?}");
        }
    }
    let log = std::fs::read_to_string(dir.join("bench.log")).unwrap();
    assert!(
        log.contains("neo_hookean_cube_stretch reference: implicit increment=0.025s"),
        "{log}"
    );
    assert!(
        log.lines()
            .any(|l| l.contains("mass_scaling=1e-2s") && l.contains("warning: the kinetic energy")),
        "{log}"
    );
    assert!(dir.join("work_precision.png").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `musclefem run --tolerance`: the cheapest measured run of the scene within the
/// tolerance; runs of another scene or mesh, or none within it, are errors before any
/// output.
#[test]
fn run_with_a_tolerance_takes_the_cheapest_measured_run_of_the_scene() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("musclefem-run-tolerance-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/neo_hookean_cube_stretch.toml");
    let name = "neo_hookean_cube_stretch";
    let metric = "max_nodal_displacement_error_at_the_end";
    std::fs::write(
        dir.join("table.csv"),
        format!(
            "{WORK_PRECISION_HEADER}
{name},implicit,hex8-fbar,2.5,increment=0.1s,0.5,1e-3,{metric}
{name},implicit,hex8-fbar,2.5,increment=0.05s,0.9,1e-5,{metric}
{name},explicit,hex8-fbar,2.5,mass_scaling=1e-2s;safety=0.9,0.1,5e-2,{metric}
{name},implicit,tet4,2.5,increment=0.5s,0.01,0,{metric}
other,implicit,hex8-fbar,2.5,increment=0.5s,0.01,0,{metric}
"
        ),
    )
    .unwrap();
    let run = |percent: &str, out: &str| {
        Command::new(env!("CARGO_BIN_EXE_musclefem"))
            .arg("run")
            .arg(&scene)
            .args(["--tolerance", percent, "--bench-table"])
            .arg(dir.join("table.csv"))
            .arg("--out")
            .arg(dir.join(out))
            .output()
            .unwrap()
    };
    // 10 %: the mass-scaled explicit run (5 %, 0.1 s); the tet4 row is another mesh.
    let output = run("10", "loose");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}");
    assert!(
        stdout.contains("--tolerance 10 %: explicit mass_scaling=1e-2s;safety=0.9")
            && stdout.contains("of the 3 measured runs"),
        "{stdout}"
    );
    assert!(dir.join("loose/history.csv").is_file());
    // 0.01 %: only the 0.05 s increments.
    let output = run("0.01", "tight");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}");
    assert!(stdout.contains("implicit increment=0.05s"), "{stdout}");
    assert!(stdout.contains("1 s in 20 increments"), "{stdout}");
    // 1e-4 %: none.
    let output = run("1e-4", "none");
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("no run of 'neo_hookean_cube_stretch'")
            && stderr.contains("meets 0.0001 %"),
        "{stderr}"
    );
    assert!(!dir.join("none").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `musclefem bench --problem scaling`: each tiny cube with both linear solvers, each in a
/// child process, in one table with the right unknowns, the same end force from both
/// solvers, the chart and the log with the ratios.
#[test]
fn the_scaling_bench_times_each_cube_with_each_solver() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("musclefem-bench-scaling-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let stdout = succeeding_stdout(
        Command::new(env!("CARGO_BIN_EXE_musclefem"))
            .args([
                "bench",
                "--problem",
                "scaling",
                "--sizes",
                "2,3",
                "--no-felupe",
            ])
            .arg("--out")
            .arg(&dir),
    );
    assert!(
        stdout.contains("wall time ratio amg_cg / direct:"),
        "{stdout}"
    );

    let table = std::fs::read_to_string(dir.join("scaling.csv")).unwrap();
    let mut lines = table.lines();
    assert_eq!(lines.next(), Some(SCALING_HEADER));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // 2 sizes × 2 Poisson's ratios × 2 solvers.
    assert_eq!(rows.len(), 8, "{table}");
    for row in &rows {
        assert_eq!(row.len(), 9, "{row:?}");
        assert_eq!(row[0], "musclefem");
        let n: usize = row[2].parse().unwrap();
        let unknowns: usize = row[3].parse().unwrap();
        assert_eq!(unknowns, 3 * (n + 1).pow(3) - 4 * (n + 1).pow(2), "{row:?}");
        let wall: f64 = row[5].parse().unwrap();
        assert!(wall > 0.0, "{row:?}");
        let memory: f64 = row[8].parse().unwrap();
        assert!(memory > 0.0, "{row:?}");
    }
    let force = |solver: &str, n: &str, nu: &str| -> f64 {
        rows.iter()
            .find(|r| r[1] == solver && r[2] == n && r[4] == nu)
            .unwrap_or_else(|| panic!("{solver} {n} {nu}"))[7]
            .parse()
            .unwrap()
    };
    for n in ["2", "3"] {
        for nu in ["0.3", "0.49"] {
            let direct = force("direct", n, nu);
            let amg_cg = force("amg_cg", n, nu);
            assert!(
                (amg_cg - direct).abs() <= 1e-8 * direct.abs(),
                "{n}³ ν = {nu}: {amg_cg} N against {direct} N"
            );
        }
    }
    let png = std::fs::read(dir.join("scaling.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let log = std::fs::read_to_string(dir.join("scaling.log")).unwrap();
    assert!(log.contains("felupe not run (--no-felupe)"), "{log}");
    assert!(
        log.contains("musclefem direct, ν = 0.3: slope") && log.contains("(within)"),
        "{log}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
