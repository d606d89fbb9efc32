//! `musclefem sweep` end to end on the cheap homogeneous model (the cylinder with sliding
//! grips, 72 elements, 0.2 s increments: about 0.2 s a run): the table, a failed run that
//! does not stop the others, resuming, and the sensitivities.

mod support;

use std::path::Path;

use support::run::{CHEAP_ELONGATION, musclefem, test_dir, text};

/// The cheap model's flags, then `extra`.
fn sweep(dir: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["sweep", "--base", "passive", "--jobs", "2"];
    args.extend_from_slice(&CHEAP_ELONGATION);
    args.extend_from_slice(extra);
    musclefem(dir, &args)
}

const VARY: [&str; 6] = [
    "--vary",
    "sigma0=5e5,9e5",
    "--vary",
    "b=12,18",
    "--vary",
    "c=379,-1",
];

fn rows(path: &Path) -> Vec<Vec<String>> {
    let table = std::fs::read_to_string(path).unwrap();
    table
        .lines()
        .skip(1)
        .map(|line| line.splitn(10, ',').map(str::to_string).collect())
        .collect()
}

#[test]
fn a_grid_sweep_records_every_run_resumes_and_ranks_the_parameters() {
    let dir = test_dir("sweep", "grid");
    let out = sweep(&dir, &[&VARY[..], &["--out", "study"]].concat());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table_path = dir.join("study/sweep.csv");
    let table = std::fs::read_to_string(&table_path).unwrap();
    assert_eq!(
        table.lines().next().unwrap(),
        "run,sigma0,b,c,status,wall_time_s,steps,stress_10pct_pa,stress_20pct_pa,error"
    );
    let first = rows(&table_path);
    assert_eq!(first.len(), 8);
    for (run, row) in first.iter().enumerate() {
        assert_eq!(row[0], run.to_string());
        if row[3] == "-1" {
            // c < 0 is outside the Hill matrix's valid range: recorded, not fatal.
            assert_eq!(row[4], "failed", "{row:?}");
            assert!(row[9].contains("'c'"), "{row:?}");
        } else {
            assert_eq!(row[4], "ok", "{row:?}");
            let stress_20: f64 = row[8].parse().unwrap();
            assert!(stress_20 > row[7].parse::<f64>().unwrap() && stress_20 > 0.0);
        }
    }
    // The stiffer runs give the larger stress at 20 %: sigma0 9e5 against 5e5 at b = 12.
    let stress_20 = |run: usize| first[run][8].parse::<f64>().unwrap();
    assert!(stress_20(4) > stress_20(0));

    // The sensitivities: sigma0 and b, both positive; c took one working value only.
    let sensitivities = std::fs::read_to_string(dir.join("study/sensitivity.csv")).unwrap();
    for output in ["stress_10pct_pa", "stress_20pct_pa"] {
        for name in ["sigma0", "b"] {
            let line = sensitivities
                .lines()
                .find(|l| l.starts_with(&format!("{name},{output},")))
                .unwrap_or_else(|| panic!("{name} {output} in {sensitivities}"));
            let s: f64 = line.rsplit(',').next().unwrap().parse().unwrap();
            assert!(s > 0.0 && s < 2.0, "{line}");
        }
        assert!(!sensitivities.contains(&format!("c,{output}")));
    }
    let png = std::fs::read(dir.join("study/sensitivity.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"));

    // Drop the row of run 5 as if the sweep had been stopped before it: the rerun runs
    // it alone and keeps the other rows as they were (their wall times included).
    let without_5: String = table
        .lines()
        .filter(|l| !l.starts_with("5,"))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&table_path, without_5).unwrap();
    let resumed = sweep(&dir, &[&VARY[..], &["--out", "study"]].concat());
    assert!(resumed.status.success(), "{}", text(&resumed.stderr));
    assert!(
        text(&resumed.stdout).contains("8 runs, 7 already in"),
        "{}",
        text(&resumed.stdout)
    );
    let second = rows(&table_path);
    assert_eq!(second.len(), 8);
    for run in (0..8).filter(|&r| r != 5) {
        assert_eq!(second[run], first[run]);
    }
    assert_eq!(second[5][..5], first[5][..5]);
    assert_eq!(
        second[5][7..9],
        first[5][7..9],
        "a rerun gives the same stresses"
    );

    // Another design in the same directory is refused, naming the file.
    let other = sweep(&dir, &["--vary", "sigma0=5e5,6e5", "--out", "study"]);
    assert!(!other.status.success());
    let error = text(&other.stderr);
    assert!(
        error.contains("sweep.csv") && error.contains("another sweep"),
        "{error}"
    );
}

