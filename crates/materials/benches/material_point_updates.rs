//! Material point updates per second, neo-Hookean and Hill, on one thread and on two
//! (rayon, blocks of 1024 points, small enough that the checks and the update of a block
//! share the L2 cache). Run with `cargo bench -p musclefem-materials`.
//! Criterion reports the throughput in elements (= material points) per second.

use std::collections::BTreeMap;
use std::sync::Arc;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use musclefem_materials::{Material, MaterialLibrary, PointBlock, PointResponse, VoigtStress};

const POINTS: usize = 1 << 16;
const BATCH: usize = 1024;

/// Inputs of a realistic step: F near identity with stretch along the fiber, an active
/// Hill state in the middle of an isometric-to-lengthening transition.
struct Inputs {
    f_old: Vec<Matrix3<f64>>,
    f_new: Vec<Matrix3<f64>>,
    fiber: Vec<Vector3<f64>>,
    state: Vec<f64>,
}

fn inputs(material: &dyn Material) -> Inputs {
    let mut f_old = Vec::with_capacity(POINTS);
    let mut f_new = Vec::with_capacity(POINTS);
    let mut fiber = Vec::with_capacity(POINTS);
    for i in 0..POINTS {
        let s = (i as f64 * 0.618_034).fract();
        let a = Vector3::new(1.0, 0.2 * s, -0.1 * s).normalize();
        let stretch = 1.0 + 0.1 * s;
        let f = Matrix3::new(
            stretch,
            0.01 * s,
            0.0,
            0.0,
            1.0 / stretch.sqrt(),
            0.005,
            0.0,
            0.0,
            1.0 / stretch.sqrt(),
        );
        f_old.push(f);
        f_new.push(f * (Matrix3::identity() + a * a.transpose() * 2.5e-6));
        fiber.push(a);
    }
    // Hill state (λ_m, λ_s, σ_SEE) consistent with F_old: an SEE stretched to λ_s = 1.6
    // and λ_m from the length relation (1 + k) λ̄_f = λ_m + k λ_s.
    let mut state = material.initial_state(POINTS);
    if material.state_count() == 3 {
        for (point, (f, a)) in state.chunks_exact_mut(3).zip(f_old.iter().zip(&fiber)) {
            let fiber_stretch = (f * a).norm() / f.determinant().cbrt();
            let lambda_s = 1.6;
            point.copy_from_slice(&[
                1.3 * fiber_stretch - 0.3 * lambda_s,
                lambda_s,
                1e3 * ((10.0f64 * 0.6).exp() - 1.0),
            ]);
        }
    }
    Inputs {
        f_old,
        f_new,
        fiber,
        state,
    }
}

fn update_batch(
    material: &dyn Material,
    inputs: &Inputs,
    range: std::ops::Range<usize>,
    stress: &mut [VoigtStress],
    state_new: &mut [f64],
) {
    let n = material.state_count();
    let block = PointBlock {
        time: 0.6,
        dt: 1e-6,
        deformation_gradient_old: &inputs.f_old[range.clone()],
        deformation_gradient_new: &inputs.f_new[range.clone()],
        fiber_direction: &inputs.fiber[range.clone()],
        state_old: &inputs.state[range.start * n..range.end * n],
    };
    let mut response = PointResponse {
        cauchy_stress: stress,
        state_new,
        tangent: None,
    };
    material.update(&block, &mut response).expect("valid block");
}

fn bench_material(c: &mut Criterion, name: &str, material: Arc<dyn Material>) {
    let inputs = inputs(material.as_ref());
    let n = material.state_count();
    let mut stress = vec![VoigtStress::zeros(); POINTS];
    let mut state_new = vec![0.0; POINTS * n];
    let mut group = c.benchmark_group(format!("material_point_update/{name}"));
    group.throughput(Throughput::Elements(POINTS as u64));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool");
        group.bench_function(format!("{threads}_thread"), |b| {
            b.iter(|| {
                pool.install(|| {
                    if n == 0 {
                        stress
                            .par_chunks_mut(BATCH)
                            .enumerate()
                            .for_each(|(i, stress)| {
                                let range = i * BATCH..(i + 1) * BATCH;
                                update_batch(material.as_ref(), &inputs, range, stress, &mut []);
                            });
                    } else {
                        stress
                            .par_chunks_mut(BATCH)
                            .zip(state_new.par_chunks_mut(BATCH * n))
                            .enumerate()
                            .for_each(|(i, (stress, state))| {
                                let range = i * BATCH..(i + 1) * BATCH;
                                update_batch(material.as_ref(), &inputs, range, stress, state);
                            });
                    }
                })
            })
        });
    }
    group.finish();
}

fn material_point_updates(c: &mut Criterion) {
    let library = MaterialLibrary::with_builtins();
    let neo_hookean = library.create("neo-hookean", &BTreeMap::new()).unwrap();
    let hill = library
        .create("hill", &BTreeMap::from([("n2".to_string(), 1.0)]))
        .unwrap();
    bench_material(c, "neo-hookean", neo_hookean);
    bench_material(c, "hill", hill);
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(20)
        .measurement_time(std::time::Duration::from_secs(3))
        .warm_up_time(std::time::Duration::from_secs(1));
    targets = material_point_updates
}
criterion_main!(benches);
