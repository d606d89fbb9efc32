//! Mass scaling on a moving carrier: a cube tied at its base to a body that moves it
//! along x needs, from its base, the force M a of its mass M accelerated with the body.
//! Mass scaling multiplies M; with the body as the added mass's frame
//! (`ExplicitSettings::mass_scaling_frame`) the base carries the physical M a again.

use std::collections::BTreeMap;
use std::sync::Arc;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use musclefem_core::element::Technology;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit};
use musclefem_core::solver::{Loads, Part, PoseFollower, RigidMotion, RigidTie};
use musclefem_materials::MaterialLibrary;

const SIDE: f64 = 0.01;
const DENSITY: f64 = 1000.0;
/// The carrier's travel [m] and duration [s].
const TRAVEL: f64 = 0.05;
const DURATION: f64 = 2.0;

/// The carrier: x(t) = TRAVEL s(t/DURATION) with the quintic s(τ) = 10τ³ − 15τ⁴ + 6τ⁵,
/// which starts and ends at rest with no acceleration.
#[derive(Debug)]
struct Carrier;

impl Carrier {
    fn acceleration(time: f64) -> f64 {
        let tau = time / DURATION;
        TRAVEL / (DURATION * DURATION) * (60.0 * tau - 180.0 * tau * tau + 120.0 * tau.powi(3))
    }
}

impl PoseFollower for Carrier {
    fn isometry_at(&self, time: f64) -> Isometry3<f64> {
        let tau = time / DURATION;
        let travel = TRAVEL * tau.powi(3) * (10.0 - 15.0 * tau + 6.0 * tau * tau);
        Isometry3::from_parts(
            Translation3::new(travel, 0.0, 0.0),
            UnitQuaternion::identity(),
        )
    }
    fn reference_point(&self) -> Vector3<f64> {
        Vector3::zeros()
    }
}

/// The x-force the base tie carries at each recorded instant (time, force) [s, N].
fn base_force(mass_scaling: Option<f64>, frame: bool) -> (Vec<(f64, f64)>, f64) {
    let mesh = box_of_hexes([SIDE; 3], [2; 3]).unwrap();
    let parameters = BTreeMap::from([("mu".to_string(), 1e5), ("D".to_string(), 2e-6)]);
    let material = MaterialLibrary::with_builtins()
        .create("neo-hookean", &parameters)
        .unwrap();
    let parts = [Part {
        block: 0,
        technology: Technology::Hex8FBar,
        material,
        density: DENSITY,
    }];
    let carrier = RigidMotion::followed(Arc::new(Carrier));
    let loads = Loads {
        rigid_ties: vec![RigidTie {
            name: "base".into(),
            nodes: mesh.node_set("y0").unwrap().to_vec(),
            motion: carrier.clone(),
        }],
        ..Loads::default()
    };
    let mut settings = ExplicitSettings::new(DURATION);
    settings.history_interval = DURATION / 8.0;
    settings.mass_scaling_time_step = mass_scaling;
    if frame {
        settings.mass_scaling_frame = Some(Box::new(carrier));
    }
    let result = run_explicit(&mesh, &parts, &loads, &settings).unwrap();
    let forces = (result.history.iter())
        .map(|row| (row.time, row.rigid_reactions[0].force.x))
        .collect();
    (forces, result.added_mass_fraction)
}

#[test]
fn the_carriers_frame_takes_the_added_mass_out_of_the_base_force() {
    let mass = DENSITY * SIDE.powi(3);
    let (physical, none) = base_force(None, false);
    assert_eq!(none, 0.0);
    // The stable step of the unscaled cube is about 7.7e-5 s: scaled to 7.5e-4 s, the
    // mass grows about a hundredfold, as the knee's.
    let (scaled, added) = base_force(Some(7.5e-4), false);
    let (carried, added_too) = base_force(Some(7.5e-4), true);
    assert!(added > 50.0, "added mass fraction {added}");
    assert_eq!(added, added_too);
    eprintln!("added mass: {added:.1} × the physical");
    // At the instants of largest acceleration (τ = 1/4, 3/4) and between them.
    for k in [2, 3, 5, 6] {
        let (time, f_physical) = physical[k];
        let expected = mass * Carrier::acceleration(time);
        let (_, f_scaled) = scaled[k];
        let (_, f_carried) = carried[k];
        eprintln!(
            "t = {time:.2} s: M a = {expected:.4e} N; base force {f_physical:.4e} (unscaled), \
             {f_scaled:.4e} (mass-scaled), {f_carried:.4e} (mass-scaled, carried)"
        );
        assert!(
            (f_physical - expected).abs() < 0.01 * expected.abs(),
            "unscaled"
        );
        assert!(
            (f_scaled - (1.0 + added) * expected).abs() < 0.05 * (1.0 + added) * expected.abs(),
            "mass-scaled without the frame"
        );
        assert!(
            (f_carried - expected).abs() < 0.05 * expected.abs(),
            "mass-scaled with the frame"
        );
    }
}
