//! The smooth normal field of a main surface and the projection of a point along it,
//! shared by the smoothly sliding cohesive bonds ([`crate::TangentialMode::SmoothSlide`])
//! and the smooth penalty contact ([`crate::PenaltyContact::with_smooth_normals`]): the gap
//! and the force direction are measured along a field of normals interpolated from the
//! vertices of the faceted main surface (the projection of mortar contact with averaged
//! nodal normals), so they are continuous functions of the positions when a node slides
//! over the edges and vertices of the main surface, concave ones included (there the
//! closest point jumps between the faces, and so does its direction).
//!
//! - Vertex normals n_v [1]: the normalized sum of (x₁ − x₀) × (x₂ − x₀) over the main
//!   triangles around v (weighted by their areas, out of the main body). A rigid main's
//!   are computed once in its body frame (or given with it,
//!   [`crate::RigidSurface::with_vertex_normals`]: the facets of a marching-tetrahedra
//!   femur scatter them by up to 30° at 1 % of its vertices, and a muscle pressed on it
//!   felt a washboard of tangential forces that stalled Newton) and turned by its
//!   placement; a deformable main's are recomputed from the nodal positions at every
//!   search and force evaluation (in place), at the corners of the triangles the walks
//!   start from ([`NormalField::update_around`]: the pairs and bonds cover a small part
//!   of a muscle's surface), and on demand, with the same bits, where a walk goes
//!   beyond them ([`NormalField::normals_at`]).
//! - Projection of the secondary node x [m] on a main triangle x₀ x₁ x₂ with vertex normals
//!   n₀ n₁ n₂: the (ξ₁, ξ₂, g) that solve
//!   x₀ + ξ₁ (x₁ − x₀) + ξ₂ (x₂ − x₀) + g N(ξ) = x, N(ξ) = φ₀ n₀ + φ₁ n₁ + φ₂ n₂,
//!   φ = (1 − ξ₁ − ξ₂, ξ₁, ξ₂), by Newton from the orthogonal projection on the triangle's
//!   plane with J = [x₁ − x₀ + g (n₁ − n₀), x₂ − x₀ + g (n₂ − n₀), N] (the flat projection
//!   where J is singular or Newton does not converge). The foot is x_m = Σ φ_k x_k and
//!   x − x_m = g N.
//! - Walk ([`walk`]): from a starting triangle, across the edge opposite the most negative
//!   φ_k < −1e-10 to the triangle sharing it (edges on the rim, or of a triangle the node
//!   belongs to, are not crossed), up to [`MAX_HOPS`] triangles and never twice the same
//!   one (then the least outside of those seen); where no edge can be crossed, the
//!   projection extrapolated on the last triangle (a node past the rim). Along an edge's
//!   line N depends on that edge's two vertex normals only, so the projections of the two
//!   triangles sharing it agree there: the result does not depend on which triangle holds
//!   the foot, and the force is continuous.
//! - Gap d = g |N| [m] and direction ν = N / |N|; a force f_s = A t(d) ν on the secondary
//!   node [N] (A its area [m²], t a traction [Pa] of the gap), −φ_k f_s on the corners of a
//!   deformable main triangle (forces and moments balance: x − x_m ∥ ν), −f_s on a rigid
//!   main.
//! - Tangent ([`smooth_tangent`]) with the vertex normals held fixed (exact for a rigid
//!   main; for a deformable main the normals' dependence on the positions of the triangles
//!   around the corners is left out: a relative error of the order of the gap g over the
//!   element size). With rows a₁, a₂ [1/m] and a₃ [1] of J⁻¹,
//!   δ = dx_s − Σ φ_k dx_k, Q = (n₁ − n₀)⊗a₁ + (n₂ − n₀)⊗a₂ [1/m] and P = I − ν⊗ν:
//!   dd = (|N| a₃ + g Qᵀν)·δ, dν = P Q δ / |N|, dφ = (−a₁ − a₂, a₁, a₂)·δ and
//!   df_s = A [t' ν⊗(|N| a₃ + g Qᵀν) + t P Q / |N|] δ, t' = dt/dd [N/m³]. It is not
//!   symmetric (ν is not the gradient of d off a flat surface).

