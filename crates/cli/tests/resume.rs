//! Checkpoint and restart: a run killed at a random frame and resumed with `--resume`
//! ends with the files of a run never stopped, byte for byte.

mod support;

use std::path::Path;
use std::process::Command;

use support::run::{example, musclefem, test_dir, text};

/// The scenes: the explicit Hill block held isometric (made longer), the implicit
/// neo-Hookean cube (more increments), the implicit peel of two bonded blocks (cohesive
/// bonds that damage; also with bonds that slide along smooth normals), and the block
/// pressed on the rigid sphere (penalty contact at the closest point and along smooth
/// normals, implicit; and explicit).
fn scenes() -> Vec<(&'static str, String)> {
    let read = |name: &str| std::fs::read_to_string(example(name)).unwrap();
    vec![
        (
            "explicit",
            read("hill_block_isometric.toml").replace("duration = 0.15", "duration = 0.3"),
        ),
        (
            "implicit",
            read("neo_hookean_cube_stretch.toml")
                .replace("increments = 10 }", "increments = 40 }")
                .replace("output_interval = 0.1", "output_interval = 0.05"),
        ),
        (
            "cohesive",
            read("bonded_blocks_peel.toml").replace("increments = 30", "increments = 60"),
        ),
        (
            "sliding cohesive",
            read("bonded_blocks_peel.toml")
                .replace("increments = 30", "increments = 60")
                .replace(
                    "failure_separation = 0.004",
                    "failure_separation = 0.004\ntangential = \"smooth-slide\"",
                ),
        ),
        (
            "contact",
            read("block_on_rigid_sphere.toml")
                .replace("increments = 10", "increments = 40")
                .replace("output_interval = 0.1", "output_interval = 0.05"),
        ),
        (
            "smooth contact",
            read("block_on_rigid_sphere.toml")
                .replace("increments = 10", "increments = 40")
                .replace("output_interval = 0.1", "output_interval = 0.05")
                .replace("main = \"ball\"", "main = \"ball\"\nsmooth_normals = true"),
        ),
        (
            "explicit contact",
            read("block_on_rigid_sphere.toml")
                .replace("solver = \"implicit\"", "solver = \"explicit\"")
                .replace("duration = 1.0", "duration = 0.002")
                .replace("output_interval = 0.1", "output_interval = 0.0001"),
        ),
    ]
}

/// A pseudo-random frame number in `1..=last` (from the clock: the test prints it).
fn some_frame(last: usize) -> usize {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .subsec_nanos() as usize;
    1 + nanos % last
}

/// The files a run leaves that must not depend on whether it was stopped (run.log holds
/// timings and says it was resumed).
fn results(root: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files = vec!["history.csv".to_string(), "result.pvd".to_string()];
    // The rigid bodies' series (the contact scenes' sphere), beside the frames.
    if root.join("rigid.pvd").exists() {
        files.push("rigid.pvd".to_string());
    }
    let mut frames: Vec<String> = std::fs::read_dir(root.join("frames"))
        .unwrap()
        .map(|e| format!("frames/{}", e.unwrap().file_name().to_string_lossy()))
        .collect();
    frames.sort();
    files.extend(frames);
    files
        .into_iter()
        .map(|name| {
            let bytes = std::fs::read(root.join(&name)).unwrap();
            (name, bytes)
        })
        .collect()
}

