//! `musclefem elongate`: the files it writes and its refusal to overwrite a run (the
//! physics of the elongation tests is verified in the workspace's `tests/elongation.rs`).

/// `musclefem elongate --mode both`: DIR/passive and DIR/active each with curve.csv (exact
/// header) and frames with stress and fiber fields, DIR/curve.png, the stresses printed.
#[test]
fn the_command_writes_both_runs_and_one_chart() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("musclefem-elongate-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_musclefem"))
        .args([
            "elongate",
            "--mesh-size",
            "4",
            "--time-step",
            "0.1",
            "--frame-interval",
            "0.5",
            "--out",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
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
    let again = std::process::Command::new(env!("CARGO_BIN_EXE_musclefem"))
        .args(["elongate", "--mode", "passive", "--out"])
        .arg(dir.join("passive"))
        .output()
        .unwrap();
    assert!(!again.status.success());
}
