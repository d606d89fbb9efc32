//! Cook's membrane in plane strain with a nearly incompressible neo-Hookean solid: the
//! locking benchmark, shared by the test `tests/cooks_membrane.rs` and the table tool
//! `examples/cooks_membrane.rs`.
//!
//! - Panel of [`cooks_membrane`] (corners (0,0), (48,44), (48,60), (0,44) mm), one
//!   element of [`THICKNESS`] = 1 mm through the thickness.
//! - Material: neo-Hookean W = μ/2 (Ī₁ − 3) + (J − 1)²/D with E = 240.565 MPa and
//!   ν = [`POISSON`]: μ = E/(2(1 + ν)), κ = E/(3(1 − 2ν)), D = 2/κ.
//! - Plane strain: u_z = 0 on every node. The left edge (`clamped`) has u_x = u_y = 0.
//! - Load: a total shear force of [`TOTAL_FORCE`] = 100 N in +y on the right edge, as a
//!   uniform (dead) traction 100 N / (16 mm × 1 mm) turned into consistent nodal forces
//!   ([`consistent_nodal_areas`]: quad4 ¼ per corner, tri3 ⅓ per corner, tri6 0 at the
//!   corners and ⅓ at the mid-sides), ramped linearly over the load steps. The
//!   literature states the load as 100 N per unit thickness of a plane-strain model
//!   (N/mm); with t = 1 mm that is the same 100 N total.
//! - Read: the vertical displacement u_y of the top-right corner C (node set `tip`).
//!
//! To add an element technology to the comparison, add one line to [`technologies`].

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::element::Technology;
use crate::mesh::Mesh;
use crate::mesh::generate::{consistent_nodal_areas, cooks_membrane};
use crate::solver::implicit::{ImplicitSettings, run_quasi_static};
use crate::solver::{Loads, NodalForce, Part, PrescribedDisplacement, SolverError};
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

/// Young's modulus E [Pa].
pub const YOUNGS_MODULUS: f64 = 240.565e6;
/// Poisson's ratio ν (the literature's nearly incompressible case uses 0.4999).
pub const POISSON: f64 = 0.499;
/// Panel thickness t [m].
pub const THICKNESS: f64 = 1e-3;
/// Total shear force on the right edge [N] (100 N/mm × t).
pub const TOTAL_FORCE: f64 = 100.0;
/// Tip displacement u_y(C) [m] quoted in the literature for the F-bar hex8 in plane
/// strain at 30 elements per side (≈ 6.89 mm).
pub const LITERATURE_TIP_DISPLACEMENT: f64 = 6.89e-3;

/// Shear modulus μ = E/(2(1 + ν)) [Pa].
pub fn shear_modulus(poisson: f64) -> f64 {
    YOUNGS_MODULUS / (2.0 * (1.0 + poisson))
}

/// Compressibility D = 2/κ, κ = E/(3(1 − 2ν)) [1/Pa].
pub fn compressibility(poisson: f64) -> f64 {
    2.0 * 3.0 * (1.0 - 2.0 * poisson) / YOUNGS_MODULUS
}

/// The element technologies compared, with a label, one line each (the nodally averaged
/// tet4 is explicit-only, so it is not here: the membrane is solved implicitly).
pub fn technologies(poisson: f64) -> Vec<(&'static str, Technology)> {
    vec![
        ("hex8 full", Technology::Hex8Full),
        (
            "hex8 one-point",
            Technology::hex8_one_point(shear_modulus(poisson)),
        ),
        ("hex8 F-bar", Technology::Hex8FBar),
        ("tet4", Technology::Tet4),
        ("tet10", Technology::Tet10),
    ]
}

/// The panel's neo-Hookean solid at Poisson's ratio `poisson`.
pub fn neo_hookean(poisson: f64) -> Arc<dyn Material> {
    let params = BTreeMap::from([
        ("mu".to_string(), shear_modulus(poisson)),
        ("D".to_string(), compressibility(poisson)),
    ]);
    MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .expect("neo-Hookean parameters are valid")
}

/// Plane strain, clamped left edge, consistent nodal forces totalling [`TOTAL_FORCE`] in
/// +y on the right edge, ramped from 0 at t = 0 to full at t = 1 s.
pub fn loads(mesh: &Mesh) -> Loads {
    let held = |nodes: Vec<u32>, dof: usize| PrescribedDisplacement {
        nodes,
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).expect("a constant amplitude"),
    };
    let every_node: Vec<u32> = (0..mesh.node_count() as u32).collect();
    let clamped = mesh.node_set("clamped").expect("generated set").to_vec();
    let weights = consistent_nodal_areas(mesh, "loaded").expect("generated surface");
    let area: f64 = weights.iter().map(|(_, w)| w).sum();
    let forces = weights
        .into_iter()
        .filter(|&(_, w)| w != 0.0)
        .map(|(node, w)| NodalForce {
            nodes: vec![node],
            dof: 1,
            amplitude: Amplitude::ramp(1.0, TOTAL_FORCE * w / area).expect("a ramp"),
        })
        .collect();
    Loads {
        displacements: vec![
            held(every_node, 2),
            held(clamped.clone(), 0),
            held(clamped, 1),
        ],
        forces,
        rigid_ties: vec![],
    }
}

/// One solved Cook's membrane.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// u_y at the tip C [m].
    pub tip_displacement: f64,
    /// Newton iterations over all load steps (predictors included).
    pub iterations: usize,
    /// Converged load steps and cut attempts.
    pub steps: usize,
    pub cuts: usize,
    pub unknowns: usize,
    /// Wall time of the solve (not of the mesh generation).
    pub wall_time: Duration,
}

/// Solve Cook's membrane with `technology` on `divisions` per side in `increments` load
/// steps (with step cutting).
pub fn solve(
    technology: Technology,
    divisions: usize,
    poisson: f64,
    increments: usize,
) -> Result<Outcome, SolverError> {
    let mesh = cooks_membrane(technology.shape(), divisions, THICKNESS).expect("valid mesh");
    let parts = [Part {
        block: 0,
        technology,
        material: neo_hookean(poisson),
        density: 1000.0,
    }];
    let settings = ImplicitSettings::new(1.0, increments).with_cutting();
    let start = Instant::now();
    let result = run_quasi_static(&mesh, &parts, &loads(&mesh), &settings)?;
    let wall_time = start.elapsed();
    let tip = mesh.node_set("tip").expect("generated set");
    Ok(Outcome {
        tip_displacement: result.displacement[tip[0] as usize][1],
        iterations: result.steps.iter().map(|s| s.iterations).sum(),
        steps: result.steps.len(),
        cuts: result.cuts,
        unknowns: result.equations,
        wall_time,
    })
}
