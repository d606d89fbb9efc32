//! Rigid-body motions a quasi-static run leaves free: a body whose displacement conditions
//! do not hold all six of its rigid motions has a singular stiffness, and Newton's method
//! then "converges" to any multiple of the free motion (a net force sent a block
//! 2.5e12 m). The motions are found before the first increment.
//!
//! For every piece of the mesh (nodes connected through elements), the six
//! infinitesimal rigid motions about its centroid c are m_k(x) = e_k (translations) and
//! (e_k × (x − c)) / L (rotations, L the piece's bounding-box diagonal, so all six have
//! the same scale). Each prescribed component d of a node x of the piece (every
//! component of a node tied to a rigid body) is a row r = (m_1(x)_d, …, m_6(x)_d); the
//! motions held are the range of G = Σ r rᵀ. An eigenvector of G whose eigenvalue is
//! below 10⁻⁹ of the largest possible (the number of rows) is a free motion.

use nalgebra::{Matrix6, SymmetricEigen, Vector3, Vector6};

use crate::mesh::Mesh;

use super::loads::Loads;
use super::{Analysis, SolverError};

/// A rigid motion of one piece of the mesh that no condition holds.
#[derive(Clone, Debug, PartialEq)]
pub struct FreeMotion {
    /// The block of the piece's first element.
    pub block: String,
    /// Nodes in the piece.
    pub nodes: usize,
    /// The free motions, each as words: "translation along (1, 0, 0)" or "rotation about
    /// (0, 0, 1) through (0.005, 0.005, 0.005) m".
    pub motions: Vec<String>,
}

/// An error if `analysis` is quasi-static implicit without interactions (nothing but the
/// conditions can hold a body) and a piece of `mesh` has a rigid motion `loads` leave free.
pub fn refuse_free_motion(
    mesh: &Mesh,
    loads: &Loads,
    analysis: &Analysis,
    interactions: usize,
) -> Result<(), SolverError> {
    let quasi_static = matches!(analysis, Analysis::Implicit(s) if s.dynamics.is_none());
    if !quasi_static || interactions > 0 {
        return Ok(());
    }
    match free_rigid_motions(mesh, loads).into_iter().next() {
        Some(free) => Err(SolverError::FreeRigidMotion {
            block: free.block,
            nodes: free.nodes,
            motions: free.motions.join(", "),
        }),
        None => Ok(()),
    }
}

/// The pieces of `mesh` with rigid motions that `loads` leave free.
pub fn free_rigid_motions(mesh: &Mesh, loads: &Loads) -> Vec<FreeMotion> {
    let count = mesh.node_count();
    let mut piece = UnionFind::new(count);
    let mut used = vec![false; count];
    let mut first_block: Vec<Option<usize>> = vec![None; count];
    for (b, block) in mesh.blocks.iter().enumerate() {
        for e in 0..block.len() {
            let nodes = block.element_nodes(e);
            for &n in nodes {
                used[n as usize] = true;
                first_block[n as usize].get_or_insert(b);
            }
            for pair in nodes.windows(2) {
                piece.join(pair[0] as usize, pair[1] as usize);
            }
        }
    }
    // Held components per node: bit d for component d.
    let mut held = vec![0u8; count];
    for condition in &loads.displacements {
        for &n in &condition.nodes {
            held[n as usize] |= 1 << condition.dof;
        }
    }
    for tie in &loads.rigid_ties {
        for &n in &tie.nodes {
            held[n as usize] = 0b111;
        }
    }
    // The nodes of each piece, in one pass (pieces in the order of their smallest node).
    let mut pieces: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for n in (0..count).filter(|&n| used[n]) {
        pieces.entry(piece.root(n)).or_default().push(n);
    }
    let mut free = Vec::new();
    for members in pieces.into_values() {
        let positions: Vec<Vector3<f64>> =
            members.iter().map(|&n| mesh.nodes.position(n)).collect();
        let centroid = positions.iter().sum::<Vector3<f64>>() / positions.len() as f64;
        let (low, high) = positions
            .iter()
            .fold((positions[0], positions[0]), |(low, high), p| {
                (low.inf(p), high.sup(p))
            });
        let scale = (high - low).norm().max(f64::MIN_POSITIVE);
        let mut gram = Matrix6::<f64>::zeros();
        let mut rows = 0usize;
        for (&n, x) in members.iter().zip(&positions) {
            for d in 0..3 {
                if held[n] & (1 << d) == 0 {
                    continue;
                }
                let arm = (x - centroid) / scale;
                let row = Vector6::from_fn(|k, _| {
                    if k < 3 {
                        f64::from(u8::from(k == d))
                    } else {
                        Vector3::ith(k - 3, 1.0).cross(&arm)[d]
                    }
                });
                gram += row * row.transpose();
                rows += 1;
            }
        }
        let eigen = SymmetricEigen::new(gram);
        let threshold = 1e-9 * rows.max(1) as f64;
        let motions: Vec<String> = (0..6)
            .filter(|&k| eigen.eigenvalues[k] <= threshold)
            .map(|k| describe(&eigen.eigenvectors.column(k).into_owned(), &centroid))
            .collect();
        if !motions.is_empty() {
            let block = first_block[members[0]].unwrap_or(0);
            free.push(FreeMotion {
                block: mesh.blocks[block].name.clone(),
                nodes: members.len(),
                motions,
            });
        }
    }
    free
}

