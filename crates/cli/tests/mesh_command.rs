//! `musclefem mesh` end to end, the README's "Bring your own muscle" path: the shipped
//! fusiform surface (examples/bring_your_own_muscle/fusiform.obj, millimetres) meshed in
//! tet10 through Gmsh, its fibers computed, the example scene checked and run, and a
//! small stretch of the mesh against the bar formula F = E δ / ∫ dz / A(z). Needs Gmsh's
//! Python package in target/python-venv (scripts/setup-gmsh.sh): skipped with a message
//! without it, unless MUSCLEFEM_REQUIRE_GMSH is set (scripts/test sets it).

mod support;

use std::f64::consts::PI;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use musclefem_io::csv::read_table;
use musclefem_io::mesh_import::read_mesh;
use support::run::{musclefem, test_dir, text};

/// The shipped surface: rings of 20 vertices at z = 0, 2.5, …, 50 mm with radii
/// r(z) = 4.5 + (8.75 − 4.5) sin²(πz/50) mm, flat ends; between rings every section is a
/// regular 20-gon whose circumradius is linear in z.
const LENGTH: f64 = 0.05;
const RADIUS_END: f64 = 4.5e-3;
const RADIUS_MID: f64 = 8.75e-3;
const RINGS: usize = 20;
const RING_VERTICES: f64 = 20.0;

/// The README's meshing command's options (after the surface).
const MESH_OPTIONS: [&str; 9] = [
    "--units",
    "mm",
    "--size",
    "4",
    "--element",
    "tet10",
    "--origin-plane",
    "0,0,0.5,0,0,-1",
    "--insertion-plane=0,0,49.5,0,0,1",
];

fn example_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/bring_your_own_muscle")
}

/// The Python with gmsh ($MUSCLEFEM_PYTHON or the project's venv), or None after printing
/// why the test is skipped (a panic when MUSCLEFEM_REQUIRE_GMSH is set).
fn gmsh_python(test: &str) -> Option<String> {
    let python = std::env::var("MUSCLEFEM_PYTHON").unwrap_or_else(|_| {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../target/python-venv/bin/python")
            .to_string_lossy()
            .into_owned()
    });
    let found = Command::new(&python)
        .args(["-c", "import gmsh"])
        .output()
        .is_ok_and(|o| o.status.success());
    if found {
        return Some(python);
    }
    assert!(
        std::env::var_os("MUSCLEFEM_REQUIRE_GMSH").is_none(),
        "{test}: Gmsh's Python package is required (MUSCLEFEM_REQUIRE_GMSH is set) but \
         {python} cannot import gmsh"
    );
    // Straight to stderr, past the test harness's capture, so that the skip shows.
    let _ = writeln!(
        std::io::stderr(),
        "SKIPPED {test}: {python} cannot import gmsh (scripts/setup-gmsh.sh installs it)"
    );
    None
}

/// Runs `musclefem ARGS` in `dir`, expects success and returns stdout.
fn run_ok(dir: &Path, args: &[&str]) -> String {
    let output = musclefem(dir, args);
    assert!(
        output.status.success(),
        "musclefem {args:?}: {}{}",
        text(&output.stdout),
        text(&output.stderr)
    );
    text(&output.stdout)
}

/// Meshes the shipped surface into `dir/OUT` with the README's options and `extra`, and
/// returns the command's stdout.
fn mesh_fusiform(dir: &Path, python: &str, out: &str, extra: &[&str]) -> String {
    std::fs::copy(example_dir().join("fusiform.obj"), dir.join("fusiform.obj")).unwrap();
    let mut args = vec!["mesh", "fusiform.obj"];
    args.extend(MESH_OPTIONS);
    args.extend(["--out", out, "--python", python]);
    args.extend(extra);
    run_ok(dir, &args)
}

/// Area of the regular 20-gon of circumradius r [m²].
fn polygon_area(r: f64) -> f64 {
    0.5 * RING_VERTICES * r * r * (2.0 * PI / RING_VERTICES).sin()
}

/// Circumradius of ring `i` [m].
fn ring_radius(i: usize) -> f64 {
    let z = LENGTH * i as f64 / RINGS as f64;
    RADIUS_END + (RADIUS_MID - RADIUS_END) * (PI * z / LENGTH).sin().powi(2)
}

/// Circumradius of the faceted surface's section at z [m]: linear between rings.
fn faceted_radius(z: f64) -> f64 {
    let h = LENGTH / RINGS as f64;
    let i = ((z / h) as usize).min(RINGS - 1);
    let w = z / h - i as f64;
    (1.0 - w) * ring_radius(i) + w * ring_radius(i + 1)
}

