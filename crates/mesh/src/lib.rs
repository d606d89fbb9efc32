//! The finite-element mesh: nodes, element blocks, node sets, element sets and surfaces.
//!
//! - [`Nodes`]: reference positions [m] as a structure of arrays;
//! - [`ElementBlock`]: elements of one [`ElementShape`] (hex8, tet4, tet10) with a flat
//!   connectivity and a fiber direction per element;
//! - [`ElementRef`] and [`Face`]: an element, or one face of it, across blocks;
//! - [`Mesh`]: all of these, with named sets, lookups, volumes and [`Mesh::validate`];
//! - [`generate`]: structured boxes of hexes and tets, Cook's membrane, the fusiform
//!   muscle specimen (and a cylinder) on an O-grid, and a random interior distortion;
//! - [`geometry`]: shape-function gradients, Jacobians, volumes and face area vectors.
//!
//! A mesh is plain data with public fields, so that importers, generators and solvers use
//! it directly; nothing is checked until [`Mesh::validate`], which a solver calls once
//! before it trusts the connectivity. Lookups that take an id or a name check it and
//! return a [`MeshError`] naming what is missing.

mod block;
mod error;
pub mod generate;
pub mod geometry;
mod nodes;
mod refs;
mod shape;
mod topology;
mod validate;

use std::collections::BTreeMap;

use nalgebra::Vector3;
use rayon::prelude::*;

pub use block::ElementBlock;
pub use error::{MeshError, NameKind, quoted_list};
pub use nodes::Nodes;
pub use refs::{ElementRef, Face, FaceNodes};
pub use shape::{ElementShape, FaceShape, MAX_FACE_NODES, MAX_NODES_PER_ELEMENT};
pub use topology::NodeElements;

/// Elements per task in parallel loops over a block (and the size of the partial sums,
/// which keeps sums independent of the number of threads).
const CHUNK: usize = 4096;

/// A finite-element mesh in the reference configuration. Ids are 0-based indices: a
/// node's id indexes [`Nodes`], a block's index [`Mesh::blocks`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Node positions [m].
    pub nodes: Nodes,
    /// Element blocks, each of one shape; names are unique.
    pub blocks: Vec<ElementBlock>,
    /// Named sets of node ids (for boundary conditions and outputs).
    pub node_sets: BTreeMap<String, Vec<u32>>,
    /// Named sets of elements (for materials, sections and outputs).
    pub element_sets: BTreeMap<String, Vec<ElementRef>>,
    /// Named surfaces, made of element faces (for loads, contact and cohesion).
    pub surfaces: BTreeMap<String, Vec<Face>>,
}

