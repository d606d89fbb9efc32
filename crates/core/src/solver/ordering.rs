//! Fill-reducing orderings of the stiffness from its node graph, two kinds of nested
//! dissection; the Cholesky analysis keeps whichever (or faer's AMD) fills least (see
//! `sparse.rs`). Every degree of freedom of a node keeps its node's place, so the 3 × 3
//! blocks of the stiffness stay together.
//!
//! - Geometric nested dissection (George 1973): the nodes are split at the median of their
//!   longest coordinate extent into two halves; the nodes of the second half that share an
//!   element with the first form the separator, numbered after both halves, which are
//!   dissected in turn down to leaves of [`LEAF_NODES`] nodes. Best on box-shaped meshes.
//! - METIS's multilevel nested dissection (Karypis & Kumar 1998), which finds small
//!   separators by coarsening the graph: on the knee's curved, bonded muscles its factor
//!   is 2.6–2.9 times smaller than the geometric one's.
//!
//! For a 3-D mesh of n nodes the factor of a nested-dissection order holds O(n^{4/3})
//! entries and costs O(n²) flops; the minimum-degree orders (AMD) that sparse direct
//! solvers use by default are of the same order but, on 3-D solid meshes, with a larger
//! constant.

#[cfg(feature = "metis")]
use std::sync::Mutex;

#[cfg(feature = "metis")]
use metis_sys::idx_t;
use nalgebra::Vector3;

/// Node graph in compressed rows: the neighbours of node `a` (nodes sharing an element
/// with it, itself included) are `targets[offsets[a]..offsets[a + 1]]`, sorted.
pub(crate) struct NodeGraph {
    pub offsets: Vec<usize>,
    pub targets: Vec<u32>,
}

impl NodeGraph {
    pub fn neighbours(&self, node: usize) -> &[u32] {
        &self.targets[self.offsets[node]..self.offsets[node + 1]]
    }

    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }
}

/// Largest set of nodes numbered without further dissection.
pub(crate) const LEAF_NODES: usize = 24;

/// The nested-dissection order of the nodes of `graph` at `positions` [m]:
/// `order[k]` is the node numbered k-th. Deterministic (ties broken by node number).
pub(crate) fn nested_dissection(graph: &NodeGraph, positions: &[Vector3<f64>]) -> Vec<u32> {
    let mut nodes: Vec<u32> = (0..graph.len() as u32).collect();
    let mut side = vec![0u8; graph.len()];
    let mut order = Vec::with_capacity(graph.len());
    dissect(&mut nodes, graph, positions, &mut side, &mut order);
    debug_assert_eq!(order.len(), graph.len());
    order
}

/// Append the order of `nodes` to `order`; `side` is all zero on entry and on exit.
fn dissect(
    nodes: &mut [u32],
    graph: &NodeGraph,
    positions: &[Vector3<f64>],
    side: &mut [u8],
    order: &mut Vec<u32>,
) {
    if nodes.len() <= LEAF_NODES {
        order.extend_from_slice(nodes);
        return;
    }
    let mut low = Vector3::repeat(f64::INFINITY);
    let mut high = Vector3::repeat(f64::NEG_INFINITY);
    for &n in nodes.iter() {
        low = low.inf(&positions[n as usize]);
        high = high.sup(&positions[n as usize]);
    }
    let axis = (high - low).imax();
    nodes.sort_unstable_by(|&a, &b| {
        positions[a as usize][axis]
            .total_cmp(&positions[b as usize][axis])
            .then(a.cmp(&b))
    });
    // Split at the median, moved to the nearest change of the coordinate, so that a
    // layer of nodes (a lattice plane) is not cut in two.
    let coordinate = |k: usize| positions[nodes[k] as usize][axis];
    let middle = nodes.len() / 2;
    let change = |k: &usize| coordinate(*k - 1) < coordinate(*k);
    let below = (1..=middle).rev().find(change);
    let above = (middle + 1..nodes.len()).find(change);
    let half = match (below, above) {
        (Some(b), Some(a)) => {
            if middle - b <= a - middle {
                b
            } else {
                a
            }
        }
        (Some(b), None) => b,
        (None, Some(a)) => a,
        (None, None) => middle,
    };
    let (first, second) = nodes.split_at_mut(half);
    for &n in first.iter() {
        side[n as usize] = 1;
    }
    // Separator: nodes of the second half coupled to the first, moved to its end.
    let mut rest = 0;
    for k in 0..second.len() {
        let n = second[k] as usize;
        let coupled = graph.neighbours(n).iter().any(|&m| side[m as usize] == 1);
        if !coupled {
            second.swap(rest, k);
            rest += 1;
        }
    }
    for &n in first.iter() {
        side[n as usize] = 0;
    }
    // Keep the separator in a deterministic order (swaps permuted it).
    let (remainder, separator) = second.split_at_mut(rest);
    separator.sort_unstable();
    dissect(first, graph, positions, side, order);
    dissect(remainder, graph, positions, side, order);
    order.extend_from_slice(separator);
}

/// Held while METIS runs.
#[cfg(feature = "metis")]
static METIS_LOCK: Mutex<()> = Mutex::new(());

