//! Penalty contact: the nodes of a secondary [`DeformableSurface`] against the triangles of
//! a main [`ContactTarget`], frictionless, node to surface (one pass).
//!
//! Each secondary node s with tributary area A_s [m²] takes its closest point x_m on the
//! main surface among its broadphase candidates ([`crate::projection`]; triangles that
//! have s as a vertex are skipped, which allows self-contact). With the signed gap g [m]
//! and its direction ν (the face normal n on a face), the normal traction is
//!
//! t_n = ε ⟨−g⟩ [Pa],   ε [N/m³] the penalty stiffness per unit area,
//!
//! and the node is pushed out along ν with the force t_n A_s [N]. In the solver's sign
//! convention (f_c enters like the internal force) f_c,s = ε A_s g ν = k d with k = ε A_s
//! and d = x_s − x_m; on a deformable main surface the reaction −f_c,s is shared by the
//! vertices of the main triangle by their barycentric weights, f_c,j = −N_j k d; on a rigid
//! one it goes to the body (the report's resultant). The forces derive from the stored
//! energy ½ ε g² A_s per active node, so they are conservative and the stiffness
//! (`penalty/stiffness.rs`) is symmetric.
//!
//! A node whose closest point is on the rim of an open main surface (a boundary edge or a
//! vertex of one) may be beside the surface rather than in it. Its force fades with how
//! far it overhangs the rim, s = the distance of x − x_m from the normal's line (with
//! smooth normals: of the foot from the rim): f = w(s) ε A_s g ν with
//! w = 1 − (3t² − 2t³), t = min(s / (RIM_FADE h), 1), h = √(2 A_t) the size of the rim
//! triangle ([`rim_weight`]). A node right over the rim (on a symmetry plane, say) is in
//! contact; one that overhangs it by a quarter of the triangle's size carries nothing.
//! (A cut-off at a lean of 1 %, as before, made the force jump from ε A_s |g| to zero as a
//! penetrating node crossed the rim: Newton's method then cannot converge at any step
//! size, and the knee's muscles, whose surfaces are open at their ends, met it.) The
//! stiffness leaves out ∂w/∂x (the weight scales the blocks).
//!
//! Default penalty ([`default_penalty`]): ε = 10 E / h with E the Young's modulus of the
//! softer body [Pa] and h its element size [m]. A pressure p then penetrates by
//! g = p/ε = h (p/E)/10: a tenth of the strain p/E, in units of the element size (a
//! pressure that strains the body by 5 % penetrates by 0.5 % of h).
//!
//! Explicit runs: the contact spring k = ε A_s on a surface node of mass m ≈ ρ h A_s / 2
//! adds k/m ≈ 20 E/(ρ h²) to the node's highest squared frequency, against
//! 12 M/(ρ h²) from its elements (M the dilatational modulus, the solver's bound
//! L = h/√3), so the stable step shrinks by about √(1 + 5E/(3M)). The solver does not know
//! it: lower its safety factor by that much (0.9 → 0.7 for the tests' material, E/M =
//! 0.26; nothing for nearly incompressible muscle, E/M ≈ 10⁻⁴), or lower ε. An unstable
//! step breaks the energy balance, which stops the run.
//!
//! Smooth normals ([`PenaltyContact::with_smooth_normals`], `penalty/smooth.rs`): over
//! the edges and vertices of a faceted main surface the closest point, and with it the
//! force direction, jumps where a node crosses the bisector of a convex edge (a node
//! pressed into a ridge) and turns by the fold angle within a band of width
//! 2 |g| tan(θ/2) across a concave one: a non-smooth residual that stalls Newton's method
//! when muscles slide over a marching-tetrahedra bone. With smooth normals the gap d and
//! the direction ν are measured along the field of vertex normals of the main surface
//! (`normal_field.rs`: area-weighted, or a rigid body's own
//! [`crate::RigidSurface::with_vertex_normals`], recomputed at every evaluation for a
//! deformable main), starting from the node's closest triangle, so the force is a
//! continuous function of the positions over edges and vertices, concave ones included.
//! The node is in contact when d < 0, with the traction ε ⟨−d⟩ along ν; on a flat surface
//! this is the closest-point contact. Its stiffness is not symmetric (the solver then
//! factorizes with LU).
//!
//! Forces do not depend on the number of threads: each node's pair is evaluated on its
//! own (in parallel), then the forces are added to the nodes serially in node order.
//! Limitations: no friction; a node must not penetrate deeper than the search distance
//! (default [`DEFAULT_SEARCH_FACTOR`] × the secondary surface's element size h: penetrations
//! stay ≪ h, and an explicit step or a Newton iteration moves a node by much less) nor past
//! the middle of a thin main body.

