//! `musclefem knee` end to end on the coarse procedural knee (`--anatomy procedural`):
//! passive and active side by side, implicit with inertia, it goes 0° → 90° → 0° converged
//! at every increment with no inverted element, the peak-stress table has every muscle, angle,
//! phase and activation, the passive stress grows with flexion, the active exceeds the
//! passive at 45°, 60° and 90° for every muscle, the passive muscles come back unloaded,
//! the patellar tendon stretches under the pull, and the outputs are all there.

mod support;

use std::collections::HashMap;

use support::csv::read_csv;
use support::run::{musclefem, test_dir, text};

use musclefem_studies::knee::anatomy::TendonSpring;
use musclefem_studies::knee::simulation::patella::TENDON_CSV_HEADER;

/// The vm95 of (muscle, angle, phase, activation).
type Vm95Table = HashMap<(String, String, String, String), f64>;

/// The procedural knee's whole squat. Long (about 15 minutes on 2 cores for both squats
/// side by side, coarse, release):
/// `cargo test --release -p musclefem --test knee_squat -- --ignored`.
#[test]
#[ignore = "long: the procedural knee's whole coarse squat, passive and active (~14 min on \
            2 cores); it also checks issue #29's criteria, whose active stress band and pull \
            this anatomy does not meet (README, docs/knee-model.md)"]
