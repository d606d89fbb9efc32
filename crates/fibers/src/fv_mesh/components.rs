//! Connected components: the parts of the mesh whose cells are joined through interior
//! faces (union–find with path halving and union by size).

use super::InteriorFace;

/// The component of each cell, numbered 0, 1, … in the order of their first cell.
pub(crate) struct Components {
    /// Component of each cell.
    pub of_cell: Vec<u32>,
    /// Number of cells in each component.
    pub sizes: Vec<usize>,
    /// The smallest cell of each component (to name it in messages).
    pub first_cell: Vec<usize>,
}

impl Components {
    /// Components of `cell_count` cells joined by `faces`.
    pub fn new(cell_count: usize, faces: &[InteriorFace]) -> Self {
        let mut parent: Vec<u32> = (0..cell_count as u32).collect();
        let mut size = vec![1usize; cell_count];
        for face in faces {
            let a = find(&mut parent, face.owner);
            let b = find(&mut parent, face.neighbour);
            if a != b {
                let (big, small) = if size[a as usize] >= size[b as usize] {
                    (a, b)
                } else {
                    (b, a)
                };
                parent[small as usize] = big;
                size[big as usize] += size[small as usize];
            }
        }
        let mut label = vec![u32::MAX; cell_count];
        let mut of_cell = vec![0u32; cell_count];
        let mut sizes = Vec::new();
        let mut first_cell = Vec::new();
        for cell in 0..cell_count {
            let root = find(&mut parent, cell as u32) as usize;
            if label[root] == u32::MAX {
                label[root] = sizes.len() as u32;
                sizes.push(0);
                first_cell.push(cell);
            }
            of_cell[cell] = label[root];
            sizes[label[root] as usize] += 1;
        }
        Self {
            of_cell,
            sizes,
            first_cell,
        }
    }

    /// Number of components.
    pub fn count(&self) -> usize {
        self.sizes.len()
    }
}

/// The root of `cell`, halving the path on the way.
fn find(parent: &mut [u32], mut cell: u32) -> u32 {
    while parent[cell as usize] != cell {
        let grandparent = parent[parent[cell as usize] as usize];
        parent[cell as usize] = grandparent;
        cell = grandparent;
    }
    cell
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::*;

    fn face(owner: u32, neighbour: u32) -> InteriorFace {
        InteriorFace {
            owner,
            neighbour,
            owner_face: 0,
            area_vector: Vector3::zeros(),
            centre: Vector3::zeros(),
        }
    }

    #[test]
    fn chains_join_and_islands_stay_apart() {
        // 0–3–5 and 1–2, 4 alone.
        let components = Components::new(6, &[face(3, 5), face(1, 2), face(0, 3)]);
        assert_eq!(components.count(), 3);
        assert_eq!(components.of_cell, vec![0, 1, 1, 0, 2, 0]);
        assert_eq!(components.sizes, vec![3, 2, 1]);
        assert_eq!(components.first_cell, vec![0, 1, 4]);
    }
}
