//! A part's mesh file in millimetres (`mesh = { file = ..., units = "mm" }`) is read in
//! metres; without `units` the same file gives a part 10 m across, which the scene's
//! description warns about; a wrong unit or a unit on a generated box is refused with its
//! line.

use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_io::mesh_export::abaqus_text;
use musclefem_io::scene::load_scene;
use musclefem_materials::MaterialLibrary;

/// A scene of one 10 mm cube (its mesh file in mm) whose mesh line is `mesh`.
fn scene(mesh: &str) -> String {
    format!(
        r#"schema_version = 1

[[materials]]
name = "rubber"
model = "neo-hookean"
parameters = {{ mu = 1e4, D = 2e-5 }}

[[parts]]
name = "cube"
material = "rubber"
element = "hex8-fbar"
density = 1000.0
mesh = {mesh}

[[displacements]]
part = "cube"
nodes = "x0"
components = ["x", "y", "z"]
value = 0.0

[step]
solver = "implicit"
duration = 1.0
implicit = {{ increments = 1 }}
"#
    )
}

#[test]
fn a_mesh_in_millimetres_is_read_in_metres_and_one_read_as_metres_is_flagged() {
    let dir = std::env::temp_dir().join(format!("musclefem_units_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let in_metres = box_of_hexes([0.01, 0.01, 0.01], [2, 2, 2]).unwrap();
    let mut in_millimetres = in_metres.clone();
    for id in 0..in_millimetres.nodes.len() {
        let x = in_millimetres.nodes.position(id);
        in_millimetres.nodes.set_position(id, 1e3 * x);
    }
    std::fs::write(
        dir.join("cube_mm.inp"),
        abaqus_text(&in_millimetres, "cube in mm"),
    )
    .unwrap();
    let load = |mesh: &str| {
        let path = dir.join("scene.toml");
        std::fs::write(&path, scene(mesh)).unwrap();
        load_scene(&path, &mut MaterialLibrary::with_builtins())
    };

    let model = load(r#"{ file = "cube_mm.inp", units = "mm" }"#).unwrap();
    for id in 0..in_metres.nodes.len() {
        let (read, expected) = (model.mesh.nodes.position(id), in_metres.nodes.position(id));
        assert!(
            (read - expected).norm() < 1e-15,
            "node {id}: {read} against {expected}"
        );
    }
    assert!(
        !model.describe().contains("warning"),
        "{}",
        model.describe()
    );

    let unscaled = load(r#"{ file = "cube_mm.inp" }"#).unwrap();
    let description = unscaled.describe();
    assert!(
        description.contains("warning: part 'cube': it is 1.000e1 m across")
            && description.contains("units = \"mm\""),
        "{description}"
    );

    let wrong = load(r#"{ file = "cube_mm.inp", units = "km" }"#)
        .unwrap_err()
        .to_string();
    assert!(
        wrong.contains(":13:") && wrong.contains("\"m\" or \"mm\""),
        "{wrong}"
    );
    let generated = load(
        r#"{ generator = "box", size = [0.01, 0.01, 0.01], divisions = [1, 1, 1], units = "mm" }"#,
    )
    .unwrap_err()
    .to_string();
    assert!(generated.contains("a generated box's size"), "{generated}");
}
