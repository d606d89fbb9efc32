//! Mode-I double cantilever beam (DCB): two elastic arms bonded by a cohesive interface
//! over part of their length, their free ends pulled apart. Once the crack grows, the
//! force–opening curve follows beam theory with the fracture energy of the law,
//! G_c = ½ σ_max δ_f = ½ K_nn δ_0 δ_f.
//!
//! Beam theory (each arm a cantilever of length a, the crack length, bending stiffness
//! EI = E b h³/12, width b): the opening of the loaded ends is Δ = 2 P a³/(3 EI) and the
//! energy release rate G = P²/(2b) dC/da = P² a²/(b EI) with C = Δ/P. The crack grows
//! with G = G_c, i.e. P a = √(G_c b EI); eliminating a,
//!   Δ = 2 (G_c b)^{3/2} (EI)^{1/2} / (3 P²),  P(Δ) = (G_c b)^{3/4} (EI)^{1/4} (2/(3Δ))^{1/2}.
//! The arms' root rotation (the elastic foundation of the uncracked part and the cohesive
//! zone) acts like a longer crack a + χh in both relations, so it drops out of P(Δ) on the
//! growth branch; what remains is the shear deflection of the arms (about
//! E/(4κG) (h/a)² = 0.6 % of the deflection here, ν = 0), the finite cohesive zone and
//! the hex8 bending error (full integration, one element through each arm, elements h/4
//! long: parasitic shear stiffens the arms by about ½ (l/h)² ≈ 3 %, so P by ~0.8 %).
//!
//! Parameters (chosen so that the cohesive zone spans several elements and the arms stay
//! in small rotation): arms h = 2 mm thick, b = 2 mm wide, L = 60 mm long, initial crack
//! a₀ = 20 mm; E = 2 MPa, ν = 0 (compressible neo-Hookean, κ = 2μ/3); K_nn = 1.25e8 N/m³,
//! δ_0 = 4 µm, δ_f = 16 µm (σ_max = 500 Pa, G_c = 4e-3 J/m²). Hillerborg's length
//! E G_c/σ_max² = 32 mm gives a cohesive zone of about (E G_c/σ_max²)^{1/4} h^{3/4} ≈ 4 mm
//! = 8 elements. The ends open to Δ = 1.6 mm (rotation ≈ 3Δ/(4a) ≈ 3 %).

mod cohesive_common;

use std::time::Instant;

use cohesive_common::{BoxSpec, Recorder, held, neo_hookean, ramped, two_boxes};
use musclefem_contact::{CohesiveInterface, CohesiveSettings, DeformableSurface, TangentialMode};
use musclefem_core::element::Technology;
use musclefem_core::mesh::Face;
use musclefem_core::solver::implicit::{ImplicitSettings, run_implicit_with};
use musclefem_core::solver::{Interaction, Loads, Part};

const LENGTH: f64 = 0.06;
const WIDTH: f64 = 0.002;
const ARM: f64 = 0.002;
const CRACK: f64 = 0.02;
const ELEMENTS: usize = 120;
const YOUNG: f64 = 2e6;
const OPENING: f64 = 1.6e-3;

fn settings() -> CohesiveSettings {
    CohesiveSettings {
        normal_stiffness: 1.25e8,
        shear_stiffness: 1.25e8,
        tangential_stiffness: 1.25e8,
        initiation_separation: 4e-6,
        failure_separation: 16e-6,
        tangential: TangentialMode::Elastic,
        bond_tolerance: 1e-6,
    }
}

/// P(Δ) of beam theory on the growth branch [N].
fn beam_theory_force(opening: f64) -> f64 {
    let bending = YOUNG * WIDTH * ARM.powi(3) / 12.0;
    let toughness = settings().fracture_energy() * WIDTH;
    toughness.powf(0.75) * bending.powf(0.25) * (2.0 / (3.0 * opening)).sqrt()
}

