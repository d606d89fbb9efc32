//! A muscle swept along a 3-D centreline: elliptical cross-sections of varying semi-axes,
//! perpendicular to a smooth curve through given stations, meshed with hex8 on the
//! O-grid of the fusiform specimen.
//!
//! # Geometry ([`SweptSolid`])
//! The solid is described by ≥ 2 [`SweptStation`]s, from the origin to the insertion:
//! a centre c_i [m], a width direction w_i and the half-width a_i and half-thickness b_i
//! [m] of the cross-section there. Between them (module `centreline`) the centre follows
//! a centripetal Catmull–Rom spline c(t) and a, b and w are monotone cubic interpolants
//! over the same parameter. At every point of the curve the cross-section lies in the
//! plane normal to the unit tangent τ = c'/|c'|; its axes are
//!
//! d₁ = (w − (w·τ) τ) / |w − (w·τ) τ|   (the width axis),   d₂ = τ × d₁,
//!
//! and it is the ellipse {c + u d₁ + v d₂ : (u/a)² + (v/b)² ≤ 1}. By Pappus' theorem
//! (the section's centroid is on the curve and the section is normal to it) the volume
//! is V = ∫ π a(s) b(s) ds over the arclength s, as long as the sections do not overlap
//! (curvature radius above the section's extent in the bending plane).
//!
//! # Mesh ([`swept_muscle_mesh`])
//! Every layer is the O-grid of the unit disc (`per_side` × `per_side` inner cells and
//! `radial` rings, as in `fusiform_mesh`) mapped to the ellipse by
//! (x, y) ↦ c + k (a x d₁ + b y d₂) with k = √(π / A_n), A_n the area of the unit
//! O-grid's outer 4n-gon: the polygonal section then has exactly the ellipse's area πab
//! (its corners lie k − 1 ≈ π²/(48 n²) outside the ellipse, 1.3 % for n = 4), so the mesh
//! volume equals ∫ π a b ds up to the O(h²) error of the straight edges along the curve.
//! The `axial + 1` layers are spaced in proportion to the local size √(ab): equal steps
//! of Z(s) = ∫ ds / √(a b). Between two layers each quad sweeps one hex8 (Abaqus C3D8
//! order, positive Jacobian since (d₁, d₂, τ) is right-handed). The fiber direction of an
//! element is the mean of the unit tangents of its two layers ("along the centreline";
//! the fibers crate computes a flow-based field later).

mod centreline;
mod grading;

use std::f64::consts::PI;

use nalgebra::Vector3;

use super::fusiform::o_grid::{UnitSection, polygon_area};
use crate::{ElementBlock, ElementShape, Mesh, MeshError, Nodes};
use centreline::{Centreline, invert};

const GENERATOR: &str = "swept_muscle_mesh";

/// Profiles carried by the centreline: half-width, half-thickness, then the three
/// components of the width direction.
const HALF_WIDTH: usize = 0;
const HALF_THICKNESS: usize = 1;
const WIDTH_DIRECTION: usize = 2;

/// One control station of a swept muscle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweptStation {
    /// Centre of the cross-section [m].
    pub centre: Vector3<f64>,
    /// Direction of the section's width axis (any length, not along the centreline); it
    /// is projected onto the section's plane.
    pub width_direction: Vector3<f64>,
    /// Semi-axis a along the width axis [m].
    pub half_width: f64,
    /// Semi-axis b along the thickness axis d₂ = τ × d₁ [m].
    pub half_thickness: f64,
}

/// One cross-section of a [`SweptSolid`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Section {
    /// Centre on the centreline [m].
    pub centre: Vector3<f64>,
    /// Unit tangent τ of the centreline, from origin towards insertion.
    pub tangent: Vector3<f64>,
    /// Unit width axis d₁.
    pub width_axis: Vector3<f64>,
    /// Unit thickness axis d₂ = τ × d₁.
    pub thickness_axis: Vector3<f64>,
    /// Semi-axis a along d₁ [m].
    pub half_width: f64,
    /// Semi-axis b along d₂ [m].
    pub half_thickness: f64,
}

