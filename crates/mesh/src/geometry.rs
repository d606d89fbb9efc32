//! Geometry of one element from its node positions: reference shape-function gradients,
//! the Jacobian of the reference-to-physical map, volume, the smallest Jacobian (for the
//! validity check), and the vector area of a face.

use nalgebra::{Matrix3, Vector3};

use super::shape::{ElementShape, FaceShape, HEX8_REFERENCE, TET10_REFERENCE};

/// Volume of the reference hexahedron [−1, 1]³.
const HEX_REFERENCE_VOLUME: f64 = 8.0;
/// Volume of the reference (unit) tetrahedron.
const TET_REFERENCE_VOLUME: f64 = 1.0 / 6.0;
/// 1/√3, the abscissa of 2-point Gauss–Legendre quadrature on [−1, 1].
const GAUSS_2: f64 = 0.577_350_269_189_625_8;

/// Tetrahedron rule of degree 3 (Stroud T3:3-1, 5 points; the centroid weight is
/// negative): reference point and weight, weights summing to the reference volume 1/6.
/// Exact for det J of a tet10, a cubic polynomial.
const TET_DEGREE_3: [([f64; 3], f64); 5] = [
    ([0.25, 0.25, 0.25], -2.0 / 15.0),
    ([1.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0], 3.0 / 40.0),
    ([0.5, 1.0 / 6.0, 1.0 / 6.0], 3.0 / 40.0),
    ([1.0 / 6.0, 0.5, 1.0 / 6.0], 3.0 / 40.0),
    ([1.0 / 6.0, 1.0 / 6.0, 0.5], 3.0 / 40.0),
];

