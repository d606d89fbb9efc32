//! Structured meshes of a box [0, Lx] × [0, Ly] × [0, Lz] [m], for tests and benchmarks.
//!
//! Both generators number the lattice nodes x fastest, then y, then z (node (i, j, k) has
//! id i + (nx+1)(j + (ny+1)k)), cells in the same order, and name:
//!
//! - node sets `x0, x1, y0, y1, z0, z1`: the nodes on the faces x = 0, x = Lx, ... of
//!   the box (mid-edge nodes included);
//! - element set `all`: every element;
//! - surfaces `x0 ... z1`: the element faces on each box face, and `outer`: all boundary
//!   faces, in element order.
//!
//! The mesh has one block, named `hexes` or `tets`, with every fiber along e_x.
//!
//! [`cooks_membrane`] maps such a box onto Cook's tapered panel (a locking benchmark),
//! [`curved_tube`] onto a quarter torus (the fiber solver's curved check).
//!
//! [`fusiform_mesh`] meshes the paper's elongation specimen, a fusiform muscle (or a
//! cylinder), with hex8, tet4 or tet10 of a target size, on an O-grid cross-section, with
//! its own names (`origin`, `insertion`, `lateral`, `muscle`, ...; see there).
//!
//! [`swept_muscle_mesh`] sweeps the same O-grid along a 3-D centreline through control
//! stations, with elliptical sections of varying semi-axes ([`SweptSolid`]): the
//! quadriceps of the procedural knee.

mod cooks_membrane;
mod curved_tube;
mod distort;
mod end_sets;
mod fusiform;
mod swept_muscle;

use std::collections::{BTreeMap, BTreeSet, HashMap};

use nalgebra::Vector3;

pub use cooks_membrane::{
    COOKS_MEMBRANE_AREA, COOKS_MEMBRANE_CORNERS, consistent_nodal_areas, cooks_membrane,
};
pub use curved_tube::{circumferential, curved_tube};
pub use distort::distort;
pub use fusiform::{
    PAPER_END_RADIUS, PAPER_LENGTH, PAPER_MID_RADIUS, SpecimenDivisions, SpecimenShape,
    SpecimenSpec, fusiform_mesh,
};
pub use swept_muscle::{Section, SweptMuscleSpec, SweptSolid, SweptStation, swept_muscle_mesh};

use super::error::MeshError;
use super::refs::{ElementRef, Face};
use super::shape::ElementShape;
use super::{ElementBlock, Mesh, Nodes};

/// Interpolation order of generated tetrahedra.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TetOrder {
    /// tet4.
    Linear,
    /// tet10, with one node per edge shared by all elements around that edge.
    Quadratic,
}

/// Names of the box faces: (name, axis, on the upper side).
const BOX_FACES: [(&str, usize, bool); 6] = [
    ("x0", 0, false),
    ("x1", 0, true),
    ("y0", 1, false),
    ("y1", 1, true),
    ("z0", 2, false),
    ("z1", 2, true),
];

/// The six ways of walking from corner (0,0,0) to (1,1,1) of a cell along its edges, one
/// per permutation of the axes: each walk is one tet of the Kuhn (Freudenthal) split.
const KUHN_PERMUTATIONS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

/// A box of `divisions[0] × divisions[1] × divisions[2]` hex8 cells of size `size` [m].
///
/// Errors if a size is not finite and positive, a division is zero, or the ids would not
/// fit in `u32`.
pub fn box_of_hexes(size: [f64; 3], divisions: [usize; 3]) -> Result<Mesh, MeshError> {
    let lattice = Lattice::new("box_of_hexes", size, divisions, 1, 1)?;
    let mut connectivity = Vec::with_capacity(lattice.cell_count() * 8);
    for [i, j, k] in lattice.cells() {
        for [a, b, c] in ElementShape::Hex8.reference_nodes() {
            let corner = |r: f64, base: usize| base + usize::from(r > 0.0);
            connectivity.push(lattice.id([corner(*a, i), corner(*b, j), corner(*c, k)]));
        }
    }
    let block = ElementBlock::new("hexes", ElementShape::Hex8, connectivity)?;
    Ok(lattice.finish(lattice.nodes(), block))
}