#[test]
fn the_force_opening_curve_of_a_dcb_follows_beam_theory_once_the_crack_grows() {
    let start = Instant::now();
    let spec = |z: f64| BoxSpec {
        size: [LENGTH, WIDTH, ARM],
        divisions: [ELEMENTS, 1, 1],
        origin: [0.0, 0.0, z],
    };
    let mesh = two_boxes(&spec(0.0), &spec(ARM));
    let cell = LENGTH / ELEMENTS as f64;
    let first_bonded = (CRACK / cell).round() as u32;
    // The upper arm's bottom beyond the initial crack, bonded to the lower arm's top.
    let bonded: Vec<Face> = mesh
        .surface("upper_z0")
        .unwrap()
        .iter()
        .copied()
        .filter(|f| f.element.element >= first_bonded)
        .collect();
    let secondary = DeformableSurface::from_faces(&mesh, "upper arm, bonded", &bonded).unwrap();
    let main = DeformableSurface::from_mesh_surface(&mesh, "lower_z1").unwrap();
    let interface = CohesiveInterface::new("dcb", &secondary, main, &mesh, &settings()).unwrap();
    assert_eq!(
        interface.bond_count(),
        2 * (ELEMENTS - first_bonded as usize + 1)
    );
    let mut displacements = vec![
        ramped(
            mesh.node_set("upper_x0").unwrap().to_vec(),
            2,
            0.5 * OPENING,
        ),
        ramped(
            mesh.node_set("lower_x0").unwrap().to_vec(),
            2,
            -0.5 * OPENING,
        ),
    ];
    for arm in ["upper_x1", "lower_x1"] {
        displacements.extend((0..3).map(|dof| held(&mesh, arm, dof)));
    }
    let parts: Vec<Part> = (0..2)
        .map(|block| Part {
            block,
            technology: Technology::Hex8Full,
            material: neo_hookean(YOUNG, 0.0),
            density: 1000.0,
        })
        .collect();
    let implicit = ImplicitSettings::new(1.0, 80).with_cutting();
    let mut recorder = Recorder::default();
    let result = run_implicit_with(
        &mesh,
        &parts,
        &Loads::from(displacements),
        &mut [Box::new(interface) as Box<dyn Interaction>],
        &implicit,
        &mut recorder,
    )
    .unwrap();
    let elapsed = start.elapsed().as_secs_f64();

    // Crack length: the furthest failed bond (D = 1) from the loaded end, or a₀.
    let crack_length = |damage: &[f64]| {
        secondary
            .nodes
            .iter()
            .filter(|&&n| damage[n as usize] >= 1.0)
            .map(|&n| mesh.nodes.position(n as usize).x)
            .fold(CRACK, f64::max)
    };
    eprintln!("   Δ [mm]   a [mm]   P_FE [mN]   P_beam [mN]   P_FE/P_beam − 1");
    let mut compared = 0;
    let mut worst = 0.0f64;
    let mut next_print = 0.1e-3;
    for (row, frame) in result.history.iter().zip(&recorder.frames) {
        let opening = OPENING * row.time;
        let force = row.reactions[0];
        let reference = beam_theory_force(opening);
        let a = crack_length(frame.field("cohesive_damage"));
        let error = force / reference - 1.0;
        // Growth established: the crack has advanced by at least 4 elements.
        let growing = a >= CRACK + 4.0 * cell - 1e-12;
        if growing {
            compared += 1;
            worst = worst.max(error.abs());
        }
        if opening >= next_print - 1e-12 {
            next_print += 0.1e-3;
            eprintln!(
                "{:9.3} {:8.2} {:11.4} {:13.4} {:+14.4}{}",
                opening * 1e3,
                a * 1e3,
                force * 1e3,
                reference * 1e3,
                error,
                if growing { "" } else { "  (not compared)" }
            );
        }
    }
    let final_crack = crack_length(recorder.frames.last().unwrap().field("cohesive_damage"));
    eprintln!(
        "DCB: {} steps ({} cuts), {} rows on the growth branch, worst |P_FE/P_beam − 1| = \
         {worst:.4}, crack {:.1} → {:.1} mm; {elapsed:.1} s",
        result.steps.len(),
        result.cuts,
        compared,
        CRACK * 1e3,
        final_crack * 1e3
    );
    assert!(
        final_crack >= CRACK + 0.01,
        "the crack grew only to {final_crack}"
    );
    assert!(compared >= 20, "{compared} rows on the growth branch");
    assert!(worst <= 0.05, "worst relative error {worst}");
}