impl Section {
    /// The point at elliptical coordinates (u, v) [m]: c + u d₁ + v d₂.
    pub fn point(&self, u: f64, v: f64) -> Vector3<f64> {
        self.centre + u * self.width_axis + v * self.thickness_axis
    }

    /// Approximate signed distance [m] from the ellipse's boundary of the point at
    /// in-plane coordinates (u, v): f / |∇f| with f = (u/a)² + (v/b)² − 1 where that is
    /// accurate (|f| < ½, exact to first order at the boundary), else (√(f + 1) − 1)·min(a, b).
    /// Negative inside.
    pub fn signed_distance(&self, u: f64, v: f64) -> f64 {
        let (a, b) = (self.half_width, self.half_thickness);
        let f = (u / a).powi(2) + (v / b).powi(2) - 1.0;
        if f.abs() < 0.5 {
            let gradient = 2.0 * (u * u / a.powi(4) + v * v / b.powi(4)).sqrt();
            f / gradient.max(f64::MIN_POSITIVE)
        } else {
            ((f + 1.0).sqrt() - 1.0) * a.min(b)
        }
    }
}

/// The continuous solid of a swept muscle (see the module documentation).
#[derive(Clone, Debug)]
pub struct SweptSolid {
    curve: Centreline,
    /// (t, arclength) at the quadrature sub-interval ends.
    arclength: Vec<(f64, f64)>,
}

impl SweptSolid {
    /// The solid through `stations`. Errors unless there are at least two stations,
    /// every value is finite, the semi-axes are positive, consecutive centres differ,
    /// the width direction is nowhere within 10° of the centreline's tangent, and the
    /// centreline nowhere bends so sharply that neighbouring sections overlap (curvature
    /// × the section's extent towards the centre of curvature below 1, checked at the
    /// quadrature points).
    pub fn new(stations: &[SweptStation]) -> Result<Self, MeshError> {
        if stations.len() < 2 {
            return Err(invalid(format!(
                "a swept muscle needs at least two stations, got {}",
                stations.len()
            )));
        }
        for (i, s) in stations.iter().enumerate() {
            let finite = s
                .centre
                .iter()
                .chain(s.width_direction.iter())
                .all(|x| x.is_finite());
            if !(finite && s.half_width > 0.0 && s.half_thickness > 0.0) {
                return Err(invalid(format!(
                    "station {i} must be finite with positive semi-axes: {s:?}"
                )));
            }
            if s.width_direction.norm() == 0.0 {
                return Err(invalid(format!("station {i} has a zero width direction")));
            }
            if i > 0 && (s.centre - stations[i - 1].centre).norm() == 0.0 {
                return Err(invalid(format!("stations {} and {i} coincide", i - 1)));
            }
        }
        let mut profiles = vec![
            stations.iter().map(|s| s.half_width).collect(),
            stations.iter().map(|s| s.half_thickness).collect(),
        ];
        for k in 0..3 {
            profiles.push(
                stations
                    .iter()
                    .map(|s| s.width_direction.normalize()[k])
                    .collect(),
            );
        }
        let curve = Centreline::new(stations.iter().map(|s| s.centre).collect(), &profiles);
        let arclength = curve.cumulative(|t| curve.derivative(t).norm());
        let solid = Self { curve, arclength };
        for &(t, _) in &solid.arclength {
            let tangent = solid.curve.derivative(t).normalize();
            let w = solid.width_direction(t);
            if w.cross(&tangent).norm() < 10f64.to_radians().sin() * w.norm() {
                return Err(invalid(format!(
                    "the width direction {w:?} is within 10° of the centreline's tangent \
                     {tangent:?} at {:?}",
                    solid.curve.position(t)
                )));
            }
            let bending = solid.bending(t);
            if bending >= 1.0 {
                return Err(invalid(format!(
                    "the centreline bends too sharply for the section at {:?}: curvature × \
                     the section's extent towards the centre of curvature is {bending:.2} (≥ 1, \
                     the sections overlap)",
                    solid.curve.position(t)
                )));
            }
        }
        Ok(solid)
    }

