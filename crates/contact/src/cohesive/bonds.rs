//! Bonds between the nodes of the secondary surface and points of the main surface.
//!
//! A bond ties secondary node s (tributary area A [m²], a reference area) to the point
//! x_m = Σ ξ_k x_k of main triangle (x_0, x_1, x_2) with barycentric coordinates ξ. It
//! forms at the reference configuration when s lies within the bond tolerance of the main
//! surface (at the closest point of the closest triangle; ties go to the lowest triangle
//! index, so the choice is deterministic), and carries the law's damage history κ.
//!
//! At positions x: separation δ = x_s − x_m [m], local separation δ_loc = Rᵀ δ − δ_ref
//! with R = [n s t] the current frame of the triangle (`triangle::frame`) and δ_ref the
//! local separation at formation (a bond forms stress-free: a node bonded across an
//! initial gap of 2 mm is not pulled across it; the gap is its rest state), traction
//! t = R t_law(δ_loc) [Pa] and the force on the secondary node f_s = A t [N] (it enters
//! like an internal force, M a + f_int + f_c = f_ext: an opened bond pulls s back toward
//! the main surface).
//!
//! With equal stiffnesses (the law does not depend on the frame) the bond is a spring
//! with energy A ψ(r), r = x_s − Σ ξ_k x_k − R δ_ref, and the forces on the corners of a
//! deformable main triangle are its gradient: f_k = −ξ_k f_s − T_kᵀ f_s with
//! T_k = ∂(R δ_ref)/∂x_k, the turn of the rest offset. Without the second part a bond
//! across a gap would push the main triangle at the wrong point (its forces would not
//! balance moments) and its stiffness would be unsymmetric (on the coarse knee
//! |K − Kᵀ| reached 8.6e3 N/m and sym(K) had 12 negative eigenvalues). A rigid main takes
//! −f_s on the body. The stiffness blocks: ∂f_s/∂x_s = A R C Rᵀ =: S [N/m] with
//! C = ∂t_law/∂δ_loc, ∂f_s/∂x_k = −S (ξ_k I + T_k), holding the frame R fixed except for
//! the turn of the rest state (exact for the elastic law, C = K I); the corner rows are
//! the transposes plus the curvature ∂(T_kᵀ f_s)/∂x_j of the turning rest offset
//! ([`turned_vector_curvature`]). For equal stiffnesses the whole block is the Hessian of
//! the energy: symmetric, and positive semi-definite at rest.

use nalgebra::{Isometry3, Matrix3, Vector3};
use rayon::prelude::*;

use super::frame::{frame, turned_vector_curvature, turned_vector_derivatives};
use super::law::CohesiveLaw;
use super::slide::evaluate_sliding;
use crate::broadphase::Broadphase;
use crate::main_side::MainSide;
use crate::projection::{Projection, project_on_triangle};
use crate::surface::ContactTarget;

/// One bond (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Bond {
    /// The secondary node.
    pub node: u32,
    /// Its tributary area in the reference configuration [m²].
    pub area: f64,
    /// The main triangle (index into the main surface's triangles).
    pub triangle: u32,
    /// Barycentric coordinates ξ of the bonded point in the triangle.
    pub coordinates: Vector3<f64>,
    /// Unit normal of the triangle where the bond formed (the frame of a triangle that
    /// has collapsed to zero area falls back on it).
    pub normal: Vector3<f64>,
    /// Committed damage history κ [m].
    pub history: f64,
    /// The bond's rest state δ_ref = Rᵀ (x_s − x_m) at formation [m], in the local frame:
    /// (g₀, 0, 0) with g₀ the signed gap for a node over the face; with in-plane parts for
    /// a node that bonded to an edge or a vertex. A sliding bond uses the gap it measures
    /// at formation instead (see `super::slide` and `super::smooth_slide`).
    pub reference_separation: Vector3<f64>,
}

