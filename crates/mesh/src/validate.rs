//! [`Mesh::validate`]: the checks a solver relies on before it trusts a mesh.

use nalgebra::Vector3;
use rayon::prelude::*;

use super::error::{MeshError, NameKind};
use super::shape::MAX_NODES_PER_ELEMENT;
use super::{CHUNK, ElementBlock, Mesh, Nodes};

/// An element is degenerate when its smallest det J × reference volume is at most this
/// fraction of the cube of its longest corner-to-corner edge (a thin but sound element
/// with aspect ratio 10⁴ is at about 10⁻⁸).
const DEGENERATE: f64 = 1e-12;

impl Mesh {
    /// Checks the mesh and returns the first problem found, in this order:
    ///
    /// 1. node arrays of one length, at most 2³² nodes, finite positions;
    /// 2. block names unique; each block's connectivity a whole number of elements, at
    ///    most 2³² of them, one fiber direction per element;
    /// 3. per element (in block, then element order): every node id in range, no node
    ///    repeated, a finite non-zero fiber, and a positive Jacobian at every sample point
    ///    of [`super::ElementShape::min_jacobian_volume`] (above 10⁻¹² × longest edge³, so
    ///    flat elements fail too) — the error names the block, the element and the value;
    /// 4. node sets, element sets and surfaces refer to existing nodes, elements and
    ///    faces — the error names the set.
    pub fn validate(&self) -> Result<(), MeshError> {
        self.validate_nodes()?;
        for (b, block) in self.blocks.iter().enumerate() {
            if self.blocks[..b]
                .iter()
                .any(|other| other.name == block.name)
            {
                return Err(MeshError::DuplicateBlockName {
                    name: block.name.clone(),
                });
            }
            validate_block(block, &self.nodes)?;
        }
        self.validate_sets()
    }

    fn validate_nodes(&self) -> Result<(), MeshError> {
        let nodes = &self.nodes;
        self.check_node_arrays()?;
        if nodes.len() > u32::MAX as usize + 1 {
            return Err(MeshError::TooManyNodes { count: nodes.len() });
        }
        let bad = (0..nodes.len()).into_par_iter().find_first(|&i| {
            !(nodes.x[i].is_finite() && nodes.y[i].is_finite() && nodes.z[i].is_finite())
        });
        match bad {
            Some(node) => Err(MeshError::NonFiniteNode {
                node,
                x: nodes.x[node],
                y: nodes.y[node],
                z: nodes.z[node],
            }),
            None => Ok(()),
        }
    }

    fn validate_sets(&self) -> Result<(), MeshError> {
        let node_count = self.nodes.len();
        for (name, ids) in &self.node_sets {
            if let Some(&node) = ids.iter().find(|&&id| id as usize >= node_count) {
                return Err(in_set(NameKind::NodeSet, name)(MeshError::UnknownNode {
                    node,
                    node_count,
                }));
            }
        }
        for (name, elements) in &self.element_sets {
            for &element in elements {
                self.element_nodes(element)
                    .map_err(in_set(NameKind::ElementSet, name))?;
            }
        }
        for (name, faces) in &self.surfaces {
            for &face in faces {
                self.face_nodes(face)
                    .map_err(in_set(NameKind::Surface, name))?;
            }
        }
        Ok(())
    }
}

/// Wraps an error in the named set it was found in.
fn in_set(kind: NameKind, name: &str) -> impl Fn(MeshError) -> MeshError + '_ {
    move |error| MeshError::InSet {
        kind,
        name: name.to_string(),
        error: Box::new(error),
    }
}

/// Checks 2 and 3 of [`Mesh::validate`] for one block.
fn validate_block(block: &ElementBlock, nodes: &Nodes) -> Result<(), MeshError> {
    let n = block.shape.nodes_per_element();
    if !block.connectivity.len().is_multiple_of(n) {
        return Err(MeshError::ConnectivityLength {
            block: block.name.clone(),
            shape: block.shape,
            len: block.connectivity.len(),
        });
    }
    if block.len() > u32::MAX as usize + 1 {
        return Err(MeshError::TooManyElements {
            block: block.name.clone(),
            count: block.len(),
        });
    }
    if block.fiber_direction.len() != block.len() {
        return Err(MeshError::FiberCount {
            block: block.name.clone(),
            elements: block.len(),
            fibers: block.fiber_direction.len(),
        });
    }
    let chunks = block.len().div_ceil(CHUNK);
    let first = (0..chunks).into_par_iter().find_map_first(|c| {
        (c * CHUNK..((c + 1) * CHUNK).min(block.len()))
            .find_map(|e| check_element(block, e, nodes).err())
    });
    first.map_or(Ok(()), Err)
}

/// Check 3 of [`Mesh::validate`] for element `e` of `block`.
fn check_element(block: &ElementBlock, e: usize, nodes: &Nodes) -> Result<(), MeshError> {
    let ids = block.element_nodes(e);
    let name = || block.name.clone();
    for (local, &node) in ids.iter().enumerate() {
        if node as usize >= nodes.len() {
            return Err(MeshError::NodeOutOfRange {
                block: name(),
                element: e,
                local,
                node,
                node_count: nodes.len(),
            });
        }
    }
    for first in 0..ids.len() {
        if let Some(k) = ids[first + 1..].iter().position(|&id| id == ids[first]) {
            return Err(MeshError::RepeatedNode {
                block: name(),
                element: e,
                node: ids[first],
                first,
                second: first + 1 + k,
            });
        }
    }
    let fiber = block.fiber_direction[e];
    if !(fiber.iter().all(|c| c.is_finite()) && fiber.norm_squared() > 0.0) {
        return Err(MeshError::InvalidFiber {
            block: name(),
            element: e,
            direction: [fiber.x, fiber.y, fiber.z],
        });
    }
    let shape = block.shape;
    let mut coords = [Vector3::zeros(); MAX_NODES_PER_ELEMENT];
    nodes.gather(ids, &mut coords);
    let coords = &coords[..ids.len()];
    let min_jacobian_volume = shape.min_jacobian_volume(coords);
    let longest_edge = shape
        .edges()
        .iter()
        .map(|&[a, b]| (coords[a as usize] - coords[b as usize]).norm())
        .fold(0.0, f64::max);
    if min_jacobian_volume.is_nan() || min_jacobian_volume <= DEGENERATE * longest_edge.powi(3) {
        return Err(MeshError::InvertedElement {
            block: name(),
            element: e,
            shape,
            min_jacobian_volume,
            volume: shape.volume(coords),
            longest_edge,
        });
    }
    Ok(())
}
