//! `musclefem fit` end to end: fitting to curves that `musclefem elongate` made with known
//! parameters gives those parameters back (to 1e-4 relative), passive and active, on the
//! cheap homogeneous model (the cylinder with sliding grips, 72 elements, 0.2 s
//! increments); and bad input is refused by name.

mod support;

use std::collections::BTreeMap;
use std::path::Path;

use support::run::{CHEAP_ELONGATION, musclefem, test_dir, text};

/// `curve.csv` of the `mode` test with `params` (KEY=VALUE), in `dir/name`.
fn synthetic_curve(dir: &Path, mode: &str, params: &[&str], name: &str) {
    let mut args = vec![
        "elongate",
        "--mode",
        mode,
        "--frame-interval",
        "0",
        "--out",
        name,
    ];
    args.extend_from_slice(&CHEAP_ELONGATION);
    for param in params {
        args.extend_from_slice(&["--param", param]);
    }
    let out = musclefem(dir, &args);
    assert!(out.status.success(), "{}", text(&out.stderr));
}

/// fit.csv by parameter: (start, fitted, ci95_low, ci95_high).
fn fitted(path: &Path) -> BTreeMap<String, [f64; 4]> {
    let table = std::fs::read_to_string(path).unwrap();
    let mut lines = table.lines();
    assert_eq!(
        lines.next().unwrap(),
        "parameter,start,fitted,standard_error,ci95_low,ci95_high,at_bound"
    );
    lines
        .map(|line| {
            let cells: Vec<&str> = line.split(',').collect();
            let number = |i: usize| cells[i].parse::<f64>().unwrap();
            assert_eq!(cells[6], "false", "{line}");
            (
                cells[0].to_string(),
                [number(1), number(2), number(4), number(5)],
            )
        })
        .collect()
}

fn recovers(mode: &str, truth: &[(&str, f64)]) {
    let dir = test_dir("fit", mode);
    let params: Vec<String> = truth.iter().map(|(n, v)| format!("{n}={v}")).collect();
    let params: Vec<&str> = params.iter().map(String::as_str).collect();
    synthetic_curve(&dir, mode, &params, "measured");
    let names: Vec<&str> = truth.iter().map(|(n, _)| *n).collect();
    let names = names.join(",");
    let mut args = vec![
        "fit",
        "--data",
        "measured/curve.csv",
        "--test",
        mode,
        "--params",
        &names,
        "--out",
        "fit",
    ];
    args.extend_from_slice(&CHEAP_ELONGATION);
    let out = musclefem(&dir, &args);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let fit = fitted(&dir.join("fit/fit.csv"));
    for (name, value) in truth {
        let [start, x, low, high] = fit[*name];
        assert!(
            (start / value - 1.0).abs() > 0.1,
            "{name} starts away from {value}"
        );
        assert!((x / value - 1.0).abs() < 1e-4, "{name} = {x}, not {value}");
        assert!(low <= x && x <= high, "{name}: {x} not in [{low}, {high}]");
    }
    let summary = std::fs::read_to_string(dir.join("fit/fit.txt")).unwrap();
    assert!(summary.contains("RMS residual"), "{summary}");
    let curve = std::fs::read_to_string(dir.join("fit/fit_curve.csv")).unwrap();
    assert!(curve.starts_with("engineering_strain,measured_stress_pa,fitted_stress_pa\n"));
    assert!(
        std::fs::read(dir.join("fit/fit.png"))
            .unwrap()
            .starts_with(b"\x89PNG")
    );
}

#[test]
fn a_passive_fit_recovers_the_matrix_and_parallel_element_parameters() {
    recovers("passive", &[("c", 450.0), ("A", 3.2)]);
}

#[test]
fn an_active_fit_recovers_the_isometric_stress_and_lengthening_curvature() {
    recovers("active", &[("sigma0", 6e5), ("k_e", 3.0)]);
}

#[test]
fn bad_fits_are_refused_by_name() {
    let dir = test_dir("fit", "bad");
    synthetic_curve(&dir, "passive", &[], "measured");
    let fit = |extra: &[&str]| {
        let mut args = vec!["fit", "--out", "fit"];
        if !extra.contains(&"--data") {
            args.extend_from_slice(&["--data", "measured/curve.csv"]);
        }
        args.extend_from_slice(&CHEAP_ELONGATION);
        args.extend_from_slice(extra);
        musclefem(&dir, &args)
    };
    for (args, expected) in [
        (vec!["--params", "sigma"], "no parameter 'sigma'"),
        (vec!["--params", "n2"], "sets the activation"),
        (vec!["--params", "c", "--start", "b=3"], "--start b"),
        (
            vec!["--params", "c", "--bound", "c=5:1"],
            "LO must be below HI",
        ),
        (
            vec!["--params", "c", "--stress-column", "stress"],
            "no column 'stress'",
        ),
        (
            vec!["--params", "c", "--data", "missing.csv"],
            "missing.csv",
        ),
    ] {
        let out = fit(&args);
        assert!(!out.status.success(), "{args:?}");
        let error = text(&out.stderr);
        assert!(error.contains(expected), "{args:?}: {error}");
    }
    std::fs::create_dir_all(dir.join("fit")).unwrap();
    std::fs::write(dir.join("fit/fit.csv"), "earlier").unwrap();
    let refused = fit(&["--params", "c"]);
    let error = text(&refused.stderr);
    assert!(error.contains("--force"), "{error}");
    assert_eq!(
        std::fs::read_to_string(dir.join("fit/fit.csv")).unwrap(),
        "earlier"
    );
}
