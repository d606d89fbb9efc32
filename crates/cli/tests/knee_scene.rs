//! The knee as a scene (issue 30, step 4): `musclefem knee` writes `scene.toml` with the
//! files it names into each squat's directory and runs it through the directory runner
//! of `musclefem run`, which reruns it to the same files.

mod support;

use support::csv::{number, read_csv};
use support::run::{musclefem, test_dir, text};

use musclefem_studies::knee::simulation::peak_stress::{
    peak_stress_from_history, stage_peak_stress_csv,
};
use musclefem_studies::knee::simulation::{Activation, KneeGeometry};
use musclefem_studies::knee::{Anatomy, Resolution, Squat};

/// The shallow passive squat (10° in 0.2 s, coarse, a frame every 0.05 s; about a
/// minute in release on 2 cores) writes its scene into `OUT/passive`; `musclefem run` on
/// that scene writes the squat's `history.csv` byte for byte (time, Newton counts,
/// energies, every tie's and interaction's force, and each part's vm95, the columns
/// `[output] von_mises_percentile = 95` adds), and `peak_stress.csv` built from the
/// rerun's history is the knee's, byte for byte (the shallow squat stays below the
/// table's first angle, 30°: its header alone). The muscles' vm95 columns are
/// `vm95.csv`'s at every recorded instant.
#[test]
fn the_knees_scene_reruns_its_squat_bit_for_bit() {
    let dir = test_dir("musclefem-knee-scene", "shallow");
    let knee = musclefem(
        &dir,
        &[
            "knee",
            "--anatomy",
            "procedural",
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

    let history = std::fs::read(squat.join("history.csv")).unwrap();
    assert!(
        history == std::fs::read(dir.join("rerun/history.csv")).unwrap(),
        "the rerun's history.csv differs"
    );
    let squat_motion = Squat {
        duration: 0.2,
        peak_flexion: 10f64.to_radians(),
    };
    let anatomy = Anatomy::procedural_knee(Resolution::Coarse).unwrap();
    let geometry = KneeGeometry::procedural_knee(&anatomy, &squat_motion).unwrap();
    let bellies: Vec<&str> = (0..geometry.muscles.len())
        .map(|m| geometry.block_name(m))
        .collect();
    let rows = peak_stress_from_history(
        &dir.join("rerun/history.csv"),
        &bellies,
        &geometry.muscles,
        &squat_motion,
        Activation::Passive,
    )
    .unwrap();
    stage_peak_stress_csv(&dir.join("rerun/peak_stress.csv"), &rows)
        .unwrap()
        .commit()
        .unwrap();
    assert_eq!(
        std::fs::read_to_string(dir.join("rerun/peak_stress.csv")).unwrap(),
        std::fs::read_to_string(dir.join("knee/peak_stress.csv")).unwrap()
    );

    // The knee's columns, then one vm95 column per part (bellies first).
    let (scene_header, scene_rows) = read_csv(&dir.join("rerun/history.csv"));
    let stresses: Vec<&String> = (scene_header.iter())
        .filter(|c| c.starts_with("von_mises_p95_"))
        .collect();
    let columns = scene_header.len() - stresses.len();
    assert!(
        stresses.iter().all(|c| c.ends_with("_pa"))
            && scene_header[columns..].iter().eq(stresses.iter().copied()),
        "{scene_header:?}"
    );
    assert!(scene_rows.len() > 10, "{} rows", scene_rows.len());

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
    assert_eq!(compared, scene_rows.len());
    std::fs::remove_dir_all(&dir).unwrap();
}