/// "translation along (1, 0, 0)" or "rotation about (0, 0, 1) through (…) m".
fn describe(mode: &Vector6<f64>, centroid: &Vector3<f64>) -> String {
    let translation = Vector3::new(mode[0], mode[1], mode[2]);
    let rotation = Vector3::new(mode[3], mode[4], mode[5]);
    let direction = |v: Vector3<f64>| {
        let v = v.normalize();
        let v = if v.iter().sum::<f64>() < 0.0 { -v } else { v };
        let round = |x: f64| {
            let x = (x * 1000.0).round() / 1000.0;
            if x == 0.0 { 0.0 } else { x }
        };
        format!("({}, {}, {})", round(v.x), round(v.y), round(v.z))
    };
    if translation.norm() >= rotation.norm() {
        format!("translation along {}", direction(translation))
    } else {
        format!(
            "rotation about {} through ({:.4}, {:.4}, {:.4}) m",
            direction(rotation),
            centroid.x,
            centroid.y,
            centroid.z
        )
    }
}

/// Pieces of a graph, joined edge by edge.
struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    fn new(count: usize) -> Self {
        Self {
            parent: (0..count).collect(),
        }
    }

    fn root(&mut self, mut n: usize) -> usize {
        while self.parent[n] != n {
            self.parent[n] = self.parent[self.parent[n]];
            n = self.parent[n];
        }
        n
    }

    fn join(&mut self, a: usize, b: usize) {
        let (a, b) = (self.root(a), self.root(b));
        if a != b {
            self.parent[a.max(b)] = a.min(b);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::box_of_hexes;
    use crate::solver::loads::PrescribedDisplacement;
    use musclefem_materials::Amplitude;

    fn held(mesh: &Mesh, set: &str, dofs: &[usize]) -> Vec<PrescribedDisplacement> {
        dofs.iter()
            .map(|&dof| PrescribedDisplacement {
                nodes: mesh.node_set(set).unwrap().to_vec(),
                dof,
                amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
            })
            .collect()
    }

    #[test]
    fn symmetry_planes_hold_a_box_and_one_face_along_x_does_not() {
        let mesh = box_of_hexes([0.01, 0.01, 0.01], [2, 2, 2]).unwrap();
        // x0, y0, z0 held normal to themselves: every rigid motion is held.
        let mut planes = held(&mesh, "x0", &[0]);
        planes.extend(held(&mesh, "y0", &[1]));
        planes.extend(held(&mesh, "z0", &[2]));
        assert!(free_rigid_motions(&mesh, &Loads::from(planes)).is_empty());
        // x0 held along x only: y and z translations and the rotation about x are free.
        let free = free_rigid_motions(&mesh, &Loads::from(held(&mesh, "x0", &[0])));
        assert_eq!(free.len(), 1);
        assert_eq!(free[0].nodes, 27);
        let motions = free[0].motions.join("; ");
        assert_eq!(free[0].motions.len(), 3, "{motions}");
        assert!(motions.contains("rotation about (1, 0, 0)"), "{motions}");
        assert_eq!(motions.matches("translation").count(), 2, "{motions}");
        // Nothing held: all six.
        assert_eq!(
            free_rigid_motions(&mesh, &Loads::default())[0]
                .motions
                .len(),
            6
        );
        // One face clamped: nothing free.
        let clamped = held(&mesh, "x0", &[0, 1, 2]);
        assert!(free_rigid_motions(&mesh, &Loads::from(clamped)).is_empty());
    }
}
