//! Random, reproducible distortion of the interior nodes of a mesh, for patch tests.

use nalgebra::Vector3;

use super::super::error::MeshError;
use super::super::refs::ElementRef;
use super::super::shape::MAX_NODES_PER_ELEMENT;
use super::super::{ElementBlock, Mesh};

/// A trial move is kept only if every element around the node keeps at least this
/// fraction of its initial smallest Jacobian (see
/// [`super::super::ElementShape::min_jacobian_volume`]).
const KEEP: f64 = 0.2;
/// A rejected trial move is halved at most this many times before the node stays put.
const HALVINGS: usize = 6;

/// Moves every interior corner node of a valid `mesh` by a random vector of length up to
/// `amplitude` × (the shortest edge at that node); `amplitude` is dimensionless, 0.2–0.3
/// makes a visibly irregular mesh. Returns the number of nodes moved.
///
/// - Interior: not on a boundary face ([`Mesh::boundary_faces`]); boundary nodes and
///   the boundary (hence the total volume) stay as they are.
/// - Mid-edge nodes are not moved on their own: those on an edge with a moved corner are
///   put at the edge's midpoint, so quadratic elements keep straight edges inside.
/// - Valid by construction: a move is kept only if every element around the node keeps
///   a fifth of its smallest Jacobian; otherwise it is halved (up to 6 times) or dropped.
/// - Reproducible: the same mesh, amplitude and seed give the same nodes (SplitMix64).
///
/// Errors if `mesh` is not valid ([`Mesh::validate`]) or `amplitude` is not finite and
/// non-negative.
pub fn distort(mesh: &mut Mesh, amplitude: f64, seed: u64) -> Result<usize, MeshError> {
    if !(amplitude.is_finite() && amplitude >= 0.0) {
        return Err(MeshError::InvalidArgument {
            generator: "distort",
            reason: format!("amplitude {amplitude} must be finite and non-negative"),
        });
    }
    mesh.validate()?;
    let count = mesh.nodes.len();
    let mut fixed = vec![false; count];
    for face in mesh.boundary_faces()? {
        for &id in mesh.face_nodes(face)?.iter() {
            fixed[id as usize] = true;
        }
    }
    let mut mid_edge = vec![false; count];
    for block in &mesh.blocks {
        for ids in block.elements() {
            for &id in &ids[block.shape.corner_count()..] {
                mid_edge[id as usize] = true;
            }
        }
    }
    let around = mesh.node_elements()?;
    let initial: Vec<Vec<f64>> = mesh
        .blocks
        .iter()
        .map(|block| {
            (0..block.len())
                .map(|e| min_jacobian(mesh, block, e, None))
                .collect()
        })
        .collect();
    let mut random = SplitMix64(seed);
    let mut moved = 0;
    for node in 0..count {
        let elements = around.of(node);
        if fixed[node] || mid_edge[node] || elements.is_empty() {
            continue;
        }
        let direction = random.in_unit_ball();
        let mut step = amplitude * shortest_edge(mesh, elements, node as u32);
        let start = mesh.nodes.position(node);
        for _ in 0..=HALVINGS {
            let trial = start + step * direction;
            let keeps = elements.iter().all(|r| {
                let block = &mesh.blocks[r.block as usize];
                let q = min_jacobian(
                    mesh,
                    block,
                    r.element as usize,
                    Some((node as u32, trial, &fixed)),
                );
                q >= KEEP * initial[r.block as usize][r.element as usize]
            });
            if keeps {
                move_node(mesh, elements, node as u32, trial, &fixed);
                moved += 1;
                break;
            }
            step *= 0.5;
        }
    }
    Ok(moved)
}

/// The moved node: its id, trial position [m], and which nodes are fixed.
type Trial<'a> = (u32, Vector3<f64>, &'a [bool]);

/// Smallest Jacobian volume of element `e` of `block`, with the trial move applied.
fn min_jacobian(mesh: &Mesh, block: &ElementBlock, e: usize, trial: Option<Trial>) -> f64 {
    let ids = block.element_nodes(e);
    let mut coords = [Vector3::zeros(); MAX_NODES_PER_ELEMENT];
    mesh.nodes.gather(ids, &mut coords);
    if let Some((node, position, fixed)) = trial {
        apply(block, ids, &mut coords, node, position, fixed);
    }
    block.shape.min_jacobian_volume(&coords[..ids.len()])
}

/// Puts `node` at `position` in the element coordinates `coords` and the free mid-edge
/// nodes of its edges at their midpoints.
fn apply(
    block: &ElementBlock,
    ids: &[u32],
    coords: &mut [Vector3<f64>],
    node: u32,
    position: Vector3<f64>,
    fixed: &[bool],
) {
    let Some(local) = ids.iter().position(|&id| id == node) else {
        return;
    };
    coords[local] = position;
    for (edge, &[a, b]) in block.shape.edges().iter().enumerate() {
        let (a, b) = (a as usize, b as usize);
        if let Some(m) = block.shape.mid_edge_node(edge) {
            let m = m as usize;
            if (a == local || b == local) && !fixed[ids[m] as usize] {
                coords[m] = 0.5 * (coords[a] + coords[b]);
            }
        }
    }
}

/// Writes the accepted move of `node` (and its mid-edge nodes) into the mesh.
fn move_node(
    mesh: &mut Mesh,
    elements: &[ElementRef],
    node: u32,
    position: Vector3<f64>,
    fixed: &[bool],
) {
    for r in elements {
        let block = &mesh.blocks[r.block as usize];
        let ids = block.element_nodes(r.element as usize);
        let mut coords = [Vector3::zeros(); MAX_NODES_PER_ELEMENT];
        mesh.nodes.gather(ids, &mut coords);
        apply(block, ids, &mut coords, node, position, fixed);
        for (&id, p) in ids.iter().zip(coords) {
            mesh.nodes.set_position(id as usize, p);
        }
    }
}

/// Length [m] of the shortest corner-to-corner edge at `node`.
fn shortest_edge(mesh: &Mesh, elements: &[ElementRef], node: u32) -> f64 {
    let mut shortest = f64::INFINITY;
    for r in elements {
        let block = &mesh.blocks[r.block as usize];
        let ids = block.element_nodes(r.element as usize);
        for &[a, b] in block.shape.edges() {
            let (a, b) = (ids[a as usize], ids[b as usize]);
            if a == node || b == node {
                let d = mesh.nodes.position(a as usize) - mesh.nodes.position(b as usize);
                shortest = shortest.min(d.norm());
            }
        }
    }
    shortest
}

/// SplitMix64 (Steele, Lea, Flood 2014): a small, fast, reproducible generator.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [−1, 1).
    fn symmetric(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (2.0 / (1u64 << 53) as f64) - 1.0
    }

    /// Uniform in the unit ball (rejection from the cube).
    fn in_unit_ball(&mut self) -> Vector3<f64> {
        loop {
            let v = Vector3::new(self.symmetric(), self.symmetric(), self.symmetric());
            if v.norm_squared() <= 1.0 {
                return v;
            }
        }
    }
}
