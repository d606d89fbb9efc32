//! The one-point hex8's hourglass control at work in an explicit run where hourglass
//! modes are excited: a clamped cube of 4 × 4 × 4 elements with half of the opposite face
//! pulled (a shearing, non-homogeneous deformation), nearly incompressible enough
//! (K/μ = 100) that full integration would lock. The reference is F-bar on the same
//! mesh (locking-free, no hourglass modes).
//!
//! Measured (0.2 s ramp, 4³ elements, at safety 0.6 before the stable-step fix below): one point with the default control departs from
//! F-bar by 15 % in displacement (RMS over nodes), with an hourglass energy of 1.3 % of
//! the internal energy; without control (G_hg = 0) it departs by 114 %. With a 1.5 s ramp
//! on 8³ elements the departure with control fell to 5.7 % (hourglass energy 0.6 %): the
//! two discretizations converge to the same solution.
//!
//! This case first exposed that the solver's stable step, with L₀ = volume / largest face
//! area, was not conservative (a lone cube hex8 with lumped mass ρ₀V/8 per node has a
//! critical step of about 0.62 L₀ √(ρ₀/M)): the runs blew up at the default safety 0.9.
//! The solver now uses the Flanagan–Belytschko length (h/√3 on a cube), and these runs use
//! the default safety factor.

use std::collections::BTreeMap;
use std::sync::Arc;

use nalgebra::Vector3;

use musclefem_core::element::{BlockKernel, Technology};
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit};
use musclefem_core::solver::{Part, PrescribedDisplacement};
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

const SIDE: f64 = 0.01;
const SHEAR_MODULUS: f64 = 1e4;
const RAMP: f64 = 0.2;

/// Neo-Hookean, μ = 10 kPa, K = 2/D = 1 MPa.
fn material() -> Arc<dyn Material> {
    let params = BTreeMap::from([("mu".to_string(), SHEAR_MODULUS), ("D".to_string(), 2e-6)]);
    MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap()
}

/// x0 clamped; the nodes of x1 with y ≤ side/2 pulled along x by 20 % of the side over a
/// smooth ramp.
fn loading(mesh: &Mesh) -> Vec<PrescribedDisplacement> {
    let knots = (0..=40)
        .map(|i| {
            let s = i as f64 / 40.0;
            (s * RAMP, 0.2 * SIDE * s * s * (3.0 - 2.0 * s))
        })
        .collect();
    let pulled: Vec<u32> = mesh
        .node_set("x1")
        .unwrap()
        .iter()
        .copied()
        .filter(|&n| mesh.nodes.position(n as usize)[1] <= 0.5 * SIDE + 1e-12)
        .collect();
    let mut bcs = vec![PrescribedDisplacement {
        nodes: pulled,
        dof: 0,
        amplitude: Amplitude::new(knots).unwrap(),
    }];
    for dof in 0..3 {
        bcs.push(PrescribedDisplacement {
            nodes: mesh.node_set("x0").unwrap().to_vec(),
            dof,
            amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
        });
    }
    bcs
}

/// Final displacements, internal energy and total hourglass energy of a run.
fn run(mesh: &Mesh, technology: Technology) -> (Vec<Vector3<f64>>, f64, f64) {
    let parts = [Part {
        block: 0,
        technology,
        material: material(),
        density: 1000.0,
    }];
    let settings = ExplicitSettings::new(RAMP * 4.0 / 3.0);
    let result = run_explicit(mesh, &parts, &loading(mesh).into(), &settings).unwrap();
    let kernel = BlockKernel::new(&mesh.nodes, &mesh.blocks[0], technology).unwrap();
    let hourglass: f64 = mesh.blocks[0]
        .elements()
        .enumerate()
        .map(|(e, ids)| {
            let x: Vec<Vector3<f64>> = ids
                .iter()
                .map(|&n| mesh.nodes.position(n as usize) + result.displacement[n as usize])
                .collect();
            kernel.hourglass_energy(e, &x)
        })
        .sum();
    let internal = result.history.last().unwrap().internal_energy;
    (result.displacement, internal, hourglass)
}

fn relative_difference(u: &[Vector3<f64>], reference: &[Vector3<f64>]) -> f64 {
    let difference: f64 = u
        .iter()
        .zip(reference)
        .map(|(a, b)| (a - b).norm_squared())
        .sum();
    let size: f64 = reference.iter().map(|b| b.norm_squared()).sum();
    (difference / size).sqrt()
}

#[test]
fn hourglass_control_keeps_the_one_point_hex8_close_to_fbar() {
    let mesh = box_of_hexes([SIDE; 3], [4, 4, 4]).unwrap();
    let (reference, _, none) = run(&mesh, Technology::Hex8FBar);
    assert_eq!(none, 0.0);
    let (controlled, internal, hourglass) = run(&mesh, Technology::hex8_one_point(SHEAR_MODULUS));
    let (free, _, _) = run(
        &mesh,
        Technology::Hex8OnePoint {
            hourglass_modulus: 0.0,
        },
    );
    let with_control = relative_difference(&controlled, &reference);
    let without = relative_difference(&free, &reference);
    println!(
        "one point vs F-bar: {with_control:.4} with control (E_hg / W_int = {:.4}), \
         {without:.4} without",
        hourglass / internal
    );
    assert!(with_control < 0.25, "{with_control}");
    assert!(
        hourglass > 0.0 && hourglass < 0.05 * internal,
        "{hourglass} vs {internal}"
    );
    assert!(without > 2.0 * with_control, "{without} vs {with_control}");
}
