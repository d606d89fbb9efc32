//! Property test over the command line's numbers (issue: reliability): `musclefem point`
//! with random material parameters, stretch histories and time steps, drawn from the
//! values careless input holds (0, negatives, huge and tiny numbers, NaN, infinity) now
//! and then, ordinary ones otherwise. Every run ends within its time budget, never panics, and either
//! fails with an error message or exits 0 with nothing but finite numbers in its CSV.
//!
//! Cases: 48 per run (`PROPTEST_CASES` changes it); the counts of each outcome are printed.
//! A second property does the same over `musclefem elongate`'s mesh size, time step and
//! frame interval.

mod support;

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::process::Command;
use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::test_runner::{TestCaseError, TestRunner};

use support::run::test_dir;

/// Numbers careless input holds.
const WILD: [&str; 10] = [
    "0", "-1", "-0.1", "1e-300", "1e300", "NaN", "inf", "-inf", "1e9", "-1e9",
];

/// `ordinary` most of the time, one of [`WILD`] otherwise.
fn sometimes_wild(ordinary: impl Strategy<Value = f64>) -> impl Strategy<Value = String> {
    prop_oneof![
        6 => ordinary.prop_map(|x| format!("{x}")),
        1 => (0..WILD.len()).prop_map(|i| WILD[i].to_string()),
    ]
}

/// A stretch history of 1 to 4 knots `time:stretch` after the first at t = 0: times
/// growing by 0.01–1 s and stretches of 0.7–1.5, each now and then replaced by a wild
/// number.
fn stretch_history() -> impl Strategy<Value = String> {
    proptest::collection::vec(
        (sometimes_wild(0.01f64..1.0), sometimes_wild(0.7f64..1.5)),
        1..5,
    )
    .prop_map(|knots| {
        let mut time = 0.0;
        let mut text = vec!["0:1".to_string()];
        for (step, stretch) in knots {
            // A wild step stands in for the time itself.
            let at = match step.parse::<f64>() {
                Ok(dt) if (0.01..1.0).contains(&dt) => {
                    time += dt;
                    format!("{time}")
                }
                _ => step,
            };
            text.push(format!("{at}:{stretch}"));
        }
        text.join(",")
    })
}

/// The Hill parameters a sweep or a typo most often touches.
const HILL_KEYS: [&str; 5] = ["n2", "sigma0", "c", "b", "D"];
/// Their defaults (`musclefem materials`; n2 = 1 is full activation).
const HILL_DEFAULTS: [f64; 5] = [1.0, 7e5, 379.0, 15.0, 5e-9];

#[test]
fn random_numbers_on_the_command_line_never_panic_nor_give_non_finite_results() {
    let dir = test_dir("musclefem-numeric", "point");
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(48);
    let mut runner = TestRunner::new(ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    });
    let outcomes = RefCell::new(BTreeMap::<&str, usize>::new());
    let strategy = (
        prop::bool::ANY,
        proptest::collection::vec((0..HILL_KEYS.len(), sometimes_wild(0.1f64..10.0)), 0..3),
        stretch_history(),
        prop::option::of(sometimes_wild(1e-4f64..1e-2)),
    );
    let result = runner.run(&strategy, |(hill, params, stretch, dt)| {
        let out = dir.join("point.csv");
        let mut command = Command::new(env!("CARGO_BIN_EXE_musclefem"));
        command.current_dir(&dir).args([
            "point",
            "--material",
            if hill { "hill" } else { "neo-hookean" },
            "--stretch",
            &stretch,
            "--no-plot",
            "--force",
            "--out",
        ]);
        command.arg(&out);
        if hill {
            // An ordinary value scales the parameter's default; a wild one replaces it.
            for (key, value) in &params {
                let value = match value.parse::<f64>() {
                    Ok(factor) if (0.1..10.0).contains(&factor) => {
                        format!("{}", factor * HILL_DEFAULTS[*key])
                    }
                    _ => value.clone(),
                };
                command
                    .arg("--param")
                    .arg(format!("{}={value}", HILL_KEYS[*key]));
            }
        }
        if let Some(dt) = &dt {
            command.arg("--dt").arg(dt);
        }
        let _ = std::fs::remove_file(&out);
        run_and_judge(&mut command, &out, 0, &outcomes)
    });
    println!("{cases} command lines: {:?}", outcomes.borrow());
    if let Err(failure) = result {
        panic!("{failure}");
    }
}

