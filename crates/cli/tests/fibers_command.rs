//! `musclefem fibers` end to end: meshes written as Gmsh .msh and Abaqus .inp files into a
//! temporary directory, the binary run on them, and its fibers.csv, fibers.png and report
//! checked against the exact flows (axial in a box, circles in a curved tube).

mod support;

use support::run::{musclefem, test_dir, text};

use std::path::Path;

use musclefem_core::mesh::generate::{TetOrder, box_of_tets, circumferential};
use musclefem_io::csv::read_table;
use nalgebra::Vector3;
use support::mesh_files::{
    CURVED_TUBE_DIVISIONS, abaqus_text, curved_tube, element_tag, gmsh_text,
};

const FIBERS_HEADER: &str = "element,cx,cy,cz,fx,fy,fz";
const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

/// Runs `musclefem fibers` from `inlet` to `outlet` into `out`, expects success and
/// returns stdout.
fn run_fibers(dir: &Path, mesh: &str, inlet: &str, outlet: &str, out: &str) -> String {
    let output = musclefem(
        dir,
        &[
            "fibers", "--mesh", mesh, "--inlet", inlet, "--outlet", outlet, "--out", out,
        ],
    );
    assert!(
        output.status.success(),
        "{mesh}: {}{}",
        text(&output.stdout),
        text(&output.stderr)
    );
    text(&output.stdout)
}

/// The rows of fibers.csv after checking its header exactly.
fn fiber_rows(path: &Path) -> Vec<Vec<f64>> {
    let content = std::fs::read_to_string(path).unwrap();
    assert_eq!(
        content.lines().next(),
        Some(FIBERS_HEADER),
        "{}",
        path.display()
    );
    read_table(path, FIBERS_HEADER).unwrap()
}

/// Width and height of a PNG from its IHDR chunk, after checking the signature.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        bytes.len() > 24,
        "{}: {} bytes",
        path.display(),
        bytes.len()
    );
    assert_eq!(&bytes[..8], PNG_SIGNATURE, "{}", path.display());
    assert_eq!(&bytes[12..16], b"IHDR", "{}", path.display());
    let width = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    let height = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
    (width, height)
}

/// The flux printed on the report line of region `name` of side `side` [m], after
/// checking its face count and share.
fn reported_flux(stdout: &str, side: &str, name: &str, faces: usize, share: &str) -> f64 {
    let prefix = format!("{side} '{name}': {faces} faces, flux ");
    let line = stdout
        .lines()
        .map(str::trim)
        .find(|l| l.starts_with(&prefix))
        .unwrap_or_else(|| panic!("no line '{prefix}…' in:\n{stdout}"));
    assert!(
        line.contains(&format!("({share} % of the {side} flux)")),
        "{line}"
    );
    line[prefix.len()..]
        .split_whitespace()
        .next()
        .and_then(|flux| flux.parse().ok())
        .unwrap_or_else(|| panic!("no flux in '{line}'"))
}

/// The Abaqus/CAE-style two-hex mesh of the io tests (part, instance, GENERATE sets),
/// from node set `left` (x = 0) to surface `right` (x = 2): both elements' fibers along
/// +x, labelled as in the file, the VTU with its fields, the PNG, and the flux of each end
/// (area/length = 1 m² / 2 m); an unknown set is named with the valid ones and nothing is
/// written.
#[test]
fn abaqus_part_instance_mesh_from_node_set_to_surface() {
    let dir = test_dir("musclefem-fibers", "part-instance");
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("../io/tests/meshes/part_instance.inp");
    let mesh = mesh.to_string_lossy();
    let stdout = run_fibers(&dir, &mesh, "left", "right", "f");
    let rows = fiber_rows(&dir.join("f/fibers.csv"));
    assert_eq!(rows.len(), 2);
    for (row, label) in rows.iter().zip([11.0, 12.0]) {
        assert_eq!(row[0], label);
        assert!((row[4] - 1.0).abs() < 1e-12 && row[5].abs() < 1e-12 && row[6].abs() < 1e-12);
    }
    let vtu = std::fs::read_to_string(dir.join("f/fibers.vtu")).unwrap();
    assert!(
        vtu.contains("Name=\"fiber_direction_reference\"") && vtu.contains("Name=\"potential\"")
    );
    let (width, height) = png_size(&dir.join("f/fibers.png"));
    assert!(width > 0 && height > 0);
    for (side, name) in [("inlet", "left"), ("outlet", "right")] {
        let flux = reported_flux(&stdout, side, name, 1, "100.00");
        assert!((flux - 0.5).abs() < 1e-6, "{side} '{name}': {flux}");
    }

    let bad = musclefem(
        &dir,
        &[
            "fibers", "--mesh", &mesh, "--inlet", "lft", "--outlet", "right", "--out", "g",
        ],
    );
    assert!(!bad.status.success());
    let stderr = text(&bad.stderr);
    assert!(
        stderr.contains("'lft'") && stderr.contains("'left'"),
        "{stderr}"
    );
    assert!(!dir.join("g/fibers.csv").exists());
}

/// Box of the axial tests: 30 mm along x, 10 mm by 10 mm, in tet4.
const BOX: [f64; 3] = [0.03, 0.01, 0.01];