    /// The sweep's folding measure at parameter `t`: max over the section of κ·(u d₁ + v d₂)
    /// = √((a κ·d₁)² + (b κ·d₂)²), κ the curvature vector. The Jacobian of
    /// (s, u, v) ↦ c + u d₁ + v d₂ is |c'| a b (1 − κ·(u d₁ + v d₂)) up to the in-plane
    /// scaling, so the solid is free of overlapping sections where this is below 1.
    fn bending(&self, t: f64) -> f64 {
        let h = 1e-6 * self.curve.end();
        let (lo, hi) = ((t - h).max(0.0), (t + h).min(self.curve.end()));
        let first = self.curve.derivative(t);
        let second = (self.curve.derivative(hi) - self.curve.derivative(lo)) / (hi - lo);
        let speed = first.norm();
        let tangent = first / speed;
        let curvature = (second - second.dot(&tangent) * tangent) / (speed * speed);
        let section = self.section_at_parameter(t);
        (section.half_width * curvature.dot(&section.width_axis))
            .hypot(section.half_thickness * curvature.dot(&section.thickness_axis))
    }

    fn width_direction(&self, t: f64) -> Vector3<f64> {
        Vector3::from_fn(|k, _| self.curve.profile(WIDTH_DIRECTION + k, t))
    }

    /// Length of the centreline [m].
    pub fn length(&self) -> f64 {
        self.arclength[self.arclength.len() - 1].1
    }

    /// Arclength [m] from the origin to each station's centre, in station order.
    pub fn station_arclengths(&self) -> Vec<f64> {
        self.curve
            .knots()
            .iter()
            .map(|&t| self.arclength_of(t))
            .collect()
    }

    /// The cross-section at curve parameter `t`.
    fn section_at_parameter(&self, t: f64) -> Section {
        let tangent = self.curve.derivative(t).normalize();
        let w = self.width_direction(t);
        let width_axis = (w - w.dot(&tangent) * tangent).normalize();
        Section {
            centre: self.curve.position(t),
            tangent,
            width_axis,
            thickness_axis: tangent.cross(&width_axis),
            half_width: self.curve.profile(HALF_WIDTH, t),
            half_thickness: self.curve.profile(HALF_THICKNESS, t),
        }
    }

    /// The cross-section at arclength `s` [m] from the origin (clamped to the curve).
    pub fn section(&self, s: f64) -> Section {
        let t = invert(&self.arclength, s, |t| self.curve.derivative(t).norm());
        self.section_at_parameter(t)
    }

    /// V = ∫ π a b ds [m³], by Gauss–Legendre quadrature along the curve.
    pub fn volume(&self) -> f64 {
        let table = self.curve.cumulative(|t| {
            PI * self.curve.profile(HALF_WIDTH, t)
                * self.curve.profile(HALF_THICKNESS, t)
                * self.curve.derivative(t).norm()
        });
        table[table.len() - 1].1
    }

    /// V = ∫ π a b ds between arclengths `from` and `to` [m³].
    pub fn volume_between(&self, from: f64, to: f64) -> f64 {
        let table = self.curve.cumulative(|t| {
            PI * self.curve.profile(HALF_WIDTH, t)
                * self.curve.profile(HALF_THICKNESS, t)
                * self.curve.derivative(t).norm()
        });
        self.sizes_along(&table, to) - self.sizes_along(&table, from)
    }

    fn arclength_of(&self, t: f64) -> f64 {
        let j = self
            .arclength
            .partition_point(|&(tj, _)| tj < t)
            .clamp(1, self.arclength.len() - 1);
        let ((t0, s0), (t1, s1)) = (self.arclength[j - 1], self.arclength[j]);
        if t1 == t0 {
            s0
        } else {
            s0 + (s1 - s0) * (t - t0) / (t1 - t0)
        }
    }