/// The same over `musclefem elongate`'s numbers (the cheap passive cylinder with sliding
/// grips): `--mesh-size` [mm], `--time-step` [s] and `--frame-interval` [s], ordinary
/// mostly and wild now and then. A run ends in time, never panics, and either refuses with
/// a message and no curve, or writes a curve of finite numbers.
///
/// Cases: 16 per run (`PROPTEST_CASES` changes it).
#[test]
fn random_elongation_options_never_panic_nor_give_non_finite_curves() {
    let dir = test_dir("musclefem-numeric", "elongate");
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(16);
    let mut runner = TestRunner::new(ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    });
    let outcomes = RefCell::new(BTreeMap::<&str, usize>::new());
    let strategy = (
        sometimes_wild(6.0f64..8.75),
        sometimes_wild(0.1f64..0.4),
        prop::option::of(sometimes_wild(0.1f64..1.0)),
    );
    let result = runner.run(&strategy, |(mesh_size, time_step, frame_interval)| {
        let out = dir.join("curve");
        let _ = std::fs::remove_dir_all(&out);
        let mut command = Command::new(env!("CARGO_BIN_EXE_musclefem"));
        command.current_dir(&dir).args([
            "elongate",
            "--mode",
            "passive",
            "--shape",
            "cylinder",
            "--grips",
            "sliding",
            "--mesh-size",
            &mesh_size,
            "--time-step",
            &time_step,
            "--out",
            "curve",
        ]);
        if let Some(interval) = &frame_interval {
            command.arg("--frame-interval").arg(interval);
        }
        run_and_judge(&mut command, &out.join("curve.csv"), 5, &outcomes)
    });
    println!("{cases} elongation command lines: {:?}", outcomes.borrow());
    if let Err(failure) = result {
        panic!("{failure}");
    }
}

/// Runs `command` (at most 60 s) and checks its outcome: no panic, and either exit 0 with
/// `csv` holding more than `min_rows` rows of finite numbers, or exit 1 or 2 with an
/// error message and no `csv`. Counts the outcome in `outcomes`.
fn run_and_judge(
    command: &mut Command,
    csv: &std::path::Path,
    min_rows: usize,
    outcomes: &RefCell<BTreeMap<&'static str, usize>>,
) -> Result<(), TestCaseError> {
    let started = Instant::now();
    let output = command.output().unwrap();
    prop_assert!(
        started.elapsed() < Duration::from_secs(60),
        "{command:?} took {:?}",
        started.elapsed()
    );
    let stderr = String::from_utf8_lossy(&output.stderr).to_string();
    prop_assert!(!stderr.contains("panicked"), "{command:?}: {stderr}");
    if output.status.success() {
        let table = std::fs::read_to_string(csv).unwrap();
        prop_assert!(
            table.lines().count() > min_rows,
            "{command:?}: a table of {table}"
        );
        for line in table.lines().skip(1) {
            for value in line.split(',') {
                let number: f64 = value.trim().parse().unwrap_or(f64::NAN);
                prop_assert!(number.is_finite(), "{command:?} wrote '{value}' in: {line}");
            }
        }
        *outcomes.borrow_mut().entry("ran, all finite").or_default() += 1;
    } else {
        prop_assert!(
            matches!(output.status.code(), Some(1 | 2)),
            "{command:?}: {:?}",
            output.status
        );
        prop_assert!(
            stderr.contains("error"),
            "{command:?}: no message: {stderr}"
        );
        prop_assert!(
            !csv.exists(),
            "{command:?} failed but left {}",
            csv.display()
        );
        *outcomes
            .borrow_mut()
            .entry("refused with a message")
            .or_default() += 1;
    }
    Ok(())
}
