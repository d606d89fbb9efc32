//! Time per material-point update through the VUMAT and UMAT paths against the built-in
//! materials: the neo-Hookean (also as the C plugin plugins/neo_hookean_c and as the UMAT,
//! with its DDSDDE and with the host's finite differences) and the active Hill muscle
//! (n2 = 1), each against its VUMAT in examples/vumat, on one thread:
//! blocks of 512 points (an explicit chunk of 64 hex8 elements), 64 Ki points per
//! repetition, 15 repetitions, min and median in ns per point; then the same with the
//! tangent dP/dF (analytic for the built-in, central finite differences, 18 more one-point
//! calls per point, for the plugins). Builds the plugins with gfortran and cc first.
//!
//! cargo run --release -p musclefem-vumat --example update_timing

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;
use std::time::Instant;

use musclefem_materials::{
    Material, MaterialLibrary, PointBlock, PointResponse, Tangent, VoigtStress,
};
use musclefem_vumat::{FiberConvention, Prop, Subroutine, TangentSource, VumatBuild, build_plugin};
use nalgebra::{Matrix3, Vector3};

const POINTS: usize = 1 << 16;
const BLOCK: usize = 512;
const REPETITIONS: usize = 15;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The Hill VUMAT's props: the built-in's parameters in hill_vumat.f's order.
const HILL_PROPS: &str = "D=5e-9:1/Pa,b=15,c=379:Pa,A=4,lambda_pe=1,sigma0=7e5:Pa,alpha=10,\
                          beta=1000:Pa,lambda_opt=1.05,k=0.3,k_c=4,k_e=5,d=1.45,\
                          lambda_dot_min=-17:1/s,S=50:1/s,n1=0,n2=0,t0=0:s,t1=1e30:s";

/// Build examples/vumat/`file` as material `name` into `dir`.
fn vumat(dir: &Path, file: &str, name: &str, props: &str, initial: &[f64]) -> PathBuf {
    subroutine(
        dir,
        file,
        name,
        props,
        initial,
        Subroutine::Vumat,
        TangentSource::Ddsdde,
    )
}

/// Build examples/vumat/`file` as a `kind` subroutine, material `name`, into `dir`.
fn subroutine(
    dir: &Path,
    file: &str,
    name: &str,
    props: &str,
    initial: &[f64],
    kind: Subroutine,
    tangent: TangentSource,
) -> PathBuf {
    let fiber = match kind {
        Subroutine::Vumat => FiberConvention::Orientation,
        Subroutine::Umat => FiberConvention::None,
    };
    build_plugin(&VumatBuild {
        source: workspace().join("examples/vumat").join(file),
        name: name.into(),
        cmname: None,
        props: Prop::parse_list(props).unwrap(),
        nstatev: initial.len(),
        statev_initial: initial.to_vec(),
        fiber,
        out: dir.join(format!("lib{}.so", name.replace('-', "_"))),
        replace: true,
        subroutine: kind,
        tangent,
    })
    .unwrap_or_else(|e| panic!("{e}"))
    .library
}

/// The two VUMATs and the C plugin, built.
fn plugins() -> [PathBuf; 5] {
    let dir = workspace().join("target/vumat-timing");
    std::fs::create_dir_all(&dir).unwrap();
    let neo_hookean = vumat(
        &dir,
        "neo_hookean_vumat.f",
        "neo-hookean-vumat",
        "mu=11370:Pa,D=5e-9:1/Pa",
        &[],
    );
    let hill = vumat(
        &dir,
        "hill_vumat.f",
        "hill-vumat",
        HILL_PROPS,
        &[1.0, 1.0, 0.0],
    );
    let umat = |name: &str, tangent| {
        let props = "mu=11370:Pa,D=5e-9:1/Pa";
        let file = "neo_hookean_umat.f";
        subroutine(&dir, file, name, props, &[], Subroutine::Umat, tangent)
    };
    let umat_ddsdde = umat("neo-hookean-umat", TangentSource::Ddsdde);
    let umat_fd = umat("neo-hookean-umat-fd", TangentSource::FiniteDifference);
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
    [neo_hookean, hill, c, umat_ddsdde, umat_fd]
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
    let mut library = MaterialLibrary::with_builtins();
    for plugin in plugins() {
        library.load_plugin(&plugin).unwrap();
    }
    let create = |name: &str, n2: f64| {
        let given = if n2 > 0.0 {
            [("n2".to_string(), n2)].into_iter().collect()
        } else {
            Default::default()
        };
        library.create(name, &given).unwrap()
    };
    let materials: Vec<(&str, Arc<dyn Material>)> = vec![
        ("built-in neo-hookean (Rust)", create("neo-hookean", 0.0)),
        (
            "C plugin neo-hookean-c-plugin",
            create("neo-hookean-c-plugin", 0.0),
        ),
        (
            "VUMAT neo_hookean_vumat.f",
            create("neo-hookean-vumat", 0.0),
        ),
        (
            "UMAT neo_hookean_umat.f (DDSDDE)",
            create("neo-hookean-umat", 0.0),
        ),
        (
            "UMAT neo_hookean_umat.f (--tangent finite-difference)",
            create("neo-hookean-umat-fd", 0.0),
        ),
        ("built-in hill, n2 = 1 (Rust)", create("hill", 1.0)),
        ("VUMAT hill_vumat.f, n2 = 1", create("hill-vumat", 1.0)),
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
