//! The multigrid on a linear-elastic block of hex8: CG preconditioned with it reaches the
//! dense direct solution, and the hierarchy is the same bit for bit on 1 and 2 threads.

use nalgebra::{DMatrix, DVector, SMatrix};

use super::Multigrid;
use super::csr::Csr;
use super::tentative::rigid_body_modes;
use crate::solver::amg_cg::{AmgCg, AmgCgSettings, HierarchyReuse};

/// The stiffness of a trilinear hex8 of side `h` [m], Young's modulus 1, Poisson's
/// ratio `nu` (2 × 2 × 2 Gauss points), unknowns node-major (x, y, z per node), nodes
/// (i, j, k) ∈ {0, 1}³ numbered i + 2 j + 4 k.
fn hex8_stiffness(h: f64, nu: f64) -> SMatrix<f64, 24, 24> {
    let lambda = nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mu = 0.5 / (1.0 + nu);
    let g = 1.0 / 3f64.sqrt();
    let mut k = SMatrix::<f64, 24, 24>::zeros();
    for point in 0..8 {
        let xi = [
            if point & 1 == 0 { -g } else { g },
            if point & 2 == 0 { -g } else { g },
            if point & 4 == 0 { -g } else { g },
        ];
        // ∇N_a in physical coordinates (x = h (ξ + 1) / 2), weight (h/2)³.
        let mut grads = [[0.0; 3]; 8];
        for (a, grad) in grads.iter_mut().enumerate() {
            let s = [
                if a & 1 == 0 { -1.0 } else { 1.0 },
                if a & 2 == 0 { -1.0 } else { 1.0 },
                if a & 4 == 0 { -1.0 } else { 1.0 },
            ];
            for d in 0..3 {
                let mut v = 0.125 * s[d];
                for e in 0..3 {
                    if e != d {
                        v *= 1.0 + s[e] * xi[e];
                    }
                }
                grad[d] = v * 2.0 / h;
            }
        }
        let weight = (0.5 * h).powi(3);
        for a in 0..8 {
            for b in 0..8 {
                for i in 0..3 {
                    for j in 0..3 {
                        // λ ∂_i N_a ∂_j N_b + μ (∂_j N_a ∂_i N_b + δ_ij ∇N_a · ∇N_b).
                        let mut v =
                            lambda * grads[a][i] * grads[b][j] + mu * grads[a][j] * grads[b][i];
                        if i == j {
                            v += mu * (0..3).map(|d| grads[a][d] * grads[b][d]).sum::<f64>();
                        }
                        k[(3 * a + i, 3 * b + j)] += weight * v;
                    }
                }
            }
        }
    }
    k
}

