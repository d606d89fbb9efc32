//! Broadphase: a parry3d bounding-volume hierarchy (BVH) of the main side's triangles,
//! queried with a box of half-width `search_distance` around each secondary node; the
//! candidate triangles of each node are kept until the next search and reused by every
//! force evaluation in between.
//!
//! - Rigid main side: the tree holds the triangles in the body frame, is built once and
//!   never changes; each query point is taken into the body frame, X = R(t)ᵀ(x − c − T(t))
//!   + c (the inverse of the surface's isometry at the search time).
//! - Deformable main side: each leaf holds its triangle's box fattened by
//!   [`FATTENING`] × `search_distance`. At each search every triangle's current box is
//!   compared with its leaf: a leaf that no longer contains it is rewritten (fattened
//!   again) and the tree refitted. The tree is rebuilt from scratch when its quality has
//!   degraded: when the sum of the half surface areas of all its nodes (the SAH cost of a
//!   query, up to a constant) exceeds [`REBUILD_RATIO`] times its value right after the
//!   last build.
//!
//! Candidate lists are stored per chunk of [`CHUNK`] consecutive secondary nodes, filled in
//! parallel, each in a fixed order (the tree's traversal order, which does not depend on
//! the thread count), into buffers kept from one search to the next.
//!
//! **Verlet margin.** The tree is queried with a box of half-width s + m (s the search
//! distance, m = [`VERLET_MARGIN`] × s), and a search reuses the lists of the last query
//! while the secondary nodes (in the tree's frame) and the main side's vertices have moved,
//! since that query, by at most δ_s and δ_m with δ_s + δ_m ≤ m: a triangle whose box now
//! comes within s of a node came within s + δ_s + δ_m ≤ s + m of it at the query. The
//! lists then hold a superset of the triangles within s, so the closest one among them is
//! the same. An explicit step moves nodes by micrometres against margins of millimetres:
//! the tree is queried once in thousands of steps.

use nalgebra::{Point3, Vector3};
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume as _};
use parry3d_f64::math::Vector;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhLeafUpdateStatus, BvhWorkspace};
use rayon::prelude::*;

use crate::surface::ContactTarget;

/// Secondary nodes per parallel task (and per candidate buffer).
pub const CHUNK: usize = 512;

/// Leaves hold their triangle's box grown by this fraction of the search distance, so that
/// small motions leave the tree untouched.
pub const FATTENING: f64 = 0.5;

/// The tree is rebuilt when its cost exceeds this multiple of the cost after the last build.
pub const REBUILD_RATIO: f64 = 1.5;

/// The Verlet margin m as a fraction of the search distance (see the module docs).
pub const VERLET_MARGIN: f64 = 0.5;

/// Counts of the tree updates since the start.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BroadphaseStatistics {
    /// Searches done.
    pub searches: usize,
    /// Searches that queried the tree (the others reused the lists within the margin).
    pub queries: usize,
    /// Builds from scratch (the first one included).
    pub builds: usize,
    /// Refits (some leaf had moved out of its fattened box).
    pub refits: usize,
}

/// The candidate triangles of one chunk of secondary nodes, in compressed rows.
#[derive(Debug, Clone, Default)]
struct CandidateChunk {
    offsets: Vec<u32>,
    triangles: Vec<u32>,
    /// Each candidate's box distance from its node at the query [m].
    distances: Vec<f64>,
    /// One node's (distance, triangle) pairs while they are sorted.
    scratch: Vec<(f64, u32)>,
}

/// The BVH of a main surface and the candidate triangles of each secondary node.
#[derive(Clone)]
pub struct Broadphase {
    search_distance: f64,
    bvh: Bvh,
    workspace: BvhWorkspace,
    built_cost: f64,
    /// Each main triangle's box at the last query (rigid: in the body frame, fixed).
    boxes: Vec<Aabb>,
    chunks: Vec<CandidateChunk>,
    /// The secondary nodes in the tree's frame now, and at the last query [m].
    points: Vec<Vector3<f64>>,
    queried_points: Vec<Vector3<f64>>,
    /// A deformable main side's vertices at the last query [m].
    queried_main: Vec<Vector3<f64>>,
    statistics: BroadphaseStatistics,
}

impl std::fmt::Debug for Broadphase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Broadphase")
            .field("search_distance", &self.search_distance)
            .field("leaves", &self.bvh.leaf_count())
            .field("statistics", &self.statistics)
            .finish()
    }
}