/// Volume [m³] and area [m²] of the faceted surface: frusta of 20-gon pyramids between
/// rings, V = h/3 (A₀ + A₁ + √(A₀A₁)), side = mean perimeter × slant height of the facets
/// (apothem change Δr cos(π/20)), plus both ends.
fn faceted_volume_and_area() -> (f64, f64) {
    let h = LENGTH / RINGS as f64;
    let perimeter = |r: f64| 2.0 * RING_VERTICES * r * (PI / RING_VERTICES).sin();
    let mut volume = 0.0;
    let mut area = 2.0 * polygon_area(RADIUS_END);
    for i in 0..RINGS {
        let (r0, r1) = (ring_radius(i), ring_radius(i + 1));
        let (a0, a1) = (polygon_area(r0), polygon_area(r1));
        volume += h / 3.0 * (a0 + a1 + (a0 * a1).sqrt());
        let slant = (h * h + ((r1 - r0) * (PI / RING_VERTICES).cos()).powi(2)).sqrt();
        area += 0.5 * (perimeter(r0) + perimeter(r1)) * slant;
    }
    (volume, area)
}

/// ∫₀ᴸ dz / A(z) [1/m] of the faceted surface (Simpson, 2000 intervals).
fn compliance_integral() -> f64 {
    let n = 2000;
    let h = LENGTH / n as f64;
    let f = |i: usize| 1.0 / polygon_area(faceted_radius(i as f64 * h));
    let inner: f64 = (1..n)
        .map(|i| if i % 2 == 1 { 4.0 * f(i) } else { 2.0 * f(i) })
        .sum();
    h / 3.0 * (f(0) + inner + f(n))
}

/// Area [m²] of a surface of a mesh, Σ |∫ n dA| over its faces.
fn surface_area(mesh: &musclefem_core::mesh::Mesh, name: &str) -> f64 {
    mesh.surface(name)
        .unwrap()
        .iter()
        .map(|&f| mesh.face_area_vector(f).unwrap().norm())
        .sum()
}

/// The column `name` of a run's history.csv.
fn history_column(run: &Path, name: &str) -> Vec<f64> {
    let content = std::fs::read_to_string(run.join("history.csv")).unwrap();
    let header: Vec<&str> = content.lines().next().unwrap().split(',').collect();
    let column = header
        .iter()
        .position(|h| *h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"));
    content
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(column).unwrap().parse().unwrap())
        .collect()
}

