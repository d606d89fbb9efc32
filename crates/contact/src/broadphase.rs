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

use nalgebra::{Isometry3, Point3, Vector3};
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

/// Counts of the tree updates since the start.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BroadphaseStatistics {
    /// Searches done.
    pub searches: usize,
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
}

/// The BVH of a main surface and the candidate triangles of each secondary node.
#[derive(Clone)]
pub struct Broadphase {
    search_distance: f64,
    bvh: Bvh,
    workspace: BvhWorkspace,
    built_cost: f64,
    boxes: Vec<Aabb>,
    chunks: Vec<CandidateChunk>,
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
            statistics: BroadphaseStatistics::default(),
        }
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
    /// `target` at nodal `positions` [m] and `time` [s].
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
            ContactTarget::Deformable(surface) => {
                self.boxes.clear();
                self.boxes.extend(
                    (0..surface.triangles.len())
                        .map(|t| triangle_box(&surface.corners(t, positions))),
                );
                self.update_tree();
                None
            }
        };
        self.query(frame.as_ref(), positions, secondary);
    }

    /// The candidate triangles of secondary node number `i` (its index in the list given to
    /// [`Self::search`]), in a fixed order.
    #[inline]
    pub fn candidates(&self, i: usize) -> &[u32] {
        let chunk = &self.chunks[i / CHUNK];
        let k = i % CHUNK;
        &chunk.triangles[chunk.offsets[k] as usize..chunk.offsets[k + 1] as usize]
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

    fn query(
        &mut self,
        frame: Option<&Isometry3<f64>>,
        positions: &[Vector3<f64>],
        secondary: &[u32],
    ) {
        let chunk_count = secondary.len().div_ceil(CHUNK);
        self.chunks
            .resize_with(chunk_count, CandidateChunk::default);
        let bvh = &self.bvh;
        let half = Vector::splat(self.search_distance);
        self.chunks
            .par_iter_mut()
            .zip(secondary.par_chunks(CHUNK))
            .for_each(|(chunk, nodes)| {
                chunk.offsets.clear();
                chunk.triangles.clear();
                chunk.offsets.push(0);
                for &n in nodes {
                    let x = positions[n as usize];
                    let x = frame.map_or(x, |iso| iso.transform_point(&Point3::from(x)).coords);
                    let p = vector(&x);
                    let query = Aabb::new(p - half, p + half);
                    chunk.triangles.extend(bvh.intersect_aabb(&query));
                    chunk.offsets.push(chunk.triangles.len() as u32);
                }
            });
    }
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
        // The 1 mm shear stays inside the fattened leaves (no refit); the others do not.
        assert!(
            statistics.refits >= 2 && statistics.refits <= 3,
            "{statistics:?}"
        );
    }
}
