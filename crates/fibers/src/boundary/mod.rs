//! Inlets and outlets: which boundary faces have a fixed potential.
//!
//! The flow enters through the inlet (the muscle's origin, φ = 1) and leaves through the
//! outlet (its insertion, φ = 0); every other boundary face is an impermeable wall
//! (∇φ·n = 0). Each end is a union of [`BoundaryRegion`]s — surfaces (lists of element
//! faces) and node sets — so a branched muscle with several heads is just several
//! regions. [`classify`] turns them into a [`BoundaryKind`] and a region per boundary face.

mod classify;

use musclefem_mesh::{Face, Mesh};

pub(crate) use classify::{BoundaryKind, ClassifiedBoundary, classify_boundary};

use crate::error::FiberError;

/// One piece of an inlet or an outlet.
#[derive(Clone, Debug, PartialEq)]
pub enum BoundaryRegion {
    /// Element faces, e.g. a surface of the mesh. Every face must be on the boundary of
    /// the mesh (not shared by two elements).
    Faces {
        /// Name used in messages.
        name: String,
        /// The faces.
        faces: Vec<Face>,
    },
    /// A node set: the region is every boundary face whose corner nodes are all in it.
    Nodes {
        /// Name used in messages.
        name: String,
        /// Node ids.
        nodes: Vec<u32>,
    },
}

impl BoundaryRegion {
    /// The surface `name` of `mesh`. Errors if there is none.
    pub fn surface(mesh: &Mesh, name: &str) -> Result<Self, FiberError> {
        Ok(Self::Faces {
            name: name.to_string(),
            faces: mesh.surface(name)?.to_vec(),
        })
    }

    /// The node set `name` of `mesh`. Errors if there is none.
    pub fn node_set(mesh: &Mesh, name: &str) -> Result<Self, FiberError> {
        Ok(Self::Nodes {
            name: name.to_string(),
            nodes: mesh.node_set(name)?.to_vec(),
        })
    }

    /// The surface `name` of `mesh` if it has one, otherwise its node set `name`. Errors
    /// if it has neither, listing the names it has.
    pub fn named(mesh: &Mesh, name: &str) -> Result<Self, FiberError> {
        if mesh.surfaces.contains_key(name) {
            Self::surface(mesh, name)
        } else if mesh.node_sets.contains_key(name) {
            Self::node_set(mesh, name)
        } else {
            Err(FiberError::UnknownRegion {
                name: name.to_string(),
                surfaces: mesh.surfaces.keys().cloned().collect(),
                node_sets: mesh.node_sets.keys().cloned().collect(),
            })
        }
    }

    /// The name given to the region.
    pub fn name(&self) -> &str {
        match self {
            Self::Faces { name, .. } | Self::Nodes { name, .. } => name,
        }
    }
}

/// The two ends of the flow, each the union of its regions.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlowBoundary {
    /// Where the flow enters: the muscle's origin, potential φ = 1.
    pub inlet: Vec<BoundaryRegion>,
    /// Where the flow leaves: the muscle's insertion, potential φ = 0.
    pub outlet: Vec<BoundaryRegion>,
}

impl FlowBoundary {
    /// An inlet and an outlet of one region each.
    pub fn new(inlet: BoundaryRegion, outlet: BoundaryRegion) -> Self {
        Self {
            inlet: vec![inlet],
            outlet: vec![outlet],
        }
    }

    /// The regions of `mesh` with these names (each a surface, or else a node set: see
    /// [`BoundaryRegion::named`]).
    pub fn from_names<S: AsRef<str>>(
        mesh: &Mesh,
        inlet: &[S],
        outlet: &[S],
    ) -> Result<Self, FiberError> {
        let regions = |names: &[S]| -> Result<Vec<BoundaryRegion>, FiberError> {
            names
                .iter()
                .map(|name| BoundaryRegion::named(mesh, name.as_ref()))
                .collect()
        };
        Ok(Self {
            inlet: regions(inlet)?,
            outlet: regions(outlet)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use musclefem_mesh::generate::box_of_hexes;

    use super::*;

    #[test]
    fn names_resolve_to_surfaces_then_node_sets() {
        let mut mesh = box_of_hexes([1.0; 3], [2, 2, 2]).unwrap();
        let nodes = mesh.node_sets.remove("x1").unwrap();
        mesh.node_sets.insert("tip".to_string(), nodes);
        let boundary = FlowBoundary::from_names(&mesh, &["x0"], &["tip"]).unwrap();
        assert!(
            matches!(&boundary.inlet[0], BoundaryRegion::Faces { name, faces } if name == "x0" && faces.len() == 4)
        );
        assert!(
            matches!(&boundary.outlet[0], BoundaryRegion::Nodes { nodes, .. } if nodes.len() == 9)
        );
        assert_eq!(boundary.outlet[0].name(), "tip");
        let err = FlowBoundary::from_names(&mesh, &["x0"], &["nowhere"]).unwrap_err();
        let message = err.to_string();
        assert!(
            message.contains("'nowhere'") && message.contains("'tip'"),
            "{message}"
        );
        let err = BoundaryRegion::surface(&mesh, "tip").unwrap_err();
        assert!(err.to_string().contains("no surface named 'tip'"), "{err}");
    }
}
