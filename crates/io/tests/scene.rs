//! Scene files: a table of malformed scenes each fails with the file, the line and the
//! cause named (the examples are `scene_examples.rs`).

use std::path::{Path, PathBuf};

use musclefem_io::scene::{Analysis, load_scene, parse_scene};
use musclefem_materials::MaterialLibrary;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

const VALID: &str = r#"schema_version = 1

[[materials]]
name = "rubber"
model = "neo-hookean"
parameters = { mu = 1e4, D = 2e-5 }

[[parts]]
name = "cube"
material = "rubber"
element = "hex8-full"
density = 1000.0
mesh = { generator = "box", size = [0.01, 0.01, 0.01], divisions = [2, 2, 2] }

[[amplitudes]]
name = "ramp"
points = [[0.0, 0.0], [1.0, 1.0]]

[[displacements]]
part = "cube"
nodes = "x1"
components = ["x"]
value = 0.001
amplitude = "ramp"

[step]
solver = "implicit"
duration = 1.0
"#;

/// Each case (what, text replaced in [`VALID`], its replacement, the error's location,
/// a fragment of its message) is refused with that location and message.
fn assert_edits_are_refused(cases: &[(&str, &str, &str, &str, &str)]) {
    for &(what, from, to, location, fragment) in cases {
        assert!(VALID.contains(from), "{what}: the edit does not apply");
        let message = error_of(&VALID.replacen(from, to, 1));
        assert!(
            message.starts_with(location) && message.contains(fragment),
            "{what}: got \"{message}\", expected {location} … {fragment}"
        );
    }
}