/// The path of the README: mesh (groups and areas against the polygon's, volume against
/// the surface's), fibers along the axis from origin to insertion, the example scene
/// checked and run to a plausible isometric force.
#[test]
fn the_shipped_surface_is_meshed_given_fibers_and_run() {
    let Some(python) = gmsh_python("the_shipped_surface_is_meshed_given_fibers_and_run") else {
        return;
    };
    let dir = test_dir("mesh_command", "readme_path");
    let (faceted_volume, faceted_area) = faceted_volume_and_area();
    let end = polygon_area(RADIUS_END);

    // On the surface's own triangles the mesh fills the faceted surface exactly (up to the
    // file's 1e-6 mm digits): the ends are the 20-gons' fans (20 faces each), the outer
    // surface every triangle.
    let report = mesh_fusiform(&dir, &python, "exact.msh", &["--keep-surface"]);
    assert!(
        report.contains("surface 'origin': 20 faces, area 6.2575"),
        "{report}"
    );
    let mesh = read_mesh(dir.join("exact.msh")).unwrap().mesh;
    for (name, faces, area) in [
        ("origin", 20, end),
        ("insertion", 20, end),
        ("outer", 840, faceted_area),
    ] {
        assert_eq!(mesh.surface(name).unwrap().len(), faces, "{name}");
        let measured = surface_area(&mesh, name);
        assert!(
            (measured - area).abs() < 2e-6 * area,
            "{name}: {measured} against {area} m²"
        );
    }
    let origin_z = mesh
        .node_set("origin")
        .unwrap()
        .iter()
        .map(|&n| mesh.nodes.position(n as usize).z.abs())
        .fold(0.0, f64::max);
    assert!(origin_z < 1e-12, "an origin node {origin_z} m off z = 0");
    let volume = mesh.total_volume().unwrap();
    assert!(
        (volume - faceted_volume).abs() < 2e-6 * faceted_volume,
        "volume {volume} against {faceted_volume} m³"
    );

    // Remeshed at 4 mm (the README's command): the ends' edges become chords of the
    // 20-gons, so their areas and the volume shrink a little.
    mesh_fusiform(&dir, &python, "fusiform.msh", &[]);
    let mesh = read_mesh(dir.join("fusiform.msh")).unwrap().mesh;
    assert_eq!(mesh.blocks.len(), 1);
    assert_eq!(mesh.blocks[0].name, "muscle");
    for name in ["origin", "insertion"] {
        let area = surface_area(&mesh, name);
        assert!(
            0.85 * end < area && area <= end,
            "{name}: {area} against {end} m²"
        );
    }
    let volume = mesh.total_volume().unwrap();
    assert!(
        0.95 * faceted_volume < volume && volume < faceted_volume,
        "volume {volume} against {faceted_volume} m³"
    );
    let outer = surface_area(&mesh, "outer");
    assert!(
        (outer - faceted_area).abs() < 0.03 * faceted_area,
        "outer {outer} against {faceted_area} m²"
    );

    // Fibers: from the origin (z = 0) to the insertion (z = 50 mm), along the axis.
    run_ok(
        &dir,
        &[
            "fibers",
            "--mesh",
            "fusiform.msh",
            "--inlet",
            "origin",
            "--outlet",
            "insertion",
            "--out",
            "fibers",
        ],
    );
    let rows = read_table(&dir.join("fibers/fibers.csv"), "element,cx,cy,cz,fx,fy,fz").unwrap();
    assert_eq!(rows.len(), mesh.element_count());
    let mean = rows
        .iter()
        .fold([0.0; 3], |m, r| [m[0] + r[4], m[1] + r[5], m[2] + r[6]]);
    let norm = (mean[0].powi(2) + mean[1].powi(2) + mean[2].powi(2)).sqrt();
    let mean_angle = (mean[2] / norm).acos().to_degrees();
    assert!(
        mean_angle < 1.0,
        "mean fiber {mean:?}: {mean_angle}° from +z"
    );
    let mut angles: Vec<f64> = rows
        .iter()
        .map(|r| r[6].clamp(-1.0, 1.0).acos().to_degrees())
        .collect();
    angles.sort_by(f64::total_cmp);
    let (p95, worst) = (angles[angles.len() * 95 / 100], angles[angles.len() - 1]);
    eprintln!("fibers: mean {mean_angle}° from +z, 95 % within {p95}°, worst {worst}°");
    // The surface's slope dr/dz is at most π (8.75 − 4.5) / 50 = 0.27, 15°; single
    // elements at the coarse ends' rims turn further.
    assert!(
        p95 < 20.0 && worst < 40.0,
        "95 % within {p95}°, worst {worst}°"
    );

    // The example scene: checked, then run; the reaction that holds the insertion points
    // along +z, against the muscle's pull.
    std::fs::copy(example_dir().join("scene.toml"), dir.join("scene.toml")).unwrap();
    run_ok(&dir, &["check", "scene.toml"]);
    run_ok(&dir, &["run", "scene.toml", "--out", "run"]);
    let force = *history_column(&dir.join("run"), "reaction_muscle.insertion.z_n")
        .last()
        .unwrap();
    eprintln!("isometric force {force} N");
    let isometric_stress = 692.8e3;
    let (low, high) = (
        isometric_stress * PI * RADIUS_END.powi(2),
        isometric_stress * PI * RADIUS_MID.powi(2),
    );
    assert!(
        low < force && force < high,
        "isometric force {force} N outside ({low}, {high}) N"
    );
}

/// A 0.1 % stretch of the meshed muscle in a neo-Hookean material with ν = 0 (no lateral
/// contraction, so the held ends do not matter) against the bar formula
/// F = E δ / ∫ dz / A(z), E = 2μ. Its field of plane sections, u = (0, 0, u(z)), meets
/// every end condition, so (minimum potential energy) it bounds the stiffness from above;
/// the finite elements' richer field comes in below it, within the 1-D theory's error
/// on this taper (slope ≤ 0.27).
#[test]
fn a_small_stretch_of_the_mesh_carries_the_bar_formula_force() {
    let Some(python) = gmsh_python("a_small_stretch_of_the_mesh_carries_the_bar_formula_force")
    else {
        return;
    };
    let dir = test_dir("mesh_command", "bar_formula");
    // On the surface's own triangles, whose sections are known exactly.
    mesh_fusiform(&dir, &python, "fusiform.msh", &["--keep-surface"]);
    let (mu, stretch) = (1.0e4, 5.0e-5);
    // ν = 0: K = 2μ/3, and the material's D = 2/K = 3/μ.
    let scene = format!(
        r#"schema_version = 1
[[materials]]
name = "elastic"
model = "neo-hookean"
parameters = {{ mu = {mu}, D = {d} }}

[[parts]]
name = "muscle"
material = "elastic"
element = "tet10"
density = 1000.0
mesh = {{ file = "fusiform.msh" }}

[[amplitudes]]
name = "ramp"
points = [[0.0, 0.0], [1.0, 1.0]]

[[displacements]]
part = "muscle"
nodes = "origin"
components = ["x", "y", "z"]

[[displacements]]
part = "muscle"
nodes = "insertion"
components = ["x", "y"]

[[displacements]]
part = "muscle"
nodes = "insertion"
components = ["z"]
value = {stretch}
amplitude = "ramp"

[step]
solver = "implicit"
duration = 1.0
output_interval = 0.5
implicit = {{ increments = 2 }}
"#,
        d = 3.0 / mu
    );
    std::fs::write(dir.join("stretch.toml"), scene).unwrap();
    run_ok(&dir, &["run", "stretch.toml", "--out", "run"]);
    let force = *history_column(&dir.join("run"), "reaction_muscle.insertion.z_n")
        .last()
        .unwrap();
    let expected = 2.0 * mu * stretch / compliance_integral();
    eprintln!("stretch: reaction {force} N, bar formula {expected} N");
    assert!(
        0.92 * expected < force && force < expected,
        "reaction {force} N, bar formula {expected} N"
    );
}