#[cfg(unix)]
#[test]
fn a_run_killed_at_a_random_frame_resumes_to_the_same_files_byte_for_byte() {
    for (name, scene) in scenes() {
        let dir = test_dir("musclefem-resume", &name.replace(' ', "-"));
        std::fs::write(dir.join("scene.toml"), &scene).unwrap();
        let whole = musclefem(&dir, &["run", "scene.toml", "--out", "whole"]);
        assert!(whole.status.success(), "{}", text(&whole.stderr));
        assert!(
            !dir.join("whole/checkpoint.bin").exists(),
            "a complete run leaves no checkpoint"
        );
        let frames = (results(&dir.join("whole")).iter())
            .filter(|(name, _)| name.starts_with("frames/frame_"))
            .count();

        // Killed (abort: no handler, no clean-up) right after the checkpoint of a frame
        // between the first and the one before the last.
        let kill_after = some_frame(frames - 2);
        let killed = Command::new(env!("CARGO_BIN_EXE_musclefem"))
            .args(["run", "scene.toml", "--out", "cut"])
            .env("MUSCLEFEM_ABORT_AFTER_CHECKPOINT", kill_after.to_string())
            .current_dir(&dir)
            .output()
            .unwrap();
        assert!(
            !killed.status.success() && killed.status.code().is_none(),
            "{name}: the run was to be killed after checkpoint {kill_after}: {:?}",
            killed.status
        );
        assert!(dir.join("cut/checkpoint.bin").is_file());

        let resumed = musclefem(&dir, &["run", "scene.toml", "--out", "cut", "--resume"]);
        assert!(
            resumed.status.success(),
            "{name}, killed after checkpoint {kill_after}: {}",
            text(&resumed.stderr)
        );
        let (expected, found) = (results(&dir.join("whole")), results(&dir.join("cut")));
        assert_eq!(
            expected.iter().map(|f| &f.0).collect::<Vec<_>>(),
            found.iter().map(|f| &f.0).collect::<Vec<_>>(),
            "{name}, killed after checkpoint {kill_after}: other files"
        );
        for ((file, a), (_, b)) in expected.iter().zip(&found) {
            assert!(
                a == b,
                "{name}, killed after checkpoint {kill_after}: {file} differs"
            );
        }
        let log = std::fs::read_to_string(dir.join("cut/run.log")).unwrap();
        assert!(
            log.contains("resumed = from the checkpoint at t = "),
            "{log}"
        );
        assert!(log.contains("end = complete"), "{log}");
        assert!(!dir.join("cut/checkpoint.bin").exists());

        // Nothing left to resume.
        let again = musclefem(&dir, &["run", "scene.toml", "--out", "cut", "--resume"]);
        assert!(!again.status.success());
        assert!(
            text(&again.stderr).contains("no checkpoint to resume from"),
            "{}",
            text(&again.stderr)
        );
    }
}

/// A checkpoint resumes only the model it was taken from: another scene text (here a
/// changed load) is refused before anything in the directory changes.
#[cfg(unix)]
#[test]
fn a_checkpoint_of_another_scene_is_refused() {
    let dir = test_dir("musclefem-resume", "other");
    let (_, scene) = scenes().remove(1);
    std::fs::write(dir.join("scene.toml"), &scene).unwrap();
    let killed = Command::new(env!("CARGO_BIN_EXE_musclefem"))
        .args(["run", "scene.toml", "--out", "cut"])
        .env("MUSCLEFEM_ABORT_AFTER_CHECKPOINT", "3")
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(!killed.status.success());
    let before = results(&dir.join("cut"));
    std::fs::write(
        dir.join("scene.toml"),
        scene.replace("value = 0.005", "value = 0.004"),
    )
    .unwrap();
    let resumed = musclefem(&dir, &["run", "scene.toml", "--out", "cut", "--resume"]);
    assert!(!resumed.status.success());
    let message = text(&resumed.stderr);
    assert!(
        message.contains("another scene, mesh or solver"),
        "{message}"
    );
    assert_eq!(before, results(&dir.join("cut")), "nothing changed");
    // --resume and --force do not go together.
    let both = musclefem(
        &dir,
        &["run", "scene.toml", "--out", "cut", "--resume", "--force"],
    );
    assert!(!both.status.success());
}