use std::collections::HashMap;

use nalgebra::{Isometry3, Matrix2, Matrix3, UnitQuaternion, Vector2, Vector3};

use crate::main_side::MainSide;
use crate::surface::ContactTarget;

/// Triangles a walk may visit.
pub const MAX_HOPS: usize = 64;

/// A barycentric coordinate below this puts a foot outside its triangle.
pub const OUTSIDE: f64 = -1e-10;

/// No triangle across an edge (the rim of an open surface).
const RIM: u32 = u32::MAX;

/// Newton converges when its last step moved ξ by at most this and g by this times the
/// triangle's size (both scaled up by the node's distance in triangle sizes, the scale of
/// the round-off).
const TOLERANCE: f64 = 1e-13;

/// Newton iterations before the projection falls back on the flat one.
const MAX_ITERATIONS: usize = 32;

/// The smooth normal field of a main surface: its vertex normals and the triangles
/// across the edges of each triangle.
#[derive(Debug, Clone)]
pub struct NormalField {
    /// Per triangle, the indices of its corners' normals in `normals`.
    corners: Vec<[u32; 3]>,
    /// Per triangle, the triangle across edge i (corner i to i + 1), [`RIM`] if none.
    across: Vec<[u32; 3]>,
    /// Unit vertex normals: in the body frame of a rigid main, at the last update for a
    /// deformable one.
    normals: Vec<Vector3<f64>>,
    /// Whether the normals follow the nodal positions.
    deformable: bool,
    /// The triangles around each vertex, in increasing order (compressed rows: vertex v's
    /// are `rings[ring_starts[v]..ring_starts[v + 1]]`).
    ring_starts: Vec<u32>,
    rings: Vec<u32>,
    /// Whether `normals[v]` is that of the last update (a deformable main updated
    /// [`NormalField::update_around`] some triangles only; the others are computed when
    /// asked for, [`NormalField::normals_at`]).
    current: Vec<bool>,
    /// Per triangle, whether it is around a vertex that the update computes.
    around: Vec<bool>,
}

impl NormalField {
    /// The field of `main` at nodal `positions` [m] (a rigid main: in its body frame). A
    /// deformable main given no `positions` has no normals until the first
    /// [`Self::update_around`].
    pub fn new(main: &ContactTarget, positions: &[Vector3<f64>]) -> Self {
        let (corners, count) = match main {
            ContactTarget::Rigid(s) => (s.triangles.clone(), s.vertices.len()),
            ContactTarget::Deformable(s) => {
                let local = |n: u32| s.local_index(n).expect("a node of the surface") as u32;
                let corners = s.triangles.iter().map(|t| t.map(local)).collect();
                (corners, s.nodes.len())
            }
        };
        let deformable = matches!(main, ContactTarget::Deformable(_));
        let (ring_starts, rings) = vertex_rings(&corners, count);
        let mut field = NormalField {
            corners,
            across: across_edges(main.triangles()),
            normals: vec![Vector3::zeros(); count],
            deformable,
            ring_starts,
            rings,
            current: vec![!deformable; count],
            around: Vec::new(),
        };
        match main {
            // A rigid body that knows its own normals (an implicit or analytic shape).
            ContactTarget::Rigid(s) if s.vertex_normals.is_some() => {
                field
                    .normals
                    .clone_from(s.vertex_normals.as_ref().expect("checked"));
            }
            // Vertex positions: the rigid body's own, or the nodal ones; none yet.
            ContactTarget::Deformable(_) if positions.is_empty() => {}
            _ => field.accumulate(main, positions),
        }
        field
    }