mod checkpoint;
mod closest_point;
mod interaction;
mod smooth;
mod stiffness;

use nalgebra::{Isometry3, Point3, Vector3};
use rayon::prelude::*;

use musclefem_core::solver::InteractionReport;

use crate::broadphase::Broadphase;
use crate::error::ContactError;
use crate::main_side::MainSide;
use crate::projection::{Feature, closest_feature, project_on_triangle};
use crate::surface::{ContactTarget, DeformableSurface};
use closest_point::{Bounds, box_distance, closest};
use smooth::{SmoothContact, SmoothNormals};
use stiffness::FeatureGeometry;

/// Secondary nodes per parallel task of the closest-point evaluation.
const EVALUATION_CHUNK: usize = 32;

/// The default search distance is this fraction of the secondary surface's element size.
pub const DEFAULT_SEARCH_FACTOR: f64 = 0.5;

/// Factor β of the default penalty ε = β E / h.
pub const DEFAULT_PENALTY_FACTOR: f64 = 10.0;

/// The default penalty stiffness ε = [`DEFAULT_PENALTY_FACTOR`] · E / h [N/m³] for a body of
/// Young's modulus `modulus` [Pa] meshed with elements of size `element_size` [m].
pub fn default_penalty(modulus: f64, element_size: f64) -> Result<f64, ContactError> {
    for (what, value) in [("Young's modulus", modulus), ("element size", element_size)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(ContactError::invalid(
                what,
                value,
                "must be finite and positive",
            ));
        }
    }
    Ok(DEFAULT_PENALTY_FACTOR * modulus / element_size)
}

/// Past the rim of an open main surface a node's force fades over this share of the rim
/// triangle's size (see the module docs).
pub const RIM_FADE: f64 = 0.25;

/// The weight w ∈ [0, 1] of the force of a node that overhangs the rim of the main
/// triangle `corners` by `overhang` [m]: 1 − (3t² − 2t³), t = min(s / (RIM_FADE h), 1),
/// h = √(2 A) [m] (C¹ in s; 1 over the rim, 0 a quarter of the triangle's size past it).
pub fn rim_weight(overhang: f64, corners: &[Vector3<f64>; 3]) -> f64 {
    let area = 0.5
        * (corners[1] - corners[0])
            .cross(&(corners[2] - corners[0]))
            .norm();
    let width = RIM_FADE * (2.0 * area).sqrt();
    // A degenerate triangle (no width, or NaN): over it or not.
    if width.is_nan() || width <= 0.0 {
        return if overhang > 0.0 { 0.0 } else { 1.0 };
    }
    let t = (overhang / width).clamp(0.0, 1.0);
    1.0 - t * t * (3.0 - 2.0 * t)
}

/// The state of one secondary node at the last force evaluation.
#[derive(Debug, Clone, Copy)]
struct NodeContact {
    /// The main triangle of the closest point (`u32::MAX`: no candidate).
    triangle: u32,
    /// Signed gap g [m] (0 without a candidate).
    gap: f64,
    /// Carries a force.
    active: bool,
    /// The force's share past the rim ([`rim_weight`]; 1 over the face).
    weight: f64,
    /// d = x_s − x_m in world axes [m].
    offset: Vector3<f64>,
    /// Vertices, weights and tangents of the feature, world axes.
    geometry: FeatureGeometry,
}

impl Default for NodeContact {
    fn default() -> Self {
        NodeContact {
            triangle: u32::MAX,
            gap: 0.0,
            active: false,
            weight: 0.0,
            offset: Vector3::zeros(),
            geometry: FeatureGeometry::new(
                Feature::Vertex(0),
                &[1.0, 0.0, 0.0],
                &[Vector3::zeros(); 3],
            ),
        }
    }
}

