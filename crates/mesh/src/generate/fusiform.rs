//! The elongation specimen of the paper (seed §2.2): a fusiform muscle 50 mm long along
//! its axis z, 9 mm across at both ends (the smallest cross-section) and 17.5 mm at
//! mid-length (the largest), fibers along the axis; and a cylinder of the same length,
//! whose homogeneous stretch has a closed-form answer, for verification.
//!
//! The mesh ([`fusiform_mesh`]) is structured: every cross-section is the same O-grid of
//! the unit disc (module `o_grid`: a bulged square of `n × n` quads inside a ring of
//! `4n × m` quads), scaled by the radius r(z) and placed at one of `axial + 1` layers
//! spaced in proportion to r(z) (see [`SpecimenShape::layer_heights`]), so that every
//! slab of elements is close to a scaled copy of the mid-belly one. Between two layers
//! each quad sweeps one hex8, or six tets. Lengths are in metres.

pub(super) mod o_grid;
mod prism_split;

use std::f64::consts::PI;

use nalgebra::Vector3;

use super::add_mid_edge_nodes;
use crate::{ElementBlock, ElementShape, Mesh, MeshError, Nodes};
use o_grid::{UnitSection, polygon_area, ring_thickness};
use prism_split::tets;

/// Length of the paper's specimen along its axis [m] (50 mm).
pub const PAPER_LENGTH: f64 = 0.050;
/// Radius of the paper's specimen at its ends [m] (diameter 9 mm).
pub const PAPER_END_RADIUS: f64 = 0.0045;
/// Radius of the paper's specimen at mid-length, the mid-belly [m] (diameter 17.5 mm).
pub const PAPER_MID_RADIUS: f64 = 0.00875;

const GENERATOR: &str = "fusiform_mesh";

/// The shape of a specimen: a solid of revolution about the z axis, z ∈ [0, L].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpecimenShape {
    /// A fusiform (spindle) solid of radius
    ///
    /// r(z) = r_end + (r_mid − r_end) sin²(π z / L)   [m],   z ∈ [0, L] [m].
    ///
    /// The profile is smooth, r = r_end at both ends and r_mid at z = L/2, and its slope
    /// dr/dz = (r_mid − r_end)(π/L) sin(2π z/L) vanishes at the ends as well as at
    /// mid-length: the side meets the end caps at right angles, so each gripped end face
    /// is exactly the smallest cross-section, without a sharp rim, and the solid is
    /// symmetric about mid-length. (The profile r_end + (r_mid − r_end) sin(π z/L) would
    /// meet the ends at a slope of 0.27, a 15° rim, for the paper's sizes.)
    Fusiform {
        /// Length L along the axis [m].
        length: f64,
        /// Radius r_end at z = 0 and z = L [m].
        end_radius: f64,
        /// Radius r_mid at z = L/2 [m].
        mid_radius: f64,
    },
    /// A circular cylinder, r(z) = radius [m], for homogeneous-deformation checks.
    Cylinder {
        /// Length L along the axis [m].
        length: f64,
        /// Radius [m].
        radius: f64,
    },
}

impl SpecimenShape {
    /// The paper's fusiform specimen: L = 50 mm, r_end = 4.5 mm, r_mid = 8.75 mm.
    pub fn paper_fusiform() -> Self {
        SpecimenShape::Fusiform {
            length: PAPER_LENGTH,
            end_radius: PAPER_END_RADIUS,
            mid_radius: PAPER_MID_RADIUS,
        }
    }

    /// A cylinder as long as the paper's specimen (50 mm) of radius `radius` [m]; the
    /// paper's mid-belly radius is [`PAPER_MID_RADIUS`].
    pub fn cylinder(radius: f64) -> Self {
        SpecimenShape::Cylinder {
            length: PAPER_LENGTH,
            radius,
        }
    }

    /// Length L along the axis [m].
    pub fn length(&self) -> f64 {
        match *self {
            SpecimenShape::Fusiform { length, .. } | SpecimenShape::Cylinder { length, .. } => {
                length
            }
        }
    }