/// One bond at the positions of the last force evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BondState {
    /// Force f_s on the secondary node, as it enters the balance [N].
    pub force: Vector3<f64>,
    /// ∂f_s/∂x_j [N/m] for j = the secondary node and the main triangle's corners 0, 1, 2
    /// (material-point bond: A R C Rᵀ times 1, −ξ_0, −ξ_1, −ξ_2).
    pub coupling: [Matrix3<f64>; 4],
    /// ∂ξ_k/∂x_j [1/m] (row k) for the same j: how the reactions −ξ_k f_s shift along the
    /// triangle (zero for material-point bonds).
    pub coordinate_gradients: [Matrix3<f64>; 4],
    /// T_k = ∂(R δ_ref)/∂x_k [1]: how the rest offset turns with corner k of a deformable
    /// main triangle (zero for a rigid main, a bond without rest offset, a sliding bond);
    /// the corners take −T_kᵀ f_s besides −ξ_k f_s.
    pub turning: [Matrix3<f64>; 3],
    /// ∂(T_kᵀ f_s)/∂x_j [N/m] for corners k, j (with the stiffness; zero where `turning`
    /// is).
    pub turning_curvature: [[Matrix3<f64>; 3]; 3],
    /// Traction on the secondary surface, −R t_law [Pa].
    pub traction: Vector3<f64>,
    /// Local separation (δ_n, δ_s, δ_t) [m] (a sliding bond: (g, 0, 0), g the gap).
    pub separation: Vector3<f64>,
    /// The main triangle the state refers to: the bond's, or the one a smoothly sliding
    /// bond's walk reached (`super::smooth_slide`).
    pub triangle: u32,
    /// Barycentric coordinates ξ of the main point in that triangle.
    pub coordinates: Vector3<f64>,
    /// Trial damage history κ [m] and damage D.
    pub history: f64,
    pub damage: f64,
    /// Stored energy A ½ t·δ [J].
    pub energy: f64,
}

impl Default for BondState {
    fn default() -> Self {
        BondState {
            force: Vector3::zeros(),
            coupling: [Matrix3::zeros(); 4],
            coordinate_gradients: [Matrix3::zeros(); 4],
            turning: [Matrix3::zeros(); 3],
            turning_curvature: [[Matrix3::zeros(); 3]; 3],
            traction: Vector3::zeros(),
            separation: Vector3::zeros(),
            triangle: 0,
            coordinates: Vector3::zeros(),
            history: 0.0,
            damage: 0.0,
            energy: 0.0,
        }
    }
}

/// Bonds of the secondary `nodes` (with tributary `areas` [m²]; nodes of zero area carry
/// nothing and do not bond) to the `main` surface at the reference nodal `positions` [m]
/// (a rigid main placed at t = 0), within `tolerance` [m]. A node never bonds to a triangle
/// of which it is a vertex. The candidates come from the broadphase (a BVH of the main
/// triangles, boxes within `tolerance`), the closest point from
/// [`project_on_triangle`]; the nodes are treated in parallel, each on its own, so the
/// bonds do not depend on the number of threads.
pub fn form_bonds(
    nodes: &[u32],
    areas: &[f64],
    main: &ContactTarget,
    positions: &[Vector3<f64>],
    tolerance: f64,
) -> Vec<Bond> {
    let placement = main.placement(0.0);
    let mut broadphase = Broadphase::new(tolerance);
    broadphase.search(main, 0.0, positions, nodes);
    let found: Vec<Option<Bond>> = (0..nodes.len())
        .into_par_iter()
        .map(|i| {
            let node = nodes[i];
            if areas[i] <= 0.0 {
                return None;
            }
            let x = positions[node as usize];
            let mut best: Option<(u32, Projection, f64)> = None;
            for &triangle in broadphase.candidates(i) {
                if main
                    .nodes(triangle as usize)
                    .is_some_and(|ids| ids.contains(&node))
                {
                    continue;
                }
                let corners = main.corners(triangle as usize, positions, &placement);
                let projection = project_on_triangle(&x, &corners);
                let distance2 = (x - projection.point).norm_squared();
                let better =
                    best.is_none_or(|(t, _, d)| distance2 < d || (distance2 == d && triangle < t));
                if better {
                    best = Some((triangle, projection, distance2));
                }
            }
            let (triangle, projection, distance2) = best?;
            (distance2.sqrt() <= tolerance).then(|| {
                let [a, b, c] = main.corners(triangle as usize, positions, &placement);
                let rotation = frame(&a, &b, &c, &projection.normal);
                Bond {
                    node,
                    area: areas[i],
                    triangle,
                    coordinates: Vector3::from(projection.barycentric),
                    normal: projection.normal,
                    history: 0.0,
                    reference_separation: rotation.transpose() * (x - projection.point),
                }
            })
        })
        .collect();
    found.into_iter().flatten().collect()
}

/// The smallest distance from any of `nodes` to the `main` surface at the reference
/// `positions` [m] (every node against every triangle: for the message when nothing
/// bonds), infinite if there is no pair.
pub fn closest_distance(nodes: &[u32], main: &ContactTarget, positions: &[Vector3<f64>]) -> f64 {
    let placement = main.placement(0.0);
    nodes
        .par_iter()
        .map(|&node| {
            let x = positions[node as usize];
            (0..main.triangles().len())
                .filter(|&t| main.nodes(t).is_none_or(|ids| !ids.contains(&node)))
                .map(|t| {
                    let corners = main.corners(t, positions, &placement);
                    (x - project_on_triangle(&x, &corners).point).norm()
                })
                .fold(f64::INFINITY, f64::min)
        })
        .reduce(|| f64::INFINITY, f64::min)
}