    /// Recomputes all of a deformable main's vertex normals at nodal `positions` [m], in
    /// place (a rigid main's stay in its body frame): the reference the tests hold
    /// [`Self::update_around`] to.
    #[cfg(test)]
    pub fn update(&mut self, main: &ContactTarget, positions: &[Vector3<f64>]) {
        if self.deformable {
            self.accumulate(main, positions);
        }
    }

    /// Recomputes a deformable main's vertex normals at nodal `positions` [m] at the
    /// corners of `triangles` only (any order, repeats allowed); the others are computed
    /// from `positions` when [`Self::normals_at`] asks for them. Each vertex gets the bits
    /// a full update (every vertex) would give it: its triangles' terms are added in the
    /// same order. A rigid main's normals stay in its body frame.
    pub fn update_around(
        &mut self,
        main: &ContactTarget,
        positions: &[Vector3<f64>],
        triangles: impl Iterator<Item = u32>,
    ) {
        if !self.deformable {
            return;
        }
        self.current.fill(false);
        self.around.clear();
        self.around.resize(self.corners.len(), false);
        for t in triangles {
            for &v in &self.corners[t as usize] {
                if !self.current[v as usize] {
                    self.current[v as usize] = true;
                    self.normals[v as usize] = Vector3::zeros();
                    let ring = &self.rings[self.ring_starts[v as usize] as usize
                        ..self.ring_starts[v as usize + 1] as usize];
                    for &r in ring {
                        self.around[r as usize] = true;
                    }
                }
            }
        }
        // In increasing triangle order, as the full update adds them.
        let identity = Isometry3::identity();
        for (t, corners) in self.corners.iter().enumerate() {
            if !self.around[t] {
                continue;
            }
            let [a, b, c] = main.corners(t, positions, &identity);
            let weighted = (b - a).cross(&(c - a));
            for &v in corners {
                if self.current[v as usize] {
                    self.normals[v as usize] += weighted;
                }
            }
        }
        for v in 0..self.normals.len() {
            if self.current[v] {
                let normal =
                    unit_or_first_face(self.normals[v], self.ring(v as u32), main, positions);
                self.normals[v] = normal;
            }
        }
    }

    /// The triangles around vertex `v`, in increasing order.
    fn ring(&self, v: u32) -> &[u32] {
        let v = v as usize;
        &self.rings[self.ring_starts[v] as usize..self.ring_starts[v + 1] as usize]
    }

    /// The unit vertex normals of `triangle`, turned by `rotation` (the rigid body's; the
    /// identity for a deformable main). A deformable main's must have been updated at all
    /// three corners; [`Self::normals_at`] computes those missing (for the tests).
    #[cfg(test)]
    pub fn normals(&self, triangle: usize, rotation: &UnitQuaternion<f64>) -> [Vector3<f64>; 3] {
        debug_assert!(
            self.corners[triangle]
                .iter()
                .all(|&v| self.current[v as usize])
        );
        self.corners[triangle].map(|v| rotation * self.normals[v as usize])
    }

    /// [`Self::normals`], a deformable main's corners that the last update left out
    /// computed from nodal `positions` [m] (the same bits as an update's).
    pub fn normals_at(
        &self,
        triangle: usize,
        main: &ContactTarget,
        positions: &[Vector3<f64>],
        rotation: &UnitQuaternion<f64>,
    ) -> [Vector3<f64>; 3] {
        self.corners[triangle].map(|v| {
            let normal = if self.current[v as usize] {
                self.normals[v as usize]
            } else {
                let identity = Isometry3::identity();
                let ring = self.ring(v);
                let sum = ring.iter().fold(Vector3::zeros(), |sum, &t| {
                    let [a, b, c] = main.corners(t as usize, positions, &identity);
                    sum + (b - a).cross(&(c - a))
                });
                unit_or_first_face(sum, ring, main, positions)
            };
            rotation * normal
        })
    }