    /// Radius r(z) [m] of the cross-section at height `z` [m] (see the variants).
    pub fn radius(&self, z: f64) -> f64 {
        match *self {
            SpecimenShape::Fusiform {
                length,
                end_radius,
                mid_radius,
            } => end_radius + (mid_radius - end_radius) * (PI * z / length).sin().powi(2),
            SpecimenShape::Cylinder { radius, .. } => radius,
        }
    }

    /// Largest radius over z ∈ [0, L] [m].
    pub fn max_radius(&self) -> f64 {
        match *self {
            SpecimenShape::Fusiform {
                end_radius,
                mid_radius,
                ..
            } => end_radius.max(mid_radius),
            SpecimenShape::Cylinder { radius, .. } => radius,
        }
    }

    /// Smallest radius over z ∈ [0, L] [m].
    pub fn min_radius(&self) -> f64 {
        match *self {
            SpecimenShape::Fusiform {
                end_radius,
                mid_radius,
                ..
            } => end_radius.min(mid_radius),
            SpecimenShape::Cylinder { radius, .. } => radius,
        }
    }

    /// Reference mid-belly cross-section area π r(L/2)² [m²]: the area the engineering
    /// stress of the elongation test divides the reaction force by.
    pub fn mid_belly_area(&self) -> f64 {
        PI * self.radius(0.5 * self.length()).powi(2)
    }

    /// Volume ∫₀ᴸ π r(z)² dz [m³]. Fusiform: π L [r_end² + r_end Δ + (3/8) Δ²] with
    /// Δ = r_mid − r_end (the means of sin² and sin⁴ over [0, L] are 1/2 and 3/8);
    /// cylinder: π r² L.
    pub fn volume(&self) -> f64 {
        match *self {
            SpecimenShape::Fusiform {
                length,
                end_radius: a,
                mid_radius,
            } => {
                let d = mid_radius - a;
                PI * length * (a * a + a * d + 0.375 * d * d)
            }
            SpecimenShape::Cylinder { length, radius } => PI * radius * radius * length,
        }
    }

    /// Heights z_k [m] of `layers + 1` node layers, k = 0..=layers, from 0 to L, spaced in
    /// proportion to the radius (Δz ∝ r): equal steps of Z(z) = ∫₀^z dζ / r(ζ).
    ///
    /// For the fusiform, with θ = π z / L,
    /// Z = (L/π) atan(√(r_mid/r_end) tan θ) / √(r_end r_mid), so with ψ_k = π k / layers
    ///
    /// z_k = (L/π) atan2(√r_end sin ψ_k, √r_mid cos ψ_k);
    ///
    /// the cylinder's layers are equally spaced. The heights are computed for
    /// k ≤ layers/2 and mirrored, so they are symmetric about L/2 and hit 0, L/2 (for even
    /// `layers`) and L exactly.
    pub fn layer_heights(&self, layers: usize) -> Vec<f64> {
        let length = self.length();
        let graded = |fraction: f64| match *self {
            SpecimenShape::Fusiform {
                end_radius,
                mid_radius,
                ..
            } => {
                let psi = PI * fraction;
                let theta = (end_radius.sqrt() * psi.sin()).atan2(mid_radius.sqrt() * psi.cos());
                length * theta / PI
            }
            SpecimenShape::Cylinder { .. } => length * fraction,
        };
        (0..=layers)
            .map(|k| {
                let mirrored = 2 * k > layers;
                let j = if mirrored { layers - k } else { k };
                let z = if 2 * j == layers {
                    0.5 * length
                } else {
                    graded(j as f64 / layers as f64)
                };
                if mirrored { length - z } else { z }
            })
            .collect()
    }

    /// ∫₀ᴸ R_max / r(z) dz [m]: the length of the axis measured in elements of the
    /// largest section's size, so that `layer_heights` needs about this / h layers for
    /// elements of size h at the largest section (and h r(z)/R_max elsewhere). Fusiform:
    /// R_max L / √(r_end r_mid); cylinder: L.
    pub fn graded_length(&self) -> f64 {
        match *self {
            SpecimenShape::Fusiform {
                length,
                end_radius,
                mid_radius,
            } => self.max_radius() * length / (end_radius * mid_radius).sqrt(),
            SpecimenShape::Cylinder { length, .. } => length,
        }
    }

