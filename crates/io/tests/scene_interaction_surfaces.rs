//! `[[interactions]]` on a surface across parts (a list of part surfaces, the parts
//! sharing a file's nodes), cohesive bonds limited to a band of heights with a minimum
//! bond count, and the default contact penalty per node from the stiffest part holding it.

use std::path::PathBuf;

use musclefem_contact::default_penalty;
use musclefem_io::scene::{InteractionModel, Model, load_scene, small_strain_shear_modulus};
use musclefem_materials::MaterialLibrary;

/// Two hexes in a row along x, 10 mm each: the belly (element 1, x ∈ [0, 10] mm) and
/// the tendon (element 2, x ∈ [10, 20] mm) sharing the face at x = 10 mm; `TOP` is their
/// faces at z = 10 mm. Node n(i, j, k) = 1 + i + 3 j + 6 k at (10 i, 10 j, 10 k) mm.
const DECK: &str = "*NODE
1, 0.0, 0.0, 0.0
2, 0.01, 0.0, 0.0
3, 0.02, 0.0, 0.0
4, 0.0, 0.01, 0.0
5, 0.01, 0.01, 0.0
6, 0.02, 0.01, 0.0
7, 0.0, 0.0, 0.01
8, 0.01, 0.0, 0.01
9, 0.02, 0.0, 0.01
10, 0.0, 0.01, 0.01
11, 0.01, 0.01, 0.01
12, 0.02, 0.01, 0.01
*ELEMENT, TYPE=C3D8, ELSET=BELLY
1, 1, 2, 5, 4, 7, 8, 11, 10
*ELEMENT, TYPE=C3D8, ELSET=TENDON
2, 2, 3, 6, 5, 8, 9, 12, 11
*SURFACE, NAME=TOP, TYPE=ELEMENT
1, S2
2, S2
";

/// The scene's head: a soft belly and a stiff tendon on `DECK`'s blocks sharing its
/// nodes, and a rigid plate facing down 0.5 mm above their top.
const HEAD: &str = r#"schema_version = 1

[[materials]]
name = "soft"
model = "neo-hookean"
parameters = { mu = 1e4 }

[[materials]]
name = "stiff"
model = "neo-hookean"
parameters = { mu = 1e6 }

[[parts]]
name = "belly"
material = "soft"
element = "hex8-fbar"
density = 1000.0
mesh = { file = "row.inp", block = "BELLY", shared_nodes = true }

[[parts]]
name = "tendon"
material = "stiff"
element = "hex8-fbar"
density = 1000.0
mesh = { file = "row.inp", block = "TENDON", shared_nodes = true }

[[rigid_bodies]]
name = "plate"
surface = { shape = "plane", point = [0.01, 0.005, 0.0105], normal = [0.0, 0.0, -1.0], half_size = 0.05 }

"#;

/// The step, after the interaction.
const STEP: &str = "\n[step]\nsolver = \"implicit\"\nduration = 1.0\n";