    /// n_v = Σ (x₁ − x₀) × (x₂ − x₀) / |Σ …| over the triangles around v; a vertex whose
    /// sum vanishes (a sheet folded onto itself) takes the unit normal of its first
    /// triangle that has one.
    fn accumulate(&mut self, main: &ContactTarget, positions: &[Vector3<f64>]) {
        self.current.fill(true);
        let identity = Isometry3::identity();
        self.normals.fill(Vector3::zeros());
        for (t, corners) in self.corners.iter().enumerate() {
            let [a, b, c] = main.corners(t, positions, &identity);
            let weighted = (b - a).cross(&(c - a));
            for &v in corners {
                self.normals[v as usize] += weighted;
            }
        }
        for v in 0..self.normals.len() {
            let normal = unit_or_first_face(self.normals[v], self.ring(v as u32), main, positions);
            self.normals[v] = normal;
        }
    }
}

/// The sum `sum` of a vertex's (x₁ − x₀) × (x₂ − x₀) normalized; where it vanishes (a
/// sheet folded onto itself), the unit normal of the first triangle of its `ring` (in
/// increasing order) that has one, else zero, as a full update has it.
fn unit_or_first_face(
    sum: Vector3<f64>,
    ring: &[u32],
    main: &ContactTarget,
    positions: &[Vector3<f64>],
) -> Vector3<f64> {
    let length = sum.norm();
    if length > 0.0 && length.is_finite() {
        return sum / length;
    }
    let identity = Isometry3::identity();
    ring.iter()
        .find_map(|&t| {
            let [a, b, c] = main.corners(t as usize, positions, &identity);
            (b - a).cross(&(c - a)).try_normalize(0.0)
        })
        .unwrap_or_else(Vector3::zeros)
}

/// Per vertex of `count`, the triangles of `corners` around it, in increasing order
/// (compressed rows: offsets, then the triangles).
fn vertex_rings(corners: &[[u32; 3]], count: usize) -> (Vec<u32>, Vec<u32>) {
    let mut starts = vec![0u32; count + 1];
    for t in corners {
        for &v in t {
            starts[v as usize + 1] += 1;
        }
    }
    for v in 0..count {
        starts[v + 1] += starts[v];
    }
    let mut filled = starts.clone();
    let mut rings = vec![0u32; starts[count] as usize];
    for (t, corners) in corners.iter().enumerate() {
        for &v in corners {
            rings[filled[v as usize] as usize] = t as u32;
            filled[v as usize] += 1;
        }
    }
    (starts, rings)
}

/// Per triangle, the triangle across each edge i (corner i to i + 1), [`RIM`] if none (of
/// three or more triangles on an edge, the first two in index order see each other).
fn across_edges(triangles: &[[u32; 3]]) -> Vec<[u32; 3]> {
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut by_edge: HashMap<(u32, u32), [u32; 2]> = HashMap::with_capacity(3 * triangles.len());
    for (t, tri) in triangles.iter().enumerate() {
        for i in 0..3 {
            let pair = by_edge
                .entry(key(tri[i], tri[(i + 1) % 3]))
                .or_insert([RIM; 2]);
            if let Some(slot) = pair.iter_mut().find(|s| **s == RIM) {
                *slot = t as u32;
            }
        }
    }
    triangles
        .iter()
        .enumerate()
        .map(|(t, tri)| {
            std::array::from_fn(|i| {
                let pair = by_edge[&key(tri[i], tri[(i + 1) % 3])];
                match pair {
                    [a, b] if a == t as u32 => b,
                    [a, _] => a,
                }
            })
        })
        .collect()
}

/// A point's projection along the normal field of one triangle (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalProjection {
    /// Barycentric coordinates φ of the foot x_m (some negative when it lies outside the
    /// triangle: extrapolated).
    pub barycentric: Vector3<f64>,
    /// g [m]: x − x_m = g N.
    pub along: f64,
    /// N = Σ φ_k n_k at the foot [1] (not a unit vector).
    pub normal: Vector3<f64>,
    /// J⁻¹ at the solution (rows [1/m], [1/m], [1]); `None` for a collapsed triangle.
    pub inverse: Option<Matrix3<f64>>,
    /// The vertex normals n_k the projection used: the triangle's, or its face normal
    /// three times where their J was singular (the flat projection).
    pub normals: [Vector3<f64>; 3],
}

