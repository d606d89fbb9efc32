//! The solvers' per-part element fields ([`PartFields`]) laid out as frame arrays: one
//! value per element over all blocks, in block order (the VTU cell order).
//!
//! Arrays written: `cauchy_stress` (and from it `von_mises`), `fiber_direction_current`,
//! `fiber_stretch` (|F a₀|), `activation` when any part's material has one (0 in passive parts), and one
//! `state_NAME` array per material state variable (characters other than letters, digits,
//! `_`, `-` and `.` replaced by `_`; NaN in parts whose material does not
//! carry it, so ParaView shows them as "no value").

use nalgebra::Vector3;

use musclefem_core::mesh::Mesh;
use musclefem_core::solver::element_fields::PartFields;
use musclefem_materials::VoigtStress;

use super::frame::Frame;

/// Element fields of every block, owned, in block order.
#[derive(Debug, Clone, PartialEq)]
pub struct ElementFieldArrays {
    pub cauchy_stress: Vec<VoigtStress>,
    pub fiber_direction: Vec<Vector3<f64>>,
    /// Fiber stretch |F a₀| of each element [1] (1 in blocks without fields).
    pub fiber_stretch: Vec<f64>,
    /// Activation of each element's material [1], if any material has one.
    pub activation: Option<Vec<f64>>,
    /// (`state_NAME`, value per element) for every state variable name of any material.
    pub state: Vec<(String, Vec<f64>)>,
}

impl ElementFieldArrays {
    /// Lay `parts` out over the blocks of `mesh`. Elements of blocks without fields get
    /// zero stress, a zero fiber vector and NaN states.
    pub fn gather(mesh: &Mesh, parts: &[PartFields]) -> Self {
        let offsets: Vec<usize> = mesh
            .blocks
            .iter()
            .scan(0, |next, block| {
                let first = *next;
                *next += block.len();
                Some(first)
            })
            .collect();
        let elements = mesh.element_count();
        let mut arrays = ElementFieldArrays {
            cauchy_stress: vec![VoigtStress::zeros(); elements],
            fiber_direction: vec![Vector3::zeros(); elements],
            fiber_stretch: vec![1.0; elements],
            activation: parts
                .iter()
                .any(|p| p.activation.is_some())
                .then(|| vec![0.0; elements]),
            state: Vec::new(),
        };
        for part in parts {
            let Some(&first) = offsets.get(part.block) else {
                continue;
            };
            let range = first..first + part.cauchy_stress.len();
            arrays.cauchy_stress[range.clone()].copy_from_slice(&part.cauchy_stress);
            arrays.fiber_direction[range.clone()].copy_from_slice(&part.fiber_direction);
            arrays.fiber_stretch[range.clone()].copy_from_slice(&part.fiber_stretch);
            if let (Some(values), Some(level)) = (&mut arrays.activation, part.activation) {
                values[range.clone()].fill(level);
            }
            for (index, variable) in part.state_variables.iter().enumerate() {
                let name: String = format!("state_{}", variable.name)
                    .chars()
                    .map(|c| match c {
                        'a'..='z' | 'A'..='Z' | '0'..='9' | '_' | '-' | '.' => c,
                        _ => '_',
                    })
                    .collect();
                let position = match arrays.state.iter().position(|(n, _)| *n == name) {
                    Some(position) => position,
                    None => {
                        arrays.state.push((name, vec![f64::NAN; elements]));
                        arrays.state.len() - 1
                    }
                };
                let values = part.state_variable(index);
                arrays.state[position].1[range.clone()].copy_from_slice(&values);
            }
        }
        arrays
    }

    /// `frame` with these arrays attached.
    pub fn attach<'a>(&'a self, frame: Frame<'a>) -> Frame<'a> {
        let mut frame = frame
            .with_cauchy_stress(&self.cauchy_stress)
            .with_current_fiber_direction(&self.fiber_direction)
            .with_cell_scalar("fiber_stretch", &self.fiber_stretch);
        if let Some(activation) = &self.activation {
            frame = frame.with_cell_scalar("activation", activation);
        }
        for (name, values) in &self.state {
            frame = frame.with_cell_scalar(name, values);
        }
        frame
    }
}
