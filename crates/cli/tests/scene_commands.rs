//! `musclefem check` and `musclefem run` on the examples and on broken scenes.

mod support;

use support::run;

use run::{example, musclefem, test_dir, text};

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use musclefem_io::csv::read_table;
use musclefem_io::output::read_pvd;

#[test]
fn check_describes_a_good_scene_and_names_the_line_of_a_bad_one() {
    let dir = test_dir("musclefem-scene", "check");
    let out = musclefem(&dir, &["check", &example("hill_block_isometric.toml")]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains(": ok") && stdout.contains("part 'block': 16"),
        "{stdout}"
    );

    let good = std::fs::read_to_string(example("neo_hookean_cube_stretch.toml")).unwrap();
    let bad = good.replacen("density = 1000.0", "densty = 1000.0", 1);
    std::fs::write(dir.join("bad.toml"), &bad).unwrap();
    let out = musclefem(&dir, &["check", "bad.toml"]);
    assert!(!out.status.success());
    let line = bad.lines().position(|l| l.starts_with("densty")).unwrap() + 1;
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains(&format!("bad.toml:{line}:")) && stderr.contains("did you mean `density`?"),
        "{stderr}"
    );
    // A run of the bad scene writes nothing.
    let out = musclefem(&dir, &["run", "bad.toml", "--out", "never"]);
    assert!(!out.status.success());
    assert!(!dir.join("never").exists());
}

