//! The consistent stiffness of one active node-on-feature penalty pair.
//!
//! With d = x_s − x_m (x_m = Σ_j N_j x_j the closest point on the feature: face, edge or
//! vertex of the main triangle) and k = ε A_s [N/m], the forces are f_s = k d and
//! f_j = −N_j k d, i.e. f_l = γ_l k d with γ_s = 1, γ_j = −N_j. They derive from the
//! potential ½ k |d|² = ½ ε A_s g² (d = g ν), so the stiffness is symmetric.
//!
//! The feature has tangents a_α (two on a face, a₁ = x₂ − x₁, a₂ = x₃ − x₁; one on an
//! edge, x_q − x_p; none on a vertex), metric M_αβ = a_α·a_β, dual vectors
//! a^α = M⁻¹_αβ a_β and tangent projector P_T = a_α ⊗ a^α. Its local coordinates ξ^α move
//! the weights by δN_j = c_jα δξ^α (face: c₁ = (−1, −1), c₂ = (1, 0), c₃ = (0, 1); edge:
//! c_p = −1, c_q = 1). From the orthogonality (x_s − x_m)·a_α = 0:
//!
//! δξ^α = a^α·Σ_l γ_l δx_l + M⁻¹_αβ d·δa_β,
//!
//! and with u_j = c_jα a^α (u_s = 0) the blocks K_lm = ∂f_l/∂x_m [N/m] are
//!
//! K_lm = k [γ_l γ_m (I − P_T) − γ_l u_m ⊗ d − γ_m d ⊗ u_l − (c_l·M⁻¹ c_m) d ⊗ d].
//!
//! On a face I − P_T = n ⊗ n and d = g n; on an edge I − P_T projects across the edge; on
//! a vertex it is I. Exact for a node on a rigid plane (k n ⊗ n) and on a rigid faceted
//! sphere (k (I − P_T) on its facets, edges and vertices); exact for a deformable main
//! surface too, as long as the node stays on the same feature of the same triangle (the
//! switches between features and triangles are not differentiated).

use nalgebra::{Matrix2, Matrix3, Vector3};

use crate::projection::Feature;

/// The geometry of an active pair on its feature, in world axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FeatureGeometry {
    /// Local triangle vertices of the feature (face: 3, edge: 2, vertex: 1).
    pub vertices: [u8; 3],
    pub count: usize,
    /// Weights N_j of those vertices.
    pub weights: [f64; 3],
    /// Tangents a_α of the feature.
    pub tangents: [Vector3<f64>; 2],
    pub tangent_count: usize,
}

impl FeatureGeometry {
    /// The feature's vertices, weights and tangents on the triangle `corners` with
    /// barycentric coordinates `barycentric`.
    pub fn new(feature: Feature, barycentric: &[f64; 3], corners: &[Vector3<f64>; 3]) -> Self {
        let zero = Vector3::zeros();
        match feature {
            Feature::Face => FeatureGeometry {
                vertices: [0, 1, 2],
                count: 3,
                weights: *barycentric,
                tangents: [corners[1] - corners[0], corners[2] - corners[0]],
                tangent_count: 2,
            },
            Feature::Edge(i) => {
                let (p, q) = (i as usize, (i as usize + 1) % 3);
                FeatureGeometry {
                    vertices: [p as u8, q as u8, 0],
                    count: 2,
                    weights: [barycentric[p], barycentric[q], 0.0],
                    tangents: [corners[q] - corners[p], zero],
                    tangent_count: 1,
                }
            }
            Feature::Vertex(i) => FeatureGeometry {
                vertices: [i, 0, 0],
                count: 1,
                weights: [1.0, 0.0, 0.0],
                tangents: [zero, zero],
                tangent_count: 0,
            },
        }
    }

    /// The same geometry with its tangents rotated by `rotation` (body to world frame).
    pub fn rotated(mut self, rotation: &Matrix3<f64>) -> Self {
        for t in &mut self.tangents {
            *t = rotation * *t;
        }
        self
    }

    /// c_jα of feature vertex `j` (see the module docs).
    fn c(&self, j: usize) -> [f64; 2] {
        match (self.tangent_count, j) {
            (2, 0) => [-1.0, -1.0],
            (2, 1) => [1.0, 0.0],
            (2, _) => [0.0, 1.0],
            (1, 0) => [-1.0, 0.0],
            (1, _) => [1.0, 0.0],
            _ => [0.0, 0.0],
        }
    }

