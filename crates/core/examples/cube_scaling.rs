//! The implicit cube of issue #36 with a chosen linear solver, for timing and peak-memory
//! measurements (`/usr/bin/time -v`): a neo-Hookean cube (μ = 10 kPa, Poisson's ratio ν)
//! of side 10 mm, n³ F-bar hex8, symmetry on x0, y0, z0, x1 pulled to λ = 1.5 in 10 steps
//! (`musclefem_core::verification::uniaxial_cube`). `musclefem bench --problem scaling`
//! times the same cubes side by side and charts them.
//!
//! `cargo run --release -p musclefem-core --example cube_scaling -- 20 0.3 amg_cg`
//! (solvers: direct, amg_cg, amg_cg_every: a numeric set-up for every tangent;
//! an optional fourth argument is AMG-CG's tolerance, a fifth `exact` turns Newton's
//! forcing term and the extrapolated first guess off, `noextrapolate` only the latter). Prints one line
//! of `key=value`.

use std::time::Instant;

use musclefem_core::solver::amg_cg::{HierarchyReuse, LinearSolver};
use musclefem_core::solver::implicit::run_quasi_static;
use musclefem_core::verification::uniaxial_cube::UniaxialCube;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map_or(10, |a| a.parse().expect("divisions"));
    let nu: f64 = args
        .get(2)
        .map_or(0.3, |a| a.parse().expect("Poisson's ratio"));
    let solver = args.get(3).map_or("direct", |s| s.as_str());
    let tolerance: f64 = args.get(4).map_or(1e-8, |a| a.parse().expect("tolerance"));
    let cube = UniaxialCube::with_poisson(n, nu);
    let model = cube.model();
    let mut settings = cube.settings();
    settings.amg_cg.tolerance = tolerance;
    if args.get(5).is_some_and(|a| a == "exact") {
        settings.forcing = None;
        settings.extrapolate = false;
    }
    if args.get(5).is_some_and(|a| a == "noextrapolate") {
        settings.extrapolate = false;
    }
    match solver {
        "direct" => {}
        "amg_cg" => settings.linear_solver = LinearSolver::AmgCg,
        "amg_cg_every" => {
            settings.linear_solver = LinearSolver::AmgCg;
            settings.amg_cg.reuse = HierarchyReuse::EveryTangent;
        }
        other => panic!("unknown solver {other}"),
    }
    let start = Instant::now();
    let result = run_quasi_static(&model.mesh, &model.parts, &model.loads, &settings).unwrap();
    let seconds = start.elapsed().as_secs_f64();
    let iterations: usize = result.steps.iter().map(|s| s.iterations).sum();
    let s = &result.linear_solves;
    let force = result.history.last().unwrap().reactions[0];
    println!(
        "n={n} nu={nu} solver={solver} unknowns={} seconds={seconds:.3} newton={iterations} \
         solves={} amg_solves={} cg_per_solve={:.1} amg_failures={} factorizations={} \
         amg_setup={:.2} amg_cg={:.2} numeric={:.2} levels={:?} complexity={:.2} \
         force={force:.15e} threads={}",
        result.equations,
        s.solves,
        s.amg.solves,
        s.amg.iterations as f64 / s.amg.solves.max(1) as f64,
        s.amg.failures,
        s.numeric_factorizations,
        s.amg.setup_seconds,
        s.amg.solve_seconds,
        s.numeric_seconds,
        s.amg.levels,
        s.amg.operator_complexity,
        rayon::current_num_threads(),
    );
    // FNV-1a of every displacement component's bits: equal on 1 and 2 threads.
    let checksum = result
        .displacement
        .iter()
        .flat_map(|u| u.iter().map(|v| v.to_bits()))
        .fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ b).wrapping_mul(0x100_0000_01b3)
        });
    println!("  displacement_checksum={checksum:016x}");
    let e = &result.evaluation_times;
    println!(
        "  evaluations={} stiffness_builds={} elements={:.2} (stiffness {:.2}) assembly={:.2} \
         symbolic={:.2} numeric={:.2} substitution={:.2} krylov_solves={} krylov_iterations={}",
        e.evaluations,
        e.stiffness_builds,
        e.element_seconds,
        e.stiffness_seconds,
        e.assembly_seconds,
        s.symbolic_seconds,
        s.numeric_seconds,
        s.substitution_seconds,
        s.krylov_solves,
        s.krylov_iterations
    );
    for reason in &s.amg.failure_reasons {
        println!("  amg failure: {reason}");
    }
}
