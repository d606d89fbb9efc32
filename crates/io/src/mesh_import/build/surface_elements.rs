//! 2-D elements of an Abaqus deck (R3D3/R3D4, S3/S4, M3D3/M3D4, ...) as surfaces: each
//! is matched by its corners to the face of a volume element; the surface and a node set
//! of its nodes are named after the `*ELEMENT`'s `ELSET=` (or its type) and after every
//! `*ELSET` that lists it.

use std::collections::{BTreeMap, HashMap};

use musclefem_mesh::{ElementRef, Face, Mesh};

use super::super::face_match::FaceIndex;
use super::{Loc, RawMesh};
use crate::mesh_import::ImportError;

/// A 2-D element as read.
#[derive(Debug)]
pub(crate) struct RawSurfaceElement {
    pub label: i64,
    pub type_name: String,
    /// The surface (and node set) it belongs to: the `ELSET=` of its `*ELEMENT`, or the type.
    pub surface: String,
    /// Node labels, corners first.
    pub nodes: Vec<i64>,
    pub corners: usize,
    pub loc: Loc,
}

/// What an element label names: a volume element, or a 2-D element (index into
/// [`RawMesh::surface_elements`]) with the volume face it lies on, if any.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Target {
    Volume(ElementRef),
    Surface(usize, Option<Face>),
}

impl Target {
    pub fn volume(self) -> Option<ElementRef> {
        match self {
            Target::Volume(r) => Some(r),
            Target::Surface(..) => None,
        }
    }
}

type Warnings = Vec<(Loc, String, String)>;

impl RawMesh {
    /// Every element label with what it names; 2-D elements matched to volume faces (a
    /// warning for each that lies on none).
    pub(super) fn surface_targets(
        &self,
        element_ids: &HashMap<i64, ElementRef>,
        warnings: &mut Warnings,
    ) -> Result<HashMap<i64, Target>, ImportError> {
        let mut targets: HashMap<i64, Target> = element_ids
            .iter()
            .map(|(&label, &r)| (label, Target::Volume(r)))
            .collect();
        if self.surface_elements.is_empty() {
            return Ok(targets);
        }
        let faces = FaceIndex::new(&self.blocks);
        for (i, element) in self.surface_elements.iter().enumerate() {
            let corners = element.nodes.get(..element.corners).unwrap_or_default();
            let face = faces
                .find(corners)
                .and_then(|(label, face)| element_ids.get(&label).map(|&r| Face::new(r, face)));
            if face.is_none() {
                warnings.push((
                    element.loc,
                    "ELEMENT".into(),
                    format!(
                        "*ELEMENT, TYPE={}: 2-D elements on no face of a volume element are \
                         kept only in the node set '{}'",
                        element.type_name, element.surface
                    ),
                ));
            }
            if targets
                .insert(element.label, Target::Surface(i, face))
                .is_some()
            {
                return Err(self.error(
                    element.loc,
                    format!(
                        "element {} ({}) is defined twice",
                        element.label, element.type_name
                    ),
                ));
            }
        }
        Ok(targets)
    }

    /// Adds a surface and a node set per `*ELEMENT` block of 2-D elements and per element
    /// set that holds 2-D elements (`sets`: name and resolved members).
    pub(super) fn add_element_surfaces(
        &self,
        mesh: &mut Mesh,
        node_ids: &HashMap<i64, u32>,
        targets: &HashMap<i64, Target>,
        sets: Vec<(String, Vec<Target>)>,
    ) -> Result<(), ImportError> {
        let mut groups: BTreeMap<String, Vec<Target>> = BTreeMap::new();
        for element in &self.surface_elements {
            if let Some(&target) = targets.get(&element.label) {
                groups
                    .entry(element.surface.clone())
                    .or_default()
                    .push(target);
            }
        }
        for (name, members) in sets {
            groups.entry(name).or_default().extend(members);
        }
        let defined: Vec<String> = mesh.node_sets.keys().cloned().collect();
        for (name, members) in groups {
            let mut faces = Vec::new();
            let mut nodes = Vec::new();
            for target in members {
                let Target::Surface(i, face) = target else {
                    continue;
                };
                let element = &self.surface_elements[i];
                faces.extend(face);
                for label in &element.nodes {
                    let id = node_ids.get(label).ok_or_else(|| {
                        self.error(
                            element.loc,
                            format!(
                                "element {} ({}): node {label} is not defined",
                                element.label, element.type_name
                            ),
                        )
                    })?;
                    nodes.push(*id);
                }
            }
            if !faces.is_empty() {
                let surface = mesh.surfaces.entry(name.clone()).or_default();
                surface.extend(faces);
                surface.sort_unstable();
                surface.dedup();
            }
            if !defined.contains(&name) {
                let set = mesh.node_sets.entry(name).or_default();
                set.extend(nodes);
                set.sort_unstable();
                set.dedup();
            }
        }
        Ok(())
    }
}