    /// Approximate signed distance [m] of `point` from the solid's lateral surface
    /// (negative inside): the section whose plane contains the point, nearest along the
    /// curve to the closest centreline point, measured in that plane with
    /// [`Section::signed_distance`]. Beyond the end caps it is the larger of the in-plane
    /// distance of the end section and the distance past the cap. Good where the point
    /// is within about a section's size of the solid, which is where overlaps are
    /// judged.
    pub fn signed_distance(&self, point: &Vector3<f64>) -> f64 {
        let table = &self.arclength;
        let axial = |t: f64| (point - self.curve.position(t)).dot(&self.curve.derivative(t));
        let nearest = (0..table.len())
            .min_by(|&i, &j| {
                let di = (point - self.curve.position(table[i].0)).norm_squared();
                let dj = (point - self.curve.position(table[j].0)).norm_squared();
                di.total_cmp(&dj)
            })
            .unwrap_or(0);
        // The sign change of the axial coordinate closest to the nearest sample.
        let crossing = (0..table.len() - 1)
            .filter(|&i| axial(table[i].0) * axial(table[i + 1].0) <= 0.0)
            .min_by_key(|&i| i.abs_diff(nearest));
        let (t, beyond) = match crossing {
            Some(i) => {
                let (mut lo, mut hi) = (table[i].0, table[i + 1].0);
                let positive_low = axial(lo) > 0.0;
                for _ in 0..50 {
                    let mid = 0.5 * (lo + hi);
                    if (axial(mid) > 0.0) == positive_low {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                (0.5 * (lo + hi), f64::NEG_INFINITY)
            }
            None => {
                let (t, sign) = if nearest < table.len() / 2 {
                    (0.0, -1.0)
                } else {
                    (self.curve.end(), 1.0)
                };
                (t, sign * axial(t) / self.curve.derivative(t).norm())
            }
        };
        let section = self.section_at_parameter(t);
        let d = point - section.centre;
        let in_plane =
            section.signed_distance(d.dot(&section.width_axis), d.dot(&section.thickness_axis));
        in_plane.max(beyond)
    }
}

/// What to mesh: the stations and the divisions of the structured hex8 mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct SweptMuscleSpec {
    /// Name of the element block (the muscle).
    pub name: String,
    /// Control stations from origin to insertion (see [`SweptSolid::new`]).
    pub stations: Vec<SweptStation>,
    /// Cells n along each side of the O-grid's inner block (even, ≥ 2).
    pub per_side: usize,
    /// Ring layers m of the O-grid (≥ 1).
    pub radial: usize,
    /// Element layers along the centreline (≥ 1, and at least one per segment).
    pub axial: usize,
    /// Arclengths [m] (increasing, inside the centreline) at which a layer of nodes must
    /// lie: the junctions between segments of the muscle (e.g. belly and tendon).
    pub junctions: Vec<f64>,
    /// Layers of each segment, origin first (one more entry than `junctions`, each ≥ 1;
    /// `axial` is then ignored); `None`: `axial` layers split among the segments in
    /// proportion to the section sizes each spans.
    pub segment_layers: Option<Vec<usize>>,
}

impl SweptMuscleSpec {
    /// Element layers along the centreline: the sum of `segment_layers` if given, else
    /// `axial`.
    pub fn layers(&self) -> usize {
        self.segment_layers
            .as_ref()
            .map_or(self.axial, |layers| layers.iter().sum())
    }