/// A box of tets written as Gmsh .msh (physical surfaces "origin" and "insertion", the
/// faces x = 0 and x = 30 mm, and the physical volume "muscle") and as the same mesh in
/// Abaqus .inp ("origin" a *SURFACE, "insertion" an *NSET): both give one row per element,
/// labelled with the file's element tag, every fiber e_x to 1e-8, and the exact flux
/// area/length through both ends. An unknown inlet name fails, names the set and the
/// surfaces there are, and writes nothing.
#[test]
fn box_from_msh_and_inp_has_axial_fibers_with_file_tags() {
    let dir = test_dir("musclefem-fibers", "box");
    let mesh = box_of_tets(BOX, [6, 2, 2], TetOrder::Linear).unwrap();
    let ends = [("origin", "x0"), ("insertion", "x1")];
    std::fs::write(dir.join("box.msh"), gmsh_text(&mesh, &ends)).unwrap();
    std::fs::write(
        dir.join("box.inp"),
        abaqus_text(&mesh, &ends[..1], &ends[1..]),
    )
    .unwrap();
    let end_faces = mesh.surfaces["x0"].len();
    assert_eq!(end_faces, 8);
    let exact_flux = BOX[1] * BOX[2] / BOX[0];

    for file in ["box.msh", "box.inp"] {
        let out = format!("out-{file}");
        let stdout = run_fibers(&dir, file, "origin", "insertion", &out);
        let rows = fiber_rows(&dir.join(&out).join("fibers.csv"));
        assert_eq!(rows.len(), mesh.element_count(), "{file}");
        for (e, row) in rows.iter().enumerate() {
            assert_eq!(row[0], element_tag(e) as f64, "{file}: row {e}");
            let direction = Vector3::new(row[4], row[5], row[6]);
            assert!(
                (direction.norm() - 1.0).abs() < 1e-8 && (direction - Vector3::x()).norm() < 1e-8,
                "{file}: element {}: {direction}",
                row[0]
            );
        }
        let inlet = reported_flux(&stdout, "inlet", "origin", end_faces, "100.00");
        let outlet = reported_flux(&stdout, "outlet", "insertion", end_faces, "100.00");
        for flux in [inlet, outlet] {
            // Printed with 7 significant digits.
            assert!(
                (flux - exact_flux).abs() < 1e-6 * exact_flux,
                "{file}: {flux}"
            );
        }
        let (width, height) = png_size(&dir.join(&out).join("fibers.png"));
        assert!(width > 0 && height > 0);
    }

    let failed = musclefem(
        &dir,
        &[
            "fibers",
            "--mesh",
            "box.msh",
            "--inlet",
            "orign",
            "--outlet",
            "insertion",
            "--out",
            "never",
        ],
    );
    assert!(!failed.status.success());
    let stderr = text(&failed.stderr);
    assert!(
        stderr.contains("'orign'") && stderr.contains("'origin'") && stderr.contains("box.msh"),
        "{stderr}"
    );
    assert!(!dir.join("never").join("fibers.csv").exists());
    assert!(!dir.join("never").join("fibers.png").exists());
}

/// Mean angle allowed between the fibers and the circles [°].
const TUBE_MEAN_ANGLE: f64 = 1.0;

/// The curved tube (a quarter torus of rectangular section, hex8, Gmsh .msh) from its cut
/// θ = 0 to its cut θ = π/2: fibers.png is a PNG, and the fibers of fibers.csv follow the
/// circles about the torus axis with a mean angle error below 1°.
#[test]
fn curved_tube_fibers_follow_the_circles_and_draw_a_png() {
    let dir = test_dir("musclefem-fibers", "curved-tube");
    let mesh = curved_tube(CURVED_TUBE_DIVISIONS);
    let ends = [("origin", "y0"), ("insertion", "y1")];
    std::fs::write(dir.join("curved_tube.msh"), gmsh_text(&mesh, &ends)).unwrap();
    let stdout = run_fibers(&dir, "curved_tube.msh", "origin", "insertion", "out");
    println!("{stdout}");

    let (width, height) = png_size(&dir.join("out/fibers.png"));
    assert!(width > 0 && height > 0);
    println!("fibers.png: {width} x {height} px");

    let rows = fiber_rows(&dir.join("out/fibers.csv"));
    assert_eq!(rows.len(), mesh.element_count());
    let angles: Vec<f64> = rows
        .iter()
        .map(|row| {
            let centroid = Vector3::new(row[1], row[2], row[3]);
            let direction = Vector3::new(row[4], row[5], row[6]);
            assert!((direction.norm() - 1.0).abs() < 1e-12, "{direction}");
            let exact = circumferential(centroid);
            direction
                .cross(&exact)
                .norm()
                .atan2(direction.dot(&exact))
                .to_degrees()
        })
        .collect();
    let mean = angles.iter().sum::<f64>() / angles.len() as f64;
    let max = angles.iter().copied().fold(0.0, f64::max);
    println!(
        "curved tube {CURVED_TUBE_DIVISIONS:?}: {} elements, angle to the circles mean {mean:.4}°, max {max:.4}°",
        rows.len()
    );
    assert!(mean < TUBE_MEAN_ANGLE, "mean {mean}°");
}