fn vector(p: &Vector3<f64>) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

fn triangle_box(corners: &[Vector3<f64>; 3]) -> Aabb {
    let mins = corners[0].inf(&corners[1]).inf(&corners[2]);
    let maxs = corners[0].sup(&corners[1]).sup(&corners[2]);
    Aabb::new(vector(&mins), vector(&maxs))
}

impl Broadphase {
    /// A broadphase that pairs a node with every triangle whose box comes within
    /// `search_distance` [m] of it.
    pub fn new(search_distance: f64) -> Self {
        Broadphase {
            search_distance,
            bvh: Bvh::new(),
            workspace: BvhWorkspace::default(),
            built_cost: 0.0,
            boxes: Vec::new(),
            chunks: Vec::new(),
            points: Vec::new(),
            queried_points: Vec::new(),
            queried_main: Vec::new(),
            statistics: BroadphaseStatistics::default(),
        }
    }

    /// Forget the tree and the candidate lists: the next search builds and queries
    /// afresh, as a new broadphase's first would (at a checkpoint, so that a run and its
    /// resumption find the same candidates).
    pub fn forget(&mut self) {
        self.bvh = Bvh::new();
        self.built_cost = 0.0;
        self.queried_points.clear();
        self.queried_main.clear();
    }

    /// The search distance [m].
    pub fn search_distance(&self) -> f64 {
        self.search_distance
    }

    /// Counts of builds and refits.
    pub fn statistics(&self) -> BroadphaseStatistics {
        self.statistics
    }

    /// Finds the candidate triangles of every node of `secondary` (global ids) against
    /// `target` at nodal `positions` [m] and `time` [s]: every triangle whose box comes
    /// within the search distance of the node, and possibly others within the margin.
    /// Queries the tree only when the nodes have moved too far since the last query.
    pub fn search(
        &mut self,
        target: &ContactTarget,
        time: f64,
        positions: &[Vector3<f64>],
        secondary: &[u32],
    ) {
        self.statistics.searches += 1;
        let frame = match target {
            ContactTarget::Rigid(rigid) => {
                if self.bvh.is_empty() {
                    self.boxes.clear();
                    self.boxes.extend(
                        rigid
                            .triangles
                            .iter()
                            .map(|t| triangle_box(&t.map(|v| rigid.vertices[v as usize]))),
                    );
                    self.build();
                }
                Some(rigid.motion.isometry_at(time).inverse())
            }
            ContactTarget::Deformable(_) => None,
        };
        self.points.clear();
        self.points.extend(secondary.iter().map(|&n| {
            let x = positions[n as usize];
            frame.map_or(x, |iso| iso.transform_point(&Point3::from(x)).coords)
        }));
        let secondary_motion = largest_motion(&self.points, &self.queried_points);
        let main_motion = self.main_motion_since_query(target, positions);
        if secondary_motion + main_motion <= VERLET_MARGIN * self.search_distance {
            return;
        }
        if let ContactTarget::Deformable(surface) = target {
            self.boxes.clear();
            self.boxes.extend(
                (0..surface.triangles.len()).map(|t| triangle_box(&surface.corners(t, positions))),
            );
            self.update_tree();
            self.queried_main.clear();
            self.queried_main
                .extend(surface.nodes.iter().map(|&n| positions[n as usize]));
        }
        self.query();
        std::mem::swap(&mut self.points, &mut self.queried_points);
        self.statistics.queries += 1;
    }

    /// The distance [m] from `x` (in the body frame) to the box of triangle `t` of a rigid
    /// main side: a lower bound of the distance to the triangle.
    /// Only for a rigid main side, whose boxes never change (a deformable one's are those
    /// of the last query).
    #[inline]
    pub fn rigid_box_distance(&self, t: usize, x: &Vector3<f64>) -> f64 {
        box_distance(&self.boxes[t], x)
    }

    /// The candidate triangles of secondary node number `i` (its index in the list given to
    /// [`Self::search`]), nearest box (at the last query) first, ties by triangle index.
    #[inline]
    pub fn candidates(&self, i: usize) -> &[u32] {
        let chunk = &self.chunks[i / CHUNK];
        let k = i % CHUNK;
        &chunk.triangles[chunk.offsets[k] as usize..chunk.offsets[k + 1] as usize]
    }

