//! The knee's follower kinds reach the `musclefem` binary (their crate registers them
//! with `inventory`): `check` lists a misspelt kind's known ones, and `run` stretches a
//! block between a held face and one tied to the femur of the squat's closed chain.

mod support;

use support::run;

use run::{musclefem, test_dir, text};

use musclefem_io::csv::read_columns;

/// A block whose x0 face rides on the femur of a 0.5° squat of 0.2 s, its x1 face held.
const SCENE: &str = r#"schema_version = 1

[[materials]]
name = "muscle"
model = "neo-hookean"

[[parts]]
name = "block"
material = "muscle"
element = "hex8-full"
density = 1060.0
mesh = { generator = "box", size = [0.01, 0.01, 0.01], divisions = [1, 1, 1], origin = [0.02, 0.2, 0.0] }

[[rigid_ties]]
name = "femur_origin"
part = "block"
nodes = "x0"
motion = { follower = "knee-closed-chain", bone = "femur", duration = 0.2, peak_flexion = 0.008726646259971648 }

[[rigid_ties]]
name = "held"
part = "block"
nodes = "x1"

[step]
solver = "implicit"
duration = 0.2
output_interval = 0.1

[step.implicit]
increments = 4

[output]
frames = false
"#;

#[test]
fn the_binary_knows_the_knees_follower_kinds() {
    let dir = test_dir("musclefem-scene-followers", "kinds");
    std::fs::write(
        dir.join("bad.toml"),
        SCENE.replace("knee-closed-chain", "knee-closed-chian"),
    )
    .unwrap();
    let out = musclefem(&dir, &["check", "bad.toml"]);
    assert!(!out.status.success());
    let line = SCENE.lines().position(|l| l.starts_with("motion")).unwrap() + 1;
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains(&format!("bad.toml:{line}:"))
            && stderr.contains("did you mean `knee-closed-chain`?")
            && stderr.contains("known: knee-closed-chain, knee-patella"),
        "{stderr}"
    );

    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    let out = musclefem(&dir, &["run", "scene.toml", "--out", "result"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (names, columns) = read_columns(&dir.join("result/history.csv")).unwrap();
    let column = |name: &str| &columns[names.iter().position(|n| n == name).unwrap()];
    assert_eq!(column("time_s"), &vec![0.05, 0.1, 0.15000000000000002, 0.2]);
    // The femur moves the x0 face and the block pulls back; the held face takes the
    // opposite force (quasi-static, no other load); at the end the knee is straight again
    // and the block at rest.
    let peak = column("reaction_femur_origin_x_n")[1].hypot(column("reaction_femur_origin_y_n")[1]);
    assert!(peak > 1.0, "{peak} N");
    for axis in ["x", "y", "z"] {
        let (moved, held) = (
            column(&format!("reaction_femur_origin_{axis}_n")),
            column(&format!("reaction_held_{axis}_n")),
        );
        for (a, b) in moved.iter().zip(held) {
            assert!((a + b).abs() < 1e-6 * peak, "{axis}: {a} + {b}");
        }
        assert!(moved[3].abs() < 1e-6 * peak, "{axis}: {}", moved[3]);
    }
}
