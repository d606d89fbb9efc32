//! Shared by the cohesive tests (`cohesive.rs`, `cohesive_threads.rs`, `dcb.rs`): two boxes
//! of hex8 stacked along z into one mesh, a neo-Hookean material, loads and the analytic
//! law.

#![allow(dead_code)]

use std::collections::BTreeMap;
use std::sync::Arc;

use musclefem_contact::CohesiveSettings;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::mesh::{ElementRef, Face, Mesh};
use musclefem_core::solver::PrescribedDisplacement;
use musclefem_materials::{Amplitude, Material, MaterialLibrary};
use nalgebra::Vector3;

/// A box of `size` [m] cut into `divisions` hex8 cells, its corner at `origin` [m].
pub struct BoxSpec {
    pub size: [f64; 3],
    pub divisions: [usize; 3],
    pub origin: [f64; 3],
}

/// Block 0 `lower` and block 1 `upper`, each box of [`box_of_hexes`] at its origin, with
/// its own nodes (none shared), node sets and surfaces prefixed `lower_` and `upper_`
/// (`lower_z1`, `upper_z0`, ...).
pub fn two_boxes(lower: &BoxSpec, upper: &BoxSpec) -> Mesh {
    let mut mesh = Mesh::default();
    for (b, (name, spec)) in [("lower", lower), ("upper", upper)].into_iter().enumerate() {
        let part = box_of_hexes(spec.size, spec.divisions).expect("a valid box");
        let offset = mesh.node_count() as u32;
        for i in 0..part.node_count() {
            let shift = Vector3::from(spec.origin);
            mesh.nodes.push(part.nodes.position(i) + shift);
        }
        let mut block = part.blocks[0].clone();
        block.name = name.to_string();
        block.connectivity.iter_mut().for_each(|n| *n += offset);
        mesh.blocks.push(block);
        for (set, nodes) in &part.node_sets {
            let nodes = nodes.iter().map(|n| n + offset).collect();
            mesh.node_sets.insert(format!("{name}_{set}"), nodes);
        }
        for (surface, faces) in &part.surfaces {
            let faces = faces
                .iter()
                .map(|f| Face::new(ElementRef::new(b as u32, f.element.element), f.face))
                .collect();
            mesh.surfaces.insert(format!("{name}_{surface}"), faces);
        }
    }
    mesh.validate().expect("a valid mesh");
    mesh
}

/// Neo-Hookean W = μ/2 (Ī₁ − 3) + (J − 1)²/D of Young's modulus `young` [Pa] and Poisson's
/// ratio `poisson`: μ = E/(2(1 + ν)), D = 2/κ, κ = E/(3(1 − 2ν)).
pub fn neo_hookean(young: f64, poisson: f64) -> Arc<dyn Material> {
    let mu = young / (2.0 * (1.0 + poisson));
    let kappa = young / (3.0 * (1.0 - 2.0 * poisson));
    let params = BTreeMap::from([("mu".to_string(), mu), ("D".to_string(), 2.0 / kappa)]);
    MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .expect("valid neo-Hookean parameters")
}

/// Component `dof` of the nodes of set `set` held at 0.
pub fn held(mesh: &Mesh, set: &str, dof: usize) -> PrescribedDisplacement {
    PrescribedDisplacement {
        nodes: mesh.node_set(set).expect("a generated set").to_vec(),
        dof,
        amplitude: Amplitude::new(vec![(0.0, 0.0)]).expect("a constant"),
    }
}

/// Component `dof` of `nodes` ramped linearly from 0 at t = 0 to `value` [m] at t = 1 s.
pub fn ramped(nodes: Vec<u32>, dof: usize, value: f64) -> PrescribedDisplacement {
    PrescribedDisplacement {
        nodes,
        dof,
        amplitude: Amplitude::ramp(1.0, value).expect("a ramp"),
    }
}