    /// Elements of the mesh: (n² + 4 n m) · layers.
    pub fn element_count(&self) -> usize {
        (self.per_side * self.per_side + 4 * self.per_side * self.radial) * self.layers()
    }
}

/// The hex8 mesh of `spec` (see the module documentation for the geometry).
///
/// Names: block `spec.name` (fibers along the centreline); element set `all`; node sets
/// and surfaces `origin` (the first layer, s = 0) and `insertion` (the last layer,
/// s = L), surface `lateral` (the other boundary faces) and `outer` (all boundary
/// faces); node sets `lateral`. With junctions: element sets `segment_0`, `segment_1`, …
/// (the layers between consecutive junctions, origin first) and node sets
/// `junction_0`, … (the layer of nodes at each junction). Nodes: layer k holds nodes
/// k·P … k·P + P − 1, P the O-grid's node count; elements run layer by layer.
///
/// Errors as [`SweptSolid::new`], on divisions out of range or beyond 2³² ids, and if an
/// element is inverted or flat (the centreline bends more sharply than the section is
/// wide), naming the layer.
pub fn swept_muscle_mesh(spec: &SweptMuscleSpec) -> Result<Mesh, MeshError> {
    let solid = SweptSolid::new(&spec.stations)?;
    let (n, m, axial) = (spec.per_side, spec.radial, spec.layers());
    if n < 2 || !n.is_multiple_of(2) || m < 1 || axial < 1 {
        return Err(invalid(format!(
            "divisions per_side {n} (even, ≥ 2), radial {m} (≥ 1), axial {axial} (≥ 1)"
        )));
    }
    let section = UnitSection::new(n, m);
    let per_layer = section.node_count();
    if per_layer
        .checked_mul(axial + 1)
        .is_none_or(|c| c > u32::MAX as usize)
        || spec.element_count() > u32::MAX as usize
    {
        return Err(invalid(format!(
            "divisions {n}, {m}, {axial} give more than 2^32 nodes or elements"
        )));
    }
    let scale = (PI / polygon_area(n)).sqrt();
    let stations = match &spec.segment_layers {
        Some(layers) => solid.graded_stations_per_segment(&spec.junctions, layers)?,
        None => solid.graded_stations_with_junctions(axial, &spec.junctions)?,
    };
    let sections: Vec<Section> = stations.iter().map(|&s| solid.section(s)).collect();
    let mut nodes = Nodes::with_capacity(per_layer * (axial + 1));
    for sec in &sections {
        for p in &section.points {
            nodes.push(sec.point(
                scale * sec.half_width * p.x,
                scale * sec.half_thickness * p.y,
            ));
        }
    }
    let mut connectivity = Vec::with_capacity(section.quads.len() * axial * 8);
    let mut fibers = Vec::with_capacity(section.quads.len() * axial);
    for k in 0..axial {
        let (low, high) = ((k * per_layer) as u32, ((k + 1) * per_layer) as u32);
        let fiber = (sections[k].tangent + sections[k + 1].tangent).normalize();
        for quad in &section.quads {
            connectivity.extend(quad.iter().map(|&p| p + low));
            connectivity.extend(quad.iter().map(|&p| p + high));
            fibers.push(fiber);
        }
    }
    let mut block = ElementBlock::new(spec.name.clone(), ElementShape::Hex8, connectivity)?;
    block.fiber_direction = fibers;
    let cells = section.quads.len();
    let mut coords = [Vector3::zeros(); 8];
    for (e, ids) in block.elements().enumerate() {
        nodes.gather(ids, &mut coords);
        if ElementShape::Hex8.min_jacobian_volume(&coords) <= 0.0 {
            return Err(invalid(format!(
                "element {e} of layer {} (arclength {:.4} m to {:.4} m) is inverted or \
                 flat: the centreline bends too sharply for the section",
                e / cells,
                stations[e / cells],
                stations[e / cells + 1]
            )));
        }
    }
    let mut mesh = finish(nodes, block, per_layer, axial)?;
    insert_segment_sets(&mut mesh, &stations, &spec.junctions, per_layer, cells);
    Ok(mesh)
}

/// The element sets `segment_i` and node sets `junction_i` of the layers at `stations`
/// (arclengths, junctions among them exactly).
fn insert_segment_sets(
    mesh: &mut Mesh,
    stations: &[f64],
    junctions: &[f64],
    per_layer: usize,
    cells: usize,
) {
    if junctions.is_empty() {
        return;
    }
    let layer_of = |s: f64| stations.iter().position(|&x| x == s);
    let mut boundaries = vec![0];
    for (i, &s) in junctions.iter().enumerate() {
        let layer = layer_of(s).expect("every junction is a station");
        boundaries.push(layer);
        mesh.node_sets.insert(
            format!("junction_{i}"),
            ((layer * per_layer) as u32..((layer + 1) * per_layer) as u32).collect(),
        );
    }
    boundaries.push(stations.len() - 1);
    for (i, pair) in boundaries.windows(2).enumerate() {
        mesh.element_sets.insert(
            format!("segment_{i}"),
            ((pair[0] * cells) as u32..(pair[1] * cells) as u32)
                .map(|e| crate::ElementRef::new(0, e))
                .collect(),
        );
    }
}

/// The mesh with its named sets (see [`swept_muscle_mesh`]).
fn finish(
    nodes: Nodes,
    block: ElementBlock,
    per_layer: usize,
    axial: usize,
) -> Result<Mesh, MeshError> {
    let mut mesh = Mesh::new(nodes, vec![block]);
    super::end_sets::insert_end_sets(&mut mesh, per_layer, axial)?;
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
