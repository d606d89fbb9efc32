//! The one-point hex8 of `hex8_one_point.rs` for the explicit solver, [`LANES`] elements at
//! a time in structure-of-arrays form (every quantity an array over the elements of the
//! batch, so that the compiler turns the loops over lanes into vector instructions).
//!
//! With the node positions taken from node 0 of each element, d_a = x_a − x_0 (a = 1…7),
//! and B̄_0 = −Σ_{a≥1} B̄_a (the mean gradients sum to zero):
//! - F = Σ_{a≥1} d_a ⊗ B̄_a (no round-off from the distance to the origin);
//! - the hourglass displacements q^α = Σ_a γ^α_a x_a with γ^α_a = h^α_a − H^α·B̄_a,
//!   H^α = Σ_b h^α_b X_b [m], are q^α = Σ_{a≥1} h^α_a d_a − F H^α [m]: the γ vectors
//!   (32 numbers per element) are never stored, only H^α (12);
//! - the internal forces f_a = V P B̄_a + k Σ_α q^α γ^α_a [N] are
//!   f_a = S B̄_a + k Σ_α h^α_a q^α with S = V P − k Σ_α q^α ⊗ H^α [N·m],
//!   P = σ cof F [Pa] the first Piola–Kirchhoff stress (J σ F⁻ᵀ with cof F = J F⁻ᵀ:
//!   no inverse, no determinant), and f_0 = −Σ_{a≥1} S B̄_a + k Σ_α h^α_0 q^α.
//!
//! These are the forces of [`super::BlockKernel::add_element_forces`] rearranged; they
//! agree to round-off (tested below).

use nalgebra::{Matrix3, Vector3};

use musclefem_materials::VoigtStress;

use super::hex8_one_point::OnePointReference;

/// Elements per batch.
pub(crate) const LANES: usize = 4;

/// One number per element of a batch.
pub(crate) type Lanes = [f64; LANES];

/// h^α_a over the C3D8 corners: η ζ, ζ ξ, ξ η, ξ η ζ (checked against
/// `hourglass_base` by a test).
const HOURGLASS_BASE: [[f64; 8]; 4] = [
    [1.0, 1.0, -1.0, -1.0, -1.0, -1.0, 1.0, 1.0],
    [1.0, -1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0],
    [1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0, 1.0, 1.0, -1.0, 1.0, -1.0],
];

/// Positions of nodes 1…7 from node 0, d_a = x_a − x_0 [m]: `[a − 1][component][lane]`.
pub(crate) type RelativePositions = [[Lanes; 3]; 7];

/// Reference data of up to [`LANES`] elements (unused lanes are zero): 140 numbers,
/// 280 bytes per element.
#[derive(Debug, Clone)]
pub(crate) struct OnePointBatch {
    /// B̄_a of nodes a = 1…7 [1/m], `[a − 1][component][lane]`.
    gradients: [[Lanes; 3]; 7],
    /// Reference volume V [m³].
    volume: Lanes,
    /// Hourglass stiffness k [N/m].
    hourglass_stiffness: Lanes,
    /// H^α = Σ_b h^α_b (X_b − X̄) [m], `[α][component][lane]`.
    hourglass_positions: [[Lanes; 3]; 4],
}

/// Deformation of a batch: F `[row][column][lane]` and q^α `[α][component][lane]` [m].
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct BatchDeformation {
    pub deformation_gradient: [[Lanes; 3]; 3],
    pub hourglass_modes: [[Lanes; 3]; 4],
}