impl NormalProjection {
    /// The gap d = g |N| [m].
    pub fn gap(&self) -> f64 {
        self.along * self.normal.norm()
    }
}

/// The projection of `x` [m] on the triangle `corners` [m] along the vertex `normals`
/// (see the module docs): Newton from the orthogonal projection; the orthogonal
/// projection itself where their Jacobian is singular or Newton does not converge; the
/// centroid of a collapsed triangle.
pub fn project_along_normals(
    x: &Vector3<f64>,
    corners: &[Vector3<f64>; 3],
    normals: &[Vector3<f64>; 3],
) -> NormalProjection {
    let e1 = corners[1] - corners[0];
    let e2 = corners[2] - corners[0];
    let offset = x - corners[0];
    let metric = Matrix2::new(e1.dot(&e1), e1.dot(&e2), e1.dot(&e2), e2.dot(&e2));
    let face = e1.cross(&e2).try_normalize(0.0);
    let (Some(metric_inverse), Some(face)) = (metric.try_inverse(), face) else {
        return collapsed(x, corners, normals);
    };
    let flat = (
        metric_inverse * Vector2::new(e1.dot(&offset), e2.dot(&offset)),
        offset.dot(&face),
    );
    let size = e1
        .norm()
        .max(e2.norm())
        .max((corners[2] - corners[1]).norm());
    let scale = 1.0 + offset.norm() / size;
    let solve =
        |normals: &[Vector3<f64>; 3]| newton(&offset, (&e1, &e2), normals, flat, size, scale);
    solve(normals)
        .or_else(|| solve(&[face; 3]))
        .unwrap_or_else(|| collapsed(x, corners, normals))
}

/// Newton on the projection equations in coordinates relative to x₀ (`offset` = x − x₀,
/// `edges` x₁ − x₀ and x₂ − x₀), from `start` (ξ₁, ξ₂), g; `None` where J is singular or
/// the iterations do not converge.
fn newton(
    offset: &Vector3<f64>,
    (e1, e2): (&Vector3<f64>, &Vector3<f64>),
    normals: &[Vector3<f64>; 3],
    start: (Vector2<f64>, f64),
    size: f64,
    scale: f64,
) -> Option<NormalProjection> {
    let [n0, n1, n2] = normals;
    let (d1, d2) = (n1 - n0, n2 - n0);
    let (mut xi, mut along) = start;
    for _ in 0..MAX_ITERATIONS {
        let normal = n0 + xi.x * d1 + xi.y * d2;
        let residual = xi.x * e1 + xi.y * e2 + along * normal - offset;
        let jacobian = Matrix3::from_columns(&[e1 + along * d1, e2 + along * d2, normal]);
        let columns = (0..3).map(|j| jacobian.column(j).norm()).product::<f64>();
        let determinant = jacobian.determinant().abs();
        if determinant.is_nan() || determinant <= 1e-12 * columns {
            return None;
        }
        let inverse = jacobian.try_inverse()?;
        let step = inverse * residual;
        if !step.iter().all(|s| s.is_finite()) {
            return None;
        }
        xi -= step.xy();
        along -= step.z;
        let moved = step.x.abs().max(step.y.abs()).max(step.z.abs() / size);
        if moved <= TOLERANCE * scale {
            // J⁻¹ of the iterate before this last step, which moved it by round-off.
            return Some(NormalProjection {
                barycentric: Vector3::new(1.0 - xi.x - xi.y, xi.x, xi.y),
                along,
                normal: n0 + xi.x * d1 + xi.y * d2,
                inverse: Some(inverse),
                normals: *normals,
            });
        }
    }
    None
}