    /// Calls `add(l, m, K_lm)` for the blocks of the pair with penalty `k` [N/m] and offset
    /// `d` = x_s − x_m [m]: l, m = 0 for the secondary node, 1 + j for feature vertex j.
    /// With `secondary_only`, only K_00 (a rigid main side).
    pub fn blocks(
        &self,
        k: f64,
        d: &Vector3<f64>,
        secondary_only: bool,
        mut add: impl FnMut(usize, usize, &Matrix3<f64>),
    ) {
        let mut inverse = Matrix2::zeros();
        let mut dual = [Vector3::zeros(); 2];
        let n = self.tangent_count;
        let a = &self.tangents;
        if n == 2 {
            let metric = Matrix2::new(
                a[0].dot(&a[0]),
                a[0].dot(&a[1]),
                a[1].dot(&a[0]),
                a[1].dot(&a[1]),
            );
            inverse = metric.try_inverse().unwrap_or_else(Matrix2::zeros);
        } else if n == 1 {
            inverse[(0, 0)] = 1.0 / a[0].norm_squared();
        }
        for alpha in 0..n {
            dual[alpha] = (0..n).map(|beta| a[beta] * inverse[(alpha, beta)]).sum();
        }
        let mut normal_projector = Matrix3::identity();
        for alpha in 0..n {
            normal_projector -= a[alpha] * dual[alpha].transpose();
        }
        // Symmetrize away the round-off of the projector (exactly symmetric in theory).
        normal_projector = 0.5 * (normal_projector + normal_projector.transpose());
        let nodes = if secondary_only { 1 } else { 1 + self.count };
        let gamma = |l: usize| if l == 0 { 1.0 } else { -self.weights[l - 1] };
        let c = |l: usize| if l == 0 { [0.0, 0.0] } else { self.c(l - 1) };
        let u = |l: usize| {
            let c = c(l);
            dual[0] * c[0] + dual[1] * c[1]
        };
        let dd = d * d.transpose();
        for l in 0..nodes {
            for m in 0..nodes {
                let (cl, cm) = (c(l), c(m));
                let mut cmc = 0.0;
                for alpha in 0..n {
                    for beta in 0..n {
                        cmc += cl[alpha] * inverse[(alpha, beta)] * cm[beta];
                    }
                }
                let block = normal_projector * (gamma(l) * gamma(m))
                    - u(m) * d.transpose() * gamma(l)
                    - d * u(l).transpose() * gamma(m)
                    - dd * cmc;
                add(l, m, &(block * k));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projection::project_on_triangle;

    /// Forces f_l = γ_l k d of a node on a triangle, all four nodes stacked (12 values).
    fn forces(x: &[Vector3<f64>; 4], k: f64) -> ([Vector3<f64>; 4], Feature) {
        let corners = [x[1], x[2], x[3]];
        let p = project_on_triangle(&x[0], &corners);
        let d = x[0] - p.point;
        let mut f = [Vector3::zeros(); 4];
        f[0] = d * k;
        for j in 0..3 {
            f[1 + j] = -d * (k * p.barycentric[j]);
        }
        (f, p.feature)
    }

    /// The blocks against central differences of the forces, on a face, an edge and a
    /// vertex of a skewed triangle, the node below it.
    #[test]
    fn blocks_are_the_derivative_of_the_forces() {
        let k = 3.0;
        let corners = [
            Vector3::new(0.1, -0.2, 0.05),
            Vector3::new(1.3, 0.1, -0.1),
            Vector3::new(0.2, 1.1, 0.2),
        ];
        for (secondary, expected) in [
            (Vector3::new(0.4, 0.3, -0.2), Feature::Face),
            (Vector3::new(0.7, -0.6, -0.3), Feature::Edge(0)),
            (Vector3::new(-0.5, -0.6, -0.4), Feature::Vertex(0)),
        ] {
            let x = [secondary, corners[0], corners[1], corners[2]];
            let p = project_on_triangle(&secondary, &corners);
            assert_eq!(p.feature, expected);
            let geometry = FeatureGeometry::new(p.feature, &p.barycentric, &corners);
            let mut stiffness = [[Matrix3::zeros(); 4]; 4];
            geometry.blocks(k, &(secondary - p.point), false, |l, m, block| {
                let (l, m) = (
                    if l == 0 {
                        0
                    } else {
                        1 + geometry.vertices[l - 1] as usize
                    },
                    if m == 0 {
                        0
                    } else {
                        1 + geometry.vertices[m - 1] as usize
                    },
                );
                stiffness[l][m] += block;
            });
            let h = 1e-6;
            for m in 0..4 {
                for j in 0..3 {
                    let (mut plus, mut minus) = (x, x);
                    plus[m][j] += h;
                    minus[m][j] -= h;
                    let (fp, feature) = forces(&plus, k);
                    let (fm, _) = forces(&minus, k);
                    assert_eq!(feature, expected);
                    for l in 0..4 {
                        let numeric = (fp[l] - fm[l]) / (2.0 * h);
                        let analytic = stiffness[l][m].column(j);
                        assert!(
                            (numeric - analytic).norm() < 1e-7 * k,
                            "{expected:?} K[{l}][{m}] column {j}: {numeric} vs {analytic}"
                        );
                    }
                }
            }
            for l in 0..4 {
                for m in 0..4 {
                    assert!((stiffness[l][m] - stiffness[m][l].transpose()).norm() < 1e-12);
                }
            }
        }
    }
}