/// Gradients of the barycentric coordinates L1 = 1 − ξ − η − ζ, L2 = ξ, L3 = η, L4 = ζ:
/// also the (constant) reference gradients of the tet4 shape functions.
pub const TET4_GRADIENTS: [[f64; 3]; 4] = [
    [-1.0, -1.0, -1.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];

/// Reference gradients ∂N_a/∂(ξ, η, ζ) of the 8 trilinear hex shape functions
/// N_a = (1 + ξ_a ξ)(1 + η_a η)(1 + ζ_a ζ)/8 at `xi` in [−1, 1]³.
pub fn hex8_gradients(xi: [f64; 3]) -> [[f64; 3]; 8] {
    let mut g = [[0.0; 3]; 8];
    for (a, [s, t, u]) in HEX8_REFERENCE.iter().copied().enumerate() {
        let (fx, fy, fz) = (1.0 + s * xi[0], 1.0 + t * xi[1], 1.0 + u * xi[2]);
        g[a] = [
            0.125 * s * fy * fz,
            0.125 * t * fx * fz,
            0.125 * u * fx * fy,
        ];
    }
    g
}

/// Reference gradients of the 10 quadratic tet shape functions at `xi` in the unit
/// tetrahedron: corners N_i = L_i(2L_i − 1), mid-edge nodes N = 4 L_a L_b (C3D10 order).
pub fn tet10_gradients(xi: [f64; 3]) -> [[f64; 3]; 10] {
    let l = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
    let dl = TET4_GRADIENTS;
    let mut g = [[0.0; 3]; 10];
    for i in 0..4 {
        for d in 0..3 {
            g[i][d] = (4.0 * l[i] - 1.0) * dl[i][d];
        }
    }
    for (m, &[a, b]) in ElementShape::Tet10.edges().iter().enumerate() {
        let (a, b) = (a as usize, b as usize);
        for d in 0..3 {
            g[4 + m][d] = 4.0 * (l[b] * dl[a][d] + l[a] * dl[b][d]);
        }
    }
    g
}

/// Jacobian J = ∂x/∂ξ = Σ_a x_a ⊗ ∇_ξ N_a of the map from reference to physical
/// coordinates [m per reference unit], from node positions and reference gradients.
#[inline]
pub fn jacobian(coords: &[Vector3<f64>], gradients: &[[f64; 3]]) -> Matrix3<f64> {
    let mut j = Matrix3::zeros();
    for (x, g) in coords.iter().zip(gradients) {
        for c in 0..3 {
            for r in 0..3 {
                j[(r, c)] += x[r] * g[c];
            }
        }
    }
    j
}

/// Volume [m³] of the tetrahedron with corners `p[0..4]` (positive when p1, p2, p3 run
/// counter-clockwise seen from p4): (p2 − p1)·((p3 − p1) × (p4 − p1))/6.
#[inline]
pub fn tet4_volume(p: &[Vector3<f64>]) -> f64 {
    (p[1] - p[0]).dot(&(p[2] - p[0]).cross(&(p[3] - p[0]))) / 6.0
}

/// The 8 points of 2×2×2 Gauss quadrature on [−1, 1]³ (each of weight 1).
fn hex_gauss_points() -> impl Iterator<Item = [f64; 3]> {
    HEX8_REFERENCE
        .iter()
        .map(|p| [GAUSS_2 * p[0], GAUSS_2 * p[1], GAUSS_2 * p[2]])
}

impl ElementShape {
    /// Volume [m³] of one element whose node positions [m] are `coords` (in the element's
    /// local node order): ∫ det J over the reference element, by 2×2×2 Gauss for hex8
    /// (exact for the trilinear map), the triple product for tet4, and a degree-3 rule for
    /// tet10 (exact for its quadratic map; straight-sided gives the tet4 volume).
    /// Negative or zero for inverted or flat elements (not necessarily pointwise valid).
    ///
    /// # Panics
    /// If `coords.len()` differs from [`Self::nodes_per_element`].
    pub fn volume(self, coords: &[Vector3<f64>]) -> f64 {
        assert_eq!(coords.len(), self.nodes_per_element(), "{self} coordinates");
        match self {
            ElementShape::Hex8 => hex_gauss_points()
                .map(|xi| jacobian(coords, &hex8_gradients(xi)).determinant())
                .sum(),
            ElementShape::Tet4 => tet4_volume(coords),
            ElementShape::Tet10 => TET_DEGREE_3
                .iter()
                .map(|&(xi, w)| w * jacobian(coords, &tet10_gradients(xi)).determinant())
                .sum(),
        }
    }

    /// Smallest det J over the sample points, times the volume of the reference element
    /// [m³]: the element's volume if its map were affine with that Jacobian, so it can be
    /// compared with the volume. Zero or negative means the element is flat or inverted
    /// somewhere. Sample points: hex8 the 8 corners and the 8 Gauss points; tet4 its
    /// (constant) Jacobian; tet10 the 10 nodes and the 5 points of the degree-3 rule.
    ///
    /// # Panics
    /// If `coords.len()` differs from [`Self::nodes_per_element`].
    pub fn min_jacobian_volume(self, coords: &[Vector3<f64>]) -> f64 {
        assert_eq!(coords.len(), self.nodes_per_element(), "{self} coordinates");
        let det = |g: &[[f64; 3]]| jacobian(coords, g).determinant();
        match self {
            ElementShape::Hex8 => {
                let min = HEX8_REFERENCE
                    .iter()
                    .copied()
                    .chain(hex_gauss_points())
                    .map(|xi| det(&hex8_gradients(xi)))
                    .fold(f64::INFINITY, f64::min);
                min * HEX_REFERENCE_VOLUME
            }
            ElementShape::Tet4 => tet4_volume(coords),
            ElementShape::Tet10 => {
                let min = TET10_REFERENCE
                    .iter()
                    .copied()
                    .chain(TET_DEGREE_3.iter().map(|&(xi, _)| xi))
                    .map(|xi| det(&tet10_gradients(xi)))
                    .fold(f64::INFINITY, f64::min);
                min * TET_REFERENCE_VOLUME
            }
        }
    }

    /// Smallest scaled Jacobian over the corners (dimensionless, 1 for a cube or a
    /// regular tetrahedron, ≤ 0 for an inverted corner): a shape-quality measure.
    ///
    /// - hex8: at each corner, det J / (|J₁| |J₂| |J₃|), J_i the columns of the Jacobian
    ///   there (half the three edges leaving the corner): the sine-like measure of how far
    ///   the corner's edges are from orthogonal;
    /// - tet4, tet10: at each corner, √2 · 6V / (l₁ l₂ l₃), V the volume of the straight
    ///   tetrahedron of the four corners and l_i the lengths of the three edges at the
    ///   corner (√2 makes the regular tetrahedron 1; tet10 mid-edge nodes are ignored).
    ///
    /// # Panics
    /// If `coords.len()` differs from [`Self::nodes_per_element`].
    pub fn min_scaled_jacobian(self, coords: &[Vector3<f64>]) -> f64 {
        assert_eq!(coords.len(), self.nodes_per_element(), "{self} coordinates");
        match self {
            ElementShape::Hex8 => HEX8_REFERENCE
                .iter()
                .map(|&xi| {
                    let j = jacobian(coords, &hex8_gradients(xi));
                    let lengths = j.column(0).norm() * j.column(1).norm() * j.column(2).norm();
                    j.determinant() / lengths
                })
                .fold(f64::INFINITY, f64::min),
            ElementShape::Tet4 | ElementShape::Tet10 => {
                let six_volume = 6.0 * tet4_volume(&coords[..4]);
                (0..4)
                    .map(|corner| {
                        let lengths: f64 = (0..4)
                            .filter(|&other| other != corner)
                            .map(|other| (coords[other] - coords[corner]).norm())
                            .product();
                        std::f64::consts::SQRT_2 * six_volume / lengths
                    })
                    .fold(f64::INFINITY, f64::min)
            }
        }
    }
}

impl FaceShape {
    /// Vector area ∫ n dA [m²] of a face whose node positions [m] are `coords` (in the
    /// face's node order): for a flat face, its area times its unit normal, which points
    /// outward for the faces of [`ElementShape::faces`]. It depends only on the face's
    /// boundary curve, (1/2)∮ x × dx, so the faces of a closed surface sum to zero
    /// (quad4: (1/2) d₁ × d₂ of the diagonals; tri6: each quadratic edge integrated
    /// exactly by Simpson's rule).
    ///
    /// # Panics
    /// If `coords.len()` differs from [`Self::node_count`].
    pub fn area_vector(self, coords: &[Vector3<f64>]) -> Vector3<f64> {
        assert_eq!(coords.len(), self.node_count(), "face coordinates");
        match self {
            FaceShape::Quad4 => 0.5 * (coords[2] - coords[0]).cross(&(coords[3] - coords[1])),
            FaceShape::Tri3 => 0.5 * (coords[1] - coords[0]).cross(&(coords[2] - coords[0])),
            FaceShape::Tri6 => {
                // Positions relative to the first corner, for round-off.
                let o = coords[0];
                let mut sum = Vector3::zeros();
                for k in 0..3 {
                    let (p0, pm, p1) = (coords[k] - o, coords[3 + k] - o, coords[(k + 1) % 3] - o);
                    // x(t) = p0(1−t)(1−2t) + 4 pm t(1−t) + p1 t(2t−1); x × x' is cubic in t.
                    let d0 = -3.0 * p0 + 4.0 * pm - p1;
                    let dm = p1 - p0;
                    let d1 = p0 - 4.0 * pm + 3.0 * p1;
                    sum += (p0.cross(&d0) + 4.0 * pm.cross(&dm) + p1.cross(&d1)) / 6.0;
                }
                0.5 * sum
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference_coords(shape: ElementShape) -> Vec<Vector3<f64>> {
        shape
            .reference_nodes()
            .iter()
            .map(|p| Vector3::new(p[0], p[1], p[2]))
            .collect()
    }

    /// An affine map x = A ξ + b with det A = 0.756 applied to the reference element.
    fn affine(shape: ElementShape) -> (Vec<Vector3<f64>>, f64) {
        let a = Matrix3::new(0.9, 0.2, -0.1, 0.1, 1.1, 0.3, 0.0, -0.2, 0.8);
        let b = Vector3::new(0.3, -1.2, 2.0);
        let coords = reference_coords(shape).iter().map(|x| a * x + b).collect();
        (coords, a.determinant())
    }

    #[test]
    fn affine_elements_have_the_mapped_reference_volume() {
        for shape in ElementShape::ALL {
            let (coords, det) = affine(shape);
            let reference = match shape {
                ElementShape::Hex8 => 8.0,
                _ => 1.0 / 6.0,
            };
            let v = shape.volume(&coords);
            assert!((v - det * reference).abs() < 1e-14, "{shape}: {v}");
            let j = shape.min_jacobian_volume(&coords);
            assert!((j - v).abs() < 1e-14, "{shape}: {j} vs {v}");
        }
    }

    #[test]
    fn hex_frustum_volume_is_exact() {
        // Bottom square [0,1]² at z = 0, top square [0,a]² at z = h: a frustum of a
        // pyramid with planar faces, volume h/3 (A₁ + A₂ + √(A₁A₂)).
        let (a, h) = (0.4, 0.7);
        let p = |x: f64, y: f64, z: f64| Vector3::new(x, y, z);
        let coords = [
            p(0.0, 0.0, 0.0),
            p(1.0, 0.0, 0.0),
            p(1.0, 1.0, 0.0),
            p(0.0, 1.0, 0.0),
            p(0.0, 0.0, h),
            p(a, 0.0, h),
            p(a, a, h),
            p(0.0, a, h),
        ];
        let exact = h / 3.0 * (1.0 + a * a + a);
        assert!((ElementShape::Hex8.volume(&coords) - exact).abs() < 1e-15);
    }

    /// Quadratic tet shape functions, written independently of `tet10_gradients`.
    fn tet10_map(coords: &[Vector3<f64>], xi: [f64; 3]) -> Vector3<f64> {
        let l = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
        let mut x = Vector3::zeros();
        for i in 0..4 {
            x += l[i] * (2.0 * l[i] - 1.0) * coords[i];
        }
        let edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];
        for (m, (a, b)) in edges.iter().enumerate() {
            x += 4.0 * l[*a] * l[*b] * coords[4 + m];
        }
        x
    }

    #[test]
    fn curved_tet10_volume_matches_a_collapsed_gauss_rule() {
        let shape = ElementShape::Tet10;
        let (mut coords, _) = affine(shape);
        // Every mid-edge node moved in its own direction: det J then has cubic terms (with
        // one or two moved nodes it would be quadratic, and a degree-2 rule exact).
        let moves = [
            [0.05, -0.08, 0.11],
            [-0.07, 0.02, 0.06],
            [0.03, 0.09, -0.04],
            [-0.06, -0.05, 0.02],
            [0.08, 0.01, -0.07],
            [0.02, -0.06, -0.09],
        ];
        for (m, [x, y, z]) in moves.into_iter().enumerate() {
            coords[4 + m] += Vector3::new(x, y, z);
        }
        // Reference: ∫ det J over the unit tet by a Duffy-collapsed 5×5×5 Gauss rule, with
        // J by central differences (exact for the quadratic map up to round-off).
        let (g, w) = (
            [
                0.0,
                -0.538_469_310_105_683,
                0.538_469_310_105_683,
                -0.906_179_845_938_664,
                0.906_179_845_938_664,
            ],
            [
                0.568_888_888_888_889,
                0.478_628_670_499_366,
                0.478_628_670_499_366,
                0.236_926_885_056_189,
                0.236_926_885_056_189,
            ],
        );
        let h = 1e-4;
        let mut reference = 0.0;
        for i in 0..5 {
            for j in 0..5 {
                for k in 0..5 {
                    let (u, v, t): (f64, f64, f64) =
                        ((g[i] + 1.0) / 2.0, (g[j] + 1.0) / 2.0, (g[k] + 1.0) / 2.0);
                    let xi = [u, v * (1.0 - u), t * (1.0 - u) * (1.0 - v)];
                    let weight = w[i] * w[j] * w[k] / 8.0 * (1.0 - u).powi(2) * (1.0 - v);
                    let mut jac = Matrix3::zeros();
                    for d in 0..3 {
                        let (mut plus, mut minus) = (xi, xi);
                        plus[d] += h;
                        minus[d] -= h;
                        let col =
                            (tet10_map(&coords, plus) - tet10_map(&coords, minus)) / (2.0 * h);
                        jac.set_column(d, &col);
                    }
                    reference += weight * jac.determinant();
                }
            }
        }
        let v = shape.volume(&coords);
        let straight = tet4_volume(&coords[..4]);
        assert!(
            (v - straight).abs() > 1e-3,
            "the test element must be curved"
        );
        assert!(
            (v - reference).abs() < 1e-9 * reference.abs(),
            "{v} vs {reference}"
        );
        assert!(shape.min_jacobian_volume(&coords) > 0.0);
    }

    #[test]
    fn straight_tet10_has_the_tet4_volume() {
        let (corners, _) = affine(ElementShape::Tet4);
        let mut coords = corners.clone();
        for &[a, b] in ElementShape::Tet10.edges() {
            coords.push(0.5 * (corners[a as usize] + corners[b as usize]));
        }
        let v4 = ElementShape::Tet4.volume(&corners);
        assert!((ElementShape::Tet10.volume(&coords) - v4).abs() < 1e-15);
        assert!((ElementShape::Tet10.min_jacobian_volume(&coords) - v4).abs() < 1e-14);
    }

    #[test]
    fn scaled_jacobian_is_one_for_ideal_shapes_and_falls_with_shear() {
        let cube = reference_coords(ElementShape::Hex8);
        assert!((ElementShape::Hex8.min_scaled_jacobian(&cube) - 1.0).abs() < 1e-15);
        // Regular tetrahedron: alternate corners of a cube.
        let p = |x: f64, y: f64, z: f64| Vector3::new(x, y, z);
        let regular = [
            p(0.0, 0.0, 0.0),
            p(1.0, 1.0, 0.0),
            p(0.0, 1.0, 1.0),
            p(1.0, 0.0, 1.0),
        ];
        let s = ElementShape::Tet4.min_scaled_jacobian(&regular);
        assert!((s - 1.0).abs() < 1e-14, "{s}");
        // A hex sheared by 45° in x–z: every corner has edges at 45° (or 135°): sin 45°.
        let sheared: Vec<_> = cube
            .iter()
            .map(|x| Vector3::new(x.x + x.z, x.y, x.z))
            .collect();
        let s = ElementShape::Hex8.min_scaled_jacobian(&sheared);
        assert!((s - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15, "{s}");
        let (mut coords, _) = affine(ElementShape::Hex8);
        coords.swap(1, 2);
        assert!(ElementShape::Hex8.min_scaled_jacobian(&coords) < 0.0);
    }

    #[test]
    fn swapped_nodes_give_a_negative_jacobian() {
        for shape in ElementShape::ALL {
            let (mut coords, _) = affine(shape);
            coords.swap(1, 2);
            assert!(shape.min_jacobian_volume(&coords) < 0.0, "{shape}");
        }
    }

    #[test]
    fn reference_faces_point_outward_and_close() {
        for shape in ElementShape::ALL {
            let coords = reference_coords(shape);
            let centroid = coords[..shape.corner_count()].iter().sum::<Vector3<f64>>()
                / shape.corner_count() as f64;
            let mut sum = Vector3::zeros();
            for (f, face) in shape.faces().iter().enumerate() {
                let fc: Vec<_> = face.iter().map(|&l| coords[l as usize]).collect();
                let a = shape.face_shape(f).area_vector(&fc);
                let face_centroid = fc.iter().sum::<Vector3<f64>>() / fc.len() as f64;
                // Outward: along the direction from the element centre to the face centre,
                // and normal to the (flat) face.
                let out = face_centroid - centroid;
                assert!(a.dot(&out) > 0.0, "{shape} face S{}", f + 1);
                for p in &fc {
                    assert!(a.dot(&(p - fc[0])).abs() < 1e-15, "{shape} face S{}", f + 1);
                }
                sum += a;
            }
            assert!(sum.norm() < 1e-15, "{shape}: {sum}");
        }
    }

    #[test]
    fn curved_tri6_area_vector_is_the_boundary_integral() {
        // A tri6 with a bowed edge in its plane: area = flat triangle + parabolic segment
        // (2/3 · chord · sagitta, Archimedes).
        let p = |x: f64, y: f64| Vector3::new(x, y, 0.0);
        let s = 0.1;
        let coords = [
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(0.0, 1.0),
            p(0.5, -s),
            p(0.5, 0.5),
            p(0.0, 0.5),
        ];
        let a = FaceShape::Tri6.area_vector(&coords);
        let exact = 0.5 + 2.0 / 3.0 * 1.0 * s;
        assert!((a - Vector3::new(0.0, 0.0, exact)).norm() < 1e-15, "{a}");
    }
}