impl Bond {
    /// The bonded point x_m = Σ ξ_k x_k of the triangle with `vertices` [m].
    pub fn main_point(&self, vertices: &[Vector3<f64>; 3]) -> Vector3<f64> {
        self.coordinates.x * vertices[0]
            + self.coordinates.y * vertices[1]
            + self.coordinates.z * vertices[2]
    }

    /// The bond at secondary position `x` [m] with the main triangle at `vertices` [m],
    /// the triangle of a deformable main (`deformable_main`: its corners take the turn of
    /// the rest offset) or of a rigid one; the stiffness blocks only `with_stiffness`,
    /// zero otherwise.
    pub fn evaluate(
        &self,
        law: &CohesiveLaw,
        vertices: &[Vector3<f64>; 3],
        x: &Vector3<f64>,
        (deformable_main, with_stiffness): (bool, bool),
    ) -> BondState {
        let [a, b, c] = vertices;
        let rotation = frame(a, b, c, &self.normal);
        let separation =
            rotation.transpose() * (x - self.main_point(vertices)) - self.reference_separation;
        let response = law.evaluate(&separation, self.history);
        let traction = rotation * response.traction;
        let force = self.area * traction;
        let turns = deformable_main && self.reference_separation != Vector3::zeros();
        let turning = if turns {
            turned_vector_derivatives(vertices, &self.reference_separation)
        } else {
            [Matrix3::zeros(); 3]
        };
        let (coupling, turning_curvature) = if with_stiffness {
            let stiffness = self.area * rotation * response.tangent * rotation.transpose();
            let mut coupling = point_coupling(&stiffness, &self.coordinates);
            // f_s ∋ −S R δ_ref: the corners also move the rest state, −S T_k.
            for k in 0..3 {
                coupling[1 + k] -= stiffness * turning[k];
            }
            let curvature = if turns {
                turned_vector_curvature(vertices, &self.reference_separation, &force)
            } else {
                [[Matrix3::zeros(); 3]; 3]
            };
            (coupling, curvature)
        } else {
            ([Matrix3::zeros(); 4], [[Matrix3::zeros(); 3]; 3])
        };
        BondState {
            force,
            coupling,
            coordinate_gradients: [Matrix3::zeros(); 4],
            turning,
            turning_curvature,
            traction: -traction,
            separation,
            triangle: self.triangle,
            coordinates: self.coordinates,
            history: response.history,
            damage: response.damage,
            energy: self.area * response.energy,
        }
    }
}

/// The blocks ∂f_s/∂x_j of a bond whose force depends on x_s − Σ ξ_k x_k only, through
/// `stiffness` = ∂f_s/∂x_s: (1, −ξ_0, −ξ_1, −ξ_2) × stiffness.
pub fn point_coupling(stiffness: &Matrix3<f64>, coordinates: &Vector3<f64>) -> [Matrix3<f64>; 4] {
    [
        *stiffness,
        -coordinates.x * stiffness,
        -coordinates.y * stiffness,
        -coordinates.z * stiffness,
    ]
}

/// Evaluates every bond at nodal `positions` with the main placed by `placement` into
/// `states` (one per bond), as material-point bonds or, with `sliding`, as sliding bonds
/// ([`evaluate_sliding`]), the stiffness blocks only `with_stiffness`; in parallel over
/// fixed blocks of bonds: each state depends on its bond only, so the result does not
/// depend on the number of threads.
pub fn evaluate_all(
    bonds: &[Bond],
    law: &CohesiveLaw,
    main: &ContactTarget,
    positions: &[Vector3<f64>],
    placement: &Isometry3<f64>,
    (sliding, with_stiffness): (bool, bool),
    states: &mut [BondState],
) {
    let deformable = matches!(main, ContactTarget::Deformable(_));
    states
        .par_iter_mut()
        .zip(bonds.par_iter())
        .with_min_len(64)
        .for_each(|(state, bond)| {
            let triangle = bond.triangle as usize;
            let vertices = main.corners(triangle, positions, placement);
            let x = &positions[bond.node as usize];
            *state = if sliding {
                let rim = main.rim(triangle);
                evaluate_sliding(bond, law, &vertices, rim, x, with_stiffness)
            } else {
                bond.evaluate(law, &vertices, x, (deformable, with_stiffness))
            };
        });
}