/// Frictionless penalty contact of a deformable surface's nodes on a main surface (see the
/// module docs).
#[derive(Debug, Clone)]
pub struct PenaltyContact {
    name: String,
    secondary: DeformableSurface,
    target: ContactTarget,
    penalty: f64,
    /// ε of each secondary node [N/m³] where they differ ([`Self::with_node_penalties`]);
    /// `None`: `penalty` for every node.
    node_penalty: Option<Vec<f64>>,
    broadphase: Broadphase,
    /// Per main triangle, bit i set when vertex i is on the rim of the main surface.
    rim_vertices: Vec<u8>,
    contacts: Vec<NodeContact>,
    /// The smooth normal field and the nodes' projections along it, when the contact
    /// measures gaps along it ([`PenaltyContact::with_smooth_normals`]).
    smooth: Option<SmoothNormals>,
    report: InteractionReport,
}

impl PenaltyContact {
    /// Contact of the nodes of `secondary` on `target` with penalty `penalty` ε [N/m³],
    /// searched within [`DEFAULT_SEARCH_FACTOR`] × the secondary surface's element size.
    pub fn new(
        name: &str,
        secondary: DeformableSurface,
        target: impl Into<ContactTarget>,
        penalty: f64,
    ) -> Result<Self, ContactError> {
        if !(penalty.is_finite() && penalty > 0.0) {
            return Err(ContactError::invalid(
                &format!("contact '{name}': penalty stiffness [N/m³]"),
                penalty,
                "must be finite and positive",
            ));
        }
        let target = target.into();
        let (triangles, boundary) = match &target {
            ContactTarget::Deformable(s) => (&s.triangles, &s.boundary_edges),
            ContactTarget::Rigid(s) => (&s.triangles, &s.boundary_edges),
        };
        let mut rim = std::collections::HashSet::new();
        for (t, bits) in triangles.iter().zip(boundary) {
            for e in 0..3 {
                if bits & (1 << e) != 0 {
                    rim.insert(t[e]);
                    rim.insert(t[(e + 1) % 3]);
                }
            }
        }
        let rim_vertices = triangles
            .iter()
            .map(|t| {
                (0..3)
                    .filter(|&i| rim.contains(&t[i]))
                    .fold(0u8, |b, i| b | (1 << i))
            })
            .collect();
        let search_distance = DEFAULT_SEARCH_FACTOR * secondary.element_size();
        Ok(PenaltyContact {
            name: name.to_string(),
            contacts: vec![NodeContact::default(); secondary.nodes.len()],
            secondary,
            target,
            penalty,
            node_penalty: None,
            broadphase: Broadphase::new(search_distance),
            rim_vertices,
            smooth: None,
            report: InteractionReport {
                name: name.to_string(),
                ..InteractionReport::default()
            },
        })
    }

    /// Contact with the [`default_penalty`] for a secondary body of Young's modulus
    /// `modulus` [Pa], h = the secondary surface's element size.
    pub fn with_default_penalty(
        name: &str,
        secondary: DeformableSurface,
        target: impl Into<ContactTarget>,
        modulus: f64,
    ) -> Result<Self, ContactError> {
        let penalty = default_penalty(modulus, secondary.element_size())?;
        Self::new(name, secondary, target, penalty)
    }

    /// The same contact searching within `distance` [m] of each node.
    pub fn with_search_distance(mut self, distance: f64) -> Result<Self, ContactError> {
        if !(distance.is_finite() && distance > 0.0) {
            return Err(ContactError::invalid(
                "search distance",
                distance,
                "must be finite and positive",
            ));
        }
        self.broadphase = Broadphase::new(distance);
        Ok(self)
    }

    /// The same contact measuring the gap and the force direction along the smooth field
    /// of vertex normals of the main surface instead of at the closest point (see the
    /// module docs and `penalty/smooth.rs`): the force is a continuous function of the
    /// positions when a node slides over the edges and vertices of the faceted main
    /// surface, concave ones included. A rigid main uses its own vertex normals
    /// ([`crate::RigidSurface::with_vertex_normals`]) if it has them, else the
    /// area-weighted ones of its facets, in its body frame; a deformable main's are
    /// recomputed at every force evaluation. The stiffness is not symmetric.
    pub fn with_smooth_normals(mut self) -> Self {
        self.smooth = Some(SmoothNormals::new(&self.target, self.secondary.nodes.len()));
        self
    }