impl OnePointBatch {
    /// The batch of `references` (at most [`LANES`]), with hourglass modulus G_hg [Pa].
    pub fn new(references: &[OnePointReference], hourglass_modulus: f64) -> Self {
        assert!(
            references.len() <= LANES,
            "at most {LANES} elements per batch"
        );
        let mut batch = OnePointBatch {
            gradients: [[[0.0; LANES]; 3]; 7],
            volume: [0.0; LANES],
            hourglass_stiffness: [0.0; LANES],
            hourglass_positions: [[[0.0; LANES]; 3]; 4],
        };
        for (l, reference) in references.iter().enumerate() {
            for a in 1..8 {
                for i in 0..3 {
                    batch.gradients[a - 1][i][l] = reference.mean_gradients[a][i];
                }
            }
            batch.volume[l] = reference.volume;
            batch.hourglass_stiffness[l] = reference.hourglass_stiffness(hourglass_modulus);
            for (alpha, h) in reference.hourglass_positions.iter().enumerate() {
                for i in 0..3 {
                    batch.hourglass_positions[alpha][i][l] = h[i];
                }
            }
        }
        batch
    }

    /// Reference volume of lane `l` [m³].
    pub fn volume(&self, l: usize) -> f64 {
        self.volume[l]
    }

    /// Σ_a |B̄_a|² of lane `l` [1/m²] (B̄_0 = −Σ_{a≥1} B̄_a).
    pub fn gradient_sum_squares(&self, l: usize) -> f64 {
        let mut first = [0.0; 3];
        let mut sum = 0.0;
        for g in &self.gradients {
            for i in 0..3 {
                first[i] -= g[i][l];
                sum += g[i][l] * g[i][l];
            }
        }
        sum + first.iter().map(|x| x * x).sum::<f64>()
    }

    /// Hourglass energy ½ k Σ_α |q^α|² of lane `l` [J].
    pub fn hourglass_energy(&self, deformation: &BatchDeformation, l: usize) -> f64 {
        let squares: f64 = deformation
            .hourglass_modes
            .iter()
            .map(|q| {
                q.iter()
                    .map(|component| component[l] * component[l])
                    .sum::<f64>()
            })
            .sum();
        0.5 * self.hourglass_stiffness[l] * squares
    }

    /// F and q^α of every lane from the relative node positions `d`.
    #[inline(always)]
    pub fn deformation(&self, d: &RelativePositions) -> BatchDeformation {
        let mut f = [[[0.0; LANES]; 3]; 3];
        for (da, ga) in d.iter().zip(&self.gradients) {
            for i in 0..3 {
                for j in 0..3 {
                    for l in 0..LANES {
                        f[i][j][l] += da[i][l] * ga[j][l];
                    }
                }
            }
        }
        let mut modes = [[[0.0; LANES]; 3]; 4];
        for (alpha, q) in modes.iter_mut().enumerate() {
            for a in 1..8 {
                let h = HOURGLASS_BASE[alpha][a];
                for i in 0..3 {
                    for l in 0..LANES {
                        q[i][l] += h * d[a - 1][i][l];
                    }
                }
            }
            let hx = &self.hourglass_positions[alpha];
            for i in 0..3 {
                for j in 0..3 {
                    for l in 0..LANES {
                        q[i][l] -= f[i][j][l] * hx[j][l];
                    }
                }
            }
        }
        BatchDeformation {
            deformation_gradient: f,
            hourglass_modes: modes,
        }
    }

