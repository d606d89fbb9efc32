//! Errors of the mesh. Every variant names the block, element, node or set it concerns
//! (ids are 0-based), so that the caller can report it as is.

use std::fmt;

use super::shape::ElementShape;

/// The kinds of named things a mesh holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NameKind {
    /// An element block ([`super::ElementBlock::name`]).
    Block,
    /// A node set ([`super::Mesh::node_sets`]).
    NodeSet,
    /// An element set ([`super::Mesh::element_sets`]).
    ElementSet,
    /// A surface ([`super::Mesh::surfaces`]).
    Surface,
}

impl fmt::Display for NameKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            NameKind::Block => "element block",
            NameKind::NodeSet => "node set",
            NameKind::ElementSet => "element set",
            NameKind::Surface => "surface",
        })
    }
}

/// Everything that can be wrong with a mesh or a request to it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// The coordinate arrays of [`super::Nodes`] differ in length.
    #[error("node coordinate arrays differ in length: x has {x}, y has {y}, z has {z}")]
    NodeArrayLengths { x: usize, y: usize, z: usize },
    /// More nodes than `u32` ids can name.
    #[error("{count} nodes: node ids are u32, so a mesh holds at most 2^32 nodes")]
    TooManyNodes { count: usize },
    /// A node coordinate is NaN or infinite.
    #[error("node {node} has a non-finite position ({x}, {y}, {z}) m")]
    NonFiniteNode { node: usize, x: f64, y: f64, z: f64 },
    /// Two blocks have the same name.
    #[error("two element blocks are named '{name}'")]
    DuplicateBlockName { name: String },
    /// A block's connectivity is not a whole number of elements.
    #[error(
        "element block '{block}': the connectivity has {len} entries, not a multiple of the {} nodes of a {shape}",
        shape.nodes_per_element()
    )]
    ConnectivityLength {
        block: String,
        shape: ElementShape,
        len: usize,
    },
    /// A block has more elements than `u32` ids can name.
    #[error("element block '{block}' has {count} elements: element ids are u32")]
    TooManyElements { block: String, count: usize },
    /// A block does not have one fiber direction per element.
    #[error("element block '{block}': {fibers} fiber directions for {elements} elements")]
    FiberCount {
        block: String,
        elements: usize,
        fibers: usize,
    },
    /// A fiber direction is not a finite non-zero vector.
    #[error(
        "element block '{block}', element {element}: fiber direction ({}, {}, {}) is not a finite non-zero vector",
        direction[0], direction[1], direction[2]
    )]
    InvalidFiber {
        block: String,
        element: usize,
        direction: [f64; 3],
    },
    /// An element refers to a node that does not exist.
    #[error(
        "element block '{block}', element {element}: local node {local} is node {node}, but the mesh has {node_count} nodes"
    )]
    NodeOutOfRange {
        block: String,
        element: usize,
        local: usize,
        node: u32,
        node_count: usize,
    },
    /// An element lists the same node twice.
    #[error(
        "element block '{block}', element {element}: node {node} appears twice (local nodes {first} and {second})"
    )]
    RepeatedNode {
        block: String,
        element: usize,
        node: u32,
        first: usize,
        second: usize,
    },
    /// An element is inverted or flat: det J is not positive at some sample point.
    #[error(
        "element block '{block}', element {element} ({shape}) is inverted or degenerate: smallest det J × reference volume = {min_jacobian_volume:e} m³ (element volume {volume:e} m³, longest edge {longest_edge:e} m)"
    )]
    InvertedElement {
        block: String,
        element: usize,
        shape: ElementShape,
        /// See [`ElementShape::min_jacobian_volume`] [m³].
        min_jacobian_volume: f64,
        /// [m³].
        volume: f64,
        /// [m].
        longest_edge: f64,
    },
    /// A block index that the mesh does not have.
    #[error("there is no element block {block}: the mesh has {count} blocks")]
    BlockOutOfRange { block: u32, count: usize },
    /// An element index that the block does not have.
    #[error("element block '{block}' has no element {element}: it has {count} elements")]
    ElementOutOfRange {
        block: String,
        element: u32,
        count: usize,
    },
    /// A local face index that the element's shape does not have.
    #[error(
        "element block '{block}', element {element}: a {shape} has no face {face} (faces are 0..{})",
        shape.face_count()
    )]
    FaceOutOfRange {
        block: String,
        element: u32,
        shape: ElementShape,
        face: u8,
    },
    /// A node id that the mesh does not have.
    #[error("there is no node {node}: the mesh has {node_count} nodes")]
    UnknownNode { node: u32, node_count: usize },
    /// A name looked up in the mesh that it does not hold.
    #[error("the mesh has no {kind} named '{name}'; known: {}", quoted_list(known))]
    UnknownName {
        kind: NameKind,
        name: String,
        known: Vec<String>,
    },
    /// Something wrong inside a named set or surface.
    #[error("{kind} '{name}': {error}")]
    InSet {
        kind: NameKind,
        name: String,
        error: Box<MeshError>,
    },
    /// An argument of a generator is unusable (sizes, divisions, amplitudes).
    #[error("{generator}: {reason}")]
    InvalidArgument {
        generator: &'static str,
        reason: String,
    },
}

/// The names quoted and joined by commas (`'a', 'b'`), or `none`, for error messages.
pub fn quoted_list(names: &[String]) -> String {
    if names.is_empty() {
        "none".to_string()
    } else {
        names
            .iter()
            .map(|n| format!("'{n}'"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_what_they_concern() {
        let e = MeshError::UnknownName {
            kind: NameKind::NodeSet,
            name: "x2".into(),
            known: vec!["x0".into(), "x1".into()],
        };
        assert_eq!(
            e.to_string(),
            "the mesh has no node set named 'x2'; known: 'x0', 'x1'"
        );
        let e = MeshError::InSet {
            kind: NameKind::Surface,
            name: "outer".into(),
            error: Box::new(MeshError::FaceOutOfRange {
                block: "b".into(),
                element: 3,
                shape: ElementShape::Tet4,
                face: 4,
            }),
        };
        assert_eq!(
            e.to_string(),
            "surface 'outer': element block 'b', element 3: a tet4 has no face 4 (faces are 0..4)"
        );
    }
}
