//! A scene end to end, through the library as `musclefem run` drives it: read the TOML
//! (`examples/neo_hookean_cube_stretch.toml`), run it into a directory, read the last
//! VTU frame back, and compare what it holds with the closed form of the neo-Hookean
//! cube in uniaxial stress, which nothing in the program computes.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use musclefem_io::output::{ExistingResults, RunStart, read_frame};
use musclefem_io::scene::load_scene;
use musclefem_materials::MaterialLibrary;
use musclefem_studies::run_directory::{DirectoryRun, run_into_directory};

/// The example scene's material and load (`examples/neo_hookean_cube_stretch.toml`):
/// μ [Pa], D [1/Pa], edge [m], stretch of the pulled face.
const MU: f64 = 1e4;
const D: f64 = 2e-5;
const EDGE: f64 = 0.01;
const STRETCH: f64 = 1.5;

fn scene_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/neo_hookean_cube_stretch.toml")
}

fn test_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join("musclefem-end-to-end")
        .join(format!("{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Cauchy stresses (σ_axial, σ_lateral) [Pa] of W = μ/2 (Ī₁ − 3) + (J − 1)²/D with
/// F = diag(λ, λ_t, λ_t): σ = (μ/J) dev(b̄) + (2/D)(J − 1) I, b̄ = J^(−2/3) F Fᵀ.
fn cauchy_stresses(stretch: f64, lateral: f64) -> (f64, f64) {
    let j = stretch * lateral * lateral;
    let scale = MU / j * j.powf(-2.0 / 3.0);
    let pressure = 2.0 / D * (j - 1.0);
    let difference = stretch * stretch - lateral * lateral;
    (
        scale * 2.0 / 3.0 * difference + pressure,
        -scale / 3.0 * difference + pressure,
    )
}

/// The lateral stretch at which the lateral faces are free (σ_lateral = 0), by bisection.
fn free_lateral_stretch(stretch: f64) -> f64 {
    let (mut low, mut high) = (0.5, 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (low + high);
        // σ_lateral grows with the lateral stretch (the volume term dominates).
        if cauchy_stresses(stretch, mid).1 > 0.0 {
            high = mid;
        } else {
            low = mid;
        }
    }
    0.5 * (low + high)
}

#[test]
fn a_scene_runs_into_a_directory_whose_last_frame_is_the_closed_form_cube() {
    let scene = scene_path();
    let model = load_scene(&scene, &mut MaterialLibrary::with_builtins()).unwrap();
    let scene_text = std::fs::read_to_string(&scene).unwrap();
    let out = test_dir("neo_hookean_cube");
    let report = run_into_directory(
        &model,
        DirectoryRun {
            scene: &scene,
            scene_text: &scene_text,
            beside: &[],
            out: &out,
            start: RunStart::Fresh(ExistingResults::Replace),
            frame_instants: &[],
            log_header: String::new(),
            setup_time: Duration::ZERO,
            keep_checkpoint: false,
            interrupted: &AtomicBool::new(false),
            bar: None,
            companion: None,
        },
    )
    .unwrap();
    assert!(report.outcome.is_ok(), "{:?}", report.outcome.err());
    for file in ["result.pvd", "history.csv", "scene.toml", "run.log"] {
        assert!(out.join(file).is_file(), "no {file}");
    }
    assert_eq!(
        std::fs::read_to_string(out.join("scene.toml")).unwrap(),
        scene_text
    );
    assert!(!out.join("checkpoint.bin").exists());

    // Frames at t = 0, every 0.1 s and the end: 11, the last at λ = 1.5.
    let frames = report.directory.frames();
    assert_eq!(frames.len(), 11, "{frames:?}");
    let frame = read_frame(&out.join(&frames.last().unwrap().file)).unwrap();

    let lateral = free_lateral_stretch(STRETCH);
    let (axial, free) = cauchy_stresses(STRETCH, lateral);
    assert!(free.abs() < 1e-9 * axial, "{free}");
    eprintln!(
        "closed form at λ = {STRETCH}: lateral stretch {lateral:.6}, σ_xx {axial:.3} Pa \
         (J = {:.5})",
        STRETCH * lateral * lateral
    );

    // Homogeneous deformation: every node where F puts it.
    for (node, u) in frame.displacement.iter().enumerate() {
        let x = frame.mesh.nodes.position(node);
        let expected = [
            (STRETCH - 1.0) * x.x,
            (lateral - 1.0) * x.y,
            (lateral - 1.0) * x.z,
        ];
        for axis in 0..3 {
            assert!(
                (u[axis] - expected[axis]).abs() < 1e-9 * EDGE,
                "node {node}: u = {u:?}, closed form {expected:?}"
            );
        }
    }
    // Every element carries the closed form's Cauchy stress (xx, yy, zz, yz, xz, xy).
    let (_, components, stress) = frame
        .cell_arrays
        .iter()
        .find(|(name, _, _)| name == "cauchy_stress")
        .expect("a cauchy_stress cell array");
    assert_eq!(*components, 6);
    assert_eq!(stress.len(), 6 * frame.mesh.element_count());
    for (element, sigma) in stress.chunks(6).enumerate() {
        assert!(
            (sigma[0] - axial).abs() < 1e-6 * axial,
            "element {element}: σ_xx {} against {axial}",
            sigma[0]
        );
        for (k, value) in sigma.iter().enumerate().skip(1) {
            assert!(
                value.abs() < 1e-6 * axial,
                "element {element}: σ[{k}] {value}"
            );
        }
    }
    let von_mises = frame.cell_scalar("von_mises").unwrap();
    assert!(von_mises.iter().all(|v| (v - axial).abs() < 1e-6 * axial));
}
