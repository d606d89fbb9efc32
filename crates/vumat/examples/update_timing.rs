//! Time per material-point update through the VUMAT path against the built-in
//! neo-Hookean and the C plugin of the same model (plugins/neo_hookean_c), on one thread:
//! blocks of 512 points (an explicit chunk of 64 hex8 elements), 64 Ki points per
//! repetition, 15 repetitions, min and median in ns per point; then the same with the
//! tangent dP/dF (analytic for the built-in, central finite differences, 18 more one-point
//! calls per point, for the plugins). Builds both plugins with gfortran and cc first.
//!
//! cargo run --release -p musclefem-vumat --example update_timing

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;
use std::time::Instant;

use musclefem_materials::{
    Material, MaterialLibrary, PointBlock, PointResponse, Tangent, VoigtStress,
};
use musclefem_vumat::{FiberConvention, Prop, VumatBuild, build_plugin};
use nalgebra::{Matrix3, Vector3};

const POINTS: usize = 1 << 16;
const BLOCK: usize = 512;
const REPETITIONS: usize = 15;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn plugins() -> (PathBuf, PathBuf) {
    let dir = workspace().join("target/vumat-timing");
    std::fs::create_dir_all(&dir).unwrap();
    let vumat = build_plugin(&VumatBuild {
        source: workspace().join("examples/vumat/neo_hookean_vumat.f"),
        name: "neo-hookean-vumat".into(),
        cmname: None,
        props: Prop::parse_list("mu=11370:Pa,D=5e-9:1/Pa").unwrap(),
        nstatev: 0,
        statev_initial: Vec::new(),
        fiber: FiberConvention::None,
        out: dir.join("libneo_hookean_vumat.so"),
        replace: true,
    })
    .unwrap_or_else(|e| panic!("{e}"))
    .library;
    let c = dir.join("libneo_hookean_c.so");
    let status = Command::new(std::env::var("CC").unwrap_or_else(|_| "cc".into()))
        .args([
            "-shared",
            "-fPIC",
            "-O2",
            "-ffp-contract=off",
            "-std=c11",
            "-I",
        ])
        .arg(workspace().join("crates/materials/include"))
        .arg(workspace().join("plugins/neo_hookean_c/neo_hookean.c"))
        .arg("-o")
        .arg(&c)
        .arg("-lm")
        .status()
        .unwrap();
    assert!(status.success());
    (vumat, c)
}

/// F_old, F_new and the fiber of every point.
struct Inputs {
    f_old: Vec<Matrix3<f64>>,
    f_new: Vec<Matrix3<f64>>,
    fiber: Vec<Vector3<f64>>,
}

/// F near the identity with a stretch along a varying direction, and a small step.
fn inputs() -> Inputs {
    let mut f_old = Vec::with_capacity(POINTS);
    let mut f_new = Vec::with_capacity(POINTS);
    let mut fiber = Vec::with_capacity(POINTS);
    for i in 0..POINTS {
        let s = (i as f64 * 0.618_034).fract();
        let a = Vector3::new(1.0, 0.2 * s, -0.1 * s).normalize();
        let stretch = 1.0 + 0.1 * s;
        let lateral = 1.0 / stretch.sqrt();
        let f = Matrix3::new(
            stretch,
            0.01 * s,
            0.0,
            0.0,
            lateral,
            0.005,
            0.0,
            0.0,
            lateral,
        );
        f_old.push(f);
        f_new.push(f * (Matrix3::identity() + a * a.transpose() * 2.5e-6));
        fiber.push(a);
    }
    Inputs {
        f_old,
        f_new,
        fiber,
    }
}

/// Nanoseconds per point of each repetition, sorted.
fn time(material: &dyn Material, with_tangent: bool) -> Vec<f64> {
    let Inputs {
        f_old,
        f_new,
        fiber,
    } = inputs();
    let state = material.initial_state(POINTS);
    let nstate = material.state_count();
    let mut stress = vec![VoigtStress::zeros(); BLOCK];
    let mut state_new = vec![0.0; BLOCK * nstate];
    let mut tangent = vec![Tangent::zeros(); BLOCK];
    let mut times: Vec<f64> = (0..REPETITIONS)
        .map(|_| {
            let start = Instant::now();
            for b in (0..POINTS).step_by(BLOCK) {
                let block = PointBlock {
                    time: 0.1,
                    dt: 1e-4,
                    deformation_gradient_old: &f_old[b..b + BLOCK],
                    deformation_gradient_new: &f_new[b..b + BLOCK],
                    fiber_direction: &fiber[b..b + BLOCK],
                    state_old: &state[b * nstate..(b + BLOCK) * nstate],
                };
                let mut response = PointResponse {
                    cauchy_stress: &mut stress,
                    state_new: &mut state_new,
                    tangent: with_tangent.then_some(&mut tangent[..]),
                };
                material.update(&block, &mut response).unwrap();
            }
            start.elapsed().as_secs_f64() * 1e9 / POINTS as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times
}

fn main() {
    let (vumat, c) = plugins();
    let mut library = MaterialLibrary::with_builtins();
    library.load_plugin(&vumat).unwrap();
    library.load_plugin(&c).unwrap();
    let given = Default::default();
    let materials: Vec<(&str, Arc<dyn Material>)> = vec![
        (
            "built-in neo-hookean (Rust)",
            library.create("neo-hookean", &given).unwrap(),
        ),
        (
            "C plugin neo-hookean-c-plugin",
            library.create("neo-hookean-c-plugin", &given).unwrap(),
        ),
        (
            "VUMAT neo_hookean_vumat.f",
            library.create("neo-hookean-vumat", &given).unwrap(),
        ),
    ];
    println!(
        "ns per material-point update, one thread, blocks of {BLOCK}, {POINTS} points, \
         {REPETITIONS} repetitions\n"
    );
    println!("| material | stress: min | median | stress + tangent: min | median |");
    println!("|---|---|---|---|---|");
    for (label, material) in &materials {
        let stress = time(&**material, false);
        let tangent = time(&**material, true);
        println!(
            "| {label} | {:.0} | {:.0} | {:.0} | {:.0} |",
            stress[0],
            stress[REPETITIONS / 2],
            tangent[0],
            tangent[REPETITIONS / 2]
        );
    }
}
