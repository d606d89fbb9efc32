//! A part's mesh file in millimetres (`mesh = { file = ..., units = "mm" }`) is read in
//! metres; without `units` the same file gives a part 10 m across, which the scene's
//! description warns about; a wrong unit or a unit on a generated box is refused with its
//! line. The same for a rigid body's surface file (`surface = { file = ..., units = "mm"
//! }`), and a material's implausible shear modulus is warned about.

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

/// A scene of the 10 mm cube (generated) with one rigid body whose surface is `surface`.
fn rigid_scene(surface: &str) -> String {
    format!(
        "{}\n[[rigid_bodies]]\nname = \"bone\"\nsurface = {surface}\n",
        scene(r#"{ generator = "box", size = [0.01, 0.01, 0.01], divisions = [1, 1, 1] }"#)
    )
}

/// A closed tetrahedron of side 20 (a 20 mm bone in millimetres), as ASCII STL.
const TETRAHEDRON_MM: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [20.0, 0.0, 0.0],
    [0.0, 20.0, 0.0],
    [0.0, 0.0, 20.0],
];

fn tetrahedron_stl() -> String {
    let v = TETRAHEDRON_MM;
    let mut text = String::from("solid bone\n");
    for [a, b, c] in [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] {
        text += "facet normal 0 0 0\nouter loop\n";
        for i in [a, b, c] {
            text += &format!("vertex {} {} {}\n", v[i][0], v[i][1], v[i][2]);
        }
        text += "endloop\nendfacet\n";
    }
    text + "endsolid bone\n"
}

#[test]
fn a_rigid_surface_in_millimetres_is_read_in_metres() {
    let dir = std::env::temp_dir().join(format!("musclefem_rigid_units_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("bone.stl"), tetrahedron_stl()).unwrap();
    let load = |surface: &str| {
        let path = dir.join("scene.toml");
        std::fs::write(&path, rigid_scene(surface)).unwrap();
        load_scene(&path, &mut MaterialLibrary::with_builtins())
    };

    let model = load(r#"{ file = "bone.stl", units = "mm" }"#).unwrap();
    let vertices = &model.rigid_bodies[0].vertices;
    assert_eq!(vertices.len(), 4);
    for corner in TETRAHEDRON_MM {
        let metres = nalgebra::Vector3::from(corner) / 1000.0;
        assert!(
            vertices.iter().any(|v| (v - metres).norm() < 1e-15),
            "{metres} in {vertices:?}"
        );
    }
    assert!(
        !model.describe().contains("warning"),
        "{}",
        model.describe()
    );

    // Read as metres, the bone is 20 m across: the description says so.
    let unscaled = load(r#"{ file = "bone.stl" }"#).unwrap();
    let description = unscaled.describe();
    assert!(
        description.contains("warning: rigid body 'bone': it is 2.000e1 m across")
            && description.contains("surface = { file = ..., units = \"mm\" }"),
        "{description}"
    );

    let wrong = load(r#"{ file = "bone.stl", units = "inch" }"#)
        .unwrap_err()
        .to_string();
    assert!(
        wrong.contains(":28:") && wrong.contains("\"m\" or \"mm\""),
        "{wrong}"
    );
    let generated =
        load(r#"{ shape = "sphere", center = [0, 0, 0], radius = 0.01, units = "mm" }"#)
            .unwrap_err()
            .to_string();
    assert!(
        generated.contains(":28:") && generated.contains("a generated shape's sizes"),
        "{generated}"
    );
}

/// `check`'s description warns of a shear modulus no tissue has, naming the material and
/// its μ (for the neo-Hookean solid, μ is its parameter `mu`): 10 kPa given in MPa (0.01)
/// is too soft, 20 GPa too stiff; 10 kPa is not warned about.
#[test]
fn an_implausible_shear_modulus_is_warned_about() {
    let dir = std::env::temp_dir().join(format!("musclefem_stiffness_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let describe = |mu: &str| {
        let text =
            scene(r#"{ generator = "box", size = [0.01, 0.01, 0.01], divisions = [1, 1, 1] }"#)
                .replace("mu = 1e4", &format!("mu = {mu}"));
        let path = dir.join("scene.toml");
        std::fs::write(&path, text).unwrap();
        load_scene(&path, &mut MaterialLibrary::with_builtins())
            .unwrap()
            .describe()
    };
    let plausible = describe("1e4");
    assert!(!plausible.contains("shear modulus"), "{plausible}");
    let soft = describe("0.01");
    assert!(
        soft.contains("warning: part 'cube': material 'rubber' has a small-strain shear modulus mu = 1.000e-2 Pa")
            && soft.contains("kPa or MPa"),
        "{soft}"
    );
    let stiff = describe("2e10");
    assert!(
        stiff.contains("material 'rubber' has a small-strain shear modulus mu = 2.000e10 Pa")
            && stiff.contains("more than 10 GPa"),
        "{stiff}"
    );
}
