//! Explicit element updates per second and peak memory of one technology, in one process:
//! `cargo run --release -p musclefem-core --example explicit_rate -- TECH DIVISIONS STEPS
//! THREADS [stable]` with TECH one of hex8_one_point, hex8_fbar, hex8_full, tet4, tet10
//! (neo-Hookean, Hill for F-bar, as in the `explicit_element_updates` bench); a fixed step
//! of 0.1 µs, or with `stable` the solver's stable step.
//!
//! Prints the element updates per second of wall time and of CPU time (the process's user
//! and system time, which a busy shared machine distorts less than wall time), the peak
//! resident memory (VmHWM) and a checksum of the end displacements' bits (to compare two
//! builds or thread counts). The memory per element is the difference of the peaks of two
//! runs with different DIVISIONS over the difference of their element counts: that
//! removes the program and libraries and counts everything that grows with the mesh (mesh,
//! kernel data, nodal arrays, history).

use std::collections::BTreeMap;
use std::time::Instant;

use musclefem_core::element::Technology;
use musclefem_core::mesh::generate::{TetOrder, box_of_hexes, box_of_tets};
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit};
use musclefem_core::solver::{Part, PrescribedDisplacement};
use musclefem_materials::{Amplitude, MaterialLibrary};

/// CPU time of the process (user + system) [s], from /proc/self/stat.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit(')')
        .next()
        .unwrap_or("")
        .split_whitespace()
        .collect();
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|s| s.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (ticks(11) + ticks(12)) / 100.0
}

/// Peak resident set size [bytes], from /proc/self/status.
fn peak_rss() -> usize {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<usize>().ok())
        .map_or(0, |kb| kb * 1024)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let tech = args.get(1).map_or("hex8_one_point", String::as_str);
    let divisions: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(20);
    let steps: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(200);
    let threads: usize = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(1);
    let side = 0.02;
    let mesh = match tech {
        "tet4" => box_of_tets([side; 3], [divisions; 3], TetOrder::Linear),
        "tet10" => box_of_tets([side; 3], [divisions; 3], TetOrder::Quadratic),
        _ => box_of_hexes([side; 3], [divisions; 3]),
    }
    .expect("mesh");
    let (technology, material) = match tech {
        "hex8_one_point" => (Technology::hex8_one_point(11_370.0), "neo-hookean"),
        "hex8_fbar" => (Technology::Hex8FBar, "hill"),
        "hex8_full" => (Technology::Hex8Full, "neo-hookean"),
        "tet4" => (Technology::Tet4, "neo-hookean"),
        "tet10" => (Technology::Tet10, "neo-hookean"),
        other => panic!("unknown technology {other}"),
    };
    let params: BTreeMap<String, f64> = if material == "hill" {
        BTreeMap::from([("n2".to_string(), 1.0)])
    } else {
        BTreeMap::new()
    };
    let material = MaterialLibrary::with_builtins()
        .create(material, &params)
        .expect("material");
    let parts = vec![Part {
        block: 0,
        technology,
        material,
        density: 1060.0,
    }];
    let prescribed = vec![
        PrescribedDisplacement {
            nodes: mesh.node_set("x0").unwrap().to_vec(),
            dof: 0,
            amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
        },
        PrescribedDisplacement {
            nodes: mesh.node_set("x1").unwrap().to_vec(),
            dof: 0,
            amplitude: Amplitude::ramp(1.0, 0.1).unwrap(),
        },
    ];
    // A fixed step of 0.1 µs, or with a fifth argument `stable` the solver's stable step
    // (then STEPS × 0.1 µs is the duration, and the acoustic moduli's refreshes set it).
    let stable = args.get(5).is_some_and(|a| a == "stable");
    let step = 1e-7;
    let mut settings = ExplicitSettings::new(steps as f64 * step);
    settings.fixed_time_step = (!stable).then_some(step);
    settings.history_interval = 1.0;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    let (cpu, wall) = (cpu_seconds(), Instant::now());
    let result = pool
        .install(|| run_explicit(&mesh, &parts, &prescribed.clone().into(), &settings))
        .expect("run");
    let (cpu, wall) = (cpu_seconds() - cpu, wall.elapsed().as_secs_f64());
    let updates = (result.steps * mesh.element_count()) as f64;
    // The bits of the end state, to compare two builds or thread counts.
    let checksum = result
        .displacement
        .iter()
        .flat_map(|u| u.iter())
        .fold(0u64, |hash, x| hash.rotate_left(5) ^ x.to_bits());
    println!(
        "{tech} {divisions}^3 ({} elements, {} nodes) {} steps on {threads} thread(s): \
         {:.2} M updates/s wall, {:.2} M updates/s per CPU second, peak RSS {} bytes, \
         displacement checksum {checksum:016x}",
        mesh.element_count(),
        mesh.node_count(),
        result.steps,
        updates / wall / 1e6,
        updates / cpu / 1e6,
        peak_rss(),
    );
}