    /// Internal forces of the first `forces.len() / 8` lanes (8 per element, C3D8 order)
    /// [N], from their deformation and the Cauchy stresses (Voigt order) [Pa].
    #[inline(always)]
    pub fn forces(
        &self,
        deformation: &BatchDeformation,
        stress: &[VoigtStress],
        forces: &mut [Vector3<f64>],
    ) {
        let f = &deformation.deformation_gradient;
        let mut sigma = [[[0.0; LANES]; 3]; 3];
        for (l, s) in stress.iter().enumerate().take(LANES) {
            let m = [[s[0], s[5], s[4]], [s[5], s[1], s[3]], [s[4], s[3], s[2]]];
            for i in 0..3 {
                for j in 0..3 {
                    sigma[i][j][l] = m[i][j];
                }
            }
        }
        // cof F = J F⁻ᵀ.
        let mut cof = [[[0.0; LANES]; 3]; 3];
        for l in 0..LANES {
            let c = |r1: usize, c1: usize, r2: usize, c2: usize| {
                f[r1][c1][l] * f[r2][c2][l] - f[r1][c2][l] * f[r2][c1][l]
            };
            cof[0][0][l] = c(1, 1, 2, 2);
            cof[0][1][l] = c(1, 2, 2, 0);
            cof[0][2][l] = c(1, 0, 2, 1);
            cof[1][0][l] = c(0, 2, 2, 1);
            cof[1][1][l] = c(0, 0, 2, 2);
            cof[1][2][l] = c(0, 1, 2, 0);
            cof[2][0][l] = c(0, 1, 1, 2);
            cof[2][1][l] = c(0, 2, 1, 0);
            cof[2][2][l] = c(0, 0, 1, 1);
        }
        // S = V σ cof F − k Σ_α q^α ⊗ H^α, and k q^α.
        let (v, k) = (&self.volume, &self.hourglass_stiffness);
        let q = &deformation.hourglass_modes;
        let mut s = [[[0.0; LANES]; 3]; 3];
        let mut kq = [[[0.0; LANES]; 3]; 4];
        for i in 0..3 {
            for j in 0..3 {
                let mut p = [0.0; LANES];
                let mut hourglass = [0.0; LANES];
                for m in 0..3 {
                    for l in 0..LANES {
                        p[l] += sigma[i][m][l] * cof[m][j][l];
                    }
                }
                for alpha in 0..4 {
                    for l in 0..LANES {
                        hourglass[l] += q[alpha][i][l] * self.hourglass_positions[alpha][j][l];
                    }
                }
                for l in 0..LANES {
                    s[i][j][l] = v[l] * p[l] - k[l] * hourglass[l];
                }
            }
            for alpha in 0..4 {
                for l in 0..LANES {
                    kq[alpha][i][l] = k[l] * q[alpha][i][l];
                }
            }
        }
        let mut nodal = [[[0.0; LANES]; 3]; 8];
        for a in 1..8 {
            let g = &self.gradients[a - 1];
            for i in 0..3 {
                let mut sum = [0.0; LANES];
                for j in 0..3 {
                    for l in 0..LANES {
                        sum[l] += s[i][j][l] * g[j][l];
                    }
                }
                nodal[a][i] = sum;
                for l in 0..LANES {
                    nodal[0][i][l] -= sum[l];
                }
            }
        }
        for (a, node) in nodal.iter_mut().enumerate() {
            for alpha in 0..4 {
                let h = HOURGLASS_BASE[alpha][a];
                for i in 0..3 {
                    for l in 0..LANES {
                        node[i][l] += h * kq[alpha][i][l];
                    }
                }
            }
        }
        for (l, element) in forces.chunks_exact_mut(8).enumerate().take(LANES) {
            for (a, out) in element.iter_mut().enumerate() {
                *out = Vector3::new(nodal[a][0][l], nodal[a][1][l], nodal[a][2][l]);
            }
        }
    }
}

