//! End-to-end tests of the `musclefem` binary.

mod support;

use support::run;

use run::{musclefem, test_dir, text};

use std::path::Path;

const HEADER: &str = "time_s,stretch,engineering_stress_pa,cauchy_stress_pa,jacobian";
const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

/// Run, expect failure, return stderr.
fn fails(dir: &Path, args: &[&str]) -> String {
    let out = musclefem(dir, args);
    let stderr = text(&out.stderr);
    assert!(
        !out.status.success(),
        "{args:?} succeeded: {}",
        text(&out.stdout)
    );
    assert!(!stderr.trim().is_empty(), "{args:?}: empty stderr");
    stderr
}

/// Entries of a directory, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn assert_png(path: &Path) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(&bytes[..8], PNG_SIGNATURE, "{}", path.display());
    assert!(
        bytes.len() > 10_000,
        "{}: {} bytes",
        path.display(),
        bytes.len()
    );
}

/// Rows of a driver CSV (after checking its header).
fn read_csv(path: &Path) -> Vec<Vec<f64>> {
    let content = std::fs::read_to_string(path).unwrap();
    let mut lines = content.lines();
    assert_eq!(lines.next(), Some(HEADER));
    lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect()
}

#[test]
fn materials_lists_builtins_with_their_parameters() {
    let dir = test_dir("musclefem-cli", "materials");
    let out = musclefem(&dir, &["materials"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let neo = stdout
        .split("\n\n")
        .find(|block| block.starts_with("neo-hookean"))
        .unwrap_or_else(|| panic!("no neo-hookean block in:\n{stdout}"));
    assert!(neo.contains("built-in"), "{neo}");
    for row in [
        ["mu", "Pa", "11370", "(0, inf)"],
        ["D", "1/Pa", "5e-9", "(0, inf)"],
    ] {
        let line = neo
            .lines()
            .find(|l| l.split_whitespace().next() == Some(row[0]))
            .unwrap_or_else(|| panic!("no '{}' row in:\n{neo}", row[0]));
        for cell in row {
            assert!(line.contains(cell), "'{cell}' missing in '{line}'");
        }
    }
    assert!(stdout.contains("\nhill  (built-in)"), "{stdout}");
    assert!(stdout.contains("n2"), "{stdout}");
}

#[test]
fn point_writes_csv_with_exact_header_and_png() {
    let dir = test_dir("musclefem-cli", "point");
    let out = musclefem(
        &dir,
        &[
            "point",
            "--material",
            "neo-hookean",
            "--param",
            "mu=10000",
            "--param",
            "D=1e-10",
            "--stretch",
            "0:1,1:1.2",
            "--dt",
            "0.01",
            "--out",
            "results/nh.csv",
        ],
    );
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let rows = read_csv(&dir.join("results/nh.csv"));
    assert_eq!(rows.len(), 101);
    assert_png(&dir.join("results/nh.png"));
    assert_eq!(entries(&dir.join("results")), vec!["nh.csv", "nh.png"]);
    // Nearly incompressible neo-Hookean in uniaxial stress: P = mu (l - 1/l^2).
    let last = rows.last().unwrap();
    assert_eq!(last[0], 1.0);
    assert_eq!(last[1], 1.2);
    let expected = 1e4 * (1.2 - 1.0 / 1.44);
    assert!((last[2] - expected).abs() < 1e-3 * expected, "{last:?}");
    // The summary reports the stress at 1.1 (interpolated) and 1.2, and the peak.
    assert!(stdout.contains("100 steps"), "{stdout}");
    let at_12 = format!("stretch 1.2: {:.4} kPa", expected / 1e3);
    assert!(stdout.contains(&at_12), "{at_12} not in:\n{stdout}");
    assert!(
        stdout.contains("engineering stress at stretch 1.1:"),
        "{stdout}"
    );
    assert!(stdout.contains("peak engineering stress"), "{stdout}");
}

#[test]
fn no_plot_writes_only_the_csv() {
    let dir = test_dir("musclefem-cli", "no-plot");
    let out = musclefem(
        &dir,
        &[
            "point",
            "--material",
            "neo-hookean",
            "--stretch",
            "0:1,1:1.1",
            "--out",
            "a.csv",
            "--no-plot",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(entries(&dir), vec!["a.csv"]);
}

#[test]
fn bad_stretch_token_fails_and_writes_nothing() {
    let dir = test_dir("musclefem-cli", "bad-stretch");
    let stderr = fails(
        &dir,
        &[
            "point",
            "--material",
            "neo-hookean",
            "--stretch",
            "0:1,1:x",
            "--out",
            "out.csv",
        ],
    );
    assert!(stderr.contains("'1:x'"), "{stderr}");
    assert!(entries(&dir).is_empty(), "{:?}", entries(&dir));
}

#[test]
fn unknown_parameter_is_named() {
    let dir = test_dir("musclefem-cli", "unknown-param");
    let stderr = fails(
        &dir,
        &[
            "point",
            "--material",
            "neo-hookean",
            "--param",
            "shear=5",
            "--stretch",
            "0:1,1:1.1",
            "--out",
            "out.csv",
        ],
    );
    assert!(
        stderr.contains("'shear'") && stderr.contains("neo-hookean"),
        "{stderr}"
    );
    assert!(entries(&dir).is_empty());
}

#[test]
fn malformed_param_token_is_quoted() {
    let dir = test_dir("musclefem-cli", "bad-param");
    for token in ["mu", "mu=soft"] {
        let stderr = fails(
            &dir,
            &[
                "point",
                "--material",
                "neo-hookean",
                "--param",
                token,
                "--stretch",
                "0:1,1:1.1",
                "--out",
                "out.csv",
            ],
        );
        assert!(stderr.contains(&format!("'{token}'")), "{stderr}");
    }
    assert!(entries(&dir).is_empty());
}

#[test]
fn zero_time_step_fails() {
    let dir = test_dir("musclefem-cli", "zero-dt");
    let stderr = fails(
        &dir,
        &[
            "point",
            "--material",
            "neo-hookean",
            "--stretch",
            "0:1,1:1.1",
            "--dt",
            "0",
            "--out",
            "out.csv",
        ],
    );
    assert!(stderr.contains("--dt"), "{stderr}");
    assert!(entries(&dir).is_empty());
}

#[test]
fn unknown_material_lists_the_known_ones() {
    let dir = test_dir("musclefem-cli", "unknown-material");
    let stderr = fails(
        &dir,
        &[
            "point",
            "--material",
            "neohooke",
            "--stretch",
            "0:1,1:1.1",
            "--out",
            "o.csv",
        ],
    );
    assert!(
        stderr.contains("'neohooke'") && stderr.contains("neo-hookean"),
        "{stderr}"
    );
}

#[test]
fn missing_plugin_is_named() {
    let dir = test_dir("musclefem-cli", "missing-plugin");
    let stderr = fails(&dir, &["materials", "--plugin", "no-such-plugin.so"]);
    assert!(stderr.contains("no-such-plugin.so"), "{stderr}");
}

/// `musclefem` alone runs the demo into out/demo; a second run needs --force.
#[test]
fn default_job_writes_the_demo_outputs() {
    let dir = test_dir("musclefem-cli", "demo");
    let out = musclefem(&dir, &[]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let demo = dir.join("out/demo");
    assert_eq!(
        entries(&demo),
        vec!["active.csv", "active.png", "passive.csv", "passive.png"]
    );
    assert_png(&demo.join("active.png"));
    assert_png(&demo.join("passive.png"));
    let passive = read_csv(&demo.join("passive.csv"));
    let active = read_csv(&demo.join("active.csv"));
    assert_eq!(passive.len(), 2001);
    assert_eq!(active.len(), 2501);
    // Activation adds the contractile stress on top of the passive one.
    let (p, a) = (passive.last().unwrap(), active.last().unwrap());
    assert_eq!((p[1], a[1]), (1.2, 1.2));
    assert!(a[2] > p[2] && p[2] > 0.0, "active {a:?}, passive {p:?}");
    assert_eq!(
        stdout.matches("engineering stress at stretch 1.1:").count(),
        2
    );
    assert_eq!(
        stdout.matches("engineering stress at stretch 1.2:").count(),
        2
    );

    // `demo --out DIR` writes the same files elsewhere.
    let out = musclefem(&dir, &["demo", "--out", "elsewhere"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(entries(&dir.join("elsewhere")).len(), 4);

    // The one overwrite policy: a second run into the same place is refused before any
    // work, and replaces the results with --force.
    let before = std::fs::read(demo.join("active.csv")).unwrap();
    let again = fails(&dir, &[]);
    assert!(
        again.contains("exists") && again.contains("--force"),
        "{again}"
    );
    let point = [
        "point",
        "--material",
        "hill",
        "--stretch",
        "0:1,0.1:1.1",
        "--out",
        "p.csv",
    ];
    assert!(musclefem(&dir, &point).status.success());
    let twice = fails(&dir, &point);
    assert!(twice.contains("p.csv exists"), "{twice}");
    let forced = musclefem(&dir, &[&point[..], &["--force"]].concat());
    assert!(forced.status.success(), "{}", text(&forced.stderr));
    let replaced = musclefem(&dir, &["demo", "--force"]);
    assert!(replaced.status.success(), "{}", text(&replaced.stderr));
    assert_eq!(std::fs::read(demo.join("active.csv")).unwrap(), before);
}

/// A step that does not resolve the history is refused, not written: one 1 ms step from
/// λ = 1 to 0.5 of the active Hill muscle wrote −592 MPa and J = 0.56 (with half the step
/// its series element fails); a resolved history passes and gives the isometric stress.
#[test]
fn point_refuses_a_step_that_does_not_resolve_the_history() {
    let dir = test_dir("musclefem-cli", "point-step");
    let active_point = |stretch: &'static str, out: &'static str| {
        [
            "point",
            "--material",
            "hill",
            "--param",
            "n2=1",
            "--stretch",
            stretch,
            "--out",
            out,
        ]
    };
    let error = fails(&dir, &active_point("0:1,0.001:0.5", "coarse.csv"));
    assert!(
        error.contains("does not resolve the stretch history"),
        "{error}"
    );
    assert!(error.contains("--dt"), "{error}");
    assert!(!dir.join("coarse.csv").exists());
    // A held stretch at 1 ms steps: the isometric stress of Table 1 (σ0 f_L = 692.8 kPa).
    let out = musclefem(&dir, &active_point("0:1,0.15:1", "held.csv"));
    assert!(out.status.success(), "{}", text(&out.stderr));
    let last = read_csv(&dir.join("held.csv")).pop().unwrap();
    assert!((last[2] - 692.8e3).abs() < 0.001 * 692.8e3, "{last:?}");
}