/// Refusals: a surface with a hole, an origin plane beyond the surface, and a Python
/// without gmsh, each named.
#[test]
fn open_surfaces_empty_groups_and_missing_gmsh_are_refused() {
    let dir = test_dir("mesh_command", "refusals");
    // Needs no gmsh: the Python is checked first.
    let output = musclefem(
        &dir,
        &[
            "mesh",
            "any.stl",
            "--size",
            "1",
            "--origin-plane",
            "0,0,0,0,0,1",
            "--insertion-plane",
            "0,0,1,0,0,-1",
            "--python",
            "/nonexistent/python",
        ],
    );
    assert!(!output.status.success());
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains("no Python with the gmsh package") && stderr.contains("setup-gmsh.sh"),
        "{stderr}"
    );

    let Some(python) = gmsh_python("open_surfaces_empty_groups_and_missing_gmsh_are_refused")
    else {
        return;
    };
    let obj = std::fs::read_to_string(example_dir().join("fusiform.obj")).unwrap();
    // Without its last face (a triangle of the insertion's end): 3 edges border one face.
    let last = obj.trim_end().rfind('\n').unwrap();
    std::fs::write(dir.join("open.obj"), &obj[..last]).unwrap();
    let mut args = vec!["mesh", "open.obj"];
    args.extend(MESH_OPTIONS);
    args.extend(["--python", &python]);
    let output = musclefem(&dir, &args);
    let stderr = text(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("open.obj: the surface is not closed: 3 edges border one triangle"),
        "{stderr}"
    );
    assert!(!dir.join("open.msh").exists());

    std::fs::write(dir.join("closed.obj"), &obj).unwrap();
    let output = musclefem(
        &dir,
        &[
            "mesh",
            "closed.obj",
            "--units",
            "mm",
            "--size",
            "8",
            "--origin-plane",
            "0,0,60,0,0,1",
            "--insertion-plane",
            "0,0,49.5,0,0,1",
            "--python",
            &python,
        ],
    );
    let stderr = text(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("origin: no boundary face selected by plane '0,0,60,0,0,1'")
            && stderr.contains("z 0 .. 50 [mm]"),
        "{stderr}"
    );
}

/// Boxes and point lists choose the same ends as the planes: on the surface's own
/// triangles, in tet4, the 20 triangles of each end's fan (centroids 2.96 mm from the
/// axis; the side's nearest are 0.83 mm off the end and 4.45 mm from the axis).
#[test]
fn boxes_and_points_choose_the_ends() {
    let Some(python) = gmsh_python("boxes_and_points_choose_the_ends") else {
        return;
    };
    let dir = test_dir("mesh_command", "boxes_and_points");
    std::fs::copy(example_dir().join("fusiform.obj"), dir.join("fusiform.obj")).unwrap();
    run_ok(
        &dir,
        &[
            "mesh",
            "fusiform.obj",
            "--units",
            "mm",
            "--size",
            "4",
            "--element",
            "tet4",
            "--keep-surface",
            "--origin-box",
            "-10,-10,-0.1,10,10,0.1",
            "--insertion-points",
            "0,0,50;0,0,49",
            "--insertion-radius",
            "4",
            "--out",
            "ends.msh",
            "--python",
            &python,
        ],
    );
    let imported = read_mesh(dir.join("ends.msh")).unwrap();
    assert_eq!(imported.element_types, ["tet4"]);
    let mesh = imported.mesh;
    let end = polygon_area(RADIUS_END);
    for (name, z) in [("origin", 0.0), ("insertion", LENGTH)] {
        assert_eq!(mesh.surface(name).unwrap().len(), 20, "{name}");
        let area = surface_area(&mesh, name);
        assert!(
            (area - end).abs() < 2e-6 * end,
            "{name}: {area} against {end} m²"
        );
        for &n in mesh.node_set(name).unwrap() {
            let p = mesh.nodes.position(n as usize);
            assert!((p.z - z).abs() < 1e-9, "{name}: node at z = {} m", p.z);
        }
    }
}