    /// Errors unless the length and the radii are finite and positive.
    fn check(&self) -> Result<(), MeshError> {
        let (length, radii) = match *self {
            SpecimenShape::Fusiform {
                length,
                end_radius,
                mid_radius,
            } => (
                length,
                vec![("end radius", end_radius), ("mid radius", mid_radius)],
            ),
            SpecimenShape::Cylinder { length, radius } => (length, vec![("radius", radius)]),
        };
        for (name, value) in [("length", length)].into_iter().chain(radii) {
            if !(value.is_finite() && value > 0.0) {
                return Err(invalid(format!(
                    "the specimen's {name} {value} m must be finite and positive"
                )));
            }
        }
        Ok(())
    }
}

/// What to mesh: the specimen's shape, the element shape and the target element size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecimenSpec {
    /// The solid to mesh.
    pub shape: SpecimenShape,
    /// hex8 (one per O-grid cell and layer), tet4 or tet10 (six per cell and layer).
    pub element: ElementShape,
    /// Target element edge length h [m] at the largest cross-section (elements shrink
    /// with r(z) elsewhere), at most the smallest radius (see [`SpecimenSpec::divisions`]).
    pub mesh_size: f64,
}

/// The divisions of the structured mesh (see [`SpecimenSpec::divisions`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpecimenDivisions {
    /// Cells n along each side of the O-grid's inner block, i.e. per quarter of the
    /// circumference (even).
    pub per_side: usize,
    /// Cell layers m of the O-grid's ring.
    pub radial: usize,
    /// Element layers along the axis (even), spaced by [`SpecimenShape::layer_heights`].
    pub axial: usize,
}

impl SpecimenDivisions {
    /// Quads of one cross-section: n² + 4 n m.
    pub fn cells_per_section(&self) -> usize {
        self.per_side * self.per_side + 4 * self.per_side * self.radial
    }

    /// Nodes of one cross-section (corner nodes): (n + 1)² + 4 n m.
    pub fn nodes_per_section(&self) -> usize {
        (self.per_side + 1).pow(2) + 4 * self.per_side * self.radial
    }

    /// Elements of the mesh: (n² + 4 n m) · axial hex8, or six times as many tets.
    pub fn element_count(&self, element: ElementShape) -> usize {
        let per_cell = match element {
            ElementShape::Hex8 => 1,
            ElementShape::Tet4 | ElementShape::Tet10 => 6,
        };
        per_cell * self.cells_per_section() * self.axial
    }
}

impl SpecimenSpec {
    /// The paper's fusiform specimen ([`SpecimenShape::paper_fusiform`]) meshed with
    /// `element` of size `mesh_size` [m].
    pub fn paper(element: ElementShape, mesh_size: f64) -> Self {
        Self {
            shape: SpecimenShape::paper_fusiform(),
            element,
            mesh_size,
        }
    }