    /// The distance [m] from secondary node number `i` to the box of each of its
    /// [`candidates`](Self::candidates), both where they were at the last query:
    /// nondecreasing.
    #[inline]
    pub fn candidate_box_distances(&self, i: usize) -> &[f64] {
        let chunk = &self.chunks[i / CHUNK];
        let k = i % CHUNK;
        &chunk.distances[chunk.offsets[k] as usize..chunk.offsets[k + 1] as usize]
    }

    /// Where secondary node number `i` was at the last query, in the tree's frame [m].
    #[inline]
    pub fn queried_point(&self, i: usize) -> Vector3<f64> {
        self.queried_points[i]
    }

    /// The largest distance [m] any vertex of a deformable main side `target` has moved
    /// between the last query and nodal `positions` (0 for a rigid main side, whose
    /// candidates live in its body frame). Every point of a triangle has then moved at most
    /// this far, so a candidate's distance from node i at `positions` is at least its
    /// [`candidate_box_distances`](Self::candidate_box_distances) entry minus this minus
    /// how far the node has moved since [`queried_point`](Self::queried_point).
    pub fn main_motion_since_query(
        &self,
        target: &ContactTarget,
        positions: &[Vector3<f64>],
    ) -> f64 {
        match target {
            ContactTarget::Deformable(surface) => largest_motion_of(
                surface.nodes.iter().map(|&n| positions[n as usize]),
                &self.queried_main,
            ),
            ContactTarget::Rigid(_) => 0.0,
        }
    }

    /// Total number of (node, triangle) candidates of the last search.
    pub fn candidate_count(&self) -> usize {
        self.chunks.iter().map(|c| c.triangles.len()).sum()
    }

    fn build(&mut self) {
        let fat = FATTENING * self.search_distance;
        let fattened: Vec<Aabb> = self.boxes.iter().map(|b| b.loosened(fat)).collect();
        self.bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &fattened);
        self.built_cost = self.cost();
        self.statistics.builds += 1;
    }

    /// Refits the leaves that moved out of their fattened boxes; rebuilds when the tree's
    /// cost has grown past [`REBUILD_RATIO`].
    fn update_tree(&mut self) {
        if self.bvh.leaf_count() as usize != self.boxes.len() {
            self.build();
            return;
        }
        let fat = FATTENING * self.search_distance;
        let mut changed = false;
        for (t, b) in self.boxes.iter().enumerate() {
            let status = self.bvh.insert_or_update_partially(*b, t as u32, fat);
            changed |= status != BvhLeafUpdateStatus::Unchanged;
        }
        if !changed {
            return;
        }
        self.bvh.refit(&mut self.workspace);
        self.statistics.refits += 1;
        if self.cost() > REBUILD_RATIO * self.built_cost {
            self.build();
        }
    }

    /// Σ half surface areas of all the tree's nodes.
    fn cost(&self) -> f64 {
        let mut cost = 0.0;
        self.bvh.traverse(|node| {
            cost += node.aabb().half_area();
            parry3d_f64::partitioning::TraversalAction::Continue
        });
        cost
    }

    /// Fills the candidate lists of the nodes at `self.points` (the tree's frame), with
    /// boxes of half-width s + m.
    fn query(&mut self) {
        let chunk_count = self.points.len().div_ceil(CHUNK);
        self.chunks
            .resize_with(chunk_count, CandidateChunk::default);
        let bvh = &self.bvh;
        let half = Vector::splat((1.0 + VERLET_MARGIN) * self.search_distance);
        let boxes = &self.boxes;
        self.chunks
            .par_iter_mut()
            .zip(self.points.par_chunks(CHUNK))
            .for_each(|(chunk, points)| {
                chunk.offsets.clear();
                chunk.triangles.clear();
                chunk.distances.clear();
                chunk.offsets.push(0);
                for x in points {
                    let p = vector(x);
                    let query = Aabb::new(p - half, p + half);
                    chunk.scratch.clear();
                    chunk.scratch.extend(
                        bvh.intersect_aabb(&query)
                            .map(|t| (box_distance(&boxes[t as usize], x), t)),
                    );
                    chunk
                        .scratch
                        .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                    chunk.triangles.extend(chunk.scratch.iter().map(|c| c.1));
                    chunk.distances.extend(chunk.scratch.iter().map(|c| c.0));
                    chunk.offsets.push(chunk.triangles.len() as u32);
                }
            });
    }
}