#[test]
fn a_latin_hypercube_sweep_has_its_samples_and_reproduces_them() {
    let dir = test_dir("sweep", "latin");
    let args = [
        "--vary",
        "sigma0=5e5:9e5:2",
        "--vary",
        "A=3,5",
        "--samples",
        "5",
        "--seed",
        "3",
    ];
    let out = sweep(&dir, &[&args[..], &["--out", "one"]].concat());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let again = sweep(&dir, &[&args[..], &["--out", "two"]].concat());
    assert!(again.status.success(), "{}", text(&again.stderr));
    let one = rows(&dir.join("one/sweep.csv"));
    let two = rows(&dir.join("two/sweep.csv"));
    assert_eq!(one.len(), 5);
    for (a, b) in one.iter().zip(&two) {
        assert_eq!(a[..3], b[..3], "the same seed gives the same samples");
        let sigma0: f64 = a[1].parse().unwrap();
        let pe: f64 = a[2].parse().unwrap();
        assert!((5e5..=9e5).contains(&sigma0) && (3.0..=5.0).contains(&pe));
        assert_eq!(a[3], "ok");
    }
}

/// A user's design (Excel's "CSV UTF-8" with a byte-order mark, `;` separators and a
/// decimal comma, columns in another order than the runs'): exactly its rows run, in its
/// order, and sweep.csv holds their values.
#[test]
fn a_design_file_runs_exactly_its_parameter_sets() {
    let dir = test_dir("sweep", "design");
    std::fs::write(
        dir.join("design.csv"),
        "\u{feff}A;sigma0\r\n4;7e5\r\n3,5;5e5\r\n\r\n5;9e5\r\n",
    )
    .unwrap();
    let out = sweep(&dir, &["--design", "design.csv", "--out", "study"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = std::fs::read_to_string(dir.join("study/sweep.csv")).unwrap();
    assert!(table.starts_with("run,A,sigma0,status,"), "{table}");
    let rows = rows(&dir.join("study/sweep.csv"));
    let expected = [(4.0, 7e5), (3.5, 5e5), (5.0, 9e5)];
    assert_eq!(rows.len(), expected.len(), "{table}");
    for (run, (row, (pe, sigma0))) in rows.iter().zip(expected).enumerate() {
        assert_eq!(row[0], run.to_string());
        assert_eq!(row[1].parse::<f64>().unwrap(), pe, "{row:?}");
        assert_eq!(row[2].parse::<f64>().unwrap(), sigma0, "{row:?}");
        assert_eq!(row[3], "ok", "{row:?}");
    }
    // A bad value is named with its line; --design and --vary do not go together.
    std::fs::write(dir.join("bad.csv"), "A,sigma0\n4,7e5\n3,x\n").unwrap();
    let bad = sweep(&dir, &["--design", "bad.csv", "--out", "bad"]);
    assert!(!bad.status.success());
    assert!(
        text(&bad.stderr).contains("bad.csv:3"),
        "{}",
        text(&bad.stderr)
    );
    let both = sweep(&dir, &["--design", "design.csv", "--vary", "b=1,2"]);
    assert!(!both.status.success());
    assert!(
        text(&both.stderr).contains("--vary"),
        "{}",
        text(&both.stderr)
    );
}

#[test]
fn bad_sweeps_are_refused_with_the_flag_named() {
    let dir = test_dir("sweep", "bad");
    for (args, expected) in [
        (vec!["--vary", "sigma=1,2"], "no parameter 'sigma'"),
        (vec!["--vary", "n2=0,1"], "the mode sets the activation"),
        (vec!["--vary", "b=1:2"], "--vary 'b=1:2'"),
        (vec!["--vary", "b=1,2", "--samples", "0"], "--samples 0"),
    ] {
        let out = sweep(&dir, &args);
        assert!(!out.status.success());
        let error = text(&out.stderr);
        assert!(error.contains(expected), "{args:?}: {error}");
    }
    let scene = musclefem(&dir, &["sweep", "--base", "knee.toml", "--vary", "b=1,2"]);
    assert!(text(&scene.stderr).contains("--scene knee.toml"));
}

fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
        .display()
        .to_string()
}

/// Column `name` of a sweep.csv whose cells hold no commas.
fn column(path: &Path, name: &str) -> Vec<f64> {
    let table = std::fs::read_to_string(path).unwrap();
    let mut lines = table.lines();
    let k = lines
        .next()
        .unwrap()
        .split(',')
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
        .collect()
}

#[test]
fn a_scene_is_swept_by_its_material_parameter_and_its_history_columns() {
    // The example block held isometric and activated fully: its reaction is σ_iso × 25 mm²,
    // σ_iso ≈ 0.99 σ0 (the example's 692.8 kPa at σ0 = 700 kPa), so it scales with σ0.
    let dir = test_dir("sweep", "scene");
    let scene = example("hill_block_isometric.toml");
    let out = musclefem(
        &dir,
        &[
            "sweep",
            "--scene",
            &scene,
            "--vary",
            "sigma0=6e5,7e5",
            "--output",
            "reaction_block.x1.x_n",
            "--output",
            "reaction_block.x1.x_n@0.05",
            "--out",
            "study",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = dir.join("study/sweep.csv");
    let header = std::fs::read_to_string(&table).unwrap();
    assert!(header.starts_with(
        "run,sigma0,status,wall_time_s,steps,reaction_block.x1.x_n,\
         reaction_block.x1.x_n_at_0.05s,error\n"
    ));
    let end = column(&table, "reaction_block.x1.x_n");
    let area = 25e-6;
    for (force, sigma0) in end.iter().zip([6e5, 7e5]) {
        let ratio = force / area / (0.99 * sigma0);
        assert!((ratio - 1.0).abs() < 0.01, "σ = {} Pa", force / area);
    }
    // At 0.05 s the activation (rate 50/s) is still rising: below the end's.
    let early = column(&table, "reaction_block.x1.x_n_at_0.05s");
    assert!(
        early[0] > 0.5 * end[0] && early[0] < end[0],
        "{early:?} {end:?}"
    );
    let sensitivities = std::fs::read_to_string(dir.join("study/sensitivity.csv")).unwrap();
    let line = sensitivities
        .lines()
        .find(|l| l.starts_with("sigma0,reaction_block.x1.x_n,"))
        .unwrap();
    let s: f64 = line.rsplit(',').next().unwrap().parse().unwrap();
    assert!((s - 1.0).abs() < 0.01, "{line}");

    for (args, expected) in [
        (vec!["--vary", "sigm0=1,2"], "no parameter 'sigm0'"),
        (vec!["--vary", "bone.b=1,2"], "no material 'bone'"),
        (
            vec!["--vary", "b=10,15", "--output", "reaction_x_n"],
            "no history column 'reaction_x_n'",
        ),
        (
            vec!["--vary", "b=10,15", "--time-step", "0.1"],
            "do not apply to a scene",
        ),
    ] {
        let mut all = vec!["sweep", "--scene", scene.as_str()];
        all.extend(args.iter().copied());
        let out = musclefem(&dir, &all);
        assert!(!out.status.success());
        let error = text(&out.stderr);
        assert!(error.contains(expected), "{args:?}: {error}");
    }
}

#[test]
fn a_sweep_resumes_only_from_rows_of_the_same_base() {
    let dir = test_dir("sweep", "base");
    // One value: no sensitivities, and no chart to fail.
    let first = sweep(&dir, &["--vary", "b=15", "--out", "study"]);
    assert!(first.status.success(), "{}", text(&first.stderr));
    assert!(text(&first.stdout).contains("no parameter takes two values"));
    assert!(!dir.join("study/sensitivity.png").exists());
    let base = std::fs::read_to_string(dir.join("study/sweep_base.txt")).unwrap();
    assert!(base.contains("passive elongation") && base.contains("time step = 0.2 s"));
    // The same sweep resumes; another time step does not reuse its rows.
    let again = sweep(&dir, &["--vary", "b=15", "--out", "study"]);
    assert!(again.status.success(), "{}", text(&again.stderr));
    assert!(text(&again.stdout).contains("1 already in"));
    let mut args = vec!["sweep", "--base", "passive"];
    args.extend_from_slice(&CHEAP_ELONGATION[..6]);
    args.extend_from_slice(&["--time-step", "0.1", "--vary", "b=15", "--out", "study"]);
    let other = musclefem(&dir, &args);
    assert!(!other.status.success());
    let error = text(&other.stderr);
    assert!(
        error.contains("another base") && error.contains("time step = 0.1 s"),
        "{error}"
    );

    // A scene edited between two sweeps into one directory.
    let scene = dir.join("block.toml");
    let text_of = std::fs::read_to_string(example("hill_block_isometric.toml")).unwrap();
    std::fs::write(&scene, &text_of).unwrap();
    let scene_sweep = |dir: &Path| {
        musclefem(
            dir,
            &[
                "sweep",
                "--scene",
                "block.toml",
                "--vary",
                "sigma0=7e5",
                "--out",
                "scene",
            ],
        )
    };
    assert!(scene_sweep(&dir).status.success());
    std::fs::write(&scene, text_of.replace("duration = 0.15", "duration = 0.1")).unwrap();
    let edited = scene_sweep(&dir);
    assert!(!edited.status.success());
    assert!(text(&edited.stderr).contains("another base"));
}

/// A job array without MPI: `--shard 1/2` and `--shard 2/2` each run half of the runs
/// into their own directory, and `sweep merge` joins them into the table and the
/// sensitivities of the whole sweep (the same as one local sweep's, but for wall times).
/// Shards of different sweeps, or a merge missing a shard, are told apart.
#[test]
fn shards_merged_give_the_whole_sweep() {
    let dir = test_dir("sweep", "shards");
    let vary = ["--vary", "sigma0=5e5,7e5,9e5", "--vary", "b=12,18"];
    for k in ["1/2", "2/2"] {
        let out = format!("shard{}", &k[..1]);
        let shard = sweep(&dir, &[&vary[..], &["--shard", k, "--out", &out]].concat());
        assert!(shard.status.success(), "{}", text(&shard.stderr));
        let stdout = text(&shard.stdout);
        assert!(
            stdout.contains(&format!("3 to run in shard {k}")),
            "{stdout}"
        );
        assert!(stdout.contains("no sensitivities until the shards are merged"));
    }
    let whole = sweep(&dir, &[&vary[..], &["--out", "whole"]].concat());
    assert!(whole.status.success(), "{}", text(&whole.stderr));
    let merged = musclefem(
        &dir,
        &["sweep", "merge", "shard1", "shard2", "--out", "merged"],
    );
    assert!(merged.status.success(), "{}", text(&merged.stderr));
    assert!(text(&merged.stdout).contains("merged 6 of the 6 runs from 2 shards"));
    let without_wall_time = |rows: Vec<Vec<String>>| -> Vec<Vec<String>> {
        rows.into_iter()
            .map(|mut row| {
                row.remove(4);
                row
            })
            .collect()
    };
    assert_eq!(
        without_wall_time(rows(&dir.join("merged/sweep.csv"))),
        without_wall_time(rows(&dir.join("whole/sweep.csv")))
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("merged/sensitivity.csv")).unwrap(),
        std::fs::read_to_string(dir.join("whole/sensitivity.csv")).unwrap()
    );

    // One shard alone: the missing runs are named.
    let half = musclefem(&dir, &["sweep", "merge", "shard1", "--out", "half"]);
    assert!(half.status.success(), "{}", text(&half.stderr));
    assert!(
        text(&half.stdout)
            .contains("missing runs (rerun their shards, which resume, and merge again): 1, 3, 5"),
        "{}",
        text(&half.stdout)
    );
    // A shard of another sweep (another time step) is refused.
    let mut args = vec!["sweep", "--base", "passive"];
    args.extend_from_slice(&CHEAP_ELONGATION[..6]);
    args.extend_from_slice(&["--time-step", "0.1"]);
    args.extend_from_slice(&vary);
    args.extend_from_slice(&["--shard", "2/2", "--out", "other"]);
    let other = musclefem(&dir, &args);
    assert!(other.status.success(), "{}", text(&other.stderr));
    let mixed = musclefem(
        &dir,
        &["sweep", "merge", "shard1", "other", "--out", "mixed"],
    );
    assert!(!mixed.status.success());
    assert!(
        text(&mixed.stderr).contains("another base"),
        "{}",
        text(&mixed.stderr)
    );
    // K/N is checked.
    let bad = sweep(
        &dir,
        &[&vary[..], &["--shard", "3/2", "--out", "bad"]].concat(),
    );
    assert!(!bad.status.success());
    assert!(
        text(&bad.stderr).contains("1 <= K <= N"),
        "{}",
        text(&bad.stderr)
    );
}
