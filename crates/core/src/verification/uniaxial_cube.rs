//! The implicit cube of issue #36, the scaling benchmark of the implicit solver, shared by
//! `musclefem bench --problem scaling`, the table tool `examples/cube_scaling.rs` and the
//! criterion bench `benches/implicit_cube.rs`.
//!
//! - A cube [0, [`SIDE`]]³ of n³ hex8 elements (F-bar by default).
//! - Material: neo-Hookean W = μ/2 (Ī₁ − 3) + (J − 1)²/D with μ = [`SHEAR_MODULUS`] and
//!   the bulk modulus K = 2/D of the case (from Poisson's ratio ν:
//!   K = 2μ(1 + ν)/(3(1 − 2ν)), [`bulk_modulus`]).
//! - Symmetry planes: u_x = 0 on x0, u_y = 0 on y0, u_z = 0 on z0; the lateral faces are
//!   free.
//! - Load: the face x1 pulled along x to the stretch [`STRETCH`], linearly over 1 s, in
//!   [`STEPS`] equal implicit steps (quasi-static).
//! - Read: the reaction force on x1 along x at the end [N] (the deformation is
//!   homogeneous uniaxial stress, so every mesh and element gives the same force).

use std::collections::BTreeMap;
use std::sync::Arc;

use crate::element::Technology;
use crate::mesh::Mesh;
use crate::mesh::generate::box_of_hexes;
use crate::solver::implicit::ImplicitSettings;
use crate::solver::{Loads, Part, PrescribedDisplacement};
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

/// Edge of the cube [m].
pub const SIDE: f64 = 0.01;
/// Shear modulus μ [Pa].
pub const SHEAR_MODULUS: f64 = 1e4;
/// Stretch of the pulled face x1 at the end [1].
pub const STRETCH: f64 = 1.5;
/// Equal implicit steps of the pull.
pub const STEPS: usize = 10;
/// Duration of the pull [s].
pub const DURATION: f64 = 1.0;
/// Density [kg/m³] (unused by the quasi-static solve; a part needs one).
pub const DENSITY: f64 = 1000.0;

/// Bulk modulus K = 2μ(1 + ν)/(3(1 − 2ν)) [Pa] of Poisson's ratio `poisson` with
/// μ = [`SHEAR_MODULUS`].
pub fn bulk_modulus(poisson: f64) -> f64 {
    2.0 * SHEAR_MODULUS * (1.0 + poisson) / (3.0 * (1.0 - 2.0 * poisson))
}

/// One cube of the benchmark.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UniaxialCube {
    /// Elements per edge n.
    pub divisions: usize,
    /// Bulk modulus K = 2/D [Pa].
    pub bulk_modulus: f64,
    /// Element technology (F-bar hex8 in the issue).
    pub technology: Technology,
}

/// The cube's mesh, parts and loads, ready for
/// [`run_quasi_static`](crate::solver::implicit::run_quasi_static).
pub struct CubeModel {
    pub mesh: Mesh,
    pub parts: Vec<Part>,
    /// The pull of x1 first (its reaction is the force read), then the symmetry planes.
    pub loads: Loads,
}

impl UniaxialCube {
    /// The cube: n³ F-bar hex8 at Poisson's ratio `poisson`.
    pub fn with_poisson(divisions: usize, poisson: f64) -> Self {
        UniaxialCube {
            divisions,
            bulk_modulus: bulk_modulus(poisson),
            technology: Technology::Hex8FBar,
        }
    }

    /// The free degrees of freedom: 3 (n + 1)³ less one per node on each of the four
    /// constrained faces (x0, y0, z0 and the pulled x1), 4 (n + 1)².
    pub fn unknowns(&self) -> usize {
        let per_edge = self.divisions + 1;
        3 * per_edge.pow(3) - 4 * per_edge.pow(2)
    }

    /// The neo-Hookean material (μ = [`SHEAR_MODULUS`], D = 2/K).
    pub fn material(&self) -> Arc<dyn Material> {
        let params = BTreeMap::from([
            ("mu".to_string(), SHEAR_MODULUS),
            ("D".to_string(), 2.0 / self.bulk_modulus),
        ]);
        MaterialLibrary::with_builtins()
            .create("neo-hookean", &params)
            .expect("neo-Hookean parameters are valid")
    }

    /// Mesh, part and loads (see the module's description).
    pub fn model(&self) -> CubeModel {
        let mesh =
            box_of_hexes([SIDE; 3], [self.divisions; 3]).expect("at least one division per edge");
        let parts = vec![Part {
            block: 0,
            technology: self.technology,
            material: self.material(),
            density: DENSITY,
        }];
        let node_set = |name: &str| mesh.node_set(name).expect("generated set").to_vec();
        let held = |name: &str, dof: usize| PrescribedDisplacement {
            nodes: node_set(name),
            dof,
            amplitude: Amplitude::new(vec![(0.0, 0.0)]).expect("a constant amplitude"),
        };
        let loads: Loads = vec![
            PrescribedDisplacement {
                nodes: node_set("x1"),
                dof: 0,
                amplitude: Amplitude::ramp(DURATION, (STRETCH - 1.0) * SIDE).expect("a ramp"),
            },
            held("x0", 0),
            held("y0", 1),
            held("z0", 2),
        ]
        .into();
        CubeModel { mesh, parts, loads }
    }

    /// [`STEPS`] equal steps over [`DURATION`], the solver's defaults otherwise (the
    /// caller picks the linear solver).
    pub fn settings(&self) -> ImplicitSettings {
        ImplicitSettings::new(DURATION, STEPS)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::implicit::run_quasi_static;

    #[test]
    fn the_unknowns_are_the_free_degrees_of_freedom_of_the_solver() {
        let cube = UniaxialCube::with_poisson(2, 0.3);
        let model = cube.model();
        let result =
            run_quasi_static(&model.mesh, &model.parts, &model.loads, &cube.settings()).unwrap();
        assert_eq!(cube.unknowns(), 3 * 27 - 4 * 9);
        assert_eq!(result.equations, cube.unknowns());
        assert_eq!(UniaxialCube::with_poisson(10, 0.3).unknowns(), 3509);
    }

    #[test]
    fn the_bulk_modulus_of_poissons_ratio() {
        // ν = 0.25: K = 2μ · 1.25 / 1.5 = 5μ/3.
        assert!((bulk_modulus(0.25) - 5.0 * SHEAR_MODULUS / 3.0).abs() < 1e-9);
    }
}