/// The distance [m] from `x` to `b`.
fn box_distance(b: &Aabb, x: &Vector3<f64>) -> f64 {
    let gap = |v: f64, low: f64, high: f64| (low - v).max(v - high).max(0.0);
    let dx = gap(x.x, b.mins.x, b.maxs.x);
    let dy = gap(x.y, b.mins.y, b.maxs.y);
    let dz = gap(x.z, b.mins.z, b.maxs.z);
    (dx * dx + dy * dy + dz * dz).sqrt()
}

/// The largest distance between `now[i]` and `then[i]` [m]; infinite when the lists differ
/// in length (nothing was queried yet, or other nodes).
fn largest_motion(now: &[Vector3<f64>], then: &[Vector3<f64>]) -> f64 {
    largest_motion_of(now.iter().copied(), then)
}

fn largest_motion_of(
    now: impl ExactSizeIterator<Item = Vector3<f64>>,
    then: &[Vector3<f64>],
) -> f64 {
    if now.len() != then.len() || then.is_empty() {
        return f64::INFINITY;
    }
    now.zip(then)
        .map(|(a, b)| (a - b).norm_squared())
        .fold(0.0, f64::max)
        .sqrt()
}

#[cfg(test)]
mod tests {
    use musclefem_core::mesh::generate::box_of_hexes;
    use musclefem_core::solver::{RigidMotion, RigidRotation};
    use musclefem_materials::Amplitude;
    use nalgebra::{Unit, Vector3};

    use super::*;
    use crate::rigid_surface::RigidSurface;
    use crate::surface::DeformableSurface;

    /// Triangles whose box comes within `distance` of x (in the infinity norm), by brute force.
    fn near(
        corners: impl Iterator<Item = [Vector3<f64>; 3]>,
        x: &Vector3<f64>,
        d: f64,
    ) -> Vec<u32> {
        corners
            .enumerate()
            .filter(|(_, c)| {
                let lo = c[0].inf(&c[1]).inf(&c[2]);
                let hi = c[0].sup(&c[1]).sup(&c[2]);
                (0..3).all(|k| x[k] >= lo[k] - d && x[k] <= hi[k] + d)
            })
            .map(|(t, _)| t as u32)
            .collect()
    }

    fn points(count: usize, scale: f64, shift: Vector3<f64>) -> Vec<Vector3<f64>> {
        // A reproducible scatter (Weyl sequence).
        (0..count)
            .map(|i| {
                let f = |a: f64| ((i as f64 + 1.0) * a).fract();
                shift + Vector3::new(f(0.754877666), f(0.569840291), f(0.362345)) * scale
            })
            .collect()
    }

    /// Candidates contain every triangle whose box is within the search distance of the
    /// node, for a rigid sphere moved and turned away from its body frame.
    #[test]
    fn rigid_candidates_contain_every_near_triangle_in_the_moving_frame() {
        let sphere = RigidSurface::sphere("ball", Vector3::zeros(), 1.0, 3).unwrap();
        let motion = RigidMotion {
            translation: [Some(Amplitude::ramp(1.0, 0.5).unwrap()), None, None],
            rotation: Some(RigidRotation {
                center: Vector3::new(0.0, 0.2, 0.0),
                axis: Unit::new_normalize(Vector3::new(1.0, 1.0, 0.0)),
                angle: Amplitude::ramp(1.0, 0.7).unwrap(),
            }),
            follower: None,
        };
        let time = 0.6;
        let iso = motion.isometry_at(time);
        let target = ContactTarget::Rigid(sphere.with_motion(motion));
        let positions = points(300, 3.0, Vector3::repeat(-1.0));
        let secondary: Vec<u32> = (0..positions.len() as u32).rev().collect();
        let mut broadphase = Broadphase::new(0.1);
        broadphase.search(&target, time, &positions, &secondary);
        let ContactTarget::Rigid(rigid) = &target else {
            unreachable!()
        };
        let mut found = 0;
        for (i, &n) in secondary.iter().enumerate() {
            let body = iso
                .inverse_transform_point(&Point3::from(positions[n as usize]))
                .coords;
            let corners = rigid
                .triangles
                .iter()
                .map(|t| t.map(|v| rigid.vertices[v as usize]));
            let candidates = broadphase.candidates(i);
            for t in near(corners, &body, 0.1) {
                assert!(candidates.contains(&t), "node {n} misses triangle {t}");
                found += 1;
            }
        }
        assert!(found > 100, "the test must find pairs: {found}");
        assert_eq!(broadphase.statistics().builds, 1);
    }