/// Build `text` (named s.toml) and return the error message.
fn error_of(text: &str) -> String {
    let path = Path::new("s.toml");
    let (scene, locator) = match parse_scene(text, path) {
        Ok(parsed) => parsed,
        Err(e) => return e.to_string(),
    };
    match musclefem_io::scene::build_model(&scene, &locator, &mut MaterialLibrary::with_builtins())
    {
        Ok(_) => "built without error".to_string(),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_valid_scene_builds() {
    assert_eq!(error_of(VALID), "built without error");
}

/// Each malformed scene: (what is wrong, the edit, the expected start of the message
/// "s.toml:LINE:", a fragment naming the cause).
#[test]
fn malformed_scenes_name_the_line_and_the_cause() {
    let cases: [(&str, &str, &str, &str, &str); 16] = [
        (
            "misspelt key",
            "density = 1000.0",
            "densty = 1000.0",
            "s.toml:12:",
            "did you mean `density`?",
        ),
        (
            "wrong type",
            "density = 1000.0",
            "density = \"heavy\"",
            "s.toml:12:",
            "invalid type",
        ),
        (
            "unknown model",
            "model = \"neo-hookean\"",
            "model = \"neo-hooke\"",
            "s.toml:5:",
            "did you mean `neo-hookean`?",
        ),
        (
            "unknown parameter",
            "mu = 1e4",
            "mew = 1e4",
            "s.toml:6:",
            "mew",
        ),
        (
            "parameter out of range",
            "mu = 1e4",
            "mu = -1.0",
            "s.toml:6:",
            "mu",
        ),
        (
            "unknown material of a part",
            "material = \"rubber\"",
            "material = \"ruber\"",
            "s.toml:10:",
            "did you mean `rubber`?",
        ),
        (
            "unknown element",
            "element = \"hex8-full\"",
            "element = \"hex8-ful\"",
            "s.toml:11:",
            "did you mean `hex8-full`?",
        ),
        (
            "negative density",
            "density = 1000.0",
            "density = -5.0",
            "s.toml:12:",
            "must be positive",
        ),
        (
            "unknown node set",
            "nodes = \"x1\"",
            "nodes = \"x2\"",
            "s.toml:21:",
            "no node set 'x2'",
        ),
        (
            "unknown part",
            "part = \"cube\"",
            "part = \"cub\"",
            "s.toml:20:",
            "did you mean `cube`?",
        ),
        (
            "bad component",
            "components = [\"x\"]",
            "components = [\"w\"]",
            "s.toml:22:",
            "unknown component 'w'",
        ),
        (
            "unknown amplitude",
            "amplitude = \"ramp\"",
            "amplitude = \"rmp\"",
            "s.toml:24:",
            "did you mean `ramp`?",
        ),
        (
            "decreasing amplitude times",
            "[[0.0, 0.0], [1.0, 1.0]]",
            "[[1.0, 0.0], [0.0, 1.0]]",
            "s.toml:17:",
            "amplitude",
        ),
        (
            "unknown solver",
            "solver = \"implicit\"",
            "solver = \"implict\"",
            "s.toml:27:",
            "did you mean `implicit`?",
        ),
        (
            "schema version",
            "schema_version = 1",
            "schema_version = 7",
            "s.toml:1:",
            "version 7 is not supported",
        ),
        (
            "TOML syntax",
            "duration = 1.0",
            "duration = ",
            "s.toml:28:",
            "must be quoted",
        ),
    ];
    assert_edits_are_refused(&cases);
}

/// Settings that passed `check` and failed only in `run` (or not at all), each refused
/// now by the scene's build with its line (issue: reliability, case 3 and 4).
#[test]
fn settings_run_would_refuse_are_refused_when_the_scene_is_built() {
    let cases = [
        (
            "safety factor 0",
            "duration = 1.0",
            "duration = 1.0\nexplicit = { safety_factor = 0.0 }",
            "s.toml:29:",
            "safety_factor = 0 must be in (0, 1]",
        ),
        (
            "safety factor NaN",
            "duration = 1.0",
            "duration = 1.0\nexplicit = { safety_factor = nan }",
            "s.toml:29:",
            "safety_factor = NaN",
        ),
        (
            "safety factor 5",
            "duration = 1.0",
            "duration = 1.0\nexplicit = { safety_factor = 5.0 }",
            "s.toml:29:",
            "safety_factor = 5 must be in (0, 1]",
        ),
        (
            "mass scaling step ≤ 0",
            "duration = 1.0",
            "duration = 1.0\nexplicit = { mass_scaling_time_step = 0.0 }",
            "s.toml:29:",
            "must be a positive time",
        ),
        (
            "negative shear viscosity",
            "duration = 1.0",
            "duration = 1.0\nexplicit = { shear_viscosity = -1.0 }",
            "s.toml:29:",
            "shear_viscosity = -1 must be a viscosity ≥ 0 [Pa s]",
        ),
        (
            "negative energy tolerance",
            "duration = 1.0",
            "duration = 1.0\nexplicit = { energy_tolerance = -1.0 }",
            "s.toml:29:",
            "energy_tolerance = -1 must be a positive fraction",
        ),
        (
            "residual tolerance 0",
            "duration = 1.0",
            "duration = 1.0\nimplicit = { residual_tolerance = 0.0 }",
            "s.toml:29:",
            "residual_tolerance = 0 must be in (0, 1)",
        ),
        (
            "amplitude twice",
            "[[amplitudes]]",
            "[[amplitudes]]\nname = \"ramp\"\npoints = [[0.0, 0.0]]\n\n[[amplitudes]]",
            "s.toml:20:",
            "amplitude 'ramp' is defined twice",
        ),
        (
            "three-value knot",
            "points = [[0.0, 0.0], [1.0, 1.0]]",
            "points = [[0.0, 0.0], [1.0, 1.0, 2.0]]",
            "s.toml:17:",
            "knot 2 has 3 values",
        ),
        (
            "NaN knot",
            "points = [[0.0, 0.0], [1.0, 1.0]]",
            "points = [[0.0, nan], [1.0, 1.0]]",
            "s.toml:17:",
            "amplitude 'ramp': knot (0.0, NaN) is not finite",
        ),
        (
            "component twice",
            "components = [\"x\"]",
            "components = [\"x\", \"x\"]",
            "s.toml:22:",
            "component \"x\" is given twice",
        ),
        (
            "a box larger than any machine",
            "divisions = [2, 2, 2]",
            "divisions = [1000, 1000, 1000]",
            "s.toml:13:",
            "1000000000 elements need at least 2048.0 GB",
        ),
    ];
    assert_edits_are_refused(&cases);
}

#[test]
fn a_missing_plugin_and_a_missing_file_are_named() {
    let with_plugin = VALID.replace(
        "model = \"neo-hookean\"",
        "model = \"neo-hookean\"\nplugin = \"no/such/libplugin.so\"",
    );
    let message = error_of(&with_plugin);
    assert!(
        message.starts_with("s.toml:6:") && message.contains("libplugin.so"),
        "{message}"
    );
    let missing = load_scene(
        Path::new("no/such/scene.toml"),
        &mut MaterialLibrary::with_builtins(),
    )
    .unwrap_err()
    .to_string();
    assert!(missing.contains("no/such/scene.toml"), "{missing}");
}

/// A part whose mesh is a block of an Abaqus file (relative to the scene): the file's node
/// sets become the part's, a wrong element shape or a missing block is named.
#[test]
fn a_part_meshed_from_an_abaqus_file_builds_and_its_errors_are_named() {
    let directory = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let scene_path = directory.join("from_file.toml");
    let scene = VALID
        .replace(
            "mesh = { generator = \"box\", size = [0.01, 0.01, 0.01], divisions = [2, 2, 2] }",
            "mesh = { file = \"meshes/part_instance.inp\", block = \"all\" }",
        )
        .replace("nodes = \"x1\"", "nodes = \"left\"");
    let build = |text: &str| {
        let (scene, locator) = parse_scene(text, &scene_path)?;
        musclefem_io::scene::build_model(&scene, &locator, &mut MaterialLibrary::with_builtins())
    };
    let model = build(&scene).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(model.mesh.blocks.len(), 1);
    assert_eq!(model.mesh.blocks[0].len(), 2);
    assert_eq!(model.mesh.nodes.len(), 12);
    assert_eq!(model.loads.displacements[0].nodes.len(), 4);
    // Node 0 is the first node of the first element, label 101 at (0, 0, 0), moved by the
    // instance's translation (10, 0, 0).
    let first = model.mesh.nodes.position(0);
    assert!(
        (first.x - 10.0).abs() < 1e-12 && first.y.abs() + first.z.abs() < 1e-12,
        "{first:?}"
    );

    // Element sets and surfaces of the block come along, renamed PART.SET.
    assert_eq!(model.mesh.element_sets["cube.first"].len(), 1);
    assert_eq!(model.mesh.element_sets["cube.both"].len(), 2);
    assert_eq!(model.mesh.surfaces["cube.right"].len(), 1);
    assert_eq!(model.mesh.surfaces["cube.bottom"].len(), 2);

    let tets = scene.replace("element = \"hex8-full\"", "element = \"tet4\"");
    let message = build(&tets).unwrap_err().to_string();
    assert!(
        message.contains("from_file.toml:11:") && message.contains("needs tet4"),
        "{message}"
    );
    let missing = scene.replace("block = \"all\"", "block = \"al\"");
    let message = build(&missing).unwrap_err().to_string();
    assert!(
        message.contains("from_file.toml:13:") && message.contains("did you mean `all`?"),
        "{message}"
    );
    let neither = scene.replace(
        "mesh = { file = \"meshes/part_instance.inp\", block = \"all\" }",
        "mesh = { block = \"all\" }",
    );
    let message = build(&neither).unwrap_err().to_string();
    assert!(message.contains("either as generator"), "{message}");
}

/// Fibers per element from a CSV file: by file label for a part read from a file, by
/// 0-based index for a generated box; unknown, repeated and missing elements are named.
#[test]
fn fibers_per_element_come_from_a_file() {
    let directory =
        std::env::temp_dir().join(format!("musclefem-scene-fibers-{}", std::process::id()));
    std::fs::create_dir_all(directory.join("meshes")).unwrap();
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/meshes/part_instance.inp");
    std::fs::copy(&source, directory.join("meshes/part_instance.inp")).unwrap();
    let scene_path = directory.join("fibers.toml");
    let from_file = VALID
        .replace(
            "mesh = { generator = \"box\", size = [0.01, 0.01, 0.01], divisions = [2, 2, 2] }",
            "mesh = { file = \"meshes/part_instance.inp\", block = \"all\" }\nfibers = { file = \"fibers.csv\" }",
        )
        .replace("nodes = \"x1\"", "nodes = \"left\"");
    let build = |text: &str, fibers: &str| {
        std::fs::write(directory.join("fibers.csv"), fibers).unwrap();
        let (scene, locator) = parse_scene(text, &scene_path)?;
        musclefem_io::scene::build_model(&scene, &locator, &mut MaterialLibrary::with_builtins())
    };
    let header = "element,cx,cy,cz,fx,fy,fz\n";
    let model = build(
        &from_file,
        &format!("{header}12,0,0,0,0,0,2\n11,0,0,0,0,1,0\n"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let fibers = &model.mesh.blocks[0].fiber_direction;
    assert_eq!(fibers[0], nalgebra::Vector3::y(), "label 11 is element 0");
    assert_eq!(fibers[1], nalgebra::Vector3::z(), "normalised");

    for (rows, fragment) in [
        (
            "11,0,0,0,1,0,0\n13,0,0,0,1,0,0\n",
            "line 3: the part has no element 13",
        ),
        (
            "11,0,0,0,1,0,0\n11,0,0,0,1,0,0\n",
            "line 3: element 11 is given twice",
        ),
        (
            "12,0,0,0,1,0,0\n",
            "no fiber for 1 of the part's 2 elements (the first: element 11)",
        ),
        ("11,0,0,0,0,0,0\n", "line 2: fiber direction"),
    ] {
        let message = build(&from_file, &format!("{header}{rows}"))
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("fibers.toml:") && message.contains(fragment),
            "{message}"
        );
    }

    // A generated box: ids are 0-based element indices.
    let boxed = VALID.replace(
        "divisions = [2, 2, 2] }",
        "divisions = [2, 1, 1] }\nfibers = { file = \"fibers.csv\" }",
    );
    let model = build(&boxed, &format!("{header}1,0,0,0,1,1,0\n0,0,0,0,0,0,1\n")).unwrap();
    let fibers = &model.mesh.blocks[0].fiber_direction;
    assert_eq!(fibers[0], nalgebra::Vector3::z());
    assert!((fibers[1] - nalgebra::Vector3::new(1.0, 1.0, 0.0).normalize()).norm() < 1e-15);

    let both = boxed.replace(
        "fibers = { file = \"fibers.csv\" }",
        "fibers = { file = \"fibers.csv\", direction = [1, 0, 0] }",
    );
    let message = build(&both, header).unwrap_err().to_string();
    assert!(message.contains("either as direction"), "{message}");
}

/// Fibers from a potential flow between two surfaces of the part (here the box faces
/// y0 → y1: every fiber along +y); a missing surface and a lone inlet are named.
#[test]
fn fibers_from_a_flow_between_surfaces() {
    let with = |fibers: &str| {
        VALID.replace(
            "divisions = [2, 2, 2] }",
            &format!("divisions = [2, 2, 2] }}\nfibers = {fibers}"),
        )
    };
    let scene_path = Path::new("s.toml");
    let build = |text: &str| {
        let (scene, locator) = parse_scene(text, scene_path)?;
        musclefem_io::scene::build_model(&scene, &locator, &mut MaterialLibrary::with_builtins())
    };
    let model =
        build(&with("{ inlet = \"y0\", outlet = [\"y1\"] }")).unwrap_or_else(|e| panic!("{e}"));
    for fiber in &model.mesh.blocks[0].fiber_direction {
        assert!((fiber - nalgebra::Vector3::y()).norm() < 1e-9, "{fiber:?}");
    }
    let message = error_of(&with("{ inlet = \"y9\", outlet = \"y1\" }"));
    assert!(
        message.contains("s.toml:") && message.contains("'y9'"),
        "{message}"
    );
    let message = error_of(&with("{ inlet = \"y0\" }"));
    assert!(message.contains("both an inlet and an outlet"), "{message}");
}

/// Without `solver` (or with "auto"), the step's speed against the time a pressure wave
/// takes to cross the model picks the solver, and the model says why: the 1 cm rubber
/// cube (c = √((K + 4μ/3)/ρ) = 10.6 m/s, 1.63 ms to cross) pulled in 1 s is slow motion,
/// implicit; the same pull in 0.1 ms is fast, explicit.
#[test]
fn solver_auto_picks_by_the_speed_of_the_step() {
    let build = |text: &str| {
        let (scene, locator) = parse_scene(text, Path::new("s.toml")).unwrap();
        musclefem_io::scene::build_model(&scene, &locator, &mut MaterialLibrary::with_builtins())
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let slow = build(&VALID.replace("solver = \"implicit\"\n", ""));
    let Analysis::Implicit(settings) = &slow.analysis else {
        panic!("a 1 s pull is slow motion: {:?}", slow.solver_rationale);
    };
    assert!(settings.dynamics.is_none());
    let why = slow.solver_rationale.as_deref().unwrap();
    assert!(
        why.contains("implicit, quasi-static") && why.contains("615 times the 1.63e-3 s"),
        "{why}"
    );
    let fast = build(
        &VALID
            .replace("solver = \"implicit\"", "solver = \"auto\"")
            .replace("duration = 1.0", "duration = 1e-4"),
    );
    assert!(matches!(fast.analysis, Analysis::Explicit(_)));
    let viscous = build(&VALID.replace(
        "solver = \"implicit\"",
        "solver = \"explicit\"\nexplicit = { bulk_viscosity = true, shear_viscosity = 2e3 }",
    ));
    let Analysis::Explicit(settings) = &viscous.analysis else {
        panic!("the scene asks for explicit");
    };
    assert_eq!(settings.shear_viscosity, Some(2e3));
    assert!(settings.bulk_viscosity.is_some());
    let why = fast.solver_rationale.as_deref().unwrap();
    assert!(
        why.contains("explicit") && why.contains("(fast motion)"),
        "{why}"
    );
    // With interactions, slow motion keeps the inertia (Newmark).
    let text = std::fs::read_to_string(example("block_on_rigid_sphere.toml")).unwrap();
    let (scene, locator) = parse_scene(
        &text.replace("solver = \"implicit\"", "solver = \"auto\""),
        &example("block_on_rigid_sphere.toml"),
    )
    .unwrap();
    let contact =
        musclefem_io::scene::build_model(&scene, &locator, &mut MaterialLibrary::with_builtins())
            .unwrap();
    let Analysis::Implicit(settings) = &contact.analysis else {
        panic!("{:?}", contact.solver_rationale);
    };
    assert!(
        settings.dynamics.is_some(),
        "{:?}",
        contact.solver_rationale
    );
    // A named solver is taken as given, with no rationale.
    assert!(build(VALID).solver_rationale.is_none());
    let message = error_of(&VALID.replace("solver = \"implicit\"", "solver = \"fast\""));
    assert!(
        message.contains("use auto, explicit or implicit"),
        "{message}"
    );
}

/// `tangential` picks the cohesive interface's shear mode by name; a misspelt one is
/// named with the closest valid mode.
#[test]
fn cohesive_tangential_modes_are_read_by_name() {
    use musclefem_contact::TangentialMode;
    use musclefem_io::scene::InteractionModel;
    let path = example("bonded_blocks_peel.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let anchor = "failure_separation = 0.004";
    assert!(text.contains(anchor));
    for (name, mode) in [
        ("elastic", TangentialMode::Elastic),
        ("free-slide", TangentialMode::FreeSlide),
        ("smooth-slide", TangentialMode::SmoothSlide),
    ] {
        let edited = text.replace(anchor, &format!("{anchor}\ntangential = \"{name}\""));
        let (scene, locator) = parse_scene(&edited, &path).unwrap();
        let model = musclefem_io::scene::build_model(
            &scene,
            &locator,
            &mut MaterialLibrary::with_builtins(),
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        let InteractionModel::Cohesive(glue) = &model.interactions[0] else {
            panic!("{name}: not a cohesive interface");
        };
        assert_eq!(glue.law().tangential(), mode, "{name}");
    }
    let message =
        error_of(&text.replace(anchor, &format!("{anchor}\ntangential = \"smooth_slide\"")));
    assert!(
        message.contains("unknown tangential mode 'smooth_slide'")
            && message.contains("did you mean `smooth-slide`?")
            && message.contains("use elastic, free-slide or smooth-slide"),
        "{message}"
    );
}

/// `smooth_normals = true` makes a contact measure along the smooth normal field of the
/// main surface; the default is the closest point. A cohesive interface refuses the key,
/// and a misspelt one is named with the closest valid key.
#[test]
fn contact_smooth_normals_are_read_and_misspellings_suggested() {
    use musclefem_io::scene::InteractionModel;
    let path = example("block_on_rigid_sphere.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let anchor = "main = \"ball\"";
    assert!(text.contains(anchor));
    for (edit, smooth) in [
        (String::new(), false),
        ("\nsmooth_normals = false".to_string(), false),
        ("\nsmooth_normals = true".to_string(), true),
    ] {
        let edited = text.replace(anchor, &format!("{anchor}{edit}"));
        let (scene, locator) = parse_scene(&edited, &path).unwrap();
        let model = musclefem_io::scene::build_model(
            &scene,
            &locator,
            &mut MaterialLibrary::with_builtins(),
        )
        .unwrap_or_else(|e| panic!("{edit}: {e}"));
        let InteractionModel::Contact(contact) = &model.interactions[0] else {
            panic!("{edit}: not a contact");
        };
        assert_eq!(contact.smooth_normals(), smooth, "{edit}");
        assert_eq!(
            model.interactions[0]
                .describe()
                .contains("along smooth normals"),
            smooth
        );
    }
    let message = error_of(&text.replace(anchor, &format!("{anchor}\nsmooth_normal = true")));
    assert!(
        message.contains("smooth_normal") && message.contains("did you mean `smooth_normals`?"),
        "{message}"
    );
    let message = error_of(&text.replace(anchor, &format!("{anchor}\nsmooth_normals = 1")));
    assert!(message.contains("invalid type"), "{message}");
    let peel = std::fs::read_to_string(example("bonded_blocks_peel.toml")).unwrap();
    let cohesive = "failure_separation = 0.004";
    assert!(peel.contains(cohesive));
    let message = error_of(&peel.replace(cohesive, &format!("{cohesive}\nsmooth_normals = true")));
    assert!(
        message.contains("`smooth_normals` does not apply to kind = \"cohesive\""),
        "{message}"
    );
}
