//! The per-element fields a snapshot evaluates (Cauchy stress, current fiber direction,
//! state, activation) are the stresses the solver used: in a homogeneous uniaxial stretch
//! every element's σxx times the current cross-section equals the reaction, for every
//! element technology and both solvers, and an active Hill block reports its activation
//! and a series-element state consistent with its law.

use std::collections::BTreeMap;
use std::ops::ControlFlow;
use std::sync::Arc;

use nalgebra::Vector3;

use musclefem_core::element::Technology;
use musclefem_core::mesh::Mesh;
use musclefem_core::mesh::generate::{TetOrder, box_of_hexes, box_of_tets};
use musclefem_core::solver::element_fields::PartFields;
use musclefem_core::solver::explicit::{ExplicitSettings, run_explicit_observed};
use musclefem_core::solver::implicit::{ImplicitSettings, run_implicit_observed};
use musclefem_core::solver::observer::{Observer, Record, Snapshot};
use musclefem_core::solver::{Loads, Part, PrescribedDisplacement};
use musclefem_materials::hill::functions::series_elastic;
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

const SIDE: f64 = 0.01;

fn material(name: &str, parameters: &[(&str, f64)]) -> Arc<dyn Material> {
    let given = parameters
        .iter()
        .map(|(k, v)| (k.to_string(), *v))
        .collect::<BTreeMap<_, _>>();
    MaterialLibrary::with_builtins()
        .create(name, &given)
        .unwrap()
}

/// Symmetry on x0, y0, z0 and the x1 face pulled along x by `elongation` [m] over
/// `duration` [s]; the reaction of the pulled face is condition 0.
fn uniaxial(mesh: &Mesh, elongation: f64, duration: f64) -> Loads {
    let fixed = |set: &str, dof: usize| PrescribedDisplacement {
        nodes: mesh.node_set(set).unwrap().to_vec(),
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).unwrap(),
    };
    Loads::from(vec![
        PrescribedDisplacement {
            nodes: mesh.node_set("x1").unwrap().to_vec(),
            dof: 0,
            amplitude: Amplitude::ramp(duration, elongation).unwrap(),
        },
        fixed("x0", 0),
        fixed("y0", 1),
        fixed("z0", 2),
    ])
}

/// Keeps the element fields and the displacement of the last recorded row.
#[derive(Default)]
struct LastFields {
    fields: Vec<PartFields>,
    displacement: Vec<Vector3<f64>>,
    reaction: f64,
    time: f64,
}

impl LastFields {
    fn keep(&mut self, snapshot: &Snapshot, reaction: f64) -> ControlFlow<()> {
        self.fields = snapshot.element_fields().unwrap();
        self.displacement = snapshot.displacement.to_vec();
        self.reaction = reaction;
        self.time = snapshot.time;
        ControlFlow::Continue(())
    }

    /// The current cross-section of the cube normal to x [m²] (homogeneous deformation:
    /// from the corner's lateral displacements).
    fn cross_section(&self, mesh: &Mesh) -> f64 {
        let corner = (0..mesh.node_count())
            .max_by(|&a, &b| {
                let key = |n| mesh.nodes.position(n).y + mesh.nodes.position(n).z;
                key(a).total_cmp(&key(b))
            })
            .unwrap();
        let u = self.displacement[corner];
        (SIDE + u.y) * (SIDE + u.z)
    }
}

impl Observer for LastFields {
    fn record(&mut self, record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        self.keep(snapshot, record.reactions()[0])
    }
}

fn mesh_for(technology: Technology) -> Mesh {
    match technology {
        Technology::Tet4 | Technology::Tet4NodalAverage => {
            box_of_tets([SIDE; 3], [2; 3], TetOrder::Linear).unwrap()
        }
        Technology::Tet10 => box_of_tets([SIDE; 3], [2; 3], TetOrder::Quadratic).unwrap(),
        _ => box_of_hexes([SIDE; 3], [2; 3]).unwrap(),
    }
}

/// Every element's σxx A equals the reaction to `tolerance` (relative), its other stress
/// components are below `tolerance` σxx, and its fiber still points along x.
fn assert_uniaxial(label: &str, mesh: &Mesh, last: &LastFields, tolerance: f64) {
    let area = last.cross_section(mesh);
    let [part] = last.fields.as_slice() else {
        panic!("{label}: one part expected");
    };
    assert_eq!(part.cauchy_stress.len(), mesh.blocks[0].len(), "{label}");
    assert!(last.reaction > 0.0, "{label}: reaction {}", last.reaction);
    for (e, stress) in part.cauchy_stress.iter().enumerate() {
        let force = stress[0] * area;
        assert!(
            (force - last.reaction).abs() <= tolerance * last.reaction,
            "{label}, element {e}: σxx A = {force:.6e} N, reaction {:.6e} N",
            last.reaction
        );
        for k in 1..6 {
            assert!(
                stress[k].abs() <= tolerance * stress[0],
                "{label}, element {e}: component {k} = {:.3e} Pa, σxx {:.3e} Pa",
                stress[k],
                stress[0]
            );
        }
        let fiber = part.fiber_direction[e];
        assert!(
            (fiber - Vector3::x()).norm() < tolerance,
            "{label}: fiber {fiber:?}"
        );
    }
    let von_mises = part.von_mises();
    assert!(
        (von_mises[0] - part.cauchy_stress[0][0]).abs() <= tolerance * von_mises[0],
        "{label}: the von Mises stress of uniaxial stress is |σxx|"
    );
}