    /// Whether the contact measures along the smooth normal field
    /// ([`Self::with_smooth_normals`]).
    pub fn smooth_normals(&self) -> bool {
        self.smooth.is_some()
    }

    /// The penalty stiffness ε [N/m³] (of the nodes without one of their own).
    pub fn penalty(&self) -> f64 {
        self.penalty
    }

    /// The same contact with a penalty ε [N/m³] per secondary node, in the order of
    /// [`DeformableSurface::nodes`]: for a surface whose parts press with pressures of
    /// different sizes (a muscle's soft belly and its stiff tendon, which wraps a bone
    /// under tension: with the belly's ε a tendon pressed with 1 MPa would sink 30 mm into
    /// the bone). Errors unless there is one finite positive value per node.
    pub fn with_node_penalties(mut self, penalties: Vec<f64>) -> Result<Self, ContactError> {
        if penalties.len() != self.secondary.nodes.len() {
            return Err(ContactError::invalid(
                &format!(
                    "contact '{}': node penalties ({} for {} nodes)",
                    self.name,
                    penalties.len(),
                    self.secondary.nodes.len()
                ),
                penalties.len() as f64,
                "must be one per secondary node",
            ));
        }
        if let Some(&bad) = penalties.iter().find(|p| !(p.is_finite() && **p > 0.0)) {
            return Err(ContactError::invalid(
                &format!("contact '{}': node penalty [N/m³]", self.name),
                bad,
                "must be finite and positive",
            ));
        }
        self.node_penalty = Some(penalties);
        Ok(self)
    }

    /// ε of secondary node `i` (index into the surface's nodes) [N/m³]: its own
    /// ([`Self::with_node_penalties`]) or [`Self::penalty`].
    #[inline]
    pub fn node_penalty(&self, i: usize) -> f64 {
        self.node_penalty.as_ref().map_or(self.penalty, |p| p[i])
    }

    /// The secondary surface.
    pub fn secondary(&self) -> &DeformableSurface {
        &self.secondary
    }

    /// The main surface.
    pub fn target(&self) -> &ContactTarget {
        &self.target
    }

    /// The broadphase (its statistics).
    pub fn broadphase(&self) -> &Broadphase {
        &self.broadphase
    }

