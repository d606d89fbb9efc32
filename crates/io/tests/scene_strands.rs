//! `[[strands]]`: tendon strands read from a CSV file, their ends named by the labels of a
//! mesh file read with `shared_nodes = true`, one of them a node in no element carried
//! by a rigid tie (the knee's quadriceps strands and the patella, in small; the same
//! column as `crates/contact/tests/strands.rs`, now from a scene).
//!
//! A column of 1 × 1 × 4 hex8 (side A, length L) stands on z = 0 (held along z), every
//! node held laterally (uniaxial strain). Its four top corners are joined by strands to
//! the node P (label 999, in no element), D above the column's axis, which a rigid tie
//! raises by δ. Each strand's slack length is its initial length. In series with the
//! neo-Hookean column (σ_zz = μ λ^(−5/3) (2/3)(λ² − 1) + K (λ − 1)), the stretch λ solves
//! 4 f(ℓ) v/ℓ = σ_zz(λ) A², v = L + D + δ − λL, ℓ = √(A²/2 + v²).

use std::fmt::Write as _;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use musclefem_contact::ToeLinearLaw;
use musclefem_core::solver::observer::{Observer, Record, Snapshot};
use musclefem_io::scene::{InteractionModel, load_scene};
use musclefem_materials::MaterialLibrary;

const A: f64 = 0.01;
const L: f64 = 0.02;
const D: f64 = 0.05;
const DELTA: f64 = 0.008;
const MU: f64 = 1e4;
const BULK: f64 = 1e5;
const STRAIN_STIFFNESS: f64 = 5.0;
const TOE_STRAIN: f64 = 0.03;
/// The label of the column's first node (labels are not indices).
const FIRST_LABEL: usize = 101;
/// P's label.
const P: usize = 999;

/// The column's mesh (labels from [`FIRST_LABEL`], P last) with the node sets BASE
/// (z = 0), COLUMN (every node of an element), TOP (z = L) and TIP (P).
fn deck() -> String {
    let label = |i: usize, j: usize, k: usize| FIRST_LABEL + i + 2 * j + 4 * k;
    let mut text = String::from("*NODE\n");
    for k in 0..=4 {
        for j in 0..2 {
            for i in 0..2 {
                let (x, y, z) = (A * i as f64, A * j as f64, L * k as f64 / 4.0);
                let _ = writeln!(text, "{}, {x}, {y}, {z}", label(i, j, k));
            }
        }
    }
    let _ = writeln!(text, "{P}, {}, {}, {}", 0.5 * A, 0.5 * A, L + D);
    text.push_str("*ELEMENT, TYPE=C3D8, ELSET=COLUMN\n");
    for k in 0..4 {
        let corner = |i, j, kk| label(i, j, kk);
        let _ = writeln!(
            text,
            "{}, {}, {}, {}, {}, {}, {}, {}, {}",
            k + 1,
            corner(0, 0, k),
            corner(1, 0, k),
            corner(1, 1, k),
            corner(0, 1, k),
            corner(0, 0, k + 1),
            corner(1, 0, k + 1),
            corner(1, 1, k + 1),
            corner(0, 1, k + 1)
        );
    }
    let set = |name: &str, labels: Vec<usize>| {
        let list: Vec<String> = labels.iter().map(usize::to_string).collect();
        format!("*NSET, NSET={name}\n{}\n", list.join(", "))
    };
    text.push_str(&set("BASE", (0..4).map(|n| FIRST_LABEL + n).collect()));
    text.push_str(&set("COLUMN", (0..20).map(|n| FIRST_LABEL + n).collect()));
    text.push_str(&set("TOP", (16..20).map(|n| FIRST_LABEL + n).collect()));
    text.push_str(&set("TIP", vec![P]));
    text
}

/// Each top corner to P, its slack length its initial length.
fn strands_csv() -> String {
    let r = A / 2f64.sqrt();
    let slack = (r * r + D * D).sqrt();
    let mut text = String::from("node_a,node_b,slack_length,strain_stiffness,toe_strain\n");
    for n in 16..20 {
        let _ = writeln!(
            text,
            "{},{P},{slack:?},{STRAIN_STIFFNESS},{TOE_STRAIN}",
            FIRST_LABEL + n
        );
    }
    text
}

/// The scene with `shared` for the part's `shared_nodes` and `strands` as its strands
/// table.
fn scene(shared: bool, strands: &str) -> String {
    format!(
        r#"schema_version = 1

[[materials]]
name = "column"
model = "neo-hookean"
parameters = {{ mu = {MU:?}, D = {:?} }}

[[parts]]
name = "column"
material = "column"
element = "hex8-fbar"
density = 1000.0
mesh = {{ file = "column.inp", shared_nodes = {shared} }}

[[amplitudes]]
name = "ramp"
points = [[0.0, 0.0], [1.0, 1.0]]

[[displacements]]
part = "column"
nodes = "BASE"
components = ["z"]

[[displacements]]
part = "column"
nodes = "COLUMN"
components = ["x", "y"]

[[rigid_ties]]
name = "patella"
part = "column"
nodes = "TIP"
translation = [0.0, 0.0, {DELTA:?}]
translation_amplitude = "ramp"

{strands}

[step]
solver = "implicit"
duration = 1.0
implicit = {{ increments = 8 }}

[output]
frames = false
"#,
        2.0 / BULK
    )
}

const STRANDS: &str =
    "[[strands]]\nname = \"quadriceps\"\npart = \"column\"\nfile = \"strands.csv\"\n";

