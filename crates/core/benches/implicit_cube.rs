//! Quasi-static implicit solves of a cube in uniaxial stretch
//! (`musclefem_core::verification::uniaxial_cube`): a compressible neo-Hookean cube
//! (μ = 10 kPa, K = 2/D = 100 kPa) of side 10 mm, symmetry on the x0, y0 and z0 faces,
//! the x1 face pulled along x to λ = 1.5 in 10 equal load steps, the lateral faces free.
//! One measurement is a whole `run_quasi_static`: set-up (kernels, sparsity pattern,
//! scatter maps), symbolic factorization, and every Newton iteration of the 10 steps
//! (material updates, element stiffness, assembly, numeric factorization, solves, line
//! search). Run with `cargo bench -p musclefem-core --bench implicit_cube`.
//!
//! Meshes of 10³, 20³ and 30³ F-bar hex8 (3 509, 26 019 and 85 529 unknowns). Criterion's
//! smallest sample (10 runs) with a short measurement time, so the 30³ case stays
//! bearable; the thread count is rayon's default (all cores).

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};

use musclefem_core::solver::implicit::run_quasi_static;
use musclefem_core::verification::uniaxial_cube::UniaxialCube;

/// Bulk modulus K = 2/D of the cube's neo-Hookean material [Pa] (D = 2e-5 1/Pa).
const BULK_MODULUS: f64 = 1e5;

fn implicit_cube(c: &mut Criterion) {
    let mut group = c.benchmark_group("implicit_cube");
    group.sample_size(10);
    for divisions in [10, 20, 30] {
        let cube = UniaxialCube {
            bulk_modulus: BULK_MODULUS,
            ..UniaxialCube::with_poisson(divisions, 0.3)
        };
        let model = cube.model();
        let (mesh, parts, loads) = (&model.mesh, &model.parts, &model.loads);
        let settings = cube.settings();
        group.measurement_time(Duration::from_secs(match divisions {
            10 => 5,
            20 => 20,
            _ => 60,
        }));
        // The last run's summary, printed when the case ran (criterion filters by name).
        let mut summary = None;
        group.bench_function(format!("{divisions}^3"), |b| {
            b.iter(|| {
                let result = run_quasi_static(mesh, parts, loads, &settings).unwrap();
                let iterations: Vec<usize> = result.steps.iter().map(|s| s.iterations).collect();
                summary = Some(format!(
                    "{divisions}^3 {:?}: {} unknowns, {} matrix entries, Newton \
                     iterations per step {iterations:?}, last factorization {:?}",
                    cube.technology,
                    result.equations,
                    result.matrix_entries,
                    result.steps.last().map(|s| s.factorization)
                ));
                result
            })
        });
        if let Some(summary) = summary {
            println!("{summary}");
        }
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_secs(1));
    targets = implicit_cube
}
criterion_main!(benches);
