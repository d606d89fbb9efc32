//! Cohesive interfaces in the implicit solver against the analytic traction–separation law:
//! two stacked blocks pulled apart (through initiation, softening and failure), sheared
//! (Elastic, FreeSlide and SmoothSlide), a block bonded to a rigid plane that moves away,
//! and the error when nothing bonds.
//!
//! The blocks are loaded so that their state is homogeneous (symmetry planes x = 0 and
//! y = 0, free lateral faces, each quad face lumping a quarter of its area on each
//! corner): every bond of the conforming interface has the same opening δ (asserted to
//! 1e-12 of it), and the traction, the reaction over the reference area, must be the
//! law's t(δ) to round-off of the Newton solution (1e-8 of σ_max). The expected force is
//! written as Σ A_i t(δ_i) over the bonds, which is A t(δ) when the openings agree.

mod cohesive_common;

use std::time::Instant;

use cohesive_common::{
    BoxSpec, Recorder, area_sum, block_nodes, facing_pairs, held, mode_one_traction, neo_hookean,
    openings, pair_areas, ramped, spread, two_boxes,
};
use musclefem_contact::{
    CohesiveError, CohesiveInterface, CohesiveSettings, DeformableSurface, RigidSurface,
    TangentialMode,
};
use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::implicit::{ImplicitResult, ImplicitSettings, run_implicit_with};
use musclefem_core::solver::{Interaction, Loads, Part, PrescribedDisplacement, RigidMotion};
use musclefem_materials::Amplitude;
use nalgebra::Vector3;

/// Side of the blocks in x and y [m] (interface area 1e-4 m²) and their height [m].
const SIDE: f64 = 0.01;
const HEIGHT: f64 = 0.005;
const AREA: f64 = SIDE * SIDE;

fn stacked() -> Mesh {
    let spec = |z: f64| BoxSpec {
        size: [SIDE, SIDE, HEIGHT],
        divisions: [2, 2, 1],
        origin: [0.0, 0.0, z],
    };
    two_boxes(&spec(0.0), &spec(HEIGHT))
}

/// Stiff blocks (E = 260 MPa, ν = 0.3): at the peak traction 1.5 MPa they stretch 0.6 %.
fn parts(mesh: &Mesh) -> Vec<Part> {
    (0..mesh.blocks.len())
        .map(|block| Part {
            block,
            technology: Technology::Hex8Full,
            material: neo_hookean(2.6e8, 0.3),
            density: 1000.0,
        })
        .collect()
}

/// The upper block's bottom bonded to the lower block's top, and the tributary area of
/// the secondary node of each facing pair.
fn interface(mesh: &Mesh, settings: &CohesiveSettings) -> (Box<dyn Interaction>, Vec<f64>) {
    let secondary = DeformableSurface::from_mesh_surface(mesh, "upper_z0").unwrap();
    let main = DeformableSurface::from_mesh_surface(mesh, "lower_z1").unwrap();
    let interface = CohesiveInterface::new("glue", &secondary, main, mesh, settings).unwrap();
    assert_eq!(interface.bond_count(), 9);
    assert!((interface.bonded_reference_area() - AREA).abs() < 1e-15);
    let areas = pair_areas(&secondary, &facing_pairs(mesh, "upper_z0", "lower_z1"));
    (Box::new(interface), areas)
}

fn solve(
    mesh: &Mesh,
    displacements: Vec<PrescribedDisplacement>,
    interaction: Box<dyn Interaction>,
    increments: usize,
) -> (ImplicitResult, Recorder) {
    let mut settings = ImplicitSettings::new(1.0, increments).with_cutting();
    settings.record_displacements = true;
    let mut recorder = Recorder::default();
    let result = run_implicit_with(
        mesh,
        &parts(mesh),
        &Loads::from(displacements),
        &mut [interaction],
        &settings,
        &mut recorder,
    )
    .unwrap();
    (result, recorder)
}