/// Write `row.inp` and the scene `HEAD + interaction + STEP` into a directory of their
/// own (named after `case`); returns the scene's path.
fn write_scene(case: &str, interaction: &str) -> PathBuf {
    let directory = std::env::temp_dir().join(format!(
        "musclefem_interaction_surfaces_{case}_{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&directory).unwrap();
    std::fs::write(directory.join("row.inp"), DECK).unwrap();
    let path = directory.join("scene.toml");
    std::fs::write(&path, format!("{HEAD}{interaction}{STEP}")).unwrap();
    path
}

/// Build the scene `HEAD + interaction + STEP`.
fn build(case: &str, interaction: &str) -> Result<Model, String> {
    let path = write_scene(case, interaction);
    let built = load_scene(&path, &mut MaterialLibrary::with_builtins()).map_err(|e| e.to_string());
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
    built
}

/// The line of `HEAD + interaction + STEP` on which `fragment` (in `interaction`) stands.
fn line_of(interaction: &str, fragment: &str) -> usize {
    let text = format!("{HEAD}{interaction}{STEP}");
    let at = text.find(fragment).expect("the fragment is in the scene");
    text[..at].lines().count() + 1
}

/// The bonded nodes (file ids from 0) of the scene's first interaction, a cohesive one.
fn bonded_nodes(model: &Model) -> Vec<u32> {
    let InteractionModel::Cohesive(glue) = &model.interactions[0] else {
        panic!("not a cohesive interface");
    };
    let mut nodes: Vec<u32> = glue.bonded_nodes().collect();
    nodes.sort_unstable();
    nodes
}

const GLUE: &str = r#"[[interactions]]
name = "glue"
kind = "cohesive"
secondary = ["belly.TOP", "tendon.TOP"]
main = "plate"
bond_tolerance = 0.001
"#;

#[test]
fn a_surface_across_parts_bonds_where_its_faces_lie_within_the_band() {
    // Both parts' top faces bond: the six top nodes (ids 6..=11).
    let model = build("whole", GLUE).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(bonded_nodes(&model), vec![6, 7, 8, 9, 10, 11]);
    let InteractionModel::Cohesive(glue) = &model.interactions[0] else {
        panic!("not a cohesive interface");
    };
    assert_eq!(glue.surfaces().0, "belly.TOP+tendon.TOP");
    // Only the belly's face has its centroid (x = 5 mm) within 0 … 10 mm along x; the
    // tendon's (15 mm) does not: the belly's four top nodes bond.
    let band = format!(
        "{GLUE}bond_band = {{ axis = [2.0, 0.0, 0.0], heights = [0.0, 0.01] }}\nminimum_bonds = 4\n"
    );
    let model = build("band", &band).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(bonded_nodes(&model), vec![6, 7, 9, 10]);
}

#[test]
fn too_few_bonds_an_empty_band_and_bad_band_keys_are_refused_at_their_line() {
    let band = "bond_band = { axis = [1.0, 0.0, 0.0], heights = [0.0, 0.01] }\n";
    let cases = [
        (
            "too few bonds",
            format!("{GLUE}{band}minimum_bonds = 5\n"),
            "minimum_bonds",
            "4 secondary nodes bonded, fewer than minimum_bonds = 5",
        ),
        (
            "no bond required",
            format!("{GLUE}minimum_bonds = 0\n"),
            "minimum_bonds",
            "minimum_bonds must be at least 1",
        ),
        (
            "an empty band",
            format!("{GLUE}bond_band = {{ axis = [1.0, 0.0, 0.0], heights = [0.5, 0.6] }}\n"),
            "bond_band",
            "no face of 'belly.TOP+tendon.TOP' has its centroid between heights 0.5 and 0.6 m",
        ),
        (
            "heights out of order",
            format!("{GLUE}bond_band = {{ axis = [1.0, 0.0, 0.0], heights = [0.01, 0.0] }}\n"),
            "bond_band",
            "must be finite, the lower first",
        ),
        (
            "no axis",
            format!("{GLUE}bond_band = {{ axis = [0.0, 0.0, 0.0], heights = [0.0, 0.01] }}\n"),
            "bond_band",
            "has no direction",
        ),
        (
            "a misspelt key of the band",
            format!("{GLUE}bond_band = {{ axis = [1.0, 0.0, 0.0], height = [0.0, 0.01] }}\n"),
            "bond_band",
            "height",
        ),
        (
            "a band on a contact",
            GLUE.replace("cohesive", "contact")
                .replace("bond_tolerance = 0.001\n", band),
            "bond_band",
            "`bond_band` does not apply to kind = \"contact\"",
        ),
        (
            "a surface listed twice",
            GLUE.replace("\"tendon.TOP\"]", "\"belly.TOP\"]"),
            "secondary",
            "'belly.TOP' is listed twice",
        ),
        (
            "an unknown part in the list",
            GLUE.replace("\"tendon.TOP\"]", "\"tendn.TOP\"]"),
            "secondary",
            "unknown part 'tendn'",
        ),
    ];
    for (what, interaction, key, fragment) in cases {
        let message = build(&what.replace(' ', "_"), &interaction).unwrap_err();
        let line = line_of(&interaction, &format!("{key} ="));
        assert!(
            message.contains(&format!("scene.toml:{line}:")) && message.contains(fragment),
            "{what}: got \"{message}\", expected line {line} and \"{fragment}\""
        );
    }
}

#[test]
fn contact_nodes_press_with_the_stiffest_part_that_holds_them() {
    let press = "[[interactions]]\nname = \"press\"\nkind = \"contact\"\nsecondary = \
                 [\"belly.TOP\", \"tendon.TOP\"]\nmain = \"plate\"\n";
    let model = build("press", press).unwrap_or_else(|e| panic!("{e}"));
    let InteractionModel::Contact(contact) = &model.interactions[0] else {
        panic!("not a contact");
    };
    let surface = contact.secondary();
    assert_eq!(surface.nodes, vec![6, 7, 8, 9, 10, 11]);
    let penalty = |part: usize| {
        let shear = small_strain_shear_modulus(model.parts[part].material.as_ref()).unwrap();
        default_penalty(3.0 * shear, surface.element_size()).unwrap()
    };
    let (soft, stiff) = (penalty(0), penalty(1));
    assert!(stiff > 50.0 * soft);
    // x = 0: the belly's only; x = 10 mm: both parts', the tendon's is stiffer; x = 20 mm:
    // the tendon's.
    let expected = [soft, stiff, stiff, soft, stiff, stiff];
    for (i, want) in expected.iter().enumerate() {
        assert_eq!(
            contact.node_penalty(i).to_bits(),
            want.to_bits(),
            "node {i}"
        );
    }
    assert_eq!(contact.penalty(), soft);

    // A given penalty_stiffness is every node's.
    let given = format!("{press}penalty_stiffness = 1e9\n");
    let model = build("given", &given).unwrap_or_else(|e| panic!("{e}"));
    let InteractionModel::Contact(contact) = &model.interactions[0] else {
        panic!("not a contact");
    };
    assert!((0..6).all(|i| contact.node_penalty(i) == 1e9));
}