    /// The divisions for the target size h = `mesh_size`, sized on the largest
    /// cross-section (radius R = [`SpecimenShape::max_radius`]):
    ///
    /// - `per_side` n: the smallest even integer ≥ π R / (2h), so that the 4n edges
    ///   around the largest circumference 2πR are at most h long;
    /// - `radial` m = ⌈w R / h⌉ ≥ 1, w ≈ 0.428 the ring's relative thickness at the
    ///   middle of the inner block's sides, so ring cells are about h thick there;
    /// - `axial`: the smallest even integer ≥ [`SpecimenShape::graded_length`] / h (so
    ///   z = L/2 is a node layer): the layers are spaced by Δz ≤ h r(z)/R.
    ///
    /// Every section has the same cells scaled by r(z)/R, and the layers are spaced in
    /// the same proportion, so elements shrink towards the fusiform's ends, in all three
    /// directions, by down to r_end/r_mid (0.51 for the paper's specimen), where the thin
    /// ends strain most. The cylinder's elements are all of size h. Within a section, the
    /// inner block's cells are about 0.73 h across and the ring's radial edges 0.5–0.7 h
    /// long (thinnest on the diagonals).
    ///
    /// Errors if the shape is not usable (non-positive or non-finite length or radius),
    /// h is not finite and positive or exceeds the smallest radius, or the mesh would
    /// have more than 2³² nodes or elements.
    pub fn divisions(&self) -> Result<SpecimenDivisions, MeshError> {
        self.shape.check()?;
        let h = self.mesh_size;
        if !(h.is_finite() && h > 0.0) {
            return Err(invalid(format!(
                "mesh size {h:e} m must be finite and positive"
            )));
        }
        let smallest = self.shape.min_radius();
        if h > smallest {
            return Err(invalid(format!(
                "mesh size {h:e} m is larger than the specimen's smallest radius {smallest:e} m"
            )));
        }
        let radius = self.shape.max_radius();
        // A relative 1e-9 below an integer counts as that integer (round-off in L / h).
        let at_least = |x: f64| (x * (1.0 - 1e-9)).ceil();
        let even_at_least = |x: f64| 2.0 * at_least(0.5 * x);
        let per_side = even_at_least(PI * radius / (2.0 * h)).max(2.0);
        let radial = at_least(ring_thickness() * radius / h).max(1.0);
        let axial = even_at_least(self.shape.graded_length() / h).max(2.0);
        let too_many = || {
            invalid(format!(
                "mesh size {h:e} m gives more than 2^32 nodes or elements"
            ))
        };
        if [per_side, radial, axial]
            .iter()
            .any(|&d| d > u32::MAX as f64)
        {
            return Err(too_many());
        }
        let divisions = SpecimenDivisions {
            per_side: per_side as usize,
            radial: radial as usize,
            axial: axial as usize,
        };
        // Tets: at most six edges (so six tet10 mid-edge nodes) per tet.
        let cells = divisions
            .cells_per_section()
            .checked_mul(divisions.axial)
            .and_then(|c| c.checked_mul(6))
            .ok_or_else(too_many)?;
        let nodes = divisions
            .nodes_per_section()
            .checked_mul(divisions.axial + 1)
            .and_then(|n| n.checked_add(cells.checked_mul(6)?))
            .ok_or_else(too_many)?;
        if cells > u32::MAX as usize || nodes > u32::MAX as usize {
            return Err(too_many());
        }
        Ok(divisions)
    }

    /// Mid-belly cross-section area of the mesh [m²]: the section z = L/2 is a node
    /// layer, the regular 4n-gon inscribed in the circle of radius r_mid, of area
    /// 2n sin(π/(2n)) r(L/2)² (below [`SpecimenShape::mid_belly_area`] by about
    /// π²/(24 n²): 0.64 % for n = 8). Errors as [`SpecimenSpec::divisions`].
    pub fn mesh_mid_belly_area(&self) -> Result<f64, MeshError> {
        let per_side = self.divisions()?.per_side;
        let r = self.shape.radius(0.5 * self.shape.length());
        Ok(polygon_area(per_side) * r * r)
    }
}

