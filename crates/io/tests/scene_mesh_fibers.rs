//! A part whose Abaqus file carries `*ORIENTATION`s takes its fibers from them when the
//! scene gives no `fibers` table, and the scene's table wins when it has one; `check`'s
//! description says which, and lists the keywords the reader ignored.

use musclefem_io::scene::load_scene;
use musclefem_materials::MaterialLibrary;

/// Two 1 mm hexes along x, fibers by a distribution with a 30° turn about local 3.
const DECK: &str = "\
*NODE
1, 0, 0, 0
2, 1, 0, 0
3, 2, 0, 0
4, 0, 1, 0
5, 1, 1, 0
6, 2, 1, 0
7, 0, 0, 1
8, 1, 0, 1
9, 2, 0, 1
10, 0, 1, 1
11, 1, 1, 1
12, 2, 1, 1
*ELEMENT, TYPE=C3D8, ELSET=MUSCLE
1, 1, 2, 5, 4, 7, 8, 11, 10
2, 2, 3, 6, 5, 8, 9, 12, 11
*NSET, NSET=x0
1, 4, 7, 10
*DISTRIBUTION TABLE, NAME=T
COORD3D, COORD3D
*DISTRIBUTION, NAME=D, LOCATION=ELEMENT, TABLE=T
, 1., 0., 0., 0., 1., 0.
1, 0., 2., 0., -1., 0., 0.
*ORIENTATION, NAME=ORI
D
3, 30.
*SOLID SECTION, ELSET=MUSCLE, MATERIAL=M, ORIENTATION=ORI
*STEP
*BOUNDARY
1, 1, 3
*END STEP
";