/// The neo-Hookean example: 11 frames listed in result.pvd (t = 0 and every 0.1 s), a history whose last
/// reaction is the material-point driver's 1.0026 N, the scene copy and the log; a second
/// run into the same directory is refused unless --force.
#[test]
fn run_writes_frames_history_scene_and_log() {
    let dir = test_dir("musclefem-scene", "run");
    let scene = example("neo_hookean_cube_stretch.toml");
    let out = musclefem(&dir, &["run", &scene, "--out", "result"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    // Not a terminal: plain progress lines instead of a bar.
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("t = 1.000000e0 s of 1 s (100 %)"),
        "{stderr}"
    );
    let root = dir.join("result");
    let frames = read_pvd(&root.join("result.pvd")).unwrap();
    assert_eq!(frames.len(), 11);
    assert_eq!(frames[0].time, 0.0);
    assert!((frames.last().unwrap().time - 1.0).abs() < 1e-12);
    for frame in &frames {
        assert!(root.join(&frame.file).is_file(), "{}", frame.file);
    }
    let last_frame = std::fs::read_to_string(root.join(&frames.last().unwrap().file)).unwrap();
    for array in [
        "displacement",
        "cauchy_stress",
        "von_mises",
        "fiber_direction_current",
        "block_id",
    ] {
        assert!(
            last_frame.contains(&format!("Name=\"{array}\"")),
            "the last frame has no '{array}' array"
        );
    }
    let header = "time_s,time_step_s,newton_iterations,reaction_cube.x1.x_n,\
                  reaction_cube.x0.x_n,reaction_cube.y0.y_n,reaction_cube.z0.z_n,\
                  internal_energy_j,kinetic_energy_j,external_work_j";
    let rows = read_table(&root.join("history.csv"), header).unwrap();
    assert_eq!(rows.len(), 10);
    let reaction = rows.last().unwrap()[3];
    assert!((reaction - 1.002568).abs() < 1e-5, "{reaction} N");
    // Quasi-static energies (they were all 0): the work of the pulled face's reaction,
    // ∫ R du with u = 5 mm × t, trapezoidal over the rows, is the strain energy put in.
    let mut work = 0.0;
    let (mut time, mut force) = (0.0, 0.0);
    for row in &rows {
        work += 0.5 * (force + row[3]) * 0.005 * (row[0] - time);
        (time, force) = (row[0], row[3]);
    }
    let last = rows.last().unwrap();
    let (internal, kinetic, external) = (last[7], last[8], last[9]);
    assert!(work > 2e-3 && work < 4e-3, "{work} J");
    assert!(
        (internal - work).abs() < 1e-6 * work,
        "{internal} J, {work} J"
    );
    assert!(
        (external - internal).abs() < 1e-6 * internal,
        "{external} J, {internal} J"
    );
    assert_eq!(kinetic, 0.0);
    assert_eq!(
        std::fs::read_to_string(root.join("scene.toml")).unwrap(),
        std::fs::read_to_string(&scene).unwrap()
    );
    assert!(
        std::fs::read_to_string(root.join("run.log"))
            .unwrap()
            .contains("solve")
    );

    let again = musclefem(&dir, &["run", &scene, "--out", "result"]);
    assert!(!again.status.success());
    assert!(
        text(&again.stderr).contains("--force"),
        "{}",
        text(&again.stderr)
    );
    let forced = musclefem(&dir, &["run", &scene, "--out", "result", "--force"]);
    assert!(forced.status.success(), "{}", text(&forced.stderr));
}

/// The same scene with the other solver: the explicit run of the quasi-static stretch gives
/// the same final reaction within 1 % (a 1 s ramp is slow for this cube).
#[test]
fn run_with_the_other_solver_agrees() {
    let dir = test_dir("musclefem-scene", "switch");
    let scene = example("neo_hookean_cube_stretch.toml");
    let out = musclefem(
        &dir,
        &[
            "run",
            &scene,
            "--out",
            "explicit",
            "--solver",
            "explicit",
            "--threads",
            "2",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let reaction: f64 = stdout
        .split("cube.x1.x ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|number| number.parse().ok())
        .unwrap_or_else(|| panic!("no reaction in {stdout}"));
    assert!((reaction - 1.002568).abs() < 0.01, "{reaction} N");
}

/// The Hill example's frames carry the activation and the material's state variables.
#[test]
fn hill_frames_carry_activation_and_state_variables() {
    let dir = test_dir("musclefem-scene", "hill");
    let scene = example("hill_block_isometric.toml");
    let out = musclefem(&dir, &["run", &scene, "--out", "result"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let root = dir.join("result");
    let frames = read_pvd(&root.join("result.pvd")).unwrap();
    let last = std::fs::read_to_string(root.join(&frames.last().unwrap().file)).unwrap();
    for array in [
        "activation",
        "state_lambda_m",
        "state_lambda_s",
        "state_sigma_see",
    ] {
        assert!(last.contains(&format!("Name=\"{array}\"")), "no '{array}'");
    }
}

/// `run long.toml --out result` in `dir` on the neo-Hookean example made long (1000 s
/// explicit on a finer mesh), started and left running.
#[cfg(unix)]
fn start_a_long_run(dir: &std::path::Path, stdout: Stdio, stderr: Stdio) -> std::process::Child {
    let scene = std::fs::read_to_string(example("neo_hookean_cube_stretch.toml"))
        .unwrap()
        .replace("divisions = [4, 4, 4]", "divisions = [8, 8, 8]")
        .replace("duration = 1.0", "duration = 1000.0")
        .replace("output_interval = 0.1", "output_interval = 0.01")
        .replace("solver = \"implicit\"", "solver = \"explicit\"");
    std::fs::write(dir.join("long.toml"), scene).unwrap();
    Command::new(env!("CARGO_BIN_EXE_musclefem"))
        .args(["run", "long.toml", "--out", "result"])
        .current_dir(dir)
        .stdout(stdout)
        .stderr(stderr)
        .spawn()
        .unwrap()
}

/// Waits (at most 2 min) until the run writing into `root` has listed `count` frames.
#[cfg(unix)]
fn wait_for_frames(root: &std::path::Path, count: usize) {
    let started = Instant::now();
    while read_pvd(&root.join("result.pvd")).map_or(0, |f| f.len()) < count {
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "no {count} frames after 2 min"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Ctrl-C (SIGINT) during a run stops it cleanly: exit status 130 (128 + SIGINT), a
/// message saying where it stopped, a run.log that says so, and a result.pvd that lists
/// only complete frames.
#[cfg(unix)]
#[test]
fn ctrl_c_stops_a_run_cleanly() {
    let dir = test_dir("musclefem-scene", "interrupt");
    let mut child = start_a_long_run(&dir, Stdio::piped(), Stdio::piped());
    // The first plain progress line (t = 0) says the solver is running.
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    stderr.read_line(&mut line).unwrap();
    assert!(line.starts_with("t = "), "{line}");
    // Let a few frames be written, then interrupt.
    wait_for_frames(&dir.join("result"), 3);
    let signal = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(signal.success());
    let deadline = Instant::now() + Duration::from_secs(60);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("the run did not stop within 60 s of SIGINT");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut stderr, &mut rest).unwrap();
    assert_eq!(status.code(), Some(130), "{status:?}\n{rest}");
    assert!(rest.contains("interrupted: stopped at t = "), "{rest}");
    let root = dir.join("result");
    let frames = read_pvd(&root.join("result.pvd")).unwrap();
    assert!(frames.len() >= 3);
    assert!(frames.last().unwrap().time < 1000.0);
    for frame in &frames {
        let vtu = std::fs::read_to_string(root.join(&frame.file)).unwrap();
        assert!(
            vtu.trim_end().ends_with("</VTKFile>"),
            "{} is cut",
            frame.file
        );
    }
    let log = std::fs::read_to_string(root.join("run.log")).unwrap();
    assert!(log.contains("end = interrupted at t = "), "{log}");
    assert!(root.join("history.csv").is_file());
}

/// Two runs into one directory used to both succeed and interleave their files: while
/// a run writes, a second `run --force` into the same `--out` is refused before it
/// deletes or writes anything, naming the first; once the first is gone it may proceed.
#[cfg(unix)]
#[test]
fn a_second_run_into_a_running_runs_directory_is_refused() {
    let dir = test_dir("musclefem-scene", "concurrent");
    let mut first = start_a_long_run(&dir, Stdio::null(), Stdio::null());
    wait_for_frames(&dir.join("result"), 2);
    let frames_before = read_pvd(&dir.join("result/result.pvd")).unwrap().len();
    let second = musclefem(&dir, &["run", "long.toml", "--out", "result", "--force"]);
    let frames_after = read_pvd(&dir.join("result/result.pvd")).unwrap().len();
    let _ = first.kill();
    let _ = first.wait();
    assert!(!second.status.success());
    let message = text(&second.stderr);
    assert!(
        message.contains("another musclefem run")
            && message.contains(&format!("process {}", first.id())),
        "{message}"
    );
    // The first run's frames were neither deleted nor replaced.
    assert!(
        frames_after >= frames_before,
        "{frames_before} -> {frames_after}"
    );
    // Killed (SIGKILL), the first leaves its lock behind; it is stale and taken over.
    let short = example("neo_hookean_cube_stretch.toml");
    let third = musclefem(&dir, &["run", &short, "--out", "result", "--force"]);
    assert!(third.status.success(), "{}", text(&third.stderr));
    assert!(text(&third.stderr).contains("taking the directory over"));
    assert!(!dir.join("result/.musclefem.lock").exists());
}

/// `output_interval` was ignored by implicit runs (a frame per increment) and they had no
/// frame of the initial state: frames now fall at t = 0, on the interval's multiples
/// (the first increment at or after each) and at the end, while the history keeps a row
/// per increment.
#[test]
fn implicit_frames_follow_the_output_interval() {
    let dir = test_dir("musclefem-scene", "interval");
    let scene = std::fs::read_to_string(example("neo_hookean_cube_stretch.toml"))
        .unwrap()
        .replace(
            "implicit = { increments = 10 }",
            "implicit = { increments = 40 }",
        )
        .replace("output_interval = 0.1", "output_interval = 0.25");
    assert!(scene.contains("increments = 40") && scene.contains("output_interval = 0.25"));
    std::fs::write(dir.join("interval.toml"), scene).unwrap();
    let out = musclefem(&dir, &["run", "interval.toml", "--out", "result"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let frames = read_pvd(&dir.join("result/result.pvd")).unwrap();
    let times: Vec<f64> = frames.iter().map(|f| f.time).collect();
    assert_eq!(times.len(), 5, "{times:?}");
    for (time, expected) in times.iter().zip([0.0, 0.25, 0.5, 0.75, 1.0]) {
        assert!((time - expected).abs() < 1e-9, "{times:?}");
    }
    let history = std::fs::read_to_string(dir.join("result/history.csv")).unwrap();
    assert_eq!(history.lines().count(), 1 + 40, "{history}");
}

/// A shared library whose constructor writes `marker` when the library is loaded, built
/// with the C compiler into `dir/libmarker.so`.
#[cfg(unix)]
fn library_with_a_constructor(dir: &std::path::Path, marker: &std::path::Path) {
    let source = dir.join("marker.c");
    std::fs::write(
        &source,
        format!(
            "#include <stdio.h>\n__attribute__((constructor)) static void mark(void) {{\n  \
             FILE *f = fopen(\"{}\", \"w\"); if (f) fclose(f);\n}}\n",
            marker.display()
        ),
    )
    .unwrap();
    let status = Command::new("cc")
        .args(["-shared", "-fPIC", "-o"])
        .arg(dir.join("libmarker.so"))
        .arg(&source)
        .status()
        .unwrap();
    assert!(status.success());
}

/// `check` on a scene with a plugin ran the library's code; `run` loaded any plugin the
/// scene named, and scenes could read any file: now `check` never loads a plugin (it
/// checks the rest and says so), `run` loads one only with `--allow-plugins`, and files
/// outside the scene's folder need `--allow-outside-paths`.
#[cfg(unix)]
#[test]
fn plugins_load_only_when_allowed_and_files_stay_in_the_scene_folder() {
    let dir = test_dir("musclefem-scene", "trust");
    let scene_dir = dir.join("scene");
    std::fs::create_dir_all(&scene_dir).unwrap();
    let marker = dir.join("constructor-ran");
    library_with_a_constructor(&scene_dir, &marker);
    let base = std::fs::read_to_string(example("neo_hookean_cube_stretch.toml")).unwrap();
    let with_plugin = base.replace(
        "model = \"neo-hookean\"",
        "model = \"neo-hookean\"\nplugin = \"libmarker.so\"",
    );
    assert_ne!(with_plugin, base);
    std::fs::write(scene_dir.join("plugin.toml"), &with_plugin).unwrap();

    let check = musclefem(&dir, &["check", "scene/plugin.toml"]);
    assert!(check.status.success(), "{}", text(&check.stderr));
    assert!(
        text(&check.stdout).contains("material rubber (libmarker.so): plugin not loaded"),
        "{}",
        text(&check.stdout)
    );
    assert!(!marker.exists(), "check ran the plugin's code");

    let run = musclefem(&dir, &["run", "scene/plugin.toml", "--out", "refused"]);
    assert!(!run.status.success());
    let message = text(&run.stderr);
    assert!(
        message.contains("plugin.toml:") && message.contains("--allow-plugins"),
        "{message}"
    );
    assert!(
        !marker.exists(),
        "run ran the plugin's code without --allow-plugins"
    );
    assert!(
        !dir.join("refused").exists(),
        "a refused run wrote its directory"
    );
    // So do the other commands that read scenes.
    let sweep = musclefem(
        &dir,
        &[
            "sweep",
            "--scene",
            "scene/plugin.toml",
            "--vary",
            "rubber.mu=1e4,2e4",
            "--out",
            "sweep",
        ],
    );
    assert!(!sweep.status.success());
    assert!(
        text(&sweep.stderr).contains("--allow-plugins"),
        "{}",
        text(&sweep.stderr)
    );
    assert!(!marker.exists(), "sweep ran the plugin's code");

    // Allowed, the library is loaded (its constructor runs); it is no musclefem plugin,
    // so the run then stops, naming it.
    let allowed = musclefem(
        &dir,
        &[
            "run",
            "scene/plugin.toml",
            "--out",
            "allowed",
            "--allow-plugins",
        ],
    );
    assert!(marker.exists(), "{}", text(&allowed.stderr));
    assert!(!allowed.status.success());

    // A mesh file outside the scene's folder.
    std::fs::write(dir.join("outside.inp"), "*NODE\n1, 0, 0, 0\n").unwrap();
    let outside = base.replace(
        "mesh = { generator = \"box\", size = [0.01, 0.01, 0.01], divisions = [4, 4, 4] }",
        "mesh = { file = \"../outside.inp\", block = \"cube\" }",
    );
    assert_ne!(outside, base);
    std::fs::write(scene_dir.join("outside.toml"), outside).unwrap();
    let refused = musclefem(&dir, &["check", "scene/outside.toml"]);
    assert!(!refused.status.success());
    let message = text(&refused.stderr);
    assert!(
        message.contains("outside the scene's folder") && message.contains("--allow-outside-paths"),
        "{message}"
    );
    // Allowed, the file is read (and found to hold no block 'cube').
    let read = musclefem(
        &dir,
        &["check", "scene/outside.toml", "--allow-outside-paths"],
    );
    let message = text(&read.stderr);
    assert!(!message.contains("outside the scene's folder"), "{message}");
}

/// `--threads 100000` started no thread pool in a minute: more threads than cores are cut
/// to the cores with a warning, and the run finishes with the usual answer; 0 is refused.
#[test]
fn more_threads_than_cores_are_cut_to_the_cores() {
    let dir = test_dir("musclefem-scene", "threads");
    let scene = example("neo_hookean_cube_stretch.toml");
    let out = musclefem(
        &dir,
        &["run", &scene, "--out", "many", "--threads", "100000"],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let log = std::fs::read_to_string(dir.join("many/run.log")).unwrap();
    assert!(log.contains("end = complete (10 steps)"), "{log}");
    assert!(
        text(&out.stderr).contains("--threads 100000 is more than the"),
        "{}",
        text(&out.stderr)
    );
    assert!(
        text(&out.stdout).contains("cube.x1.x 1.002568e0 N"),
        "{}",
        text(&out.stdout)
    );
    let none = musclefem(&dir, &["run", &scene, "--out", "none", "--threads", "0"]);
    assert!(!none.status.success());
    assert!(
        text(&none.stderr).contains("--threads 0"),
        "{}",
        text(&none.stderr)
    );
    assert!(!dir.join("none").exists());
}

/// A body pulled by a force with no displacement condition, quasi-static implicit: its
/// stiffness is singular, and the solver once "converged" to 2.5e12 m. `check` and `run`
/// refuse it naming the free motions, and nothing is written.
#[test]
fn a_body_no_condition_holds_is_refused_before_any_output() {
    let dir = test_dir("musclefem-scene", "free");
    let text_of = std::fs::read_to_string(example("neo_hookean_cube_stretch.toml")).unwrap();
    let start = text_of.find("[[displacements]]").unwrap();
    let end = text_of.find("[step]").unwrap();
    let scene = format!(
        "{}[[forces]]\npart = \"cube\"\nnodes = \"x1\"\ncomponent = \"x\"\nvalue = 0.01\n\
         amplitude = \"ramp\"\n\n{}",
        &text_of[..start],
        &text_of[end..]
    );
    std::fs::write(dir.join("free.toml"), scene).unwrap();
    for command in [
        &["check", "free.toml"][..],
        &["run", "free.toml", "--out", "result"],
    ] {
        let out = musclefem(&dir, command);
        assert!(!out.status.success(), "{command:?}");
        let error = text(&out.stderr);
        assert!(error.contains("can move as a rigid body"), "{error}");
        assert!(error.contains("translation along (1, 0, 0)"), "{error}");
        assert!(error.contains("rotation about (0, 0, 1)"), "{error}");
    }
    assert!(!dir.join("result").exists(), "nothing is written");
}

/// A run killed outright (SIGKILL: no handler runs) still leaves its history from the
/// first row on and a run.log that says it did not end (before, a run killed within its
/// first 50 rows left neither).
#[cfg(unix)]
#[test]
fn a_killed_run_leaves_its_first_rows_and_a_log_saying_so() {
    let dir = test_dir("musclefem-scene", "killed");
    let mut child = start_a_long_run(&dir, Stdio::null(), Stdio::null());
    let history = dir.join("result/history.csv");
    let started = Instant::now();
    while !history.exists() {
        assert!(started.elapsed() < Duration::from_secs(120), "no history");
        std::thread::sleep(Duration::from_millis(10));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let rows = std::fs::read_to_string(&history).unwrap();
    assert!(rows.lines().count() >= 2, "{rows}");
    assert!(rows.lines().count() < 50, "killed within its first 50 rows");
    let log = std::fs::read_to_string(dir.join("result/run.log")).unwrap();
    assert!(log.contains("end = running"), "{log}");
}
