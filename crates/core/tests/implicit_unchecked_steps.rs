//! `ImplicitSettings::unchecked_full_steps`: Newton's method with an approximate tangent
//! can converge although its first direction raises the residual, which no halving of the
//! line search lowers; taking that step whole lets it finish.
//!
//! The model: one free node of a very soft hex8 (every other node fixed) held by an
//! interaction whose force is linear, f = k (x − x_t), and whose stiffness it reports as
//! k B with B = (I − N)⁻¹ = I + N + N², N = [[0, −5, 0], [0, 0, −5], [0, 0, 0]], instead
//! of k I. Newton's residual then goes r ← N r: the predictor (taken whole) from
//! r = (0, 0, −ks) to (0, 5ks, 0), the first line-searched step to (−25ks, 0, 0), then
//! to zero. A fraction α of that step leaves r = (−25ksα, 5ks(1 − α), 0), larger than
//! 5ks for every α ≥ 1/8 that three halvings try.

use std::collections::BTreeMap;
use std::sync::Arc;

use musclefem_core::element::Technology;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::implicit::{ImplicitSettings, run_implicit_with};
use musclefem_core::solver::observer::NoObserver;
use musclefem_core::solver::{
    Interaction, InteractionReport, Loads, Part, PrescribedDisplacement, SolverError,
};
use musclefem_materials::{Amplitude, MaterialLibrary};
use nalgebra::{Matrix3, Vector3};

/// Spring stiffness [N/m] and the target's offset from the node's start [m] (the node
/// moves by up to 25 times it on the way, a quarter of the 10 mm element).
const STIFFNESS: f64 = 1e6;
const OFFSET: f64 = 1e-4;

/// f = k (x − x_t) on `node`, with the stiffness reported as k B.
struct SkewedSpring {
    node: u32,
    target: Vector3<f64>,
}

impl Interaction for SkewedSpring {
    fn name(&self) -> &str {
        "skewed spring"
    }

    fn search(&mut self, _time: f64, _positions: &[Vector3<f64>]) -> Result<(), SolverError> {
        Ok(())
    }

    fn forces(
        &mut self,
        _time: f64,
        positions: &[Vector3<f64>],
        _with_stiffness: bool,
        force: &mut [Vector3<f64>],
    ) -> Result<(), SolverError> {
        let d = positions[self.node as usize] - self.target;
        force[self.node as usize] += STIFFNESS * d;
        Ok(())
    }

    fn stiffness(&self, add: &mut dyn FnMut(u32, u32, &Matrix3<f64>)) {
        let skewed = STIFFNESS * Matrix3::new(1.0, -5.0, 25.0, 0.0, 1.0, -5.0, 0.0, 0.0, 1.0);
        add(self.node, self.node, &skewed);
    }

    fn symmetric_stiffness(&self) -> bool {
        false
    }

    fn commit(&mut self) {}

    fn report(&self) -> InteractionReport {
        InteractionReport {
            name: self.name().to_string(),
            force: Vector3::zeros(),
            active_points: 0,
            active_area: 0.0,
            bonded_area: 0.0,
            stored_energy: 0.0,
        }
    }
}

/// Runs one increment with `unchecked` whole steps allowed: the node's final position
/// error [m], or the solver's error.
fn run(unchecked: usize) -> Result<f64, SolverError> {
    let mesh = box_of_hexes([0.01, 0.01, 0.01], [1, 1, 1]).unwrap();
    let params = BTreeMap::from([("mu".to_string(), 1e-3), ("D".to_string(), 1e3)]);
    let material: Arc<_> = MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap();
    let parts = vec![Part {
        block: 0,
        technology: Technology::Hex8Full,
        material,
        density: 1000.0,
    }];
    // The free node: the corner at (0.01, 0.01, 0.01); every other node fixed.
    let free = (0..mesh.node_count())
        .find(|&n| (mesh.nodes.position(n) - Vector3::repeat(0.01)).norm() < 1e-12)
        .unwrap() as u32;
    let others: Vec<u32> = (0..mesh.node_count() as u32)
        .filter(|&n| n != free)
        .collect();
    let hold = |nodes: Vec<u32>, dof: usize| PrescribedDisplacement {
        nodes,
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    };
    let loads = Loads {
        displacements: vec![
            hold(others.clone(), 0),
            hold(others.clone(), 1),
            hold(others, 2),
        ],
        ..Loads::default()
    };
    let start = mesh.nodes.position(free as usize);
    let target = start + Vector3::new(0.0, 0.0, OFFSET);
    let mut interactions: Vec<Box<dyn Interaction>> =
        vec![Box::new(SkewedSpring { node: free, target })];
    let mut settings = ImplicitSettings::new(1.0, 1);
    settings.line_search_cuts = 3;
    settings.residual_tolerance = 1e-8;
    settings.factor_reuse = None;
    settings.unchecked_full_steps = unchecked;
    let result = run_implicit_with(
        &mesh,
        &parts,
        &loads,
        &mut interactions,
        &settings,
        &mut NoObserver,
    )?;
    let end = start + result.displacement[free as usize];
    Ok((end - target).norm())
}

#[test]
fn a_step_that_raises_the_residual_is_taken_whole_when_allowed() {
    let refused = run(0);
    assert!(
        refused
            .as_ref()
            .is_err_and(|e| e.to_string().contains("the line search found no decrease")),
        "{refused:?}"
    );
    let error = run(1).unwrap();
    // The spring (1e6 N/m) against the hex8's μ = 1 mPa: the node ends on the target.
    assert!(error < 1e-9 * OFFSET, "{error:e} m from the target");
}