/// The structured mesh of `spec`: hex8, or tets that split the same hexes.
///
/// Names (the elongation test's grips and measurements):
///
/// - block `muscle`, every fiber e_z; element set `all`;
/// - surfaces `origin` (the element faces on the end z = 0), `insertion` (on z = L),
///   `lateral` (the curved side) and `outer` (all boundary faces, in element order);
/// - node sets `origin`, `insertion`, `lateral`: the nodes of those surfaces (mid-edge
///   nodes included); `mid_belly`: the nodes on the plane z = L/2 (a node layer, as
///   `axial` is even);
/// - single-node sets `axis_origin` (0, 0, 0), `axis_insertion` (0, 0, L) and
///   `origin_rim_x` (r(0), 0, 0). A sliding grip (u_z = 0 on `origin`, the end face free
///   to contract laterally) leaves three rigid-body motions: u_x = u_y = 0 on
///   `axis_origin` and u_y = 0 on `origin_rim_x` remove them without restraining the
///   contraction.
///
/// Nodes: the P section nodes (see [`SpecimenDivisions::nodes_per_section`]) of layer
/// k = 0..=axial have ids k·P + p; tet10 mid-edge nodes follow.
///
/// Tets: each section quad is cut into two triangles along its shorter diagonal (the same
/// in every layer, the sections being scaled copies), and each triangular prism between
/// two layers into three tets by the rule of Dompierre et al. (1999): every vertical quad
/// face is cut along its diagonal through the face's smallest node id. Neighbouring
/// prisms see the same ids on a shared face and cut it alike, so the mesh is conforming,
/// and this rule never gives one of the two cyclic cut patterns along which a prism
/// cannot be split. tet10 mid-edge nodes sit at the midpoints of the straight edges, so
/// tet10 has the same geometry as tet4. All faces of a hex are planar (its side faces lie
/// in planes through the point where the straight lines of r between two layers reach
/// the axis), so the tets fill exactly the hex volume.
///
/// Errors as [`SpecimenSpec::divisions`].
pub fn fusiform_mesh(spec: &SpecimenSpec) -> Result<Mesh, MeshError> {
    let divisions = spec.divisions()?;
    let section = UnitSection::new(divisions.per_side, divisions.radial);
    let axial = divisions.axial;
    let mut nodes = layered_nodes(&spec.shape, &section, axial);
    let connectivity = match spec.element {
        ElementShape::Hex8 => hexes(&section, axial),
        ElementShape::Tet4 => tets(&section, axial, &nodes),
        ElementShape::Tet10 => {
            let corners = tets(&section, axial, &nodes);
            add_mid_edge_nodes(&mut nodes, &corners)
        }
    };
    let block = ElementBlock::new("muscle", spec.element, connectivity)?;
    finish(nodes, block, &section, axial)
}

/// The section's nodes scaled by r(z_k) at each layer z_k of
/// [`SpecimenShape::layer_heights`], k = 0..=axial.
fn layered_nodes(shape: &SpecimenShape, section: &UnitSection, axial: usize) -> Nodes {
    let mut nodes = Nodes::with_capacity(section.node_count() * (axial + 1));
    for z in shape.layer_heights(axial) {
        let r = shape.radius(z);
        for p in &section.points {
            nodes.push(Vector3::new(r * p.x, r * p.y, z));
        }
    }
    nodes
}

/// Hex8 connectivity: each section quad (counter-clockwise seen from +z) at layer k, then
/// the same quad at layer k + 1 (the Abaqus C3D8 order).
fn hexes(section: &UnitSection, axial: usize) -> Vec<u32> {
    let per_layer = section.node_count() as u32;
    let mut connectivity = Vec::with_capacity(section.quads.len() * axial * 8);
    for k in 0..axial as u32 {
        for quad in &section.quads {
            connectivity.extend(quad.iter().map(|&p| p + k * per_layer));
            connectivity.extend(quad.iter().map(|&p| p + (k + 1) * per_layer));
        }
    }
    connectivity
}

/// The mesh of `nodes` and `block` (fibers set to e_z) with the named sets and surfaces.
fn finish(
    nodes: Nodes,
    mut block: ElementBlock,
    section: &UnitSection,
    axial: usize,
) -> Result<Mesh, MeshError> {
    block.fiber_direction = vec![Vector3::z(); block.len()];
    let mut mesh = Mesh::new(nodes, vec![block]);
    let per_layer = section.node_count();
    super::end_sets::insert_end_sets(&mut mesh, per_layer, axial)?;

    // Every node of the mid layer, mid-edge nodes included, has exactly its z.
    let z_mid = mesh.nodes.z[(axial / 2) * per_layer];
    let mid_belly = (0..mesh.nodes.len() as u32)
        .filter(|&id| mesh.nodes.z[id as usize] == z_mid)
        .collect();
    mesh.node_sets.insert("mid_belly".to_string(), mid_belly);
    let top = (axial * per_layer) as u32;
    for (name, id) in [
        ("axis_origin", section.centre),
        ("axis_insertion", section.centre + top),
        ("origin_rim_x", section.rim_x),
    ] {
        mesh.node_sets.insert(name.to_string(), vec![id]);
    }
    Ok(mesh)
}

fn invalid(reason: String) -> MeshError {
    MeshError::InvalidArgument {
        generator: GENERATOR,
        reason,
    }
}

#[cfg(test)]
mod tests;