/// The normal traction of the law in monotonic pure opening δ [m] [Pa]: K δ up to δ_0,
/// K δ_0 (δ_f − δ)/(δ_f − δ_0) to δ_f, then 0 (compression K δ).
pub fn mode_one_traction(settings: &CohesiveSettings, opening: f64) -> f64 {
    let (k, d0, df) = (
        settings.normal_stiffness,
        settings.initiation_separation,
        settings.failure_separation,
    );
    if opening <= d0 {
        k * opening
    } else if opening < df {
        k * d0 * (df - opening) / (df - d0)
    } else {
        0.0
    }
}

/// What a run showed at each recorded row: time, displacements and the interactions'
/// nodal fields.
#[derive(Default)]
pub struct Recorder {
    pub frames: Vec<Frame>,
}

/// One recorded instant.
pub struct Frame {
    pub time: f64,
    pub displacement: Vec<Vector3<f64>>,
    pub fields: Vec<musclefem_core::solver::NodalField>,
}

impl Frame {
    /// The values of the nodal field `name` of the (one) interaction: the solvers name
    /// it `INTERACTION_name`.
    pub fn field(&self, name: &str) -> &[f64] {
        let suffix = format!("_{name}");
        &self
            .fields
            .iter()
            .find(|f| f.name.ends_with(&suffix))
            .unwrap_or_else(|| panic!("no nodal field {name}"))
            .values
    }
}

impl musclefem_core::solver::observer::Observer for Recorder {
    fn record(
        &mut self,
        _record: &musclefem_core::solver::observer::Record,
        snapshot: &musclefem_core::solver::observer::Snapshot,
    ) -> std::ops::ControlFlow<()> {
        self.frames.push(Frame {
            time: snapshot.time,
            displacement: snapshot.displacement.to_vec(),
            fields: snapshot.nodal_fields(),
        });
        std::ops::ControlFlow::Continue(())
    }
}

/// The nodes of block `block` of `mesh`, sorted.
pub fn block_nodes(mesh: &Mesh, block: usize) -> Vec<u32> {
    let mut nodes = mesh.blocks[block].connectivity.clone();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

/// Pairs (secondary, main) of nodes of sets `secondary` and `main` at the same reference
/// position in x and y.
pub fn facing_pairs(mesh: &Mesh, secondary: &str, main: &str) -> Vec<(u32, u32)> {
    let main_nodes = mesh.node_set(main).expect("a set");
    mesh.node_set(secondary)
        .expect("a set")
        .iter()
        .map(|&s| {
            let p = mesh.nodes.position(s as usize);
            let m = main_nodes
                .iter()
                .copied()
                .find(|&m| {
                    let q = mesh.nodes.position(m as usize);
                    (p.x - q.x).abs() < 1e-12 && (p.y - q.y).abs() < 1e-12
                })
                .expect("conforming interface");
            (s, m)
        })
        .collect()
}

/// The opening z_s − z_m of every facing pair at displacement `u` [m].
pub fn openings(mesh: &Mesh, pairs: &[(u32, u32)], u: &[Vector3<f64>]) -> Vec<f64> {
    pairs
        .iter()
        .map(|&(s, m)| {
            let xs = mesh.nodes.position(s as usize) + u[s as usize];
            let xm = mesh.nodes.position(m as usize) + u[m as usize];
            xs.z - xm.z
        })
        .collect()
}

/// Σ A_i f(δ_i) over the bonds: `areas` and `openings` per bond, in the same order.
pub fn area_sum(areas: &[f64], openings: &[f64], f: impl Fn(f64) -> f64) -> f64 {
    areas.iter().zip(openings).map(|(a, d)| a * f(*d)).sum()
}

/// Largest minus smallest of `values`.
pub fn spread(values: &[f64]) -> f64 {
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = values.iter().copied().fold(f64::INFINITY, f64::min);
    max - min
}

/// The tributary area of the secondary node of every pair, from `surface` [m²].
pub fn pair_areas(
    surface: &musclefem_contact::DeformableSurface,
    pairs: &[(u32, u32)],
) -> Vec<f64> {
    pairs
        .iter()
        .map(|&(s, _)| surface.node_area[surface.local_index(s).expect("a surface node")])
        .collect()
}