#[test]
fn stacked_blocks_pulled_apart_follow_the_law_through_softening_to_failure() {
    let start = Instant::now();
    let mesh = stacked();
    let settings = CohesiveSettings::default();
    let top = mesh.node_set("upper_z1").unwrap().to_vec();
    let pull = 0.075;
    let displacements = vec![
        ramped(top, 2, pull),
        held(&mesh, "lower_z0", 2),
        held(&mesh, "lower_x0", 0),
        held(&mesh, "upper_x0", 0),
        held(&mesh, "lower_y0", 1),
        held(&mesh, "upper_y0", 1),
    ];
    let (interaction, areas) = interface(&mesh, &settings);
    let (result, _) = solve(&mesh, displacements, interaction, 75);
    let pairs = facing_pairs(&mesh, "upper_z0", "lower_z1");
    let strength = settings.strength();
    let (mut worst_elastic, mut worst_softening, mut softening_rows) = (0.0f64, 0.0f64, 0);
    let mut largest_spread = 0.0f64;
    for (row, u) in result.history.iter().zip(&result.displacement_history) {
        let deltas = openings(&mesh, &pairs, u);
        let delta = area_sum(&areas, &deltas, |d| d) / AREA;
        largest_spread = largest_spread.max(spread(&deltas) / delta);
        let traction = row.reactions[0] / AREA;
        let expected = area_sum(&areas, &deltas, |d| mode_one_traction(&settings, d)) / AREA;
        let error = (traction - expected).abs() / strength;
        // The interface's own resultant is the force on the upper block.
        let report = &row.interactions[0];
        assert!((report.force.z + row.reactions[0]).abs() <= 1e-8 * strength * AREA);
        if delta <= settings.initiation_separation {
            worst_elastic = worst_elastic.max(error);
            assert!((report.bonded_area - AREA).abs() < 1e-15);
        } else {
            worst_softening = worst_softening.max(error);
            softening_rows += 1;
        }
        assert!(
            error <= 1e-8,
            "t = {:.4} s, δ = {delta:.6e} m: traction {traction:.9e} Pa vs {expected:.9e} Pa",
            row.time
        );
    }
    let last = result.history.last().unwrap();
    let final_openings = openings(&mesh, &pairs, &result.displacement);
    assert!(
        final_openings
            .iter()
            .all(|&d| d > settings.failure_separation)
    );
    assert_eq!(last.interactions[0].bonded_area, 0.0);
    assert!(softening_rows >= 25, "{softening_rows}");
    assert!(largest_spread <= 1e-12, "{largest_spread:e}");
    eprintln!(
        "normal pull: {} steps ({} cuts), |t − t_law|/σ_max ≤ {worst_elastic:.2e} elastic, \
         {worst_softening:.2e} softening; bond openings spread {largest_spread:.1e} of the \
         mean; {:.2} s",
        result.steps.len(),
        result.cuts,
        start.elapsed().as_secs_f64()
    );
}

/// Shear U along x (every node of the upper block moved by U) and an opening at its top
/// of W along z, its y0 face held in y; the lower block held still, so that the main
/// surface stays the plane z = 5 mm. Returns the x reaction on the upper block, the z
/// reaction at its top, Σ A_i K_nn δ_n,i over the bonds (δ_n,i the opening of facing
/// nodes), and the last frame's largest damage.
fn shear_and_open(settings: &CohesiveSettings, shear: f64, open: f64) -> (f64, f64, f64, f64) {
    let mesh = stacked();
    let top = mesh.node_set("upper_z1").unwrap().to_vec();
    let still = |dof| PrescribedDisplacement {
        nodes: block_nodes(&mesh, 0),
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    };
    let displacements = vec![
        ramped(block_nodes(&mesh, 1), 0, shear),
        ramped(top, 2, open),
        still(0),
        still(1),
        still(2),
        held(&mesh, "upper_y0", 1),
    ];
    let (interaction, areas) = interface(&mesh, settings);
    let (result, recorder) = solve(&mesh, displacements, interaction, 10);
    let pairs = facing_pairs(&mesh, "upper_z0", "lower_z1");
    let deltas = openings(&mesh, &pairs, &result.displacement);
    let normal = area_sum(&areas, &deltas, |d| settings.normal_stiffness * d);
    let last = result.history.last().unwrap();
    let damage = recorder.frames.last().unwrap().field("cohesive_damage");
    let largest_damage = damage.iter().copied().fold(0.0, f64::max);
    // The interface's resultant on the upper block balances the reactions.
    let report = &last.interactions[0];
    let scale = settings.strength() * AREA;
    assert!((report.force.x + last.reactions[0]).abs() <= 1e-8 * scale);
    (last.reactions[0], last.reactions[1], normal, largest_damage)
}

/// δ_0 = 3 mm, δ_f = 6 mm, K = 5e7 N/m³: slides of a few millimetres pass initiation.
fn small(tangential: TangentialMode) -> CohesiveSettings {
    CohesiveSettings {
        initiation_separation: 0.003,
        failure_separation: 0.006,
        tangential,
        ..CohesiveSettings::default()
    }
}