/// A directory holding the column's files and `scene` as `scene.toml`.
fn directory(name: &str, scene: &str, strands: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "musclefem-scene-strands-{name}-{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("column.inp"), deck()).unwrap();
    std::fs::write(dir.join("strands.csv"), strands).unwrap();
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    dir
}

fn load(dir: &Path) -> Result<musclefem_io::scene::Model, String> {
    load_scene(
        &dir.join("scene.toml"),
        &mut MaterialLibrary::with_builtins(),
    )
    .map_err(|e| e.to_string())
}

/// The stretch λ of the column in series with the strands, by bisection.
fn closed_form_stretch() -> f64 {
    let law = ToeLinearLaw {
        strain_stiffness: STRAIN_STIFFNESS,
        toe_strain: TOE_STRAIN,
    };
    let r = A / 2f64.sqrt();
    let slack = (r * r + D * D).sqrt();
    let imbalance = |stretch: f64| {
        let v = L + D + DELTA - stretch * L;
        let length = (r * r + v * v).sqrt();
        let pull = 4.0 * law.force(length / slack - 1.0) * v / length;
        let stress = MU * stretch.powf(-5.0 / 3.0) * (2.0 / 3.0) * (stretch * stretch - 1.0)
            + BULK * (stretch - 1.0);
        pull - stress * A * A
    };
    let (mut low, mut high) = (1.0, 1.0 + DELTA / L);
    for _ in 0..200 {
        let middle = 0.5 * (low + high);
        if imbalance(middle) > 0.0 {
            low = middle;
        } else {
            high = middle;
        }
    }
    0.5 * (low + high)
}

/// The last record's tie reaction and strands' resultant.
#[derive(Default)]
struct Last {
    tie_force: Option<nalgebra::Vector3<f64>>,
    strands_force: Option<nalgebra::Vector3<f64>>,
}

impl Observer for Last {
    fn record(&mut self, record: &Record, _snapshot: &Snapshot) -> ControlFlow<()> {
        self.tie_force = record.rigid_reactions().first().map(|r| r.force);
        self.strands_force = record.interactions().first().map(|i| i.force);
        ControlFlow::Continue(())
    }
}

#[test]
fn strands_from_a_scene_pull_the_column_through_a_node_in_no_element() {
    let dir = directory("pull", &scene(true, STRANDS), &strands_csv());
    let model = load(&dir).unwrap();
    let [InteractionModel::Strands(strands)] = model.interactions.as_slice() else {
        panic!("one strands interaction expected");
    };
    assert_eq!(strands.strands().len(), 4);
    println!("{}", model.interactions[0].describe());
    // P keeps its label's place: the file's 21st node, after the column's 20.
    assert_eq!(model.mesh.node_count(), 21);
    assert!(strands.strands().iter().all(|s| s.node_b == 20));

    let mut last = Last::default();
    let outcome = model.run(&mut last).expect("the pulled column converges");
    let displacement = outcome.displacement();
    let top = model.mesh.node_set("column.TOP").unwrap();
    let rise = displacement[top[0] as usize].z;
    let (fe, exact) = (1.0 + rise / L, closed_form_stretch());
    let error = (fe - exact).abs() / (exact - 1.0);
    let (tie, pull) = (last.tie_force.unwrap(), last.strands_force.unwrap());
    println!(
        "λ = {fe:.12} (closed form {exact:.12}, {error:.1e} of the strain); tie {tie:?} N, \
         strands {pull:?} N"
    );
    assert!(error < 1e-9, "stretch {fe} against {exact}");
    // The tie carries what the strands pull, and P is held by nothing else.
    assert!(
        (tie - pull).norm() < 1e-9 * pull.norm(),
        "{tie:?} vs {pull:?}"
    );
    assert!(pull.z > 0.0);
}

#[test]
fn strands_on_a_part_that_does_not_share_its_file_are_refused() {
    // Without `shared_nodes` a part keeps only its elements' nodes: P is not in it.
    let unshared = scene(false, STRANDS);
    let dir = directory("unshared", &unshared, &strands_csv());
    let message = load(&dir).unwrap_err();
    assert!(message.contains("has no node set 'TIP'"), "{message}");
    let tie = unshared.find("[[rigid_ties]]").unwrap();
    let untied = format!(
        "{}{}",
        &unshared[..tie],
        &unshared[unshared.find("[[strands]]").unwrap()..]
    );
    let dir = directory("unshared-untied", &untied, &strands_csv());
    let message = load(&dir).unwrap_err();
    assert!(
        message.contains("part 'column' does not share its mesh file's nodes"),
        "{message}"
    );
}

#[test]
fn a_strand_to_a_label_the_file_lacks_names_the_csv_line() {
    let text = strands_csv().replace(&format!(",{P},"), ",998,");
    let dir = directory("label", &scene(true, STRANDS), &text);
    let message = load(&dir).unwrap_err();
    assert!(message.contains("strands.csv' line 2"), "{message}");
    assert!(message.contains("node 998 is not a node"), "{message}");
}

#[test]
fn a_strand_with_no_slack_length_names_the_csv_line() {
    let mut lines: Vec<String> = strands_csv().lines().map(str::to_string).collect();
    lines[3] = format!("{},{P},0,{STRAIN_STIFFNESS},{TOE_STRAIN}", FIRST_LABEL + 18);
    let dir = directory("slack", &scene(true, STRANDS), &(lines.join("\n") + "\n"));
    let message = load(&dir).unwrap_err();
    assert!(message.contains("strands.csv' line 4"), "{message}");
    assert!(
        message.contains("slack length 0 m must be positive"),
        "{message}"
    );
}
