//! Timing of the fiber computation on boxes of tet4 cells (the Kuhn split of a cube of
//! n³ cells into 6 n³ tets), inlet on x = 0, outlet on x = 1.
//!
//! ```text
//! cargo run --release -p musclefem-fibers --example fibers_bench [-- MAX_CELLS [amg|jacobi|both]]
//! ```
//!
//! Runs about 10⁴, 10⁵ and 10⁶ tets (those up to MAX_CELLS, default 10⁶ + 10⁵) once each
//! per preconditioner (default both: multigrid, then Jacobi) and prints, per run: cells,
//! the preconditioner, the time of the mesh generation (not part of the solve),
//! the setup (cells, faces, boundary, coefficients), the solve (correction sweeps, CG,
//! gradients, directions), linear solves, CG iterations, final residual, the flux
//! balance and cells per second of the whole computation. Wall times are of one run on a
//! shared machine.

use std::time::Instant;

use musclefem_fibers::{FlowBoundary, FlowSettings, Preconditioner, compute_fibers};
use musclefem_mesh::generate::{TetOrder, box_of_tets};

fn main() {
    let max_cells: f64 = std::env::args()
        .nth(1)
        .map_or(1.1e6, |a| a.parse().expect("MAX_CELLS: a number"));
    let preconditioners = match std::env::args().nth(2).as_deref() {
        None | Some("both") => vec![Preconditioner::AggregationMultigrid, Preconditioner::Jacobi],
        Some("amg") => vec![Preconditioner::AggregationMultigrid],
        Some("jacobi") => vec![Preconditioner::Jacobi],
        Some(other) => panic!("unknown preconditioner {other}: amg, jacobi or both"),
    };
    println!(
        "threads: {}, tolerance {:e}\n",
        rayon::current_num_threads(),
        FlowSettings::default().tolerance
    );
    println!(
        "| tets | preconditioner | mesh [s] | setup [s] | solve [s] | total [s] | solves | CG its | residual | (in − out)/in | cells/s |"
    );
    println!("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    // 6 n³ ≈ 1.04e4, 1.05e5, 9.98e5.
    for n in [12usize, 26, 55] {
        let cells = 6 * n * n * n;
        if cells as f64 > max_cells {
            continue;
        }
        let start = Instant::now();
        let mesh = box_of_tets([1.0, 1.0, 1.0], [n, n, n], TetOrder::Linear).expect("box");
        let mesh_time = start.elapsed().as_secs_f64();
        let boundary = FlowBoundary::from_names(&mesh, &["x0"], &["x1"]).expect("box faces");
        for &preconditioner in &preconditioners {
            let settings = FlowSettings {
                preconditioner,
                ..FlowSettings::default()
            };
            let start = Instant::now();
            let field = match compute_fibers(&mesh, &boundary, &settings) {
                Ok(field) => field,
                Err(e) => {
                    println!("| {cells} | {preconditioner:?} | failed: {e} |");
                    continue;
                }
            };
            let total = start.elapsed().as_secs_f64();
            println!(
                "| {cells} | {preconditioner:?} | {mesh_time:.2} | {:.2} | {:.2} | {total:.2} | {} | {} | {:.1e} | {:.1e} | {:.2e} |",
                field.setup_time.as_secs_f64(),
                field.solve_time.as_secs_f64(),
                field.linear_solves,
                field.linear_iterations,
                field.residual,
                (field.inlet_flux - field.outlet_flux) / field.inlet_flux,
                cells as f64 / total
            );
        }
    }
}