#[test]
fn elastic_shear_gives_k_ss_times_the_slip_beside_the_normal_traction() {
    let settings = small(TangentialMode::Elastic);
    // λ = √(2² + 1²) mm < δ_0: linear in both directions.
    let (shear_reaction, normal_reaction, normal_law, damage) =
        shear_and_open(&settings, 0.002, 0.001);
    let scale = settings.strength() * AREA;
    let shear_error = (shear_reaction - settings.shear_stiffness * 0.002 * AREA).abs() / scale;
    let normal_error = (normal_reaction - normal_law).abs() / scale;
    eprintln!(
        "elastic shear: t_s error {shear_error:.2e}, t_n error {normal_error:.2e} (of σ_max)"
    );
    assert!(shear_error <= 1e-8 && normal_error <= 1e-8);
    // The blocks' own stretch takes a little of the 1 mm.
    let mean_opening = normal_law / (settings.normal_stiffness * AREA);
    assert!(mean_opening > 0.0009 && mean_opening < 0.001);
    assert_eq!(damage, 0.0);
}

#[test]
fn free_slide_carries_no_shear_while_the_opening_stays_resisted() {
    let settings = small(TangentialMode::FreeSlide);
    // A slide of 4 mm > δ_0 beside an opening of about 2 mm: no shear traction and no
    // damage (only the opening counts), the normal traction K_nn δ_n. The upper nodes
    // slide 0.8 elements: the bonds re-project onto neighbouring triangles, and those
    // over the edge x = 10 mm onto its rim.
    let (shear_reaction, normal_reaction, normal_law, damage) =
        shear_and_open(&settings, 0.004, 0.002);
    let scale = settings.strength() * AREA;
    let shear_error = shear_reaction.abs() / scale;
    let normal_error = (normal_reaction - normal_law).abs() / scale;
    eprintln!(
        "free slide: t_s = {:.2e} of σ_max, t_n error {normal_error:.2e} (of σ_max)",
        shear_error
    );
    assert!(shear_error <= 1e-8 && normal_error <= 1e-8);
    let mean_opening = normal_law / (settings.normal_stiffness * AREA);
    assert!(mean_opening > 0.0019 && mean_opening < 0.002);
    assert_eq!(damage, 0.0);
    // The same in Elastic mode damages (λ = √(4² + 2²) mm > δ_0) and carries shear.
    let elastic = small(TangentialMode::Elastic);
    let (shear_reaction, _, _, damage) = shear_and_open(&elastic, 0.004, 0.002);
    assert!(damage > 0.0 && damage < 1.0);
    assert!(shear_reaction > 0.1 * elastic.strength() * AREA);
}

#[test]
fn smooth_slide_carries_no_shear_while_the_opening_stays_resisted() {
    // As FreeSlide above: the main surface is flat, so its vertex normals are its face
    // normal and the smooth projection is the orthogonal one (extrapolated past the rim
    // x = 10 mm for the nodes that slide over it).
    let settings = small(TangentialMode::SmoothSlide);
    let (shear_reaction, normal_reaction, normal_law, damage) =
        shear_and_open(&settings, 0.004, 0.002);
    let scale = settings.strength() * AREA;
    let shear_error = shear_reaction.abs() / scale;
    let normal_error = (normal_reaction - normal_law).abs() / scale;
    eprintln!(
        "smooth slide: t_s = {shear_error:.2e} of σ_max, t_n error {normal_error:.2e} (of \
         σ_max)"
    );
    assert!(shear_error <= 1e-8 && normal_error <= 1e-8);
    let mean_opening = normal_law / (settings.normal_stiffness * AREA);
    assert!(mean_opening > 0.0019 && mean_opening < 0.002);
    assert_eq!(damage, 0.0);
}

