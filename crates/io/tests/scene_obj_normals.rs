//! A rigid body's OBJ surface file with vertex normals (`vn`, faces `v//vn`): written by
//! `mesh_export::obj_text` and read back by a scene, the body has the same vertices,
//! triangles and vertex normals, bit for bit (a file in millimetres scales the vertices,
//! not the normals); a face naming a normal the file lacks is refused with the file and
//! its line.

use nalgebra::Vector3;

use musclefem_contact::RigidSurface;
use musclefem_io::mesh_export::obj_text;
use musclefem_io::scene::load_scene;
use musclefem_materials::MaterialLibrary;

/// A scene of a 10 mm cube with one rigid body whose surface is `surface`.
fn scene(surface: &str) -> String {
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
mesh = {{ generator = "box", size = [0.01, 0.01, 0.01], divisions = [1, 1, 1] }}

[[rigid_bodies]]
name = "bone"
surface = {surface}

[step]
solver = "implicit"
duration = 1.0
"#
    )
}

/// The folder of this test's files.
fn folder() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("musclefem_obj_normals_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn bits(v: &[Vector3<f64>]) -> Vec<[u64; 3]> {
    v.iter().map(|x| x.map(f64::to_bits).into()).collect()
}

#[test]
fn a_bones_obj_with_normals_reads_back_bit_for_bit() {
    // A ball 20 mm across off the origin, its normals the sphere's own (not the facets').
    let center = Vector3::new(0.013, -0.2, 1.0 / 3.0);
    let ball = RigidSurface::sphere("ball", center, 0.01, 2).unwrap();
    let normals: Vec<Vector3<f64>> = ball
        .vertices
        .iter()
        .map(|v| (v - center).normalize())
        .collect();
    let dir = folder();
    let text = obj_text("a ball", &ball.vertices, &ball.triangles, Some(&normals));
    std::fs::write(dir.join("ball.obj"), &text).unwrap();
    let load = |surface: &str| {
        let path = dir.join("scene.toml");
        std::fs::write(&path, scene(surface)).unwrap();
        load_scene(&path, &mut MaterialLibrary::with_builtins())
    };

    let model = load(r#"{ file = "ball.obj" }"#).unwrap();
    let bone = &model.rigid_bodies[0];
    assert_eq!(bone.name, "bone");
    assert_eq!(bits(&bone.vertices), bits(&ball.vertices));
    assert_eq!(bone.triangles, ball.triangles);
    assert_eq!(bits(bone.vertex_normals.as_ref().unwrap()), bits(&normals));

    // The same numbers read in millimetres: the vertices scale, the normals do not.
    let model = load(r#"{ file = "ball.obj", units = "mm" }"#).unwrap();
    let bone = &model.rigid_bodies[0];
    assert_eq!(bone.vertices[5], ball.vertices[5] * 1e-3);
    assert_eq!(bits(bone.vertex_normals.as_ref().unwrap()), bits(&normals));

    // Without normals the body has none (the contact averages the facets').
    let bare = obj_text("a ball", &ball.vertices, &ball.triangles, None);
    std::fs::write(dir.join("bare.obj"), bare).unwrap();
    let model = load(r#"{ file = "bare.obj" }"#).unwrap();
    assert!(model.rigid_bodies[0].vertex_normals.is_none());
}

#[test]
fn a_face_naming_a_missing_normal_is_refused_with_its_file_and_line() {
    let dir = folder();
    let obj = "# one facet\nv 0 0 0\nv 0.01 0 0\nv 0 0.01 0\nvn 0 0 1\nf 1//1 2//1 3//2\n";
    std::fs::write(dir.join("bad_normal.obj"), obj).unwrap();
    let path = dir.join("bad_scene.toml");
    std::fs::write(&path, scene(r#"{ file = "bad_normal.obj" }"#)).unwrap();
    let message = load_scene(&path, &mut MaterialLibrary::with_builtins())
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("bad_scene.toml:17:")
            && message.contains("bad_normal.obj:6: normal 2 does not exist (1 normals so far)"),
        "{message}"
    );
}
