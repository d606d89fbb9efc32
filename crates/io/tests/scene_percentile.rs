//! `[output] von_mises_percentile`: each part's percentile of its elements' von Mises
//! stress as history columns, against the closed form of a homogeneous stretch.

use std::ops::ControlFlow;

use musclefem_core::solver::{Observer, Record, Snapshot};
use musclefem_io::output::HistoryColumns;
use musclefem_io::scene::load_scene;
use musclefem_materials::MaterialLibrary;

/// Two 10 mm cubes of nearly incompressible neo-Hookean rubber (μ = 10 kPa, K = 2/D =
/// 10 MPa): `pulled` stretched along x to λ = 1.2 on symmetry planes, `idle` left alone.
const SCENE: &str = r#"schema_version = 1

[[materials]]
name = "rubber"
model = "neo-hookean"
parameters = { mu = 1e4, D = 2e-7 }

[[parts]]
name = "pulled"
material = "rubber"
element = "hex8-fbar"
density = 1000.0
mesh = { generator = "box", size = [0.01, 0.01, 0.01], divisions = [2, 2, 2] }

[[parts]]
name = "idle"
material = "rubber"
element = "hex8-fbar"
density = 1000.0
mesh = { generator = "box", size = [0.01, 0.01, 0.01], divisions = [2, 2, 2], origin = [0.0, 0.05, 0.0] }

[[amplitudes]]
name = "ramp"
points = [[0.0, 0.0], [1.0, 1.0]]

[[displacements]]
part = "pulled"
nodes = "x0"
components = ["x"]

[[displacements]]
part = "pulled"
nodes = "y0"
components = ["y"]

[[displacements]]
part = "pulled"
nodes = "z0"
components = ["z"]

[[displacements]]
part = "pulled"
nodes = "x1"
components = ["x"]
value = 0.002
amplitude = "ramp"

[[displacements]]
part = "idle"
nodes = "x0"
components = ["x", "y", "z"]

[step]
solver = "implicit"
duration = 1.0
implicit = { increments = 4 }

[output]
frames = false
von_mises_percentile = 95
"#;

struct Rows<'a> {
    columns: &'a HistoryColumns,
    rows: Vec<Vec<f64>>,
}

impl Observer for Rows<'_> {
    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        let row = self
            .columns
            .record_row(record, snapshot, std::path::Path::new("history.csv"))
            .unwrap();
        self.rows.push(row);
        ControlFlow::Continue(())
    }
}

#[test]
fn each_parts_percentile_is_the_homogeneous_stress() {
    let dir = std::env::temp_dir().join(format!("musclefem_percentile_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, SCENE).unwrap();
    let model = load_scene(&path, &mut MaterialLibrary::with_builtins()).unwrap();
    let columns = model.history_columns();
    let header = columns.implicit_header();
    assert!(
        header.ends_with(",von_mises_p95_pulled_pa,von_mises_p95_idle_pa"),
        "{header}"
    );
    let mut rows = Rows {
        columns: &columns,
        rows: Vec::new(),
    };
    model.run(&mut rows).unwrap();
    for row in &rows.rows {
        let (time, pulled, idle) = (row[0], row[row.len() - 2], row[row.len() - 1]);
        // Uniaxial Cauchy stress of the incompressible neo-Hookean: μ (λ² − 1/λ).
        let stretch = 1.0 + 0.2 * time;
        let expected = 1e4 * (stretch * stretch - 1.0 / stretch);
        assert!(
            (pulled - expected).abs() <= 5e-3 * expected,
            "t = {time}: {pulled} Pa against {expected} Pa"
        );
        assert!(idle.abs() < 1e-6, "the idle cube carries {idle} Pa");
    }
    assert_eq!(rows.rows.len(), 4);
    let bad = "[output]\nvon_mises_percentile = 100\n";
    std::fs::write(
        &path,
        SCENE.replace("[output]\nframes = false\nvon_mises_percentile = 95\n", bad),
    )
    .unwrap();
    let refused = load_scene(&path, &mut MaterialLibrary::with_builtins())
        .unwrap_err()
        .to_string();
    assert!(refused.contains("must be in (0, 100)"), "{refused}");
}
