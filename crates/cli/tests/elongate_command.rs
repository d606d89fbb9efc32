//! `musclefem elongate`: the files it writes and its refusal to overwrite a run (the
//! physics of the elongation tests is verified in the workspace's `tests/elongation.rs`).

mod support;

use support::run::{CHEAP_ELONGATION, musclefem, test_dir, text};

/// `musclefem elongate --mode both`: DIR/passive and DIR/active each with curve.csv (exact
/// header) and frames with stress and fiber fields, DIR/curve.png, the stresses printed.
#[test]
fn the_command_writes_both_runs_and_one_chart() {
    let root = test_dir("musclefem-elongate", "both");
    let args = [
        "elongate",
        "--mesh-size",
        "4",
        "--time-step",
        "0.1",
        "--frame-interval",
        "0.5",
        "--out",
        "both",
    ];
    let output = musclefem(&root, &args);
    let dir = root.join("both");
    let stdout = text(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        text(&output.stderr)
    );
    assert_eq!(
        stdout.matches("engineering stress at 10 % strain").count(),
        2,
        "{stdout}"
    );
    assert_eq!(
        stdout.matches("engineering stress at 20 % strain").count(),
        2,
        "{stdout}"
    );
    // The default setting says why it is the default, from the measured chart.
    assert!(
        stdout.contains("implicit F-bar hex8 at 4 mm, the default: on the measured"),
        "{stdout}"
    );
    assert!(dir.join("curve.png").is_file());
    for mode in ["passive", "active"] {
        let csv = std::fs::read_to_string(dir.join(mode).join("curve.csv")).unwrap();
        assert_eq!(
            csv.lines().next(),
            Some("time_s,engineering_strain,reaction_force_n,engineering_stress_pa")
        );
        let frames = musclefem_io::output::read_pvd(&dir.join(mode).join("result.pvd")).unwrap();
        assert!(frames.len() >= 3, "{mode}: {} frames", frames.len());
        let last =
            std::fs::read_to_string(dir.join(mode).join(&frames.last().unwrap().file)).unwrap();
        for array in ["cauchy_stress", "von_mises", "fiber_direction_current"] {
            assert!(
                last.contains(&format!("Name=\"{array}\"")),
                "{mode}: no {array}"
            );
        }
    }
    // A second run into the same directory is refused without --force.
    let again = musclefem(
        &root,
        &["elongate", "--mode", "passive", "--out", "both/passive"],
    );
    assert!(!again.status.success());
}

/// `--time-step` 0 and 1e-300 ran forever, −0.1 and 1e9 took one step and printed a wrong
/// stress with exit 0: each is refused at once, naming the value, and nothing is written.
#[test]
fn a_time_step_that_cannot_give_the_curve_is_refused_before_any_output() {
    let dir = test_dir("musclefem-elongate", "time-step");
    for (step, expected) in [
        ("0", "must be a positive number"),
        ("-0.1", "must be a positive number"),
        ("1e-300", "would take"),
        ("1e9", "more than a fifth"),
        ("NaN", "must be a positive number"),
    ] {
        let mut args = vec!["elongate", "--mode", "passive"];
        args.extend_from_slice(&CHEAP_ELONGATION[..6]);
        let out = format!("step{step}");
        args.extend_from_slice(&["--time-step", step, "--out", &out]);
        let output = musclefem(&dir, &args);
        let stderr = text(&output.stderr);
        assert!(!output.status.success(), "--time-step {step} was accepted");
        assert!(
            stderr.contains(&format!(
                "--time-step {}",
                musclefem_io::csv::format_number(step.parse::<f64>().unwrap())
            )) && stderr.contains(expected),
            "--time-step {step}: {stderr}"
        );
        assert!(!dir.join(&out).exists(), "--time-step {step} wrote output");
    }
}

/// A negative `--frame-interval` was accepted silently; it is refused, naming the value,
/// by `elongate` and `knee` alike, before any output.
#[test]
fn a_negative_frame_interval_is_refused() {
    let dir = test_dir("musclefem-elongate", "frame-interval");
    for command in ["elongate", "knee"] {
        let output = musclefem(&dir, &[command, "--frame-interval", "-1", "--out", command]);
        let stderr = text(&output.stderr);
        assert!(!output.status.success(), "{command}: accepted");
        assert!(
            stderr.contains("--frame-interval -1 s must be 0"),
            "{command}: {stderr}"
        );
        assert!(!dir.join(command).exists(), "{command} wrote output");
    }
}