/// The centroid of a collapsed triangle, along the mean of its vertex normals.
fn collapsed(
    x: &Vector3<f64>,
    corners: &[Vector3<f64>; 3],
    normals: &[Vector3<f64>; 3],
) -> NormalProjection {
    let mean = (normals[0] + normals[1] + normals[2])
        .try_normalize(0.0)
        .unwrap_or_else(Vector3::z);
    let centroid = (corners[0] + corners[1] + corners[2]) / 3.0;
    NormalProjection {
        barycentric: Vector3::repeat(1.0 / 3.0),
        along: (x - centroid).dot(&mean),
        normal: mean,
        inverse: None,
        normals: [mean; 3],
    }
}

/// Where a walk ended: the triangle and the projection on it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Foot {
    pub triangle: u32,
    pub projection: NormalProjection,
}

/// The projection of secondary node `node` at `x` [m] on the `main` surface (placed by
/// `placement`, vertices at nodal `positions` [m]) along its normal `field`, walking from
/// triangle `start` (see the module docs).
pub fn walk(
    field: &NormalField,
    main: &ContactTarget,
    (positions, placement): (&[Vector3<f64>], &Isometry3<f64>),
    node: u32,
    start: u32,
    x: &Vector3<f64>,
) -> Foot {
    let project = |triangle: u32| {
        let t = triangle as usize;
        let corners = main.corners(t, positions, placement);
        let normals = field.normals_at(t, main, positions, &placement.rotation);
        Foot {
            triangle,
            projection: project_along_normals(x, &corners, &normals),
        }
    };
    let lowest = |foot: &Foot| foot.projection.barycentric.min();
    let mut visited = [RIM; MAX_HOPS];
    let mut current = project(start);
    let mut best = current;
    for hop in 0..MAX_HOPS {
        let phi = current.projection.barycentric;
        let across = field.across[current.triangle as usize];
        // The most negative φ_k whose opposite edge can be crossed.
        let next = (0..3)
            .filter(|&k| phi[k] < OUTSIDE)
            .map(|k| (phi[k], across[(k + 1) % 3]))
            .filter(|&(_, t)| {
                t != RIM
                    && main
                        .nodes(t as usize)
                        .is_none_or(|corners| !corners.contains(&node))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let Some((_, next)) = next else {
            // Inside, or past the rim: extrapolated on this triangle.
            return current;
        };
        visited[hop] = current.triangle;
        if visited[..=hop].contains(&next) {
            break;
        }
        current = project(next);
        if lowest(&current) > lowest(&best) {
            best = current;
        }
    }
    best
}

/// ∂f_s/∂x_j and ∂φ/∂x_j (row k = ∂φ_k/∂x_j) for j = the secondary node and the
/// triangle's corners 0, 1, 2, at the projection `p` with direction ν = `direction` and
/// |N| = `length`; `force` = A t [N] and `slope` = A t' [N/m].
pub fn smooth_tangent(
    p: &NormalProjection,
    direction: &Vector3<f64>,
    length: f64,
    (force, slope): (f64, f64),
) -> ([Matrix3<f64>; 4], [Matrix3<f64>; 4]) {
    let phi = p.barycentric;
    let spread = |block: Matrix3<f64>| [block, -phi.x * block, -phi.y * block, -phi.z * block];
    let Some(inverse) = p.inverse else {
        // A collapsed triangle: the node–point stiffness along ν alone.
        return (
            spread(slope * direction * direction.transpose()),
            [Matrix3::zeros(); 4],
        );
    };
    let (a1, a2, a3) = (inverse.row(0), inverse.row(1), inverse.row(2));
    let [n0, n1, n2] = p.normals;
    let q = (n1 - n0) * a1 + (n2 - n0) * a2;
    let gap_gradient = length * a3 + p.along * direction.transpose() * q;
    let across = Matrix3::identity() - direction * direction.transpose();
    let stiffness = slope * direction * gap_gradient + (force / length) * across * q;
    let shift = Matrix3::from_rows(&[-(a1 + a2), a1.into_owned(), a2.into_owned()]);
    (spread(stiffness), spread(shift))
}

#[cfg(test)]
mod tests;