fn scene(fibers: &str) -> String {
    format!(
        r#"schema_version = 1

[[materials]]
name = "rubber"
model = "neo-hookean"
parameters = {{ mu = 1e4, D = 2e-5 }}

[[parts]]
name = "muscle"
material = "rubber"
element = "hex8-fbar"
density = 1000.0
mesh = {{ file = "muscle.inp", units = "mm" }}
{fibers}

[[displacements]]
part = "muscle"
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
fn the_mesh_files_orientations_are_the_fibers_unless_the_scene_gives_them() {
    let dir = std::env::temp_dir().join(format!("musclefem_mesh_fibers_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("muscle.inp"), DECK).unwrap();
    let load = |fibers: &str| {
        let path = dir.join("scene.toml");
        std::fs::write(&path, scene(fibers)).unwrap();
        load_scene(&path, &mut MaterialLibrary::with_builtins()).unwrap()
    };

    let model = load("");
    // Element 1: cos30 y + sin30 (−x); element 2: cos30 x + sin30 y (by hand).
    let (c, s) = (0.75f64.sqrt(), 0.5);
    let fibers = &model.mesh.blocks[0].fiber_direction;
    assert!((fibers[0] - nalgebra::Vector3::new(-s, c, 0.0)).norm() < 1e-12);
    assert!((fibers[1] - nalgebra::Vector3::new(c, s, 0.0)).norm() < 1e-12);
    let description = model.describe();
    assert!(
        description.contains("  part 'muscle': fibers from the mesh file: *ORIENTATION ORI ("),
        "{description}"
    );
    assert!(description.contains("muscle.inp:24)\n"), "{description}");
    assert!(
        description.contains("  warning: part 'muscle': mesh file ")
            && description.contains("muscle.inp:28: *STEP ignored: musclefem takes loads"),
        "{description}"
    );

    let model = load("fibers = { direction = [0.0, 0.0, 2.0] }");
    for fiber in &model.mesh.blocks[0].fiber_direction {
        assert_eq!(fiber.as_slice(), &[0.0, 0.0, 1.0]);
    }
    let description = model.describe();
    assert!(
        description.contains(
            "  part 'muscle': fibers from the scene's fibers table (the mesh file's \
             *ORIENTATION ORI ("
        ),
        "{description}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Two blocks of one file (a belly and its tendon, one hex each) as two parts, both
/// reading their fibers from one file that covers the whole mesh: each part takes its
/// own elements' rows and skips the other block's; a row for an element of no block is
/// still refused.
#[test]
fn one_fibers_file_serves_every_block_of_a_mesh_file() {
    let dir = std::env::temp_dir().join(format!("musclefem_blocks_fibers_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let deck = DECK.split("*NSET").next().unwrap().replace(
        "2, 2, 3, 6, 5, 8, 9, 12, 11\n",
        "*ELEMENT, TYPE=C3D8, ELSET=TENDON\n2, 2, 3, 6, 5, 8, 9, 12, 11\n",
    );
    std::fs::write(dir.join("muscle.inp"), &deck).unwrap();
    let part = |name: &str, block: &str| {
        format!(
            "[[parts]]\nname = \"{name}\"\nmaterial = \"rubber\"\nelement = \"hex8-fbar\"\n\
             density = 1000.0\nmesh = {{ file = \"muscle.inp\", block = \"{block}\" }}\n\
             fibers = {{ file = \"fibers.csv\" }}\n\n"
        )
    };
    let text = format!(
        "schema_version = 1\n\n[[materials]]\nname = \"rubber\"\nmodel = \"neo-hookean\"\n\n{}{}\
         [step]\nsolver = \"implicit\"\nduration = 1.0\n",
        part("belly", "MUSCLE"),
        part("tendon", "TENDON")
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let header = "element,cx,cy,cz,fx,fy,fz\n";
    let load = |rows: &str| {
        std::fs::write(dir.join("fibers.csv"), format!("{header}{rows}")).unwrap();
        load_scene(&path, &mut MaterialLibrary::with_builtins()).map_err(|e| e.to_string())
    };
    let model = load("2,1.5,0.5,0.5,0,0,1\n1,0.5,0.5,0.5,0,1,0\n").unwrap();
    assert_eq!(model.part_names, vec!["belly", "tendon"]);
    assert_eq!(
        model.mesh.blocks[0].fiber_direction,
        vec![nalgebra::Vector3::y()]
    );
    assert_eq!(
        model.mesh.blocks[1].fiber_direction,
        vec![nalgebra::Vector3::z()]
    );
    let message = load("2,0,0,0,0,0,1\n1,0,0,0,0,1,0\n3,0,0,0,1,0,0\n").unwrap_err();
    assert!(
        message.contains("line 4: the part has no element 3"),
        "{message}"
    );
    // Each part copies its block's nodes: the four nodes of the face at x = 1 are there
    // twice, and the blocks are not joined.
    assert_eq!(model.mesh.node_count(), 16);
    let message = load("1,0,0,0,0,1,0\n").unwrap_err();
    assert!(
        message.contains("no fiber for 1 of the part's 1 elements (the first: element 2)"),
        "{message}"
    );
}

/// With `shared_nodes`, two parts of one file share its nodes: the belly and the tendon
/// stay joined at their common face, every node by its id in the file; a generated box
/// cannot share.
#[test]
fn parts_of_one_file_share_its_nodes_when_they_say_so() {
    let dir = std::env::temp_dir().join(format!("musclefem_shared_nodes_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let deck = DECK.split("*NSET").next().unwrap().replace(
        "2, 2, 3, 6, 5, 8, 9, 12, 11\n",
        "*ELEMENT, TYPE=C3D8, ELSET=TENDON\n2, 2, 3, 6, 5, 8, 9, 12, 11\n*NSET, NSET=end\n3, 6, 9, 12\n",
    );
    std::fs::write(dir.join("muscle.inp"), &deck).unwrap();
    let part = |name: &str, block: &str| {
        format!(
            "[[parts]]\nname = \"{name}\"\nmaterial = \"rubber\"\nelement = \"hex8-fbar\"\n\
             density = 1000.0\nmesh = {{ file = \"muscle.inp\", block = \"{block}\", shared_nodes = true }}\n\n"
        )
    };
    let text = format!(
        "schema_version = 1\n\n[[materials]]\nname = \"rubber\"\nmodel = \"neo-hookean\"\n\n{}{}\
         [[rigid_ties]]\nname = \"pull\"\npart = \"tendon\"\nnodes = \"end\"\ntranslation = [0.001, 0.0, 0.0]\n\n\
         [step]\nsolver = \"implicit\"\nduration = 1.0\n",
        part("belly", "MUSCLE"),
        part("tendon", "TENDON")
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, &text).unwrap();
    let model = load_scene(&path, &mut MaterialLibrary::with_builtins()).unwrap();
    assert_eq!(model.mesh.node_count(), 12);
    assert_eq!(
        model.mesh.blocks[0].connectivity,
        vec![0, 1, 4, 3, 6, 7, 10, 9]
    );
    assert_eq!(
        model.mesh.blocks[1].connectivity,
        vec![1, 2, 5, 4, 7, 8, 11, 10]
    );
    assert_eq!(model.loads.rigid_ties[0].nodes, vec![2, 5, 8, 11]);
    // The tendon's sets hold only its block's nodes: the belly has no `end`.
    assert!(!model.mesh.node_sets.contains_key("belly.end"));
    assert_eq!(
        model.mesh.nodes.position(11),
        nalgebra::Vector3::new(2.0, 1.0, 1.0)
    );

    let boxed = text.replacen(
        "mesh = { file = \"muscle.inp\", block = \"MUSCLE\", shared_nodes = true }",
        "mesh = { generator = \"box\", size = [1.0, 1.0, 1.0], divisions = [1, 1, 1], shared_nodes = true }",
        1,
    );
    std::fs::write(&path, &boxed).unwrap();
    let message = load_scene(&path, &mut MaterialLibrary::with_builtins())
        .unwrap_err()
        .to_string();
    assert!(message.contains("a generated box has its own"), "{message}");
}