    /// The closest point of every secondary node at `positions` and `time` (in parallel,
    /// each node on its own).
    fn evaluate(&mut self, time: f64, positions: &[Vector3<f64>]) {
        let frame = match &self.target {
            ContactTarget::Rigid(rigid) => Some(rigid.motion.isometry_at(time)),
            ContactTarget::Deformable(_) => None,
        };
        let (target, broadphase) = (&self.target, &self.broadphase);
        let rim_edges = match target {
            ContactTarget::Deformable(s) => &s.boundary_edges,
            ContactTarget::Rigid(s) => &s.boundary_edges,
        };
        let rim = (rim_edges.as_slice(), self.rim_vertices.as_slice());
        let nodes = &self.secondary.nodes;
        let main_motion = broadphase.main_motion_since_query(target, positions);
        self.contacts
            .par_chunks_mut(EVALUATION_CHUNK)
            .enumerate()
            .for_each(|(chunk, contacts)| {
                for (k, contact) in contacts.iter_mut().enumerate() {
                    let i = chunk * EVALUATION_CHUNK + k;
                    // Most nodes of a muscle's surface are nowhere near the main one: with
                    // no candidate the result is the empty contact, which a node that had
                    // none before already holds.
                    if broadphase.candidates(i).is_empty() {
                        if contact.triangle != u32::MAX {
                            *contact = NodeContact::default();
                        }
                        continue;
                    }
                    let node = nodes[i];
                    let x = positions[node as usize];
                    *contact = match (target, &frame) {
                        (ContactTarget::Rigid(rigid), Some(iso)) => {
                            let body = iso.inverse_transform_point(&Point3::from(x)).coords;
                            // The candidates come nearest box first, at the query; the node
                            // has moved by `moved` since, so the box distances now are at
                            // least those minus `moved`.
                            let moved = (body - broadphase.queried_point(i)).norm();
                            let queried = broadphase.candidate_box_distances(i);
                            let mut c = closest(
                                &body,
                                broadphase.candidates(i),
                                contact.triangle,
                                rim,
                                |_| false,
                                Bounds {
                                    box_distance: |t| broadphase.rigid_box_distance(t, &body),
                                    rest_farther: |k, best| queried[k] - moved > best,
                                },
                                |t| rigid.triangles[t].map(|v| rigid.vertices[v as usize]),
                            );
                            let rotation = iso.rotation.to_rotation_matrix().into_inner();
                            c.offset = rotation * c.offset;
                            c.geometry = c.geometry.rotated(&rotation);
                            c
                        }
                        (ContactTarget::Deformable(main), _) => {
                            // As for a rigid main, with the triangles' own motion since
                            // the query added to the node's.
                            let moved = (x - broadphase.queried_point(i)).norm() + main_motion;
                            let queried = broadphase.candidate_box_distances(i);
                            closest(
                                &x,
                                broadphase.candidates(i),
                                contact.triangle,
                                rim,
                                |t| main.triangles[t].contains(&node),
                                Bounds {
                                    box_distance: |t| box_distance(&x, &main.corners(t, positions)),
                                    rest_farther: |k, best| queried[k] - moved > best,
                                },
                                |t| main.corners(t, positions),
                            )
                        }
                        (ContactTarget::Rigid(_), None) => {
                            unreachable!("a rigid target has a frame")
                        }
                    };
                }
            });
        if let Some(smooth) = &mut self.smooth {
            // From each node's closest triangle along the normal field.
            // The normals of the triangles the walks start on (those they walk on to are
            // computed as they go).
            smooth.field.update_around(
                target,
                positions,
                self.contacts
                    .iter()
                    .filter(|c| c.triangle != u32::MAX)
                    .map(|c| c.triangle),
            );
            let placement = frame.unwrap_or_else(Isometry3::identity);
            let (field, closest) = (&smooth.field, &self.contacts);
            smooth
                .contacts
                .par_chunks_mut(EVALUATION_CHUNK)
                .enumerate()
                .for_each(|(chunk, contacts)| {
                    for (k, contact) in contacts.iter_mut().enumerate() {
                        let i = chunk * EVALUATION_CHUNK + k;
                        // No closest triangle: no contact, already held by a node that
                        // had none before.
                        if closest[i].triangle == u32::MAX && contact.triangle == u32::MAX {
                            continue;
                        }
                        let node = nodes[i];
                        *contact = SmoothContact::new(
                            field,
                            target,
                            (positions, &placement),
                            node,
                            closest[i].triangle,
                            &positions[node as usize],
                        );
                    }
                });
        }
    }

    /// Calls `f(node, force)` with each nonzero nodal force f_c [N], serially in secondary
    /// node order (each node, then its main triangle's vertices).
    fn for_each_force(&self, mut f: impl FnMut(u32, Vector3<f64>)) {
        if let Some(smooth) = &self.smooth {
            for (i, c) in smooth.contacts.iter().enumerate() {
                if !c.active {
                    continue;
                }
                let force = c.force(self.node_penalty(i) * self.secondary.node_area[i] * c.weight);
                f(self.secondary.nodes[i], force);
                if let Some(corners) = self.target.nodes(c.triangle as usize) {
                    for (vertex, phi) in corners.iter().zip(&c.projection.barycentric) {
                        f(*vertex, -force * *phi);
                    }
                }
            }
            return;
        }
        for (i, c) in self.contacts.iter().enumerate() {
            if !c.active {
                continue;
            }
            let k = self.node_penalty(i) * self.secondary.node_area[i] * c.weight;
            let force = c.offset * k;
            f(self.secondary.nodes[i], force);
            if let ContactTarget::Deformable(main) = &self.target {
                let triangle = main.triangles[c.triangle as usize];
                for j in 0..c.geometry.count {
                    let vertex = triangle[c.geometry.vertices[j] as usize];
                    f(vertex, -force * c.geometry.weights[j]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests;