#[test]
fn implicit_fields_carry_the_stress_that_balances_the_reaction() {
    let neo_hookean = material("neo-hookean", &[("mu", 1e4), ("D", 2e-5)]);
    for technology in [
        Technology::Hex8Full,
        Technology::Hex8FBar,
        Technology::hex8_one_point(1e4),
        Technology::Tet4,
        Technology::Tet10,
    ] {
        let mesh = mesh_for(technology);
        let parts = vec![Part {
            block: 0,
            technology,
            material: neo_hookean.clone(),
            density: 1000.0,
        }];
        let loads = uniaxial(&mesh, 0.3 * SIDE, 1.0);
        let mut last = LastFields::default();
        run_implicit_observed(
            &mesh,
            &parts,
            &loads,
            &ImplicitSettings::new(1.0, 4),
            &mut last,
        )
        .unwrap();
        assert_eq!(last.time, 1.0);
        assert_uniaxial(&format!("implicit {technology:?}"), &mesh, &last, 1e-7);
    }
}

#[test]
fn explicit_fields_carry_the_stress_that_balances_the_reaction() {
    let neo_hookean = material("neo-hookean", &[("mu", 1e4), ("D", 2e-5)]);
    for technology in [
        Technology::hex8_one_point(1e4),
        Technology::Hex8Full,
        Technology::Tet4NodalAverage,
    ] {
        let mesh = mesh_for(technology);
        let parts = vec![Part {
            block: 0,
            technology,
            material: neo_hookean.clone(),
            density: 1000.0,
        }];
        // Slow against the cube's wave transit (≈ 1 ms): the start of the pull excites
        // free vibrations of stress amplitude ≈ ρ c v ≈ 1000 kg/m³ · 11 m/s · 1 mm/s
        // ≈ 11 Pa against σxx ≈ 2.8 kPa at the end, i.e. ≈ 0.4 %.
        let loads = uniaxial(&mesh, 0.1 * SIDE, 1.0);
        let mut settings = ExplicitSettings::new(1.0);
        settings.history_interval = 0.1;
        let mut last = LastFields::default();
        run_explicit_observed(&mesh, &parts, &loads, &settings, &mut last).unwrap();
        assert!((last.time - 1.0).abs() < 1e-12);
        assert_uniaxial(&format!("explicit {technology:?}"), &mesh, &last, 0.02);
    }
}

#[test]
fn an_active_hill_block_reports_its_activation_and_series_element_state() {
    let hill = material("hill", &[("n2", 1.0)]);
    let mesh = box_of_hexes([SIDE; 3], [1; 3]).unwrap();
    let parts = vec![Part {
        block: 0,
        technology: Technology::Hex8Full,
        material: hill.clone(),
        density: 1060.0,
    }];
    // Both ends held along the fibers: isometric.
    let loads = uniaxial(&mesh, 0.0, 0.5);
    let mut last = LastFields::default();
    run_implicit_observed(
        &mesh,
        &parts,
        &loads,
        &ImplicitSettings::new(0.5, 50),
        &mut last,
    )
    .unwrap();
    let part = &last.fields[0];
    assert_eq!(part.activation, hill.activation(0.5));
    assert!(part.activation.unwrap() > 0.9, "{:?}", part.activation);
    let names: Vec<&str> = part
        .state_variables
        .iter()
        .map(|v| v.name.as_str())
        .collect();
    assert_eq!(names, ["lambda_m", "lambda_s", "sigma_see"]);
    let lambda_s = part.state_variable(1)[0];
    let sigma_see = part.state_variable(2)[0];
    assert!(
        lambda_s > 1.0,
        "the active CE stretches the SEE: λ_s = {lambda_s}"
    );
    // The stored SEE stress is the series law at the stored stretch (Table 1: α, β).
    let parameters = musclefem_materials::hill::HillParameters::default();
    let law = series_elastic(parameters.see_exponent, parameters.see_stress, lambda_s);
    assert!(
        (sigma_see - law).abs() <= 1e-9 * law,
        "σ_SEE {sigma_see} Pa, law {law} Pa"
    );
    // The fibers carry the tension that the held ends react.
    assert!(part.cauchy_stress[0][0] > 0.0);
    assert!(last.reaction > 0.0);
}
