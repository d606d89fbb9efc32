//! A cohesive interface in the explicit solver: two stacked blocks pulled apart through
//! initiation, softening and failure. At every recorded instant the interface force must
//! be the law's, Σ (1 − D_i) K_nn δ_i A_i over the bonds (openings δ_i of facing nodes,
//! damage D_i from the `cohesive_damage` field), whatever the dynamics; at the end, with
//! every bond failed, the work of the interface forces must be the fracture energy of the
//! interface, G_c A with G_c = ½ K_nn δ_0 δ_f, and the solver's energy balance (which
//! counts that work) must hold.

mod cohesive_common;

use std::time::Instant;

use cohesive_common::{
    BoxSpec, Recorder, facing_pairs, held, neo_hookean, openings, pair_areas, two_boxes,
};
use musclefem_contact::{CohesiveInterface, CohesiveSettings, DeformableSurface};
use musclefem_core::element::Technology;
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit_with};
use musclefem_core::solver::{Interaction, Loads, Part, PrescribedDisplacement};
use musclefem_materials::Amplitude;

#[test]
fn explicit_pull_to_failure_dissipates_the_fracture_energy() {
    let start = Instant::now();
    let (side, height) = (0.01, 0.005);
    let area = side * side;
    let spec = |z: f64| BoxSpec {
        size: [side, side, height],
        divisions: [2, 2, 1],
        origin: [0.0, 0.0, z],
    };
    let mesh = two_boxes(&spec(0.0), &spec(height));
    let settings = CohesiveSettings::default();
    let secondary = DeformableSurface::from_mesh_surface(&mesh, "upper_z0").unwrap();
    let main = DeformableSurface::from_mesh_surface(&mesh, "lower_z1").unwrap();
    let interface = CohesiveInterface::new("glue", &secondary, main, &mesh, &settings).unwrap();
    let pairs = facing_pairs(&mesh, "upper_z0", "lower_z1");
    let areas = pair_areas(&secondary, &pairs);
    // The top opens by 75 mm in 10 ms: slow against the blocks' axial period (~30 µs),
    // past the failure separation of 60 mm.
    let end = 0.01;
    let displacements = vec![
        PrescribedDisplacement {
            nodes: mesh.node_set("upper_z1").unwrap().to_vec(),
            dof: 2,
            amplitude: Amplitude::ramp(end, 0.075).unwrap(),
        },
        held(&mesh, "lower_z0", 2),
        held(&mesh, "lower_x0", 0),
        held(&mesh, "upper_x0", 0),
        held(&mesh, "lower_y0", 1),
        held(&mesh, "upper_y0", 1),
    ];
    let parts: Vec<Part> = (0..2)
        .map(|block| Part {
            block,
            technology: Technology::Hex8Full,
            material: neo_hookean(2.6e8, 0.3),
            density: 1000.0,
        })
        .collect();
    let mut recorder = Recorder::default();
    let result = run_explicit_with(
        &mesh,
        &parts,
        &Loads::from(displacements),
        &mut [Box::new(interface) as Box<dyn Interaction>],
        &ExplicitSettings::new(end),
        &mut recorder,
    )
    .unwrap();
    let scale = settings.strength() * area;
    let mut worst = 0.0f64;
    let mut softening_rows = 0;
    for (row, frame) in result.history.iter().zip(&recorder.frames) {
        let deltas = openings(&mesh, &pairs, &frame.displacement);
        let damage = frame.field("cohesive_damage");
        let law: f64 = pairs
            .iter()
            .zip(&areas)
            .zip(&deltas)
            .map(|((&(s, _), a), d)| {
                let intact = if *d > 0.0 {
                    1.0 - damage[s as usize]
                } else {
                    1.0
                };
                intact * settings.normal_stiffness * d * a
            })
            .sum();
        // The force on the upper block pulls it back down.
        let error = (row.interactions[0].force.z + law).abs() / scale;
        worst = worst.max(error);
        assert!(error <= 1e-10, "t = {:.3e} s: error {error:.2e}", row.time);
        if damage.iter().any(|&d| d > 0.0 && d < 1.0) {
            softening_rows += 1;
        }
    }
    assert!(softening_rows >= 20, "{softening_rows}");
    let last = result.history.last().unwrap();
    assert_eq!(last.interactions[0].bonded_area, 0.0);
    assert_eq!(last.interactions[0].stored_energy, 0.0);
    let fracture = settings.fracture_energy() * area;
    let dissipated = last.interaction_work;
    let energy_error = dissipated / fracture - 1.0;
    eprintln!(
        "explicit: {} steps, |f − f_law|/(σ_max A) ≤ {worst:.1e}, interface work {dissipated:.5} J \
         vs G_c A = {fracture:.5} J ({energy_error:+.2e}); {:.2} s",
        result.steps,
        start.elapsed().as_secs_f64()
    );
    assert!(energy_error.abs() <= 1e-3);
}
