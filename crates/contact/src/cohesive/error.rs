//! Why a cohesive interface cannot be built.

use thiserror::Error;

/// Errors of [`super::CohesiveInterface`] construction.
#[derive(Debug, Error)]
pub enum CohesiveError {
    #[error("cohesive interface '{interface}': {reason}")]
    InvalidSettings { interface: String, reason: String },
    #[error(
        "cohesive interface '{interface}': no node of the secondary surface '{secondary}' \
         ({nodes} nodes) lies within the bond tolerance {tolerance:.3e} m of the main \
         surface '{main}' (closest: {closest:.3e} m), so nothing bonds"
    )]
    NoBond {
        interface: String,
        secondary: String,
        main: String,
        nodes: usize,
        tolerance: f64,
        closest: f64,
    },
    #[error("cohesive interface '{interface}': {reason}")]
    InvalidSurface { interface: String, reason: String },
}