/// A block on a rigid plane z = 0 that moves to z = −0.1 m, its top held in z (x0 and y0
/// symmetry); δ_f = 3 δ_0 this time (the failure separation is a parameter). Returns the
/// largest |t − t_law| / σ_max over the steps.
fn rigid_plane(tangential: TangentialMode, poisson: f64) -> f64 {
    let start = Instant::now();
    let mesh = box_of_hexes([SIDE, SIDE, HEIGHT], [2, 2, 1]).unwrap();
    let settings = CohesiveSettings {
        failure_separation: 0.09,
        tangential,
        ..CohesiveSettings::default()
    };
    let travel = 0.1;
    let plane = RigidSurface::plane(
        "plane",
        Vector3::new(0.5 * SIDE, 0.5 * SIDE, 0.0),
        Vector3::z(),
        SIDE,
        3,
    )
    .unwrap()
    .with_motion(RigidMotion {
        translation: [None, None, Some(Amplitude::ramp(1.0, -travel).unwrap())],
        rotation: None,
        follower: None,
    });
    let bottom = DeformableSurface::from_mesh_surface(&mesh, "z0").unwrap();
    let interface = CohesiveInterface::new("bone", &bottom, plane, &mesh, &settings).unwrap();
    let bottom_nodes = bottom.nodes.clone();
    assert_eq!(interface.bond_count(), 9);
    let displacements = vec![
        held(&mesh, "z1", 2),
        held(&mesh, "x0", 0),
        held(&mesh, "y0", 1),
    ];
    let mut implicit = ImplicitSettings::new(1.0, 100).with_cutting();
    implicit.record_displacements = true;
    let result = run_implicit_with(
        &mesh,
        &[Part {
            block: 0,
            technology: Technology::Hex8Full,
            material: neo_hookean(2.6e8, poisson),
            density: 1000.0,
        }],
        &Loads::from(displacements),
        &mut [Box::new(interface) as Box<dyn Interaction>],
        &implicit,
        &mut Recorder::default(),
    )
    .unwrap();
    let mut worst = 0.0f64;
    for (row, u) in result.history.iter().zip(&result.displacement_history) {
        let plane_z = -travel * row.time;
        let gaps: Vec<f64> = bottom_nodes
            .iter()
            .map(|&n| mesh.nodes.position(n as usize).z + u[n as usize].z - plane_z)
            .collect();
        let delta = area_sum(&bottom.node_area, &gaps, |d| d) / AREA;
        // The top's reaction: the traction times the area (the block is in tension).
        let traction = row.reactions[0] / AREA;
        let expected = area_sum(&bottom.node_area, &gaps, |d| {
            mode_one_traction(&settings, d)
        }) / AREA;
        let error = (traction - expected).abs() / settings.strength();
        worst = worst.max(error);
        assert!(
            error <= 1e-8,
            "t = {:.3}: δ = {delta:.6e} m, traction {traction:.9e} vs {expected:.9e} Pa",
            row.time
        );
        let report = &row.interactions[0];
        assert!((report.force.z + traction * AREA).abs() <= 1e-8 * settings.strength() * AREA);
    }
    assert_eq!(
        result.history.last().unwrap().interactions[0].bonded_area,
        0.0
    );
    eprintln!(
        "rigid plane, {tangential:?}, ν = {poisson}: {} steps, |t − t_law|/σ_max ≤ \
         {worst:.2e}; {:.2} s",
        result.steps.len(),
        start.elapsed().as_secs_f64()
    );
    worst
}

#[test]
fn a_block_bonded_to_a_rigid_plane_moving_away_follows_the_law() {
    // Free slide: the block contracts freely (ν = 0.3), only the opening is resisted.
    assert!(rigid_plane(TangentialMode::FreeSlide, 0.3) <= 1e-8);
    assert!(rigid_plane(TangentialMode::SmoothSlide, 0.3) <= 1e-8);
    // Elastic shear holds the bottom against the Poisson contraction (a shear separation
    // that would count towards damage): with ν = 0 the opening is the only separation,
    // to second order in the 0.6 % strain.
    assert!(rigid_plane(TangentialMode::Elastic, 0.0) <= 1e-8);
}

#[test]
fn no_node_within_the_bond_tolerance_is_a_clear_error() {
    // The upper block 1 mm above the lower one; the default tolerance is 0.1 mm.
    let spec = |z: f64| BoxSpec {
        size: [SIDE, SIDE, HEIGHT],
        divisions: [2, 2, 1],
        origin: [0.0, 0.0, z],
    };
    let mesh = two_boxes(&spec(0.0), &spec(HEIGHT + 0.001));
    let secondary = DeformableSurface::from_mesh_surface(&mesh, "upper_z0").unwrap();
    let main = DeformableSurface::from_mesh_surface(&mesh, "lower_z1").unwrap();
    let error = CohesiveInterface::new(
        "quadriceps-glue",
        &secondary,
        main,
        &mesh,
        &CohesiveSettings::default(),
    )
    .unwrap_err();
    assert!(matches!(error, CohesiveError::NoBond { nodes: 9, .. }));
    let message = error.to_string();
    eprintln!("{message}");
    for part in [
        "'quadriceps-glue'",
        "'upper_z0'",
        "'lower_z1'",
        "1.000e-4 m",
        "closest: 1.000e-3 m",
    ] {
        assert!(message.contains(part), "{message}");
    }
}
