//! A curved tube: the annular sector r ∈ [1, 2], θ ∈ [0, π/2], with the inlet on the cut
//! θ = 0 and the outlet on the cut θ = π/2. The exact potential is φ = 1 − θ/(π/2) (it is
//! harmonic, constant on the cuts, and its gradient e_θ/(r π/2) is parallel to the walls
//! r = const and z = const), so the fibers are circles: direction e_θ.
//!
//! Run with `--nocapture` for the convergence table: mean and max angle error for three
//! refinements of hex and tet meshes, and the observed order log₂(e_h / e_{h/2}).

mod common;

use common::{Cells, angle_degrees, annular_sector, circumferential, element_centres};
use musclefem_fibers::{FlowBoundary, FlowSettings, compute_fibers};

/// Mean and max angle between the computed fibers and e_θ at the element centres [°].
fn angle_errors(cells: Cells, divisions: [usize; 3]) -> (f64, f64, usize) {
    let mesh = annular_sector(cells, divisions);
    let boundary = FlowBoundary::from_names(&mesh, &["y0"], &["y1"]).unwrap();
    let field = compute_fibers(&mesh, &boundary, &FlowSettings::default()).unwrap();
    let errors: Vec<f64> = field
        .direction
        .iter()
        .zip(element_centres(&mesh))
        .map(|(d, x)| angle_degrees(*d, circumferential(x)))
        .collect();
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    let max = errors.iter().copied().fold(0.0, f64::max);
    (mean, max, errors.len())
}

#[test]
fn fibers_follow_the_circles_and_converge() {
    println!(
        "| cells | divisions (r, θ, z) | elements | mean error [°] | order | max error [°] | order |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|");
    for cells in Cells::ALL {
        let mut previous: Option<(f64, f64)> = None;
        let mut means = Vec::new();
        for k in [2, 4, 8] {
            let divisions = [2 * k, 6 * k, k];
            let (mean, max, count) = angle_errors(cells, divisions);
            let order = |now: f64, before: f64| (before / now).log2();
            let (mean_order, max_order) =
                previous.map_or((String::new(), String::new()), |(m, x)| {
                    (
                        format!("{:.2}", order(mean, m)),
                        format!("{:.2}", order(max, x)),
                    )
                });
            println!(
                "| {cells:?} | {divisions:?} | {count} | {mean:.4} | {mean_order} | {max:.4} | {max_order} |"
            );
            previous = Some((mean, max));
            means.push(mean);
        }
        // Each refinement reduces the mean error.
        assert!(
            means[1] < means[0] && means[2] < means[1],
            "{cells:?}: {means:?}"
        );
        // At the middle resolution the mean error is below one degree.
        assert!(means[1] < 1.0, "{cells:?}: mean {}°", means[1]);
    }
}
