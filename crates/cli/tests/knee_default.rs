//! `musclefem knee` on its default anatomy, the Visible Human knee, for the first 5° of
//! the squat (0° → 5° → 0° in 0.1 s, passive, coarse, explicit with mass scaling; about
//! five to seven minutes in release on 2 shared cores): the command says what it runs,
//! the squat reaches its end (the explicit solver refuses to go on once its energy
//! balance is off by more than 1 %), no element turns a corner inside out, the passive
//! muscles stay far below what muscle carries, and each squat's files are there. The
//! whole squat takes hours; the README gives its tables.

mod support;

use support::csv::{number, read_csv};
use support::run::{musclefem, test_dir, text};

#[test]
fn the_default_knee_is_the_visible_human_and_its_first_degrees_run_explicitly() {
    let dir = test_dir("musclefem-knee-default", "first_degrees");
    let output = musclefem(
        &dir,
        &[
            "knee",
            "--passive",
            "--peak-flexion",
            "5",
            "--duration",
            "0.1",
            "--frame-interval",
            "0.025",
            "--out",
            "knee",
        ],
    );
    let stdout = text(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        text(&output.stderr)
    );
    assert!(
        stdout.contains("explicit solver with mass scaling")
            && stdout.contains("of tet10-fbar (visible human female, coarse resolution)"),
        "{stdout}"
    );
    let squat = dir.join("knee/passive");
    for file in [
        "scene.toml",
        "strands.csv",
        "history.csv",
        "vm95.csv",
        "tendon.csv",
        "run.log",
        "result.pvd",
    ] {
        assert!(squat.join(file).is_file(), "no {file}");
    }
    // run.log gives the step taken beside the mass-scaling target: the shear viscosity's
    // damping keeps it below the target (docs/knee-solver.md), and it is the mean of the
    // history's steps.
    let log = std::fs::read_to_string(squat.join("run.log")).unwrap();
    let value = |key: &str| {
        log.lines()
            .find_map(|l| l.strip_prefix(key))
            .and_then(|rest| rest.trim().strip_prefix('='))
            .map(|v| number(v.trim()))
            .unwrap_or_else(|| panic!("no {key} in run.log:\n{log}"))
    };
    let (target, steps, mean) = (
        value("time_step_s"),
        value("steps"),
        value("mean_time_step_s"),
    );
    assert!((mean * steps - 0.1).abs() < 1e-3 * 0.1, "{log}");
    assert!(mean < target && mean > 0.5 * target, "{log}");
    // The procedural knee's anatomy export is not written for the Visible Human knee; its
    // patella's tracking in the trochlear groove is (every 5° to the peak, 0° and 5°).
    assert!(!dir.join("knee/anatomy").exists());
    assert!(stdout.contains("patellar tracking"), "{stdout}");
    let (header, rows) = read_csv(&dir.join("knee/patella_tracking.csv"));
    assert_eq!(header[0], "knee_angle_deg");
    assert_eq!(header[4], "ridge_lateral_of_floor_mm");
    assert_eq!(rows.len(), 2);

    let (header, rows) = read_csv(&squat.join("vm95.csv"));
    assert_eq!(
        header,
        [
            "time_s",
            "knee_angle_deg",
            "VI_vm95_pa",
            "VL_vm95_pa",
            "VM_vm95_pa",
            "RF_vm95_pa",
            "min_jacobian_ratio"
        ]
    );
    // 0° → 5° → 0° in 0.1 s: the squat ends at its duration, past its peak (the rows
    // are 0.02 s apart, so the peak itself falls between two of them).
    let last = rows.last().unwrap();
    assert!((number(&last[0]) - 0.1).abs() < 1e-9, "{last:?}");
    let peak_angle = rows.iter().map(|r| number(&r[1])).fold(0.0, f64::max);
    assert!(
        (4.0..=5.0 + 1e-9).contains(&peak_angle),
        "peak {peak_angle}°"
    );
    for row in &rows {
        for value in &row[2..6] {
            let vm95 = number(value);
            // Issue #29's passive bound at 90°; 5° asks far less of the muscles.
            assert!(
                vm95.is_finite() && (0.0..=0.25e6).contains(&vm95),
                "{row:?}"
            );
        }
    }
    // No element turns a corner inside out. Before the mesh's curved tet10 were
    // straightened to a corner Jacobian ratio of at least 0.5 (they started at 0.1), one
    // distal tet10 of the vastus intermedius did so at 4.5° (ratio −0.03):
    // docs/knee-model.md, "Curved tet10 that invert".
    for row in &rows {
        let ratio = number(&row[6]);
        assert!(
            ratio > 0.0,
            "an element turned a corner inside out: {row:?}"
        );
    }

    // Stretched, the muscles carry some stress by the peak.
    let at_peak = rows
        .iter()
        .find(|r| (number(&r[1]) - peak_angle).abs() < 1e-9)
        .unwrap();
    assert!(at_peak[2..6].iter().all(|v| number(v) > 0.0), "{at_peak:?}");
}