/// Ctrl-C (SIGINT) during `elongate` stops the test after its last point: exit status
/// 130, the curve up to there in curve.csv, and a run.log that says where it stopped
/// (before, the process died with the curve lost).
#[cfg(unix)]
#[test]
fn ctrl_c_keeps_the_curve_up_to_where_the_test_stopped() {
    use std::process::{Command, Stdio};
    use std::time::{Duration, Instant};
    let dir = test_dir("elongate", "interrupt");
    // The explicit active test mass-scaled to 2e-6 s only: some 750 000 steps, tens of
    // seconds of solving.
    // The cheap model's shape, grips and mesh, with the step below.
    let mut args = vec!["elongate", "--mode", "active", "--solver", "explicit"];
    args.extend_from_slice(&CHEAP_ELONGATION[..6]);
    args.extend_from_slice(&[
        "--time-step",
        "2e-6",
        "--frame-interval",
        "0.05",
        "--out",
        "stopped",
    ]);
    let mut child = Command::new(env!("CARGO_BIN_EXE_musclefem"))
        .args(&args)
        .current_dir(&dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait for a couple of frames, then interrupt.
    let frames = dir.join("stopped/frames");
    let started = Instant::now();
    while std::fs::read_dir(&frames).map_or(0, |d| d.count()) < 2 {
        assert!(started.elapsed() < Duration::from_secs(120), "no frames");
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the test finished ({status:?}) before it could be interrupted");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let output = child.wait_with_output().unwrap();
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted: stopped at t = "), "{stderr}");
    let curve = std::fs::read_to_string(dir.join("stopped/curve.csv")).unwrap();
    let rows: Vec<&str> = curve.lines().skip(1).collect();
    assert!(rows.len() >= 2, "{curve}");
    let last_time: f64 = rows
        .last()
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(last_time > 0.0 && last_time < 1.0, "{last_time}");
    let log = std::fs::read_to_string(dir.join("stopped/run.log")).unwrap();
    assert!(log.contains("end = interrupted at t = "), "{log}");
    // The history up to there too.
    let history = std::fs::read_to_string(dir.join("stopped/history.csv")).unwrap();
    assert!(history.lines().count() >= 2, "{history}");
}

/// `elongate` writes the solver's history beside the curve: a reaction column per end
/// condition (the pulled end's is the curve's force, row for row) and the energies.
#[test]
fn the_history_beside_the_curve_holds_every_reaction() {
    let dir = test_dir("musclefem-elongate", "history");
    let mut args = vec!["elongate", "--mode", "passive"];
    args.extend_from_slice(&CHEAP_ELONGATION);
    args.extend_from_slice(&["--out", "run"]);
    let output = musclefem(&dir, &args);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let table = std::fs::read_to_string(dir.join("run/history.csv")).unwrap();
    let header: Vec<&str> = table.lines().next().unwrap().split(',').collect();
    for column in [
        "time_s",
        "newton_iterations",
        "reaction_specimen.insertion.z_n",
        "reaction_specimen.origin.z_n",
        "reaction_specimen.origin_axis.x_n",
        "reaction_specimen.origin_axis.y_n",
        "reaction_specimen.origin_edge.y_n",
        "internal_energy_j",
    ] {
        assert!(header.contains(&column), "{column} not in {header:?}");
    }
    let pulled = header
        .iter()
        .position(|c| *c == "reaction_specimen.insertion.z_n")
        .unwrap();
    let history: Vec<Vec<f64>> = table
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let curve = std::fs::read_to_string(dir.join("run/curve.csv")).unwrap();
    // The curve starts with the stress-free point at t = 0, which the implicit history
    // has no row for.
    let forces: Vec<f64> = curve
        .lines()
        .skip(2)
        .map(|l| l.split(',').nth(2).unwrap().parse().unwrap())
        .collect();
    assert_eq!(forces.len(), history.len());
    for (row, force) in history.iter().zip(&forces) {
        assert_eq!(row[pulled], *force);
    }
    // The two ends' axial reactions balance (no inertia in the quasi-static test).
    let origin = header
        .iter()
        .position(|c| *c == "reaction_specimen.origin.z_n")
        .unwrap();
    let last = history.last().unwrap();
    assert!((last[pulled] + last[origin]).abs() < 1e-8 * last[pulled].abs());
}

/// `elongate` writes its test as a scene (`scene.toml` and `specimen.inp` beside the
/// results): `musclefem run` on it reproduces `history.csv`, `result.pvd` and every frame
/// byte for byte.
#[test]
fn musclefem_run_reproduces_the_test_from_its_scene() {
    let dir = test_dir("musclefem-elongate", "scene");
    let mut args = vec!["elongate", "--mode", "active", "--frame-interval", "0.5"];
    args.extend_from_slice(&CHEAP_ELONGATION);
    args.extend_from_slice(&["--param", "sigma0=4e5", "--out", "test"]);
    let tested = musclefem(&dir, &args);
    assert!(tested.status.success(), "{}", text(&tested.stderr));
    assert!(dir.join("test/specimen.inp").is_file());
    let scene = std::fs::read_to_string(dir.join("test/scene.toml")).unwrap();
    assert!(scene.contains("sigma0 = 400000.0"), "{scene}");
    let rerun = musclefem(&dir, &["run", "test/scene.toml", "--out", "rerun"]);
    assert!(rerun.status.success(), "{}", text(&rerun.stderr));
    let files = results(&dir.join("test"));
    assert!(files.len() >= 5, "{} files", files.len());
    assert_eq!(files, results(&dir.join("rerun")));
}

/// An elongation test killed right after a checkpoint goes on with `--resume` to the
/// files of a test never stopped: history, frames and curve byte for byte.
#[cfg(unix)]
#[test]
fn a_killed_test_resumes_to_the_same_curve() {
    use std::process::Command;
    let dir = test_dir("musclefem-elongate", "resume");
    let mut args = vec!["elongate", "--mode", "passive", "--frame-interval", "0.25"];
    args.extend_from_slice(&CHEAP_ELONGATION);
    let whole = musclefem(&dir, &[&args[..], &["--out", "whole"]].concat());
    assert!(whole.status.success(), "{}", text(&whole.stderr));
    let killed = Command::new(env!("CARGO_BIN_EXE_musclefem"))
        .args([&args[..], &["--out", "cut"]].concat())
        .env("MUSCLEFEM_ABORT_AFTER_CHECKPOINT", "3")
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(killed.status.code().is_none(), "{:?}", killed.status);
    assert!(dir.join("cut/checkpoint.bin").is_file());
    let resumed = musclefem(&dir, &[&args[..], &["--out", "cut", "--resume"]].concat());
    assert!(resumed.status.success(), "{}", text(&resumed.stderr));
    assert!(
        text(&resumed.stdout).contains("resumed from the checkpoint at t = "),
        "{}",
        text(&resumed.stdout)
    );
    let mut expected = results(&dir.join("whole"));
    let mut found = results(&dir.join("cut"));
    for (files, root) in [(&mut expected, "whole"), (&mut found, "cut")] {
        let curve = std::fs::read(dir.join(root).join("curve.csv")).unwrap();
        files.push(("curve.csv".to_string(), curve));
    }
    assert_eq!(expected, found);
    // A completed test is read back, not rerun.
    let again = musclefem(&dir, &[&args[..], &["--out", "cut", "--resume"]].concat());
    assert!(again.status.success(), "{}", text(&again.stderr));
    assert!(text(&again.stdout).contains("complete in an earlier run"));
}

/// The files of a run that do not hold timings: history, frame index and frames.
fn results(root: &std::path::Path) -> Vec<(String, Vec<u8>)> {
    let mut names = vec!["history.csv".to_string(), "result.pvd".to_string()];
    let mut frames: Vec<String> = std::fs::read_dir(root.join("frames"))
        .unwrap()
        .map(|e| format!("frames/{}", e.unwrap().file_name().to_string_lossy()))
        .collect();
    frames.sort();
    names.extend(frames);
    names
        .into_iter()
        .map(|name| {
            let bytes = std::fs::read(root.join(&name)).unwrap();
            (name, bytes)
        })
        .collect()
}
