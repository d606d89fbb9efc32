//! The deformable surfaces of a scene's `[[interactions]]`: one part surface
//! `"PART.SURFACE"` or a list of them joined into one surface (a muscle's belly and tendon,
//! parts sharing a file's nodes), the faces of a surface within a band of heights (where
//! a cohesive interface may bond), and the default penalty of each node of a contact's
//! secondary surface (a node presses with the stiffest of the parts that hold it).

use std::ops::Range;

use nalgebra::Vector3;
use toml::Spanned;

use musclefem_contact::{DeformableSurface, default_penalty};
use musclefem_core::mesh::{Face, Mesh};
use musclefem_core::solver::Part;

use super::error::{Locator, SceneError, suggestion};
use super::format::{BondBandEntry, InteractionEntry, OneOrMany};
use super::locking::small_strain_shear_modulus;

/// A surface of one part or of several, with the parts it lies on.
pub(super) struct PartSurface {
    /// The parts of its faces, in the order listed (indices into the scene's parts).
    pub parts: Vec<usize>,
    pub surface: DeformableSurface,
}

/// The surface `names` names: one `"PART.SURFACE"`, or the faces of several in the order
/// listed, as one surface named after them joined by `+`.
pub(super) fn part_surfaces(
    names: &Spanned<OneOrMany>,
    mesh: &Mesh,
    part_names: &[String],
    locator: &Locator,
) -> Result<PartSurface, SceneError> {
    let span = names.span();
    let listed = names.get_ref().names();
    if listed.is_empty() {
        return Err(locator.error(span, "an empty list of surfaces".to_string()));
    }
    let mut parts = Vec::with_capacity(listed.len());
    let mut faces: Vec<Face> = Vec::new();
    for (i, full) in listed.iter().enumerate() {
        if listed[..i].contains(full) {
            return Err(locator.error(span.clone(), format!("'{full}' is listed twice")));
        }
        parts.push(part_of_surface(
            full,
            span.clone(),
            mesh,
            part_names,
            locator,
        )?);
        faces.extend_from_slice(&mesh.surfaces[full]);
    }
    let name = listed.join("+");
    let surface = DeformableSurface::from_faces(mesh, &name, &faces)
        .map_err(|e| locator.error(span, e.to_string()))?;
    Ok(PartSurface { parts, surface })
}

/// The index of the part of the part surface `full` ("PART.SURFACE"), which `mesh` has.
fn part_of_surface(
    full: &str,
    span: Range<usize>,
    mesh: &Mesh,
    part_names: &[String],
    locator: &Locator,
) -> Result<usize, SceneError> {
    let Some((part, surface)) = full.split_once('.') else {
        return Err(locator.error(
            span,
            format!("'{full}' is not a part surface \"PART.SURFACE\""),
        ));
    };
    let Some(index) = part_names.iter().position(|p| p == part) else {
        return Err(locator.error(
            span,
            format!(
                "unknown part '{part}'{}",
                suggestion(part, part_names.iter().map(String::as_str))
            ),
        ));
    };
    if !mesh.surfaces.contains_key(full) {
        let prefix = format!("{part}.");
        let known: Vec<&str> = mesh
            .surfaces
            .keys()
            .filter_map(|k| k.strip_prefix(&prefix))
            .collect();
        return Err(locator.error(
            span,
            format!(
                "part '{part}' has no surface '{surface}'{}; it has: {}",
                suggestion(surface, known.iter().copied()),
                known.join(", ")
            ),
        ));
    }
    Ok(index)
}

/// The triangles of `surface` whose centroids (the mean of their corners at the
/// reference positions) lie at heights x · axis between `band.heights` [m], both
/// included, as a surface of their own. Errors on a zero or non-finite axis, heights out
/// of order, or a band without a triangle.
pub(super) fn faces_in_band(
    entry: &InteractionEntry,
    surface: &DeformableSurface,
    band: &Spanned<BondBandEntry>,
    mesh: &Mesh,
    locator: &Locator,
) -> Result<DeformableSurface, SceneError> {
    let at = |message: String| {
        let name = entry.name.get_ref();
        locator.error(band.span(), format!("interaction '{name}': {message}"))
    };
    let BondBandEntry { axis, heights } = band.get_ref();
    let axis = Vector3::from(*axis);
    let length = axis.norm();
    if !(length.is_finite() && length > 0.0) {
        return Err(at(format!(
            "bond_band: axis {axis:?} has no direction; give a non-zero vector"
        )));
    }
    let axis = axis / length;
    let [low, high] = *heights;
    if !(low.is_finite() && high.is_finite() && low <= high) {
        return Err(at(format!(
            "bond_band: heights [{low}, {high}] must be finite, the lower first"
        )));
    }
    let triangles = surface.triangles_between_heights(mesh, &axis, [low, high]);
    if triangles.is_empty() {
        return Err(at(format!(
            "bond_band: no face of '{}' has its centroid between heights {low} and {high} m",
            surface.name
        )));
    }
    let name = format!("{} between heights {low} and {high} m", surface.name);
    DeformableSurface::from_triangles(mesh, &name, triangles).map_err(|e| at(e.to_string()))
}

/// The default penalty ε = 10 E / h [N/m³] of every node of `secondary` (in the order of
/// its nodes), h its element size and E ≈ 3 μ of the material of the stiffest of its
/// parts `surface_parts` whose elements hold the node (a muscle's tendon nodes press with
/// the tendon's ε, its belly's with the belly's); `entry` is the interaction's.
pub(super) fn default_node_penalties(
    entry: &InteractionEntry,
    secondary: &DeformableSurface,
    surface_parts: &[usize],
    parts: &[Part],
    mesh: &Mesh,
    locator: &Locator,
) -> Result<Vec<f64>, SceneError> {
    let name = entry.name.get_ref();
    let at = |message: String| {
        locator.error(
            entry.secondary.span(),
            format!("interaction '{name}': {message}"),
        )
    };
    let mut penalties = vec![0.0_f64; secondary.nodes.len()];
    for &p in surface_parts {
        let shear = small_strain_shear_modulus(parts[p].material.as_ref()).ok_or_else(|| {
            at(
                "the secondary part's material gives no shear modulus for the default \
                penalty; give penalty_stiffness"
                    .to_string(),
            )
        })?;
        // Nearly incompressible: E = 2 μ (1 + ν) ≈ 3 μ.
        let penalty = default_penalty(3.0 * shear, secondary.element_size())
            .map_err(|e| at(e.to_string()))?;
        for &n in &mesh.blocks[parts[p].block].connectivity {
            if let Some(i) = secondary.local_index(n) {
                penalties[i] = penalties[i].max(penalty);
            }
        }
    }
    Ok(penalties)
}