fn the_procedural_squat_converges_without_inversion_and_activation_raises_the_stress() {
    let dir = test_dir("knee_squat", "procedural");
    let output = musclefem(
        &dir,
        &[
            "knee",
            "--anatomy",
            "procedural",
            "--resolution",
            "coarse",
            "--out",
            "out",
        ],
    );
    let stdout = text(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        text(&output.stderr)
    );
    // Without options but the anatomy and mesh: both squats, implicit with inertia, and it
    // says so.
    assert!(
        stdout.contains("passive and active side by side, implicit solver with inertia (Newmark)"),
        "{stdout}"
    );
    let out = dir.join("out");

    // The table: 4 muscles × 4 angles × 2 phases × 2 activations.
    let (header, rows) = read_csv(&out.join("peak_stress.csv"));
    assert_eq!(
        header.join(","),
        "muscle,knee_angle_deg,phase,activation,vm95_pa"
    );
    assert_eq!(rows.len(), 64);
    let mut vm95 = Vm95Table::new();
    for row in &rows {
        let value: f64 = row[4].parse().unwrap();
        assert!(value.is_finite() && value > 0.0, "{row:?}");
        vm95.insert(
            (
                row[0].clone(),
                row[1].clone(),
                row[2].clone(),
                row[3].clone(),
            ),
            value,
        );
    }
    let at = |muscle: &str, angle: &str, activation: &str| {
        vm95[&(
            muscle.to_string(),
            angle.to_string(),
            "flexion".to_string(),
            activation.to_string(),
        )]
    };
    for muscle in ["VI", "VL", "VM", "RF"] {
        // Stretch grows with flexion: the passive peak stress rises from 30° to 90°.
        let passive = |angle| at(muscle, angle, "passive");
        assert!(passive("30") < passive("60") && passive("60") < passive("90"));
        // The activated muscles (from 35° on) carry more than the passive ones.
        for angle in ["45", "60", "90"] {
            assert!(
                at(muscle, angle, "active") > passive(angle),
                "{muscle} at {angle}°: active {} <= passive {}",
                at(muscle, angle, "active"),
                passive(angle)
            );
        }
    }

    for activation in ["passive", "active"] {
        let run = out.join(activation);
        // Every increment converged (the implicit history has one row per increment up to
        // the end) and no element inverted on the way.
        let (header, samples) = read_csv(&run.join("vm95.csv"));
        assert_eq!(header.last().unwrap(), "min_jacobian_ratio");
        let last_time: f64 = samples.last().unwrap()[0].parse().unwrap();
        assert!(
            (last_time - 2.0).abs() < 1e-9,
            "{activation}: ended at {last_time}"
        );
        let min_jacobian = samples
            .iter()
            .map(|r| r.last().unwrap().parse::<f64>().unwrap())
            .fold(f64::INFINITY, f64::min);
        assert!(
            min_jacobian > 0.0,
            "{activation}: an element inverted ({min_jacobian})"
        );
        let (history_header, history) = read_csv(&run.join("history.csv"));
        assert_eq!(history_header[2], "newton_iterations");
        assert_eq!(history.len(), samples.len());
        // Every increment's Newton residuals, one row per converged increment.
        let (newton_header, increments) = read_csv(&run.join("newton.csv"));
        assert_eq!(newton_header.last().unwrap(), "relative_residuals");
        assert_eq!(increments.len(), history.len());
        // Every failed attempt that was cut, as many as run.log counts, each with a reason.
        let (cuts_header, cut_attempts) = read_csv(&run.join("cuts.csv"));
        assert_eq!(cuts_header.last().unwrap(), "reason");
        let log_cuts: usize = std::fs::read_to_string(run.join("run.log"))
            .unwrap()
            .lines()
            .find_map(|l| l.strip_prefix("cuts = "))
            .unwrap()
            .parse()
            .unwrap();
        assert_eq!(cut_attempts.len(), log_cuts);
        for row in &cut_attempts {
            // The reason is quoted (it may hold commas) and not empty.
            assert!(row.len() >= 6 && row[5].len() > 2 && row[5].starts_with('"'));
            let increment: f64 = row[1].parse().unwrap();
            assert!(increment > 0.0, "{activation}: {row:?}");
        }
        assert!(run.join("result.pvd").is_file() && run.join("run.log").is_file());
        // The patella has no contact surface: no muscle node (the insertions' excepted)
        // enters it.
        let log = std::fs::read_to_string(run.join("run.log")).unwrap();
        let approach: f64 = log
            .lines()
            .find_map(|l| l.strip_prefix("patella_closest_approach_mm = "))
            .unwrap_or_else(|| panic!("{activation}: no patella approach in\n{log}"))
            .parse()
            .unwrap();
        assert!(
            approach > 0.0,
            "{activation}: a node {approach} mm from the patella"
        );
        // The patellar tendon, one row per increment: its force follows its law, and where
        // the pull is steady (at 90°) the patella is posed with the pull just measured.
        let (tendon_header, tendon) = read_csv(&run.join("tendon.csv"));
        assert_eq!(tendon_header.join(","), TENDON_CSV_HEADER);
        assert_eq!(tendon.len(), history.len());
        let spring = TendonSpring::procedural_knee();
        let column = |row: &Vec<String>, name: &str| -> f64 {
            let i = tendon_header.iter().position(|h| h == name).unwrap();
            row[i].parse().unwrap()
        };
        for row in &tendon {
            let strain = column(row, "tendon_strain");
            let force = spring.force(spring.slack_length * (1.0 + strain));
            assert!((column(row, "tendon_force_n") - force).abs() <= 1e-6 * force.max(1.0));
        }
        let peak = tendon
            .iter()
            .max_by(|a, b| column(a, "knee_angle_deg").total_cmp(&column(b, "knee_angle_deg")))
            .unwrap();
        let (measured, applied) = (
            column(peak, "measured_tension_n"),
            column(peak, "applied_tension_n"),
        );
        assert!(
            (applied - measured).abs() < 0.1 * measured,
            "{activation} at 90°: posed with {applied} N, measured {measured} N"
        );
        assert!(column(peak, "tendon_strain") > 0.02, "{peak:?}");
        if activation == "passive" {
            // Passive muscles and undamaged bonds are elastic: back at 0° they are
            // unloaded again (vm95 below 1 % of its peak).
            for m in 2..6 {
                let values: Vec<f64> = samples.iter().map(|r| r[m].parse().unwrap()).collect();
                let peak = values.iter().fold(0.0f64, |a, &b| a.max(b));
                assert!(
                    *values.last().unwrap() < 0.01 * peak,
                    "{}: {} of a peak {peak}",
                    header[m],
                    values.last().unwrap()
                );
            }
        }
    }
    // The plausibility criteria (#29), on the coarse mesh.
    for muscle in ["VI", "VL", "VM", "RF"] {
        let passive = at(muscle, "90", "passive");
        let active = at(muscle, "90", "active");
        // Passive muscle at 90°: well below the 0.3–0.7 MPa it carries at most actively.
        assert!(
            passive <= 0.25e6,
            "{muscle} passive vm95 at 90°: {passive} Pa"
        );
        // Half-activated: the order of half the maximum isometric stress.
        assert!(
            (0.2e6..=1.0e6).contains(&active),
            "{muscle} active vm95 at 90°: {active} Pa"
        );
        for angle in ["45", "60", "90"] {
            let key = |activation: &str| {
                vm95[&(
                    muscle.to_string(),
                    angle.to_string(),
                    "extension".to_string(),
                    activation.to_string(),
                )]
            };
            assert!(
                key("active") > key("passive"),
                "{muscle} at {angle}° in extension: active {} <= passive {}",
                key("active"),
                key("passive")
            );
        }
    }
    let plausibility = |activation: &str| {
        let (header, rows) = read_csv(&out.join(activation).join("plausibility.csv"));
        let row = rows
            .iter()
            .find(|r| r[0] == "90" && r[1] == "flexion")
            .unwrap_or_else(|| panic!("{activation}: no row at 90° in {rows:?}"))
            .clone();
        move |name: &str| -> f64 {
            let i = header.iter().position(|h| h == name).unwrap();
            row[i].parse().unwrap()
        }
    };
    let passive = plausibility("passive");
    // An unloaded passive squat: a few hundred newtons, not a loaded squat's kilonewtons.
    assert!(
        passive("total_pull_n") <= 600.0,
        "{}",
        passive("total_pull_n")
    );
    assert!(passive("fiber_stretch_p95") <= 1.30);
    for muscle in ["VI", "VL", "VM"] {
        // The femur lets the vasti slide: its interface resists a small share of the pull.
        // The sliding bonds push only along the femur's normal, so their resultant is the
        // pressure of the muscles over the vastus (the intermedius carries the rectus and
        // the other vasti as they wrap the femur) and its component along the pull is
        // what holds the muscle back (issue #29's note: the resultant itself was 55 % of
        // VI's pull on the coarse mesh, 19 % along it).
        let pull = passive(&format!("{muscle}_pull_n"));
        let share = passive(&format!("{muscle}_femur_interface_along_pull_n")) / pull;
        let all = passive(&format!("{muscle}_femur_interface_n")) / pull;
        eprintln!("{muscle}: femur interface {all:.2} of the pull, {share:.2} along it");
        assert!(
            share <= 0.2,
            "{muscle}: femur interface {share} of the pull along it"
        );
    }
    let active = plausibility("active");
    assert!(
        active("total_pull_n") <= 4400.0,
        "{}",
        active("total_pull_n")
    );
    assert!(
        active("patellar_tendon_force_n") <= 3000.0,
        "{}",
        active("patellar_tendon_force_n")
    );

    let png = std::fs::read(out.join("peak_stress.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    // Where the peaks are is reported per muscle at 90°, for both runs.
    for muscle in ["VI", "VL", "VM", "RF"] {
        assert_eq!(
            stdout.matches(&format!("{muscle} at 90°: vm95")).count(),
            2,
            "{stdout}"
        );
    }
    assert!(stdout.contains("elements above it at:"), "{stdout}");
}

#[test]
fn bad_knee_arguments_are_refused_before_any_output() {
    let dir = test_dir("knee_squat", "errors");
    let output = musclefem(&dir, &["knee", "--duration=-1", "--out", "out"]);
    assert!(!output.status.success());
    assert!(text(&output.stderr).contains("--duration -1 s must be positive"));
    assert!(!dir.join("out").exists());
    std::fs::create_dir_all(dir.join("empty")).unwrap();
    let output = musclefem(&dir, &["knee", "--anatomy", "empty", "--out", "out2"]);
    assert!(!output.status.success());
    assert!(
        text(&output.stderr).contains("neither muscles.msh nor muscles.inp"),
        "{}",
        text(&output.stderr)
    );
    // The Visible Human knee (the default) has no fine meshes: refused, nothing written.
    for anatomy in [&["--anatomy", "visible-human"][..], &[]] {
        let output = musclefem(
            &dir,
            &[
                &["knee"],
                anatomy,
                &["--resolution", "fine", "--out", "out5"],
            ]
            .concat(),
        );
        assert!(!output.status.success());
        assert!(
            text(&output.stderr).contains("has coarse and medium meshes"),
            "{}",
            text(&output.stderr)
        );
        assert!(!dir.join("out5").exists());
    }
    let output = musclefem(&dir, &["knee", "--passive", "--active"]);
    assert!(!output.status.success());
    assert!(text(&output.stderr).contains("cannot be used with"));
    // The default (Visible Human) knee is tet10: no --element; the procedural one is hex8.
    let output = musclefem(
        &dir,
        &["knee", "--element", "hex8-one-point", "--out", "out3"],
    );
    assert!(!output.status.success());
    assert!(
        text(&output.stderr).contains(
            "--element hex8-one-point: the Visible Human knee's muscles are meshed with tet10-fbar"
        ),
        "{}",
        text(&output.stderr)
    );
    let output = musclefem(
        &dir,
        &[
            "knee",
            "--anatomy",
            "procedural",
            "--element",
            "tet4",
            "--out",
            "out3",
        ],
    );
    assert!(!output.status.success());
    assert!(
        text(&output.stderr).contains("--element tet4: the knee's muscles are meshed with hex8"),
        "{}",
        text(&output.stderr)
    );
    assert!(!dir.join("out3").exists());
    let output = musclefem(&dir, &["knee", "--tolerance", "0", "--out", "out4"]);
    assert!(!output.status.success());
    assert!(
        text(&output.stderr).contains("--tolerance 0 must be a positive percentage"),
        "{}",
        text(&output.stderr)
    );
    assert!(!dir.join("out4").exists());
    let output = musclefem(
        &dir,
        &["knee", "--tolerance", "5", "--resolution", "coarse"],
    );
    assert!(!output.status.success());
    assert!(text(&output.stderr).contains("cannot be used with"));
}

/// `knee --tolerance` reads the knee rows of a work–precision table: the cheapest run
/// within the tolerance, the bench's reference (medium) when none is. The choice is
/// printed before the run, which the earlier results in `out` then refuse.
#[test]
fn knee_tolerance_picks_the_cheapest_knee_run_of_the_bench_table() {
    let dir = test_dir("knee_squat", "tolerance_table");
    std::fs::create_dir_all(dir.join("out")).unwrap();
    std::fs::write(dir.join("out/peak_stress.csv"), "earlier results\n").unwrap();
    std::fs::write(
        dir.join("table.csv"),
        "problem,solver,element,mesh_size_mm,step_setting,wall_s,error,error_metric
cube,implicit,hex8-fbar,2.5,increment=0.1s,0.1,1e-3,m
knee,implicit,hex8-fbar,12.753,increment=0.04s,30,1.5e-1,m
knee,implicit,hex8-one-point,12.753,increment=0.02s,20,3e-1,m
knee,explicit,hex8-fbar,12.753,mass_scaling=2e-5s;safety=0.9,600,1e-1,m
",
    )
    .unwrap();
    let chosen = |percent: &str| {
        let output = musclefem(
            &dir,
            &[
                "knee",
                "--passive",
                "--tolerance",
                percent,
                "--bench-table",
                "table.csv",
                "--out",
                "out",
            ],
        );
        assert!(!output.status.success());
        assert!(
            text(&output.stderr).contains("exists: use --force"),
            "{}",
            text(&output.stderr)
        );
        text(&output.stdout)
    };
    let stdout = chosen("20");
    assert!(
        stdout.contains("implicit hex8-fbar, 12.753 mm, increment=0.04s (15.0 % off")
            && stdout.contains("of the 3 knee runs in table.csv"),
        "{stdout}"
    );
    let stdout = chosen("12");
    assert!(
        stdout.contains("explicit hex8-fbar, 12.753 mm, mass_scaling=2e-5s;safety=0.9"),
        "{stdout}"
    );
    let stdout = chosen("5");
    assert!(
        stdout.contains("implicit hex8-fbar, 6.97 mm, increment=0.02s, the bench's reference")
            && stdout.contains("the best is 10.0 % off"),
        "{stdout}"
    );
}
