//! The knee as a scene (issue 30, step 4): `musclefem knee` writes `scene.toml` with the
//! files it names into each squat's directory, and `musclefem run` on it runs the same
//! squat.

mod support;

use std::path::Path;

use support::run::{musclefem, test_dir, text};

/// A CSV file's header names and its rows of fields, as text.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let split = |line: &str| line.split(',').map(str::to_string).collect::<Vec<_>>();
    let header = split(lines.next().unwrap_or_default());
    (header, lines.map(split).collect())
}

fn number(field: &str) -> f64 {
    field
        .parse()
        .unwrap_or_else(|e| panic!("'{field}' is not a number: {e}"))
}

/// The shallow passive squat (10° in 0.2 s, coarse, a frame every 0.05 s; about a
/// minute in release on 2 cores) writes its scene into `OUT/passive`; `musclefem run` on
/// that scene computes the squat's history bit for bit (every column the knee writes:
/// time, Newton counts, energies, every tie's and interaction's force) and, in the
/// columns `[output] von_mises_percentile = 95` adds, each muscle's vm95 of `vm95.csv`
/// at every recorded instant.
#[test]
fn the_knees_scene_reruns_its_squat_bit_for_bit() {
    let dir = test_dir("musclefem-knee-scene", "shallow");
    let knee = musclefem(
        &dir,
        &[
            "knee",
            "--passive",
            "--peak-flexion",
            "10",
            "--duration",
            "0.2",
            "--frame-interval",
            "0.05",
            "--resolution",
            "coarse",
            "--out",
            "knee",
        ],
    );
    assert!(knee.status.success(), "{}", text(&knee.stderr));
    let squat = dir.join("knee/passive");
    for file in [
        "scene.toml",
        "muscles.inp",
        "fibers.csv",
        "patella_table.csv",
        "femur.obj",
        "tibia.obj",
        "patella.obj",
    ] {
        assert!(squat.join(file).is_file(), "{file} is missing");
    }
    let scene = std::fs::read_to_string(squat.join("scene.toml")).unwrap();
    assert!(scene.contains("von_mises_percentile = 95"), "{scene}");

    let rerun = musclefem(&dir, &["run", "knee/passive/scene.toml", "--out", "rerun"]);
    assert!(rerun.status.success(), "{}", text(&rerun.stderr));

    // The knee's columns, then one vm95 column per part (bellies first).
    let (knee_header, knee_rows) = read_csv(&squat.join("history.csv"));
    let (scene_header, scene_rows) = read_csv(&dir.join("rerun/history.csv"));
    let columns = knee_header.len();
    assert_eq!(scene_header[..columns], knee_header[..]);
    let stresses = &scene_header[columns..];
    assert!(
        !stresses.is_empty()
            && stresses
                .iter()
                .all(|c| c.starts_with("von_mises_p95_") && c.ends_with("_pa")),
        "{stresses:?}"
    );
    assert!(knee_rows.len() > 10, "{} rows", knee_rows.len());
    assert_eq!(scene_rows.len(), knee_rows.len());
    for (scene_row, knee_row) in scene_rows.iter().zip(&knee_rows) {
        assert_eq!(scene_row[..columns], knee_row[..], "t = {} s", knee_row[0]);
    }

    // vm95.csv: time, angle, a vm95 per muscle, the smallest Jacobian ratio; a row at
    // t = 0 and at every increment.
    let (vm95_header, vm95_rows) = read_csv(&squat.join("vm95.csv"));
    let muscles = vm95_header.len() - 3;
    assert_eq!(muscles, 4, "{vm95_header:?}");
    assert!(
        stresses.len() > muscles,
        "bellies and tendons: {stresses:?}"
    );
    let mut compared = 0;
    for scene_row in &scene_rows {
        let time = number(&scene_row[0]);
        let Some(knee_row) = vm95_rows.iter().find(|row| number(&row[0]) == time) else {
            panic!("vm95.csv has no row at t = {time} s");
        };
        for m in 0..muscles {
            assert_eq!(
                number(&scene_row[columns + m]).to_bits(),
                number(&knee_row[2 + m]).to_bits(),
                "{} at t = {time} s",
                vm95_header[2 + m]
            );
        }
        compared += 1;
    }
    assert_eq!(compared, knee_rows.len());
    std::fs::remove_dir_all(&dir).unwrap();
}