/// F of lane `l` as a matrix.
#[inline]
pub(crate) fn lane_matrix(m: &[[Lanes; 3]; 3], l: usize) -> Matrix3<f64> {
    Matrix3::new(
        m[0][0][l], m[0][1][l], m[0][2][l], m[1][0][l], m[1][1][l], m[1][2][l], m[2][0][l],
        m[2][1][l], m[2][2][l],
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::hex8_one_point::hourglass_base;
    use crate::element::{BlockKernel, Technology};
    use crate::mesh::generate::box_of_hexes;

    #[test]
    fn the_hourglass_base_is_that_of_the_element() {
        assert_eq!(HOURGLASS_BASE, hourglass_base());
    }

    /// On a distorted mesh under a non-affine motion, the batched F, hourglass
    /// displacements and forces are those of the element kernel to round-off: stress
    /// forces alone (no hourglass stiffness), then hourglass forces alone (no stress).
    #[test]
    fn batched_forces_match_the_element_kernel() {
        for (modulus, stress_scale) in [(0.0, 1.0), (1.0e9, 0.0)] {
            compare_with_the_element_kernel(modulus, stress_scale);
        }
    }

    fn compare_with_the_element_kernel(modulus: f64, stress_scale: f64) {
        let mut mesh = box_of_hexes([0.01; 3], [3, 2, 1]).unwrap();
        let (nodes, block) = (&mut mesh.nodes, &mesh.blocks[0]);
        for i in 0..nodes.len() {
            let p = nodes.position(i);
            let wobble = Vector3::new((7.0 * p.y).sin(), (5.0 * p.z).cos(), (3.0 * p.x).sin());
            nodes.set_position(i, p + wobble * 4e-4);
        }
        let kernel = BlockKernel::new(
            nodes,
            block,
            Technology::Hex8OnePoint {
                hourglass_modulus: modulus,
            },
        )
        .unwrap();
        let motion = |x: Vector3<f64>| {
            Vector3::new(
                1.1 * x.x + 0.2 * x.y + 30.0 * x.y * x.z,
                0.95 * x.y - 0.1 * x.z + 40.0 * x.x * x.y,
                x.z + 0.05 * x.x + 2500.0 * x.x * x.y * x.z,
            )
        };
        let mut references = Vec::new();
        let mut relative = [[[0.0; LANES]; 3]; 7];
        let mut current = Vec::new();
        for (l, ids) in block.elements().take(LANES).enumerate() {
            let mut coords = [Vector3::zeros(); 8];
            nodes.gather(ids, &mut coords);
            references.push(OnePointReference::new(&coords).unwrap());
            let x: Vec<Vector3<f64>> = coords.iter().map(|&c| motion(c)).collect();
            for a in 1..8 {
                for i in 0..3 {
                    relative[a - 1][i][l] = x[a][i] - x[0][i];
                }
            }
            current.push(x);
        }
        let batch = OnePointBatch::new(&references, modulus);
        let deformation = batch.deformation(&relative);
        let stress: Vec<VoigtStress> = (0..LANES)
            .map(|l| {
                VoigtStress::new(1e3, -2e3, 5e2, 3e2, -4e2, 7e2) * (stress_scale * (1.0 + l as f64))
            })
            .collect();
        let mut forces = vec![Vector3::zeros(); LANES * 8];
        batch.forces(&deformation, &stress, &mut forces);
        for (l, x) in current.iter().enumerate() {
            let f = lane_matrix(&deformation.deformation_gradient, l);
            let mut expected_f = [Matrix3::zeros()];
            kernel.element_deformation_gradients(l, x, &mut expected_f);
            assert!((f - expected_f[0]).amax() < 1e-13, "{f} {}", expected_f[0]);
            let mut expected = [Vector3::zeros(); 8];
            kernel.add_element_forces(l, x, &expected_f, &stress[l..l + 1], &mut expected, None);
            let scale = expected.iter().map(|v| v.amax()).fold(0.0, f64::max);
            assert!(scale > 1e-3, "forces {scale} N");
            for (a, (got, want)) in forces[l * 8..(l + 1) * 8].iter().zip(&expected).enumerate() {
                assert!(
                    (got - want).amax() < 1e-12 * scale,
                    "element {l} node {a}: {got} vs {want}"
                );
            }
            let (gamma, _) = kernel.hourglass_vectors(l).unwrap();
            for (alpha, g) in gamma.iter().enumerate() {
                let q: Vector3<f64> = x.iter().zip(g).map(|(p, ga)| p * *ga).sum();
                let got = Vector3::from_fn(|i, _| deformation.hourglass_modes[alpha][i][l]);
                assert!((got - q).amax() < 1e-15, "q^{alpha}: {got} vs {q}");
                assert!(
                    q.amax() > 1e-7,
                    "q^{alpha} = {q} m: the motion is not linear"
                );
            }
            let sum_squares: f64 = kernel.gradients(l).iter().map(|g| g.norm_squared()).sum();
            assert!((batch.gradient_sum_squares(l) - sum_squares).abs() < 1e-12 * sum_squares);
            assert_eq!(batch.volume(l), kernel.reference_volume(l));
        }
    }
}