/// A box of `divisions` cells of size `size` [m], each cut into 6 tetrahedra by the Kuhn
/// split along its main diagonal (0,0,0)–(1,1,1). The split is the same in every cell, so
/// neighbouring cells cut their shared face along the same diagonal and the mesh is
/// conforming. For [`TetOrder::Quadratic`] every edge gets one node at its midpoint,
/// shared by all the tets around the edge; these nodes follow the lattice nodes, in the
/// order the elements first meet them.
///
/// Errors as [`box_of_hexes`].
pub fn box_of_tets(
    size: [f64; 3],
    divisions: [usize; 3],
    order: TetOrder,
) -> Result<Mesh, MeshError> {
    // Room for the edge nodes: at most 7 edges per lattice node.
    let nodes_per_lattice_node = match order {
        TetOrder::Linear => 1,
        TetOrder::Quadratic => 8,
    };
    let lattice = Lattice::new("box_of_tets", size, divisions, nodes_per_lattice_node, 6)?;
    let mut corners = Vec::with_capacity(lattice.cell_count() * 24);
    for cell in lattice.cells() {
        for permutation in KUHN_PERMUTATIONS {
            let mut offset = [0usize; 3];
            let mut path = [[0usize; 3]; 4];
            for (step, &axis) in permutation.iter().enumerate() {
                offset[axis] = 1;
                path[step + 1] = offset;
            }
            // Odd permutations walk clockwise: swap two nodes for a positive volume.
            if permutation_is_odd(permutation) {
                path.swap(1, 2);
            }
            for o in path {
                corners.push(lattice.id([cell[0] + o[0], cell[1] + o[1], cell[2] + o[2]]));
            }
        }
    }
    let mut nodes = lattice.nodes();
    let block = match order {
        TetOrder::Linear => ElementBlock::new("tets", ElementShape::Tet4, corners)?,
        TetOrder::Quadratic => {
            let connectivity = add_mid_edge_nodes(&mut nodes, &corners);
            ElementBlock::new("tets", ElementShape::Tet10, connectivity)?
        }
    };
    Ok(lattice.finish(nodes, block))
}

/// The tet10 connectivity of the tet4 connectivity `corners`: every edge gets one node at
/// the midpoint of its ends, pushed onto `nodes` in the order the elements first meet
/// it and shared by all the tets around the edge (so the mesh stays conforming).
fn add_mid_edge_nodes(nodes: &mut Nodes, corners: &[u32]) -> Vec<u32> {
    let shape = ElementShape::Tet10;
    let mut connectivity = Vec::with_capacity(corners.len() / 4 * 10);
    let mut edge_nodes: HashMap<(u32, u32), u32> = HashMap::new();
    for tet in corners.chunks_exact(4) {
        connectivity.extend_from_slice(tet);
        for &[a, b] in shape.edges() {
            let (a, b) = (tet[a as usize], tet[b as usize]);
            let id = *edge_nodes.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let mid = 0.5 * (nodes.position(a as usize) + nodes.position(b as usize));
                nodes.push(mid)
            });
            connectivity.push(id);
        }
    }
    connectivity
}

fn permutation_is_odd(p: [usize; 3]) -> bool {
    let inversions = (0..3)
        .flat_map(|i| (i + 1..3).map(move |j| (i, j)))
        .filter(|&(i, j)| p[i] > p[j])
        .count();
    inversions % 2 == 1
}

/// The lattice of cell corners of a box.
struct Lattice {
    size: [f64; 3],
    n: [usize; 3],
}

impl Lattice {
    /// Checks the arguments of `generator`; `nodes_per_lattice_node` bounds the final
    /// node count (edge nodes included) and `elements_per_cell` the element count for the
    /// u32 check.
    fn new(
        generator: &'static str,
        size: [f64; 3],
        n: [usize; 3],
        nodes_per_lattice_node: usize,
        elements_per_cell: usize,
    ) -> Result<Self, MeshError> {
        let invalid = |reason: String| MeshError::InvalidArgument { generator, reason };
        if !size.iter().all(|s| s.is_finite() && *s > 0.0) {
            return Err(invalid(format!(
                "size {size:?} m must be finite and positive"
            )));
        }
        if n.contains(&0) {
            return Err(invalid(format!("divisions {n:?} must be at least 1")));
        }
        let lattice = Self { size, n };
        let nodes = n
            .iter()
            .try_fold(nodes_per_lattice_node, |acc, d| acc.checked_mul(d + 1));
        let cells = lattice
            .n
            .iter()
            .try_fold(elements_per_cell, |acc, &d| acc.checked_mul(d));
        let fits = |count: Option<usize>| count.is_some_and(|c| c <= u32::MAX as usize);
        if !fits(nodes) || !fits(cells) {
            let count = |c: Option<usize>| c.map_or("over 2^64".to_string(), |c| c.to_string());
            return Err(invalid(format!(
                "divisions {n:?} give {} nodes and {} elements, more than the 2^32 ids a mesh \
                 can number",
                count(nodes),
                count(cells)
            )));
        }
        Ok(lattice)
    }