/// The knee: a shallow passive squat (10° in 0.2 s, a frame every 0.05 s; about 50 s on
/// 2 cores) killed after a random frame's checkpoint and resumed ends with the files of
/// the squat never stopped, byte for byte: its history and frames, and the tables built
/// from the knee's own state in the checkpoint (vm95, tendon, plausibility, peak
/// stress). A second --resume finds the study complete; other options find a checkpoint
/// of another squat.
#[cfg(unix)]
#[test]
fn a_killed_knee_squat_resumes_to_the_same_files_byte_for_byte() {
    let dir = test_dir("musclefem-resume", "knee");
    let squat = |out: &str| -> Vec<String> {
        [
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
            "--out",
            out,
        ]
        .map(String::from)
        .to_vec()
    };
    let args = |out: &str, more: &[&str]| {
        let mut args = squat(out);
        args.extend(more.iter().map(|s| s.to_string()));
        args
    };
    let run = |args: Vec<String>| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        musclefem(&dir, &args)
    };
    let whole = run(squat("whole"));
    assert!(whole.status.success(), "{}", text(&whole.stderr));
    assert!(!dir.join("whole/passive/checkpoint.bin").exists());
    let knee_results = |root: &Path| {
        let mut files = results(&root.join("passive"));
        for name in [
            "passive/vm95.csv",
            "passive/tendon.csv",
            "passive/plausibility.csv",
            "peak_stress.csv",
        ] {
            files.push((name.to_string(), std::fs::read(root.join(name)).unwrap()));
        }
        files
    };
    let expected = knee_results(&dir.join("whole"));
    // Frames at 0, 0.05, 0.1, 0.15 and 0.2 s; a checkpoint after each but the first.
    // With each frame the bones' file, listed in rigid.pvd.
    assert_eq!(
        expected.len(),
        3 + 2 * 5 + 4,
        "{:?}",
        expected.iter().map(|f| &f.0)
    );

    let kill_after = some_frame(3);
    let killed = Command::new(env!("CARGO_BIN_EXE_musclefem"))
        .args(squat("cut"))
        .env("MUSCLEFEM_ABORT_AFTER_CHECKPOINT", kill_after.to_string())
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(
        !killed.status.success() && killed.status.code().is_none(),
        "the squat was to be killed after checkpoint {kill_after}: {:?}",
        killed.status
    );
    assert!(dir.join("cut/passive/checkpoint.bin").is_file());
    let log = std::fs::read_to_string(dir.join("cut/passive/run.log")).unwrap();
    assert!(log.contains("end = running"), "{log}");

    // Other options: the checkpoint is of another squat, and nothing changes.
    let other = run(args("cut", &["--resume", "--interfaces", "elastic-shear"]));
    assert!(!other.status.success());
    assert!(
        text(&other.stderr).contains("another scene, mesh or solver"),
        "{}",
        text(&other.stderr)
    );

    let resumed = run(args("cut", &["--resume"]));
    assert!(
        resumed.status.success(),
        "killed after checkpoint {kill_after}: {}",
        text(&resumed.stderr)
    );
    assert!(
        text(&resumed.stdout).contains("resumed from its checkpoint at t = "),
        "{}",
        text(&resumed.stdout)
    );
    let found = knee_results(&dir.join("cut"));
    assert_eq!(
        expected.iter().map(|f| &f.0).collect::<Vec<_>>(),
        found.iter().map(|f| &f.0).collect::<Vec<_>>()
    );
    for ((file, a), (_, b)) in expected.iter().zip(&found) {
        assert!(
            a == b,
            "killed after checkpoint {kill_after}: {file} differs"
        );
    }
    let log = std::fs::read_to_string(dir.join("cut/passive/run.log")).unwrap();
    assert!(
        log.contains("resumed = from the checkpoint at t = "),
        "{log}"
    );
    assert!(log.contains("end = complete"), "{log}");
    assert!(!dir.join("cut/passive/checkpoint.bin").exists());

    let again = run(args("cut", &["--resume"]));
    assert!(!again.status.success());
    assert!(
        text(&again.stderr).contains("there is nothing to resume"),
        "{}",
        text(&again.stderr)
    );
}
