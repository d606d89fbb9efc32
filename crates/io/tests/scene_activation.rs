//! A part's recorded activation (`[parts.activation]`): from an amplitude, a spreadsheet's
//! CSV or an OpenSim storage file, as activation or as excitation through first-order
//! dynamics; it reaches the Hill material as a typed history, `check` prints its range,
//! and a held block of muscle pulls σ₀ f_λ a on its grips.

use std::path::{Path, PathBuf};

use musclefem_core::solver::{NoObserver, Outcome};
use musclefem_io::scene::load_scene;
use musclefem_materials::{ActivationDynamics, ActivationHistory, MaterialLibrary};

/// A 10 mm cube of `model` (fibers along x) held between its faces x0 and x1 on
/// symmetry planes, with `activation` as its part's activation table (empty: none).
fn scene(model: &str, parameters: &str, activation: &str) -> String {
    format!(
        r#"schema_version = 1

[[amplitudes]]
name = "drive"
points = [[0.0, 0.0], [0.1, 0.5], [0.4, 0.2]]

[[materials]]
name = "muscle"
model = "{model}"
{parameters}

[[parts]]
name = "cube"
material = "muscle"
element = "hex8-fbar"
density = 1060.0
mesh = {{ generator = "box", size = [0.01, 0.01, 0.01], divisions = [1, 1, 1] }}
fibers = {{ direction = [1.0, 0.0, 0.0] }}
{activation}

[[displacements]]
part = "cube"
nodes = "x0"
components = ["x"]

[[displacements]]
part = "cube"
nodes = "x1"
components = ["x"]

[[displacements]]
part = "cube"
nodes = "y0"
components = ["y"]

[[displacements]]
part = "cube"
nodes = "z0"
components = ["z"]

[step]
solver = "implicit"
duration = 1.0
implicit = {{ increments = 25 }}

[output]
frames = false
"#
    )
}

/// A fresh folder for one test's files.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "musclefem_activation_{name}_{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn load(dir: &Path, text: &str) -> Result<musclefem_io::scene::Model, String> {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    load_scene(&path, &mut MaterialLibrary::with_builtins()).map_err(|e| e.to_string())
}