    fn cell_count(&self) -> usize {
        self.n.iter().product()
    }

    fn node_count(&self) -> usize {
        self.n.iter().map(|d| d + 1).product()
    }

    fn id(&self, [i, j, k]: [usize; 3]) -> u32 {
        (i + (self.n[0] + 1) * (j + (self.n[1] + 1) * k)) as u32
    }

    /// Lattice indices of a lattice node id, `None` for ids beyond the lattice.
    fn ijk(&self, id: u32) -> Option<[usize; 3]> {
        let id = id as usize;
        if id >= self.node_count() {
            return None;
        }
        let (nx, ny) = (self.n[0] + 1, self.n[1] + 1);
        Some([id % nx, (id / nx) % ny, id / (nx * ny)])
    }

    /// Cells (i, j, k), i fastest.
    fn cells(&self) -> impl Iterator<Item = [usize; 3]> + use<> {
        let [nx, ny, nz] = self.n;
        (0..nz).flat_map(move |k| (0..ny).flat_map(move |j| (0..nx).map(move |i| [i, j, k])))
    }

    /// The lattice nodes; the upper faces lie exactly at the box size.
    fn nodes(&self) -> Nodes {
        let mut nodes = Nodes::with_capacity(self.node_count());
        let coordinate = |d: usize, i: usize| self.size[d] * (i as f64 / self.n[d] as f64);
        for k in 0..=self.n[2] {
            for j in 0..=self.n[1] {
                for i in 0..=self.n[0] {
                    nodes.push(Vector3::new(
                        coordinate(0, i),
                        coordinate(1, j),
                        coordinate(2, k),
                    ));
                }
            }
        }
        nodes
    }

    /// The mesh of `nodes` and `block` with the named sets and surfaces of the box.
    fn finish(&self, nodes: Nodes, block: ElementBlock) -> Mesh {
        let shape = block.shape;
        let mut surfaces: [Vec<Face>; 6] = Default::default();
        let mut outer = Vec::new();
        for (e, ids) in block.elements().enumerate() {
            for (f, local) in shape.faces().iter().enumerate() {
                let corners = &local[..shape.face_shape(f).corner_count()];
                for (s, &(_, axis, upper)) in BOX_FACES.iter().enumerate() {
                    let plane = if upper { self.n[axis] } else { 0 };
                    let on_plane = |&l: &u8| {
                        self.ijk(ids[l as usize])
                            .is_some_and(|ijk| ijk[axis] == plane)
                    };
                    if corners.iter().all(on_plane) {
                        let face = Face::new(ElementRef::new(0, e as u32), f as u8);
                        surfaces[s].push(face);
                        outer.push(face);
                    }
                }
            }
        }
        let mut mesh = Mesh::new(nodes, vec![block]);
        for ((name, _, _), faces) in BOX_FACES.iter().zip(surfaces) {
            let mut set = BTreeSet::new();
            for face in &faces {
                let block = &mesh.blocks[0];
                let ids = block.element_nodes(face.element.element as usize);
                let local = block.shape.faces()[face.face as usize];
                set.extend(local.iter().map(|&l| ids[l as usize]));
            }
            mesh.node_sets
                .insert(name.to_string(), set.into_iter().collect());
            mesh.surfaces.insert(name.to_string(), faces);
        }
        mesh.surfaces.insert("outer".to_string(), outer);
        let all = (0..mesh.blocks[0].len() as u32)
            .map(|e| ElementRef::new(0, e))
            .collect();
        mesh.element_sets = BTreeMap::from([("all".to_string(), all)]);
        mesh
    }
}

#[cfg(test)]
mod tests;