/// An m³ block of unit side clamped on x = 0: the stiffness (both triangles, rows
/// sorted), the unknowns' coordinates, directions and nodes.
#[allow(clippy::type_complexity)]
fn clamped_block(m: usize, nu: f64) -> (Csr, Vec<[f64; 3]>, Vec<u8>, Vec<u32>) {
    let h = 1.0 / m as f64;
    let nodes = m + 1;
    let node = |i: usize, j: usize, k: usize| i + nodes * (j + nodes * k);
    // Equation numbers: nodes with i = 0 are clamped.
    let mut equation = vec![u32::MAX; 3 * nodes.pow(3)];
    let (mut coordinates, mut dofs, mut node_of) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..nodes {
        for j in 0..nodes {
            for i in 0..nodes {
                if i == 0 {
                    continue;
                }
                let n = node(i, j, k);
                for d in 0..3 {
                    equation[3 * n + d] = coordinates.len() as u32;
                    coordinates.push([i as f64 * h, j as f64 * h, k as f64 * h]);
                    dofs.push(d as u8);
                    node_of.push(n as u32);
                }
            }
        }
    }
    let size = coordinates.len();
    let ke = hex8_stiffness(h, nu);
    let mut rows: Vec<std::collections::BTreeMap<u32, f64>> = vec![Default::default(); size];
    for k in 0..m {
        for j in 0..m {
            for i in 0..m {
                let element: Vec<usize> = (0..8)
                    .map(|a| node(i + (a & 1), j + ((a >> 1) & 1), k + ((a >> 2) & 1)))
                    .collect();
                for (a, &na) in element.iter().enumerate() {
                    for (b, &nb) in element.iter().enumerate() {
                        for di in 0..3 {
                            for dj in 0..3 {
                                let (r, c) = (equation[3 * na + di], equation[3 * nb + dj]);
                                if r != u32::MAX && c != u32::MAX {
                                    *rows[r as usize].entry(c).or_insert(0.0) +=
                                        ke[(3 * a + di, 3 * b + dj)];
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    let mut ptr = vec![0];
    let (mut idx, mut val) = (Vec::new(), Vec::new());
    for row in rows {
        for (c, v) in row {
            idx.push(c);
            val.push(v);
        }
        ptr.push(idx.len());
    }
    let a = Csr {
        rows: size,
        cols: size,
        ptr,
        idx,
        val,
    };
    (a, coordinates, dofs, node_of)
}

fn rhs(n: usize) -> Vec<f64> {
    (0..n).map(|i| (0.37 * i as f64).sin() + 0.1).collect()
}

/// 8³ block (1 944 unknowns, two levels): AMG-CG to 1e-12 equals the dense Cholesky
/// solution to 1e-10 (relative to its largest component), in a few tens of iterations.
#[test]
fn amg_cg_solves_an_elastic_block_as_the_direct_solver_does() {
    let (a, coordinates, dofs, nodes) = clamped_block(8, 0.3);
    let n = a.rows;
    let mut dense = DMatrix::zeros(n, n);
    for i in 0..n {
        let (cols, vals) = a.row(i);
        for (&j, &v) in cols.iter().zip(vals) {
            dense[(i, j as usize)] = v;
        }
    }
    let b = rhs(n);
    let expected = dense
        .cholesky()
        .expect("SPD")
        .solve(&DVector::from_vec(b.clone()));
    for reuse in [HierarchyReuse::EveryTangent, HierarchyReuse::WhileFast] {
        let mut solver = AmgCg::new(&coordinates, &dofs, &nodes);
        let settings = AmgCgSettings {
            tolerance: 1e-12,
            reuse,
            ..AmgCgSettings::default()
        };
        // Twice: the second solve reuses the hierarchy.
        for _ in 0..2 {
            let mut x = b.clone();
            let mut values = a.val.clone();
            let outcome = solver
                .solve(
                    &a.ptr,
                    &a.idx.iter().map(|&i| i as usize).collect::<Vec<_>>(),
                    &mut values,
                    &mut x,
                    &settings,
                )
                .expect("converges");
            // The values lent to the hierarchy come back unchanged.
            assert_eq!(values, a.val);
            let (levels, _) = solver.describe().expect("a hierarchy");
            assert!(levels.len() >= 2, "{levels:?}");
            assert!(
                outcome.iterations <= 40,
                "{} iterations",
                outcome.iterations
            );
            let scale = expected.amax();
            for (xi, ei) in x.iter().zip(expected.iter()) {
                assert!((xi - ei).abs() <= 1e-10 * scale, "{xi} vs {ei}");
            }
        }
    }
}

/// The hierarchy (every level's matrix and prolongator) and one V-cycle are the same bit
/// for bit on 1 and on 2 threads.
#[test]
fn the_hierarchy_is_bit_identical_on_one_and_two_threads() {
    let (a, coordinates, dofs, nodes) = clamped_block(10, 0.45);
    let mut block_ptr = vec![0];
    for i in 1..=nodes.len() {
        if i == nodes.len() || nodes[i] != nodes[i - 1] {
            block_ptr.push(i);
        }
    }
    let modes = rigid_body_modes(&coordinates, &dofs);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut multigrid = Multigrid::new(a.clone(), &block_ptr, &modes).unwrap();
            multigrid.refresh().unwrap();
            let mut z = vec![0.0; a.rows];
            multigrid.apply(&rhs(a.rows), &mut z);
            let mut fingerprint: Vec<u64> = z.iter().map(|v| v.to_bits()).collect();
            for level in &multigrid.levels {
                fingerprint.extend(level.a.val.iter().map(|v| v.to_bits()));
                fingerprint.push(level.lambda_max.to_bits());
                if let Some((p, _)) = &level.transfer {
                    fingerprint.extend(p.val.iter().map(|v| v.to_bits()));
                }
            }
            (multigrid.level_sizes(), fingerprint)
        })
    };
    let (sizes, one) = run(1);
    let (_, two) = run(2);
    assert!(
        sizes.len() >= 2 && sizes[0] > 2 * super::csr::ROWS,
        "{sizes:?}"
    );
    assert!(one == two, "1 and 2 threads differ");
}
