//! Deterministic parallel assembly of element forces into nodal forces.
//!
//! Each element writes its nodal forces into its own slots (element × n + local node,
//! n nodes per element); each node then sums the slots of its elements, listed in
//! ascending element order by a node → slot adjacency (compressed rows), in parallel
//! over nodes. The sum at a node runs in the same order whatever the number of threads,
//! and in the order of the serial element-by-element scatter it replaces, so the forces
//! are the same, bit for bit, on any number of threads.

/// For every node, the force slots of the elements of one block that hold it.
#[derive(Debug, Clone)]
pub(crate) struct NodeAdjacency {
    /// Slots of node i: `slots[offsets[i]..offsets[i + 1]]`.
    offsets: Vec<u32>,
    /// element × nodes_per_element + local node, ascending for each node.
    slots: Vec<u32>,
}

impl NodeAdjacency {
    /// The adjacency of a block with `connectivity` (`nodes_per_element` ids per element)
    /// over `node_count` nodes. Panics if the block has 2³² slots or more.
    pub fn new(node_count: usize, connectivity: &[u32]) -> Self {
        assert!(
            u32::try_from(connectivity.len()).is_ok(),
            "at most 2^32 element-node slots per block"
        );
        let mut offsets = vec![0u32; node_count + 1];
        for &id in connectivity {
            offsets[id as usize + 1] += 1;
        }
        for i in 0..node_count {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut slots = vec![0u32; connectivity.len()];
        for (slot, &id) in connectivity.iter().enumerate() {
            let next = &mut fill[id as usize];
            slots[*next as usize] = slot as u32;
            *next += 1;
        }
        NodeAdjacency { offsets, slots }
    }

    /// Force slots of `node`, ascending.
    #[inline]
    pub fn of(&self, node: usize) -> &[u32] {
        &self.slots[self.offsets[node] as usize..self.offsets[node + 1] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_node_lists_its_slots_in_element_order() {
        // Two quads sharing nodes 1 and 2; node 4 belongs to no element.
        let adjacency = NodeAdjacency::new(6, &[0, 1, 2, 3, 1, 5, 2, 3]);
        assert_eq!(adjacency.of(0), &[0]);
        assert_eq!(adjacency.of(1), &[1, 4]);
        assert_eq!(adjacency.of(2), &[2, 6]);
        assert_eq!(adjacency.of(3), &[3, 7]);
        assert!(adjacency.of(4).is_empty());
        assert_eq!(adjacency.of(5), &[5]);
    }
}
