//! Cook's membrane table: tip displacement of the nearly incompressible plane-strain panel
//! against mesh and element technology (the problem of `musclefem_core::verification::cooks_membrane`).
//!
//! ```text
//! cargo run --release -p musclefem-core --example cooks_membrane [-- MAX_DIVISIONS [POISSON]]
//! ```
//!
//! Runs every technology of `technologies` on 2, 4, 8, … up to MAX_DIVISIONS (default 32)
//! elements per side, prints a markdown table (tip u_y [mm], its ratio to the literature's
//! 6.89 mm, Newton iterations, load steps, unknowns, wall time) and writes it as CSV to
//! `target/cooks_membrane.csv`. Wall times are of one run on a shared machine: compare
//! them within one table only.

use std::fmt::Write as _;
use std::path::PathBuf;

use musclefem_core::verification::cooks_membrane::{
    LITERATURE_TIP_DISPLACEMENT, POISSON, solve, technologies,
};

/// Load steps (the first increment; cutting may add more).
const INCREMENTS: usize = 5;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let max_divisions: usize = args
        .get(1)
        .map_or(32, |a| a.parse().expect("MAX_DIVISIONS"));
    let poisson: f64 = args.get(2).map_or(POISSON, |a| a.parse().expect("POISSON"));
    let meshes: Vec<usize> = (1..)
        .map(|k| 1usize << k)
        .take_while(|&n| n <= max_divisions)
        .collect();
    println!(
        "Cook's membrane, plane strain, neo-Hookean E = 240.565 MPa, nu = {poisson}, \
         100 N shear, {INCREMENTS} load steps\n"
    );
    println!(
        "| element | n/side | unknowns | tip u_y [mm] | / 6.89 mm | Newton its | steps (cuts) | wall [s] |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    let mut csv = String::from(
        "element,divisions,unknowns,tip_uy_mm,ratio_to_literature,newton_iterations,steps,cuts,wall_s\n",
    );
    for (label, technology) in technologies(poisson) {
        for &n in &meshes {
            match solve(technology, n, poisson, INCREMENTS) {
                Ok(o) => {
                    let tip_mm = 1e3 * o.tip_displacement;
                    let ratio = o.tip_displacement / LITERATURE_TIP_DISPLACEMENT;
                    let wall = o.wall_time.as_secs_f64();
                    println!(
                        "| {label} | {n} | {} | {tip_mm:.4} | {ratio:.4} | {} | {} ({}) | {wall:.2} |",
                        o.unknowns, o.iterations, o.steps, o.cuts
                    );
                    writeln!(
                        csv,
                        "{label},{n},{},{tip_mm:.6},{ratio:.6},{},{},{},{wall:.3}",
                        o.unknowns, o.iterations, o.steps, o.cuts
                    )
                    .expect("write to a string");
                }
                Err(e) => {
                    println!("| {label} | {n} | | failed: {e} | | | | |");
                    writeln!(csv, "{label},{n},,,,,,,").expect("write to a string");
                }
            }
        }
    }
    let target = std::env::var_os("CARGO_TARGET_DIR").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target"),
        PathBuf::from,
    );
    let path = target.join("cooks_membrane.csv");
    match std::fs::write(&path, csv) {
        Ok(()) => println!("\nwritten to {}", path.display()),
        Err(e) => eprintln!("could not write {}: {e}", path.display()),
    }
}