/// METIS's multilevel nested dissection (`METIS_NodeND`, Karypis & Kumar 1998) of the
/// nodes of `graph` that carry unknowns, each weighted by their count (`unknowns[node]`,
/// 0 to 3): `order[k]` is the node numbered k-th, nodes without unknowns left out.
/// Deterministic (METIS's default options, fixed seed). Only with the `metis` feature (on
/// by default): without it the solver chooses between AMD and the geometric order.
#[cfg(feature = "metis")]
pub(crate) fn multilevel_nested_dissection(
    graph: &NodeGraph,
    unknowns: &[u8],
) -> Result<Vec<u32>, String> {
    let kept: Vec<u32> = (0..graph.len() as u32)
        .filter(|&a| unknowns[a as usize] > 0)
        .collect();
    if kept.is_empty() {
        return Ok(kept);
    }
    let mut local = vec![u32::MAX; graph.len()];
    for (k, &a) in kept.iter().enumerate() {
        local[a as usize] = k as u32;
    }
    let too_large = |_| {
        format!(
            "{} nodes are too many for METIS's 32-bit indices",
            kept.len()
        )
    };
    let mut offsets: Vec<idx_t> = Vec::with_capacity(kept.len() + 1);
    offsets.push(0);
    let mut adjacent: Vec<idx_t> = Vec::new();
    for &a in &kept {
        for &b in graph.neighbours(a as usize) {
            let k = local[b as usize];
            if b != a && k != u32::MAX {
                adjacent.push(idx_t::try_from(k).map_err(too_large)?);
            }
        }
        offsets.push(idx_t::try_from(adjacent.len()).map_err(too_large)?);
    }
    let mut weights: Vec<idx_t> = kept.iter().map(|&a| unknowns[a as usize].into()).collect();
    let mut count = idx_t::try_from(kept.len()).map_err(too_large)?;
    let mut permutation: Vec<idx_t> = vec![0; kept.len()];
    let mut inverse: Vec<idx_t> = vec![0; kept.len()];
    // METIS's random numbers come from one global state (GKlib's random.c), so calls from
    // two threads (the knee's passive and active squats) would race and make the order
    // depend on their timing.
    let _only_caller = METIS_LOCK
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    // SAFETY: the graph is in METIS's compressed form (symmetric, no self loops) with
    // `count` + 1 offsets into `adjacent`, `count` weights and `count` entries in both
    // outputs; null options select METIS's defaults. METIS keeps no pointer after return
    // and no other thread is inside METIS (the lock).
    let status = unsafe {
        metis_sys::METIS_NodeND(
            &mut count,
            offsets.as_mut_ptr(),
            adjacent.as_mut_ptr(),
            weights.as_mut_ptr(),
            std::ptr::null_mut(),
            permutation.as_mut_ptr(),
            inverse.as_mut_ptr(),
        )
    };
    if status != metis_sys::rstatus_et_METIS_OK {
        return Err(format!("METIS_NodeND failed with status {status}"));
    }
    // METIS's `perm[k]` is the vertex numbered k-th.
    Ok(permutation.iter().map(|&k| kept[k as usize]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A path of 100 nodes on the x axis: every node is numbered once, and the
    /// separator of the first cut (one node at the middle) comes last.
    #[test]
    fn a_path_is_dissected_at_its_middle() {
        let n: usize = 100;
        let mut offsets = vec![0];
        let mut targets = Vec::new();
        for a in 0..n {
            for b in a.saturating_sub(1)..(a + 2).min(n) {
                targets.push(b as u32);
            }
            offsets.push(targets.len());
        }
        let graph = NodeGraph { offsets, targets };
        let positions: Vec<Vector3<f64>> =
            (0..n).map(|a| Vector3::new(a as f64, 0.0, 0.0)).collect();
        let order = nested_dissection(&graph, &positions);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n as u32).collect::<Vec<_>>());
        assert_eq!(*order.last().unwrap(), 50);
    }

    /// The graph of a cubic lattice of `n`³ nodes, each coupled to its 26 neighbours.
    #[cfg(feature = "metis")]
    fn lattice(n: usize) -> NodeGraph {
        let index = |i: usize, j: usize, k: usize| (i + n * (j + n * k)) as u32;
        let mut offsets = vec![0];
        let mut targets = Vec::new();
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    for c in k.saturating_sub(1)..(k + 2).min(n) {
                        for b in j.saturating_sub(1)..(j + 2).min(n) {
                            for a in i.saturating_sub(1)..(i + 2).min(n) {
                                targets.push(index(a, b, c));
                            }
                        }
                    }
                    offsets.push(targets.len());
                }
            }
        }
        NodeGraph { offsets, targets }
    }

    /// METIS numbers every node that carries unknowns once and leaves out the others;
    /// four threads that order the same graph at once get the same order as one alone.
    #[test]
    #[cfg(feature = "metis")]
    fn metis_orders_the_nodes_with_unknowns_the_same_in_every_thread() {
        let graph = lattice(12);
        // The bottom layer prescribed, one unknown left on each node of the next layer.
        let unknowns: Vec<u8> = (0..graph.len())
            .map(|a| match a / 144 {
                0 => 0,
                1 => 1,
                _ => 3,
            })
            .collect();
        let alone = multilevel_nested_dissection(&graph, &unknowns).unwrap();
        let mut sorted = alone.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (144..graph.len() as u32).collect::<Vec<_>>());
        let together: Vec<Vec<u32>> = std::thread::scope(|scope| {
            let runs: Vec<_> = (0..4)
                .map(|_| scope.spawn(|| multilevel_nested_dissection(&graph, &unknowns).unwrap()))
                .collect();
            runs.into_iter().map(|run| run.join().unwrap()).collect()
        });
        for order in together {
            assert_eq!(order, alone);
        }
    }

    #[test]
    #[cfg(feature = "metis")]
    fn metis_orders_an_empty_graph() {
        let graph = lattice(2);
        assert!(
            multilevel_nested_dissection(&graph, &[0; 8])
                .unwrap()
                .is_empty()
        );
    }
}
