//! The per-node loops of the explicit step, in parallel over fixed ranges of nodes.
//! Sums over nodes are partial sums over ranges that depend only on the node count,
//! added in range order: the same bits on any number of threads.

use nalgebra::Vector3;
use rayon::prelude::*;

/// Nodes per parallel task.
pub(crate) const NODES_PER_TASK: usize = 2048;
/// Most partial sums of a [`deterministic_sum`] (they live on the stack).
const MAX_PARTIAL_SUMS: usize = 256;

/// Σ_{i < count} term(i), in parallel, the same bits on any number of threads.
pub(crate) fn deterministic_sum(count: usize, term: impl Fn(usize) -> f64 + Sync) -> f64 {
    let per_task = NODES_PER_TASK.max(count.div_ceil(MAX_PARTIAL_SUMS));
    let tasks = count.div_ceil(per_task);
    let mut partial = [0.0; MAX_PARTIAL_SUMS];
    partial[..tasks]
        .par_iter_mut()
        .enumerate()
        .for_each(|(task, sum)| {
            let end = ((task + 1) * per_task).min(count);
            *sum = (task * per_task..end).map(&term).sum();
        });
    partial[..tasks].iter().sum()
}

/// v^{n+½} = v^{n−½} + Δt^n (f_ext − f − f_visc − f_c)/m for every node (prescribed
/// components are set after), keeping v^{n−½} in `old_velocity`; `forces` holds the
/// internal force f, the bulk-viscosity force f_visc, the interaction force f_c and the
/// external force f_ext [N], `mass` m [kg] (a node of zero mass keeps v, its components
/// being all prescribed), `average_step` Δt^n [s].
pub(crate) fn update_velocities(
    velocity: &mut [Vector3<f64>],
    old_velocity: &mut [Vector3<f64>],
    forces: [&[Vector3<f64>]; 4],
    mass: &[f64],
    average_step: f64,
) {
    let [internal, viscous, interaction, external] = forces;
    velocity
        .par_chunks_mut(NODES_PER_TASK)
        .zip(old_velocity.par_chunks_mut(NODES_PER_TASK))
        .zip(internal.par_chunks(NODES_PER_TASK))
        .zip(viscous.par_chunks(NODES_PER_TASK))
        .zip(interaction.par_chunks(NODES_PER_TASK))
        .zip(external.par_chunks(NODES_PER_TASK))
        .zip(mass.par_chunks(NODES_PER_TASK))
        .for_each(|((((((v, old), f), f_visc), f_c), f_ext), m)| {
            old.copy_from_slice(v);
            for (((((v, f), f_visc), f_c), f_ext), m) in
                v.iter_mut().zip(f).zip(f_visc).zip(f_c).zip(f_ext).zip(m)
            {
                // A node without mass is held in every component (`explicit_run` checks):
                // its velocity is set from its targets after.
                if *m > 0.0 {
                    *v += (f_ext - f - f_visc - f_c) * (average_step / m);
                }
            }
        });
}

/// u^{n+1} = u^n + Δt v^{n+½} and x^{n+1} = X + u^{n+1} [m], keeping u^n in
/// `previous_displacement`.
pub(crate) fn advance_positions(
    displacement: &mut [Vector3<f64>],
    previous_displacement: &mut [Vector3<f64>],
    positions: &mut [Vector3<f64>],
    reference: &[Vector3<f64>],
    velocity: &[Vector3<f64>],
    dt: f64,
) {
    displacement
        .par_chunks_mut(NODES_PER_TASK)
        .zip(previous_displacement.par_chunks_mut(NODES_PER_TASK))
        .zip(positions.par_chunks_mut(NODES_PER_TASK))
        .zip(reference.par_chunks(NODES_PER_TASK))
        .zip(velocity.par_chunks(NODES_PER_TASK))
        .for_each(|((((u, previous), x), reference), v)| {
            previous.copy_from_slice(u);
            for (((u, x), reference), v) in u.iter_mut().zip(x).zip(reference).zip(v) {
                *u += v * dt;
                *x = reference + *u;
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The partial sums follow the node count only: a sum whose terms differ wildly in
    /// size gives the same bits on 1 and 3 threads, and agrees with the exact sum.
    #[test]
    fn sums_do_not_depend_on_the_thread_count() {
        let count = 5 * NODES_PER_TASK + 17;
        let term = |i: usize| ((i * 7919) % 1000) as f64 * 10f64.powi((i % 23) as i32 - 11);
        let on = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| deterministic_sum(count, term))
        };
        let (one, three) = (on(1), on(3));
        assert_eq!(one.to_bits(), three.to_bits());
        let exact: f64 = (0..count).map(term).sum();
        assert!((one - exact).abs() <= 1e-14 * exact, "{one} vs {exact}");
    }
}