impl Mesh {
    /// A mesh of these nodes and blocks, without sets or surfaces.
    pub fn new(nodes: Nodes, blocks: Vec<ElementBlock>) -> Self {
        Self {
            nodes,
            blocks,
            ..Self::default()
        }
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Number of elements over all blocks.
    pub fn element_count(&self) -> usize {
        self.blocks.iter().map(ElementBlock::len).sum()
    }

    /// Block number `block`.
    pub fn block(&self, block: u32) -> Result<&ElementBlock, MeshError> {
        self.blocks
            .get(block as usize)
            .ok_or(MeshError::BlockOutOfRange {
                block,
                count: self.blocks.len(),
            })
    }

    /// The index and the block named `name`.
    pub fn block_by_name(&self, name: &str) -> Result<(u32, &ElementBlock), MeshError> {
        self.blocks
            .iter()
            .enumerate()
            .find(|(_, b)| b.name == name)
            .map(|(i, b)| (i as u32, b))
            .ok_or_else(|| MeshError::UnknownName {
                kind: NameKind::Block,
                name: name.to_string(),
                known: self.blocks.iter().map(|b| b.name.clone()).collect(),
            })
    }

    /// The node set named `name`.
    pub fn node_set(&self, name: &str) -> Result<&[u32], MeshError> {
        lookup(&self.node_sets, NameKind::NodeSet, name)
    }

    /// The element set named `name`.
    pub fn element_set(&self, name: &str) -> Result<&[ElementRef], MeshError> {
        lookup(&self.element_sets, NameKind::ElementSet, name)
    }

    /// The surface named `name`.
    pub fn surface(&self, name: &str) -> Result<&[Face], MeshError> {
        lookup(&self.surfaces, NameKind::Surface, name)
    }

    /// Node ids of an element, in local order.
    pub fn element_nodes(&self, element: ElementRef) -> Result<&[u32], MeshError> {
        let block = self.block(element.block)?;
        if element.element as usize >= block.len() {
            return Err(MeshError::ElementOutOfRange {
                block: block.name.clone(),
                element: element.element,
                count: block.len(),
            });
        }
        Ok(block.element_nodes(element.element as usize))
    }

    /// Node ids of an element face, ordered so that its right-hand normal points out of
    /// the element.
    pub fn face_nodes(&self, face: Face) -> Result<FaceNodes, MeshError> {
        let block = self.block(face.element.block)?;
        let nodes = self.element_nodes(face.element)?;
        let local =
            block
                .shape
                .face(face.face as usize)
                .ok_or_else(|| MeshError::FaceOutOfRange {
                    block: block.name.clone(),
                    element: face.element.element,
                    shape: block.shape,
                    face: face.face,
                })?;
        Ok(FaceNodes::from_local(nodes, local))
    }

    /// Volume [m³] of one element (see [`ElementShape::volume`]).
    pub fn element_volume(&self, element: ElementRef) -> Result<f64, MeshError> {
        let shape = self.block(element.block)?.shape;
        let ids = self.element_nodes(element)?;
        let coords = self.coordinates(ids)?;
        Ok(shape.volume(&coords[..ids.len()]))
    }

    /// Vector area [m²] of an element face: its area times its outward unit normal when
    /// it is flat (see [`FaceShape::area_vector`]).
    pub fn face_area_vector(&self, face: Face) -> Result<Vector3<f64>, MeshError> {
        let shape = self.block(face.element.block)?.shape;
        let ids = self.face_nodes(face)?;
        let coords = self.coordinates(&ids)?;
        Ok(shape
            .face_shape(face.face as usize)
            .area_vector(&coords[..ids.len()]))
    }

    /// Sum of the element volumes [m³] over all blocks. Checks that every connectivity
    /// entry is a node (not that elements are valid: see [`Mesh::validate`]). The sum
    /// does not depend on the number of threads.
    pub fn total_volume(&self) -> Result<f64, MeshError> {
        self.check_connectivity_range()?;
        Ok((0..self.blocks.len())
            .map(|b| self.volume_of_block(b))
            .sum())
    }

    /// Sum of the element volumes of block `block` [m³], checked as
    /// [`Mesh::total_volume`].
    pub fn block_volume(&self, block: usize) -> Result<f64, MeshError> {
        self.check_connectivity_range()?;
        self.block(block as u32)?;
        Ok(self.volume_of_block(block))
    }

    fn volume_of_block(&self, block: usize) -> f64 {
        let block = &self.blocks[block];
        let shape = block.shape;
        let n = shape.nodes_per_element();
        let partial: Vec<f64> = block
            .connectivity
            .par_chunks(CHUNK * n)
            .map(|chunk| {
                let mut coords = [Vector3::zeros(); MAX_NODES_PER_ELEMENT];
                chunk
                    .chunks_exact(n)
                    .map(|ids| {
                        self.nodes.gather(ids, &mut coords);
                        shape.volume(&coords[..n])
                    })
                    .sum::<f64>()
            })
            .collect();
        partial.iter().sum::<f64>()
    }

    /// Positions of the nodes `ids` (at most [`MAX_NODES_PER_ELEMENT`]), checked.
    fn coordinates(&self, ids: &[u32]) -> Result<[Vector3<f64>; MAX_NODES_PER_ELEMENT], MeshError> {
        self.check_node_arrays()?;
        let mut coords = [Vector3::zeros(); MAX_NODES_PER_ELEMENT];
        for (c, &id) in coords.iter_mut().zip(ids) {
            if id as usize >= self.nodes.len() {
                return Err(MeshError::UnknownNode {
                    node: id,
                    node_count: self.nodes.len(),
                });
            }
            *c = self.nodes.position(id as usize);
        }
        Ok(coords)
    }

    /// Errors if the node coordinate arrays differ in length.
    pub(crate) fn check_node_arrays(&self) -> Result<(), MeshError> {
        let nodes = &self.nodes;
        if nodes.x.len() != nodes.y.len() || nodes.x.len() != nodes.z.len() {
            return Err(MeshError::NodeArrayLengths {
                x: nodes.x.len(),
                y: nodes.y.len(),
                z: nodes.z.len(),
            });
        }
        Ok(())
    }

    /// Errors on node arrays of different lengths and on the first connectivity entry
    /// (by block, element, local node) that is not a node id.
    pub(crate) fn check_connectivity_range(&self) -> Result<(), MeshError> {
        self.check_node_arrays()?;
        let count = self.nodes.len();
        for block in &self.blocks {
            if let Some(i) = block
                .connectivity
                .par_iter()
                .position_first(|&id| id as usize >= count)
            {
                let n = block.shape.nodes_per_element();
                return Err(MeshError::NodeOutOfRange {
                    block: block.name.clone(),
                    element: i / n,
                    local: i % n,
                    node: block.connectivity[i],
                    node_count: count,
                });
            }
        }
        Ok(())
    }
}

fn lookup<'a, T>(
    map: &'a BTreeMap<String, Vec<T>>,
    kind: NameKind,
    name: &str,
) -> Result<&'a [T], MeshError> {
    map.get(name)
        .map(Vec::as_slice)
        .ok_or_else(|| MeshError::UnknownName {
            kind,
            name: name.to_string(),
            known: map.keys().cloned().collect(),
        })
}

#[cfg(test)]
mod tests;

/// The README's examples, compiled and run by `cargo test --doc`.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
