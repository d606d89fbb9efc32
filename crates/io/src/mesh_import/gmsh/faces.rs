//! Matching the 2-D elements of physical surfaces to faces of volume elements.

use std::collections::BTreeMap;

use super::super::build::{Entry, Member};
use super::super::face_match::FaceIndex;
use super::{Reader, SurfaceElement};
use crate::mesh_import::ImportError;

/// A surface as the raw mesh holds it: name and (element entry, face) pairs.
type RawSurface = (String, Vec<(Entry, u8)>);

/// One surface per physical surface group, in group order.
pub(super) fn surfaces(reader: &Reader) -> Result<Vec<RawSurface>, ImportError> {
    if reader.surface_elements.is_empty() {
        return Ok(Vec::new());
    }
    let faces = FaceIndex::new(&reader.raw.blocks);
    let mut surfaces: BTreeMap<(i64, i64), Vec<(Entry, u8)>> = BTreeMap::new();
    for element in &reader.surface_elements {
        let SurfaceElement {
            tag,
            entity,
            groups,
            corners,
            loc,
        } = element;
        let (label, face) = faces.find(corners).ok_or_else(|| {
            reader.raw.error(
                *loc,
                format!(
                    "$Elements: surface element {tag} on surface {entity} (nodes {corners:?}) \
                     is not a face of any volume element"
                ),
            )
        })?;
        for &g in groups {
            surfaces.entry((2, g)).or_default().push((
                Entry {
                    member: Member::Label(label),
                    loc: *loc,
                },
                face,
            ));
        }
    }
    Ok(surfaces
        .into_iter()
        .map(|((dim, tag), faces)| (reader.group_name(dim, tag), faces))
        .collect())
}