#[test]
fn an_amplitude_drives_the_hill_material_and_check_prints_its_range() {
    let dir = folder("amplitude");
    let model = load(
        &dir,
        &scene("hill", "", r#"activation = { amplitude = "drive" }"#),
    )
    .unwrap();
    let material = &model.parts[0].material;
    for (t, expected) in [
        (0.0, 0.0),
        (0.05, 0.25),
        (0.1, 0.5),
        (0.25, 0.35),
        (0.9, 0.2),
    ] {
        let a = material.activation(t).unwrap();
        assert!(
            (a - expected).abs() < 1e-12,
            "a({t}) = {a}, amplitude {expected}"
        );
    }
    let description = model.describe();
    assert!(
        description.contains(
            "part 'cube': activation 0.000 … 0.500 over the step, recorded activation \
             amplitude 'drive'"
        ),
        "{description}"
    );
    // Without a recorded activation the line names the material's own (passive here).
    let own = load(&dir, &scene("hill", "", "")).unwrap().describe();
    assert!(
        own.contains("activation 0.000 … 0.000 over the step, the material's own (hill)"),
        "{own}"
    );
}

#[test]
fn a_spreadsheet_csv_and_an_opensim_excitation_are_read() {
    let dir = folder("files");
    // Excel's "CSV UTF-8" in a decimal-comma locale: byte-order mark, `;`, `0,25`.
    std::fs::write(
        dir.join("emg.csv"),
        "\u{feff}time;VL;VM\r\n0;0;0\r\n0,2;0,25;0,5\r\n1;0,25;0\r\n",
    )
    .unwrap();
    let csv = load(
        &dir,
        &scene(
            "hill",
            "",
            r#"activation = { file = "emg.csv", column = "VL" }"#,
        ),
    )
    .unwrap();
    let a =
        |model: &musclefem_io::scene::Model, t: f64| model.parts[0].material.activation(t).unwrap();
    assert!((a(&csv, 0.1) - 0.125).abs() < 1e-12);
    assert!((a(&csv, 0.7) - 0.25).abs() < 1e-12);

    // An OpenSim controls file: excitations from t = 0.5 s of the trial on.
    std::fs::write(
        dir.join("controls.sto"),
        "walk_controls\nversion=1\nnRows=3\nnColumns=3\ninDegrees=no\nendheader\n\
         time\tvasmed_r\tvaslat_r\n0.5\t0.0\t0.0\n0.6\t1.0\t0.6\n1.5\t1.0\t0.6\n",
    )
    .unwrap();
    let sto = load(
        &dir,
        &scene(
            "hill",
            "",
            r#"activation = { file = "controls.sto", column = "vaslat_r", excitation = true, time_offset = 0.5, activation_time_constant = 0.02 }"#,
        ),
    )
    .unwrap();
    let reference = ActivationHistory::from_excitation(
        "reference",
        vec![(0.0, 0.0), (0.1, 0.6), (1.0, 0.6)],
        ActivationDynamics {
            activation_time_constant: 0.02,
            deactivation_time_constant: 0.04,
        },
    )
    .unwrap();
    // The same dynamics on the same samples (the offset moves the times by rounding).
    for t in [0.0, 0.03, 0.1, 0.15, 0.5] {
        assert!((a(&sto, t) - reference.level(t)).abs() < 1e-12, "t = {t}");
    }
    // The activation lags the excitation, then settles on it.
    assert!(a(&sto, 0.1) < 0.6 - 0.05);
    assert!((a(&sto, 0.9) - 0.6).abs() < 1e-6);
    assert!(
        sto.describe()
            .contains("recorded excitation column 'vaslat_r' of controls.sto")
    );
}

#[test]
fn what_cannot_drive_an_activation_is_refused_with_its_line() {
    let dir = folder("errors");
    let error = |text: String| load(&dir, &text).unwrap_err();
    let passive = error(scene(
        "neo-hookean",
        "",
        r#"activation = { amplitude = "drive" }"#,
    ));
    assert!(passive.contains("has no activation to drive"), "{passive}");
    assert!(passive.contains("scene.toml:"), "{passive}");
    let both = error(scene(
        "hill",
        "parameters = { n2 = 0.5 }",
        r#"activation = { amplitude = "drive" }"#,
    ));
    assert!(
        both.contains("sets its activation parameter 'n2'"),
        "{both}"
    );
    let constant = error(scene(
        "hill",
        "",
        r#"activation = { amplitude = "drive", activation_time_constant = 0.01 }"#,
    ));
    assert!(constant.contains("add `excitation = true`"), "{constant}");
    std::fs::write(dir.join("emg.csv"), "time,VL\n0,0\n1,50\n").unwrap();
    let column = error(scene(
        "hill",
        "",
        r#"activation = { file = "emg.csv", column = "VI" }"#,
    ));
    assert!(column.contains("no column 'VI'"), "{column}");
    let percent = error(scene(
        "hill",
        "",
        r#"activation = { file = "emg.csv", column = "VL" }"#,
    ));
    assert!(percent.contains("outside [0, 1]"), "{percent}");
}

/// Held at its length (fibers along x, the lateral faces free), the block's fibers pull
/// σ₀ f_λ(1/λ_opt) a on each grip once the contractile element has come to rest
/// (f_v = 1): with Table 1, σ₀ = 700 kPa, f_λ(1/1.05) = 1 − 4 (1/1.05 − 1)², and a = 0.3
/// from the record, 0.3 × 693.7 kPa on 1 cm².
#[test]
fn a_held_block_pulls_with_the_recorded_activation() {
    let dir = folder("run");
    std::fs::write(dir.join("act.csv"), "time,a\n0,0\n0.02,0.3\n2,0.3\n").unwrap();
    let model = load(
        &dir,
        &scene(
            "hill",
            "",
            r#"activation = { file = "act.csv", column = "a" }"#,
        ),
    )
    .unwrap();
    let Outcome::Implicit(result) = model.run(&mut NoObserver).unwrap() else {
        panic!("the scene is implicit");
    };
    let last = result.history.last().unwrap();
    let x1 = model
        .displacement_names
        .iter()
        .position(|n| n == "cube.x1.x")
        .unwrap();
    let force_length = 1.0 - 4.0 * (1.0 / 1.05 - 1.0f64).powi(2);
    let expected = 7e5 * force_length * 0.3 * 1e-4;
    let pull = last.reactions[x1].abs();
    assert!(
        (pull - expected).abs() < 5e-3 * expected,
        "pull {pull} N against {expected} N"
    );
}
