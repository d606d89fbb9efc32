//! Shared set-up of the contact tests: a compressible neo-Hookean solid, boxes of hexes
//! (one or two in one mesh), held components, smooth ramps and an observer that keeps the
//! interactions' nodal fields.

#![allow(dead_code)]

use std::collections::BTreeMap;
use std::ops::ControlFlow;
use std::sync::Arc;

use nalgebra::Vector3;

use musclefem_core::element::Technology;
use musclefem_core::mesh::generate::box_of_hexes;
use musclefem_core::mesh::{ElementRef, Face, Mesh};
use musclefem_core::solver::observer::{Observer, Record, Snapshot};
use musclefem_core::solver::{NodalField, Part, PrescribedDisplacement};
use musclefem_materials::{Amplitude, Material, MaterialLibrary};

/// Shear modulus μ [Pa].
pub const MU: f64 = 1e4;
/// Bulk modulus K = 2/D [Pa].
pub const BULK: f64 = 1e5;
/// Young's modulus E = 9Kμ/(3K + μ) [Pa] (≈ 2.9e4).
pub const YOUNGS: f64 = 9.0 * BULK * MU / (3.0 * BULK + MU);
pub const DENSITY: f64 = 1000.0;

pub fn neo_hookean() -> Arc<dyn Material> {
    let params = BTreeMap::from([("mu".to_string(), MU), ("D".to_string(), 2.0 / BULK)]);
    MaterialLibrary::with_builtins()
        .create("neo-hookean", &params)
        .unwrap()
}

/// A fully integrated hex8 part on every block of `mesh`.
pub fn parts(mesh: &Mesh) -> Vec<Part> {
    (0..mesh.blocks.len())
        .map(|block| Part {
            block,
            technology: Technology::Hex8Full,
            material: neo_hookean(),
            density: DENSITY,
        })
        .collect()
}

/// Component `dof` of `nodes` follows `amplitude`.
pub fn prescribed(nodes: &[u32], dof: usize, amplitude: Amplitude) -> PrescribedDisplacement {
    PrescribedDisplacement {
        nodes: nodes.to_vec(),
        dof,
        amplitude,
    }
}

/// Component `dof` of `nodes` held at zero.
pub fn held(nodes: &[u32], dof: usize) -> PrescribedDisplacement {
    prescribed(nodes, dof, Amplitude::new(vec![(0.0, 0.0)]).unwrap())
}

/// 0 → `value` over [0, `time`] along the smooth step 3s² − 2s³ (zero rate at both ends),
/// sampled at 65 knots.
pub fn smooth_ramp(time: f64, value: f64) -> Amplitude {
    let knots = (0..=64)
        .map(|i| {
            let s = i as f64 / 64.0;
            (s * time, value * s * s * (3.0 - 2.0 * s))
        })
        .collect();
    Amplitude::new(knots).unwrap()
}

/// A box of hexes of `size` [m] with `divisions`, its corner at `origin` [m].
pub fn box_at(origin: Vector3<f64>, size: [f64; 3], divisions: [usize; 3]) -> Mesh {
    let mut mesh = box_of_hexes(size, divisions).unwrap();
    for i in 0..mesh.node_count() {
        let p = mesh.nodes.position(i);
        mesh.nodes.set_position(i, p + origin);
    }
    mesh
}

/// The two boxes in one mesh: blocks `lower` (0) and `upper` (1); the node sets and
/// surfaces of each keep their names with a prefix, `lower.z1`, `upper.z0`, ….
pub fn two_boxes(lower: Mesh, upper: Mesh) -> Mesh {
    let mut mesh = Mesh::default();
    for (b, (prefix, part)) in [("lower", lower), ("upper", upper)].into_iter().enumerate() {
        let shift = mesh.node_count() as u32;
        for i in 0..part.node_count() {
            mesh.nodes.push(part.nodes.position(i));
        }
        let mut block = part.blocks[0].clone();
        block.name = prefix.to_string();
        block.connectivity.iter_mut().for_each(|n| *n += shift);
        mesh.blocks.push(block);
        for (name, nodes) in &part.node_sets {
            let nodes = nodes.iter().map(|n| n + shift).collect();
            mesh.node_sets.insert(format!("{prefix}.{name}"), nodes);
        }
        for (name, faces) in &part.surfaces {
            let faces = faces
                .iter()
                .map(|f| Face::new(ElementRef::new(b as u32, f.element.element), f.face))
                .collect();
            mesh.surfaces.insert(format!("{prefix}.{name}"), faces);
        }
    }
    mesh.validate().unwrap();
    mesh
}

pub fn reference(mesh: &Mesh) -> Vec<Vector3<f64>> {
    (0..mesh.node_count())
        .map(|i| mesh.nodes.position(i))
        .collect()
}

/// Keeps the nodal fields of the last recorded row.
#[derive(Default)]
pub struct LastFields {
    pub time: f64,
    pub fields: Vec<NodalField>,
}

impl LastFields {
    /// The field `name` of the (one) interaction: the solvers name it
    /// `INTERACTION_name`.
    pub fn field(&self, name: &str) -> &NodalField {
        let suffix = format!("_{name}");
        self.fields
            .iter()
            .find(|f| f.name.ends_with(&suffix))
            .unwrap_or_else(|| panic!("no nodal field '{name}'"))
    }
}

impl Observer for LastFields {
    fn record(&mut self, _record: &Record, snapshot: &Snapshot) -> ControlFlow<()> {
        self.time = snapshot.time;
        self.fields = snapshot.nodal_fields();
        ControlFlow::Continue(())
    }
}