    /// Nodes that move by less than the Verlet margin keep their candidate lists, which
    /// stay complete; a larger motion queries the tree again.
    #[test]
    fn small_motions_reuse_complete_candidate_lists() {
        let sphere = RigidSurface::sphere("ball", Vector3::zeros(), 1.0, 3).unwrap();
        let target = ContactTarget::Rigid(sphere.clone());
        let start = points(300, 3.0, Vector3::repeat(-1.5));
        let secondary: Vec<u32> = (0..start.len() as u32).collect();
        let search_distance = 0.1;
        let mut broadphase = Broadphase::new(search_distance);
        let margin = VERLET_MARGIN * search_distance;
        // Moves along (1, 1, 1)/√3 from the start, in units of the margin: the first three
        // stay within it, the last goes past it.
        let moves = [0.0, 0.3, 1.0, 1.6];
        for (step, amount) in moves.into_iter().enumerate() {
            let shift = Vector3::repeat(amount * margin / 3f64.sqrt());
            let positions: Vec<Vector3<f64>> = start.iter().map(|p| p + shift).collect();
            broadphase.search(&target, 0.0, &positions, &secondary);
            let corners = || {
                sphere
                    .triangles
                    .iter()
                    .map(|t| t.map(|v| sphere.vertices[v as usize]))
            };
            let mut found = 0;
            for (i, x) in positions.iter().enumerate() {
                for t in near(corners(), x, search_distance) {
                    assert!(
                        broadphase.candidates(i).contains(&t),
                        "step {step}: node {i} misses triangle {t}"
                    );
                    found += 1;
                }
            }
            assert!(
                found > 100,
                "step {step}: the test must find pairs: {found}"
            );
        }
        let statistics = broadphase.statistics();
        assert_eq!((statistics.searches, statistics.queries), (4, 2));
    }

    /// A deformable surface that moves: small motions leave the tree, larger ones refit it,
    /// and the candidates stay complete.
    #[test]
    fn deformable_candidates_follow_the_moving_surface() {
        let mesh = box_of_hexes([1.0, 1.0, 1.0], [8, 8, 8]).unwrap();
        let surface = DeformableSurface::from_mesh_surface(&mesh, "outer").unwrap();
        let reference: Vec<Vector3<f64>> = (0..mesh.node_count())
            .map(|i| mesh.nodes.position(i))
            .collect();
        let queries = points(400, 1.4, Vector3::repeat(-0.2));
        let mut broadphase = Broadphase::new(0.05);
        for (step, amount) in [0.0, 0.001, 0.2, 0.6].into_iter().enumerate() {
            // A shear of the box: x += amount · z².
            let mut positions: Vec<Vector3<f64>> = reference
                .iter()
                .map(|p| p + Vector3::new(amount * p.z * p.z, 0.0, 0.0))
                .collect();
            let first = positions.len() as u32;
            positions.extend(&queries);
            let secondary: Vec<u32> = (first..positions.len() as u32).collect();
            let target = ContactTarget::Deformable(surface.clone());
            broadphase.search(&target, 0.0, &positions, &secondary);
            let mut found = 0;
            for (i, &n) in secondary.iter().enumerate() {
                let corners = (0..surface.triangles.len()).map(|t| surface.corners(t, &positions));
                for t in near(corners, &positions[n as usize], 0.05) {
                    assert!(
                        broadphase.candidates(i).contains(&t),
                        "step {step}: node {n}, triangle {t}"
                    );
                    found += 1;
                }
            }
            assert!(found > 50, "step {step}: {found}");
        }
        let statistics = broadphase.statistics();
        assert_eq!(statistics.searches, 4);
        // The 1 mm shear stays within the 25 mm Verlet margin: its search reused the lists.
        assert_eq!(statistics.queries, 3);
        // The 1 mm shear stays inside the fattened leaves (no refit); the others do not.
        assert!(
            statistics.refits >= 2 && statistics.refits <= 3,
            "{statistics:?}"
        );
    }
}
