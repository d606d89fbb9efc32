//! Why a set of tendon strands cannot be built: each error names the interaction and the
//! strand (its index in the list given, from 0).

use thiserror::Error;

/// Errors of [`super::TendonStrands::new`].
#[derive(Debug, Error, PartialEq)]
pub enum StrandError {
    /// The list of strands is empty.
    #[error("tendon strands '{interaction}': no strand, so nothing pulls")]
    Empty { interaction: String },
    /// The slack length ℓ₀ is not a positive finite length.
    #[error(
        "tendon strands '{interaction}': strand {strand}: slack length {value} m must be \
         positive and finite"
    )]
    SlackLength {
        interaction: String,
        strand: usize,
        value: f64,
    },
    /// The strain stiffness k = E A is not a positive finite force.
    #[error(
        "tendon strands '{interaction}': strand {strand}: strain stiffness {value} N must be \
         positive and finite"
    )]
    StrainStiffness {
        interaction: String,
        strand: usize,
        value: f64,
    },
    /// The toe strain ε_l is negative or not finite.
    #[error(
        "tendon strands '{interaction}': strand {strand}: toe strain {value} must be zero or \
         positive and finite"
    )]
    ToeStrain {
        interaction: String,
        strand: usize,
        value: f64,
    },
    /// Both ends are the same node.
    #[error("tendon strands '{interaction}': strand {strand} joins node {node} to itself")]
    SameNode {
        interaction: String,
        strand: usize,
        node: u32,
    },
    /// An end names a node the mesh does not have.
    #[error(
        "tendon strands '{interaction}': strand {strand}: node {node} does not exist (the \
         mesh has {node_count})"
    )]
    NodeOutOfRange {
        interaction: String,
        strand: usize,
        node: u32,
        node_count: usize,
    },
}

impl StrandError {
    /// The index of the strand at fault (none when the list is empty).
    pub fn strand(&self) -> Option<usize> {
        match self {
            StrandError::Empty { .. } => None,
            StrandError::SlackLength { strand, .. }
            | StrandError::StrainStiffness { strand, .. }
            | StrandError::ToeStrain { strand, .. }
            | StrandError::SameNode { strand, .. }
            | StrandError::NodeOutOfRange { strand, .. } => Some(*strand),
        }
    }
}
