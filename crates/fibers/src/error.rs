//! Errors of the fiber computation. Every variant names the region, block, element or face
//! it concerns (element ids are 0-based, faces S1…S6 as in Abaqus), so that the caller can
//! report it as is.

use std::fmt;

use musclefem_mesh::{ElementShape, MeshError, quoted_list};

/// Which end of the flow a boundary region belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// The origin of the muscle: the flow enters here (potential φ = 1).
    Inlet,
    /// The insertion of the muscle: the flow leaves here (potential φ = 0).
    Outlet,
}

impl fmt::Display for Side {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Side::Inlet => "inlet",
            Side::Outlet => "outlet",
        })
    }
}

/// One element face named by its block's name, for messages.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FaceLabel {
    /// Name of the element block.
    pub block: String,
    /// Element index in the block (0-based).
    pub element: usize,
    /// Local face index (0-based; printed as Abaqus S(face+1)).
    pub face: u8,
}

impl fmt::Display for FaceLabel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "element block '{}', element {}, face S{}",
            self.block,
            self.element,
            u32::from(self.face) + 1
        )
    }
}

/// What a part of the mesh lacks for its potential to be defined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MissingEnd {
    /// It has outlet faces but no inlet face.
    Inlet,
    /// It has inlet faces but no outlet face.
    Outlet,
    /// It has neither.
    Both,
}

impl fmt::Display for MissingEnd {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            MissingEnd::Inlet => "no inlet face",
            MissingEnd::Outlet => "no outlet face",
            MissingEnd::Both => "neither an inlet nor an outlet face",
        })
    }
}

/// Everything that can stop [`crate::compute_fibers`].
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FiberError {
    /// The mesh itself is malformed (node arrays, connectivity out of range, unknown name).
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The mesh has no element.
    #[error("the mesh has no element: there is no flow to compute")]
    EmptyMesh,
    /// A name that is neither a surface nor a node set of the mesh.
    #[error(
        "the mesh has no surface or node set named '{name}'; surfaces: {}; node sets: {}",
        quoted_list(surfaces),
        quoted_list(node_sets)
    )]
    UnknownRegion {
        name: String,
        surfaces: Vec<String>,
        node_sets: Vec<String>,
    },
    /// No region was given for the inlet or the outlet.
    #[error("no {side} given: name at least one surface or node set")]
    NoRegion { side: Side },
    /// A region holds no face or no node.
    #[error("{side} '{name}' is empty")]
    EmptyRegion { side: Side, name: String },
    /// A region refers to a face or node that the mesh does not have.
    #[error("{side} '{name}': {error}")]
    InvalidRegion {
        side: Side,
        name: String,
        error: Box<MeshError>,
    },
    /// A face of a surface region is shared by two elements, so it is not on the boundary.
    #[error(
        "{side} '{name}': {face} is not on the boundary of the mesh (another element shares it)"
    )]
    InteriorFace {
        side: Side,
        name: String,
        face: FaceLabel,
    },
    /// A region selects no boundary face (a node set must hold every corner of a face).
    #[error("{side} '{name}' has no face on the boundary of the mesh")]
    NoBoundaryFace { side: Side, name: String },
    /// A boundary face is both inlet and outlet.
    #[error("inlet '{inlet}' and outlet '{outlet}' share the boundary face {face}")]
    InletOutletOverlap {
        inlet: String,
        outlet: String,
        face: FaceLabel,
    },
    /// An element with zero or negative volume (its corner nodes are in the wrong order or
    /// collapsed).
    #[error(
        "element block '{block}', element {element} ({shape}) is inverted or flat: volume {volume:e} m³"
    )]
    InvertedElement {
        block: String,
        element: usize,
        shape: ElementShape,
        /// Volume of the cell from its corner nodes [m³].
        volume: f64,
    },
    /// More than two element faces have the same corner nodes.
    #[error("{} element faces have the same corner nodes: {}", faces.len(), join(faces))]
    NonManifoldFace { faces: Vec<FaceLabel> },
    /// A cell whose geometry the finite-volume scheme cannot use.
    #[error("element block '{block}', element {element}: {reason}")]
    DegenerateCell {
        block: String,
        element: usize,
        reason: String,
    },
    /// A part of the mesh (elements connected through shared faces) that lacks an inlet
    /// or an outlet face: its potential is not defined.
    #[error(
        "the part of the mesh that holds element block '{block}', element {element} ({cells} elements) has {missing}: its potential is not defined (connect it, give it an inlet and an outlet, or leave it out of the mesh)"
    )]
    DisconnectedPart {
        block: String,
        element: usize,
        cells: usize,
        missing: MissingEnd,
    },
    /// A setting outside its range.
    #[error("invalid flow settings: {reason}")]
    InvalidSettings { reason: String },
    /// The iterations stopped before the residual reached the tolerance.
    #[error(
        "the flow did not converge: relative residual {residual:e} after {sweeps} non-orthogonal correction sweeps and {linear_iterations} CG iterations (tolerance {tolerance:e})"
    )]
    NotConverged {
        sweeps: usize,
        linear_iterations: usize,
        residual: f64,
        tolerance: f64,
    },
    /// The potential gradient of an element is zero or not finite: no direction.
    #[error(
        "element block '{block}', element {element}: the potential gradient ({}, {}, {}) 1/m has no direction",
        gradient[0], gradient[1], gradient[2]
    )]
    UndefinedDirection {
        block: String,
        element: usize,
        gradient: [f64; 3],
    },
}

fn join(faces: &[FaceLabel]) -> String {
    faces
        .iter()
        .map(FaceLabel::to_string)
        .collect::<Vec<_>>()
        .join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_what_they_concern() {
        let face = FaceLabel {
            block: "vastus".into(),
            element: 12,
            face: 2,
        };
        assert_eq!(
            face.to_string(),
            "element block 'vastus', element 12, face S3"
        );
        let e = FiberError::InletOutletOverlap {
            inlet: "origin".into(),
            outlet: "insertion".into(),
            face,
        };
        assert_eq!(
            e.to_string(),
            "inlet 'origin' and outlet 'insertion' share the boundary face element block 'vastus', element 12, face S3"
        );
        let e = FiberError::DisconnectedPart {
            block: "b".into(),
            element: 3,
            cells: 10,
            missing: MissingEnd::Outlet,
        };
        assert!(
            e.to_string()
                .contains("element block 'b', element 3 (10 elements) has no outlet face")
        );
    }
}
