//! Per-element results of a part at a recorded instant — Cauchy stress, current fiber
//! direction, material state variables and activation — for output frames and statistics
//! (the 95th-percentile von Mises stress of a muscle, say).
//!
//! The solvers keep no stress between steps (the one-point hex8 would need 48 B more per
//! element), so the fields are evaluated on demand, when a frame is written: every
//! material point is updated once more over a step of zero length at its accepted
//! deformation gradient F and state, σ = σ(F, state; Δt = 0), which gives back the stress
//! of the accepted step for any material whose response at Δt = 0 keeps its state (the
//! built-in ones do: the Hill model puts a zero stretch increment into its SEE). A value
//! per element is the mean over the element's integration points; the current fiber
//! direction is the normalised mean of F a₀ / |a₀|.

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use musclefem_materials::{
    Material, MaterialError, PointBlock, PointResponse, StateVariable, VoigtStress,
};

use super::SolverError;
use crate::mesh::Mesh;

/// Per-element fields of one part (an element block) at one instant.
#[derive(Debug, Clone, PartialEq)]
pub struct PartFields {
    /// Index of the block in the mesh.
    pub block: usize,
    /// Mean Cauchy stress of each element in Voigt order (σxx, σyy, σzz, σyz, σxz, σxy)
    /// [Pa].
    pub cauchy_stress: Vec<VoigtStress>,
    /// Unit fiber direction of each element in the current configuration.
    pub fiber_direction: Vec<Vector3<f64>>,
    /// Fiber stretch λ_f = |F a₀| of each element, the mean over its points (a₀ the unit
    /// reference fiber direction, F the deformation gradient the material saw) [1].
    pub fiber_stretch: Vec<f64>,
    /// The material's state variables (names, units).
    pub state_variables: Vec<StateVariable>,
    /// Mean state of each element, `state_variables.len()` per element, element-major.
    pub state: Vec<f64>,
    /// Activation level of the material at this instant, if it has one [1].
    pub activation: Option<f64>,
}

/// The p-quantile (p ∈ [0, 1]) of `values` by linear interpolation between order
/// statistics: with the n values sorted, v₍ₖ₎, k = 0…n−1, it is
/// v₍⌊h⌋₎ + (h − ⌊h⌋)(v₍⌊h⌋₊₁₎ − v₍⌊h⌋₎), h = p (n − 1); `None` if there are none. The
/// paper's peak stress of a muscle is the 0.95-quantile of its elements' von Mises
/// stresses, each element counted once.
pub fn percentile(values: &[f64], p: f64) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let h = p.clamp(0.0, 1.0) * (sorted.len() - 1) as f64;
    let below = h.floor() as usize;
    let above = (below + 1).min(sorted.len() - 1);
    Some(sorted[below] + (h - below as f64) * (sorted[above] - sorted[below]))
}

impl PartFields {
    /// Von Mises equivalent stress of each element's mean Cauchy stress [Pa].
    pub fn von_mises(&self) -> Vec<f64> {
        self.cauchy_stress
            .iter()
            .map(musclefem_materials::tensor::von_mises)
            .collect()
    }

    /// Values of state variable `index` of every element.
    pub fn state_variable(&self, index: usize) -> Vec<f64> {
        let count = self.state_variables.len();
        self.state
            .iter()
            .skip(index)
            .step_by(count.max(1))
            .copied()
            .collect()
    }
}

/// The accepted material points of a run of consecutive elements of a block, each with
/// `points_per_element` points in element order.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AcceptedPoints<'a> {
    /// Deformation gradient the material saw (F̄ for the F-bar technologies).
    pub deformation_gradient: &'a [Matrix3<f64>],
    /// Reference fiber direction of each point.
    pub fiber: &'a [Vector3<f64>],
    /// State of each point, `state_count()` per point.
    pub state: &'a [f64],
    /// First element of the run (in the block), for error messages.
    pub first_element: usize,
    pub points_per_element: usize,
}

/// Evaluates the fields of one part from its runs of accepted points.
pub(crate) fn part_fields(
    mesh: &Mesh,
    block: usize,
    material: &dyn Material,
    time: f64,
    runs: &[AcceptedPoints],
) -> Result<PartFields, SolverError> {
    let pieces: Vec<PartFields> = runs
        .par_iter()
        .map(|run| run_fields(block, material, time, run))
        .collect::<Result<_, _>>()
        .map_err(|(element, source)| SolverError::Material {
            time,
            block: mesh.blocks[block].name.clone(),
            element,
            cause: source,
        })?;
    let mut fields = empty_fields(block, material, time);
    for piece in pieces {
        fields.cauchy_stress.extend(piece.cauchy_stress);
        fields.fiber_direction.extend(piece.fiber_direction);
        fields.fiber_stretch.extend(piece.fiber_stretch);
        fields.state.extend(piece.state);
    }
    Ok(fields)
}

fn empty_fields(block: usize, material: &dyn Material, time: f64) -> PartFields {
    PartFields {
        block,
        cauchy_stress: Vec::new(),
        fiber_direction: Vec::new(),
        fiber_stretch: Vec::new(),
        state_variables: material.state_variables().to_vec(),
        state: Vec::new(),
        activation: material.activation(time),
    }
}

/// The fields of one run of elements; on a material error, the element and the error.
fn run_fields(
    block: usize,
    material: &dyn Material,
    time: f64,
    run: &AcceptedPoints,
) -> Result<PartFields, (usize, MaterialError)> {
    let points = run.deformation_gradient.len();
    let ppe = run.points_per_element.max(1);
    let nstate = material.state_count();
    let mut stress = vec![VoigtStress::zeros(); points];
    let mut scratch_state = vec![0.0; points * nstate];
    let mut response = PointResponse {
        cauchy_stress: &mut stress,
        state_new: &mut scratch_state,
        tangent: None,
    };
    let accepted = PointBlock {
        time,
        dt: 0.0,
        deformation_gradient_old: run.deformation_gradient,
        deformation_gradient_new: run.deformation_gradient,
        fiber_direction: run.fiber,
        state_old: run.state,
    };
    material.update(&accepted, &mut response).map_err(|error| {
        let point = match &error {
            MaterialError::InvalidPoint { point, .. }
            | MaterialError::NonFiniteResult { point, .. } => *point,
            _ => 0,
        };
        (run.first_element + point / ppe, error)
    })?;
    let mut fields = empty_fields(block, material, time);
    let weight = 1.0 / ppe as f64;
    for element in 0..points / ppe {
        let range = element * ppe..(element + 1) * ppe;
        fields
            .cauchy_stress
            .push(stress[range.clone()].iter().sum::<VoigtStress>() * weight);
        let fiber: Vector3<f64> = range
            .clone()
            .map(|p| run.deformation_gradient[p] * run.fiber[p].normalize())
            .sum();
        fields
            .fiber_direction
            .push(fiber.try_normalize(0.0).unwrap_or_else(Vector3::zeros));
        let stretch: f64 = range
            .clone()
            .map(|p| (run.deformation_gradient[p] * run.fiber[p].normalize()).norm())
            .sum();
        fields.fiber_stretch.push(stretch * weight);
        for k in 0..nstate {
            let sum: f64 = range.clone().map(|p| run.state[p * nstate + k]).sum();
            fields.state.push(sum * weight);
        }
    }
    Ok(fields)
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;
    use std::sync::Arc;

    use musclefem_materials::MaterialLibrary;

    use super::*;
    use crate::mesh::generate::box_of_hexes;

    #[test]
    fn fields_average_the_points_and_give_back_the_accepted_stress() {
        let material: Arc<dyn Material> = MaterialLibrary::with_builtins()
            .create("neo-hookean", &BTreeMap::new())
            .unwrap();
        let mesh = box_of_hexes([1.0, 1.0, 1.0], [2, 1, 1]).unwrap();
        // Two elements of two points each: element 0 stretched along x at both points,
        // element 1 stretched at one point only.
        let stretched =
            Matrix3::from_diagonal(&Vector3::new(1.2, 1.0 / 1.2f64.sqrt(), 1.0 / 1.2f64.sqrt()));
        let f = [stretched, stretched, stretched, Matrix3::identity()];
        let fiber = [Vector3::new(2.0, 0.0, 0.0); 4];
        let run = AcceptedPoints {
            deformation_gradient: &f,
            fiber: &fiber,
            state: &[],
            first_element: 0,
            points_per_element: 2,
        };
        let fields = part_fields(&mesh, 0, material.as_ref(), 0.3, &[run]).unwrap();
        let mut one = [VoigtStress::zeros()];
        material
            .update(
                &PointBlock {
                    time: 0.3,
                    dt: 1e-3,
                    deformation_gradient_old: &[Matrix3::identity()],
                    deformation_gradient_new: &[stretched],
                    fiber_direction: &fiber[..1],
                    state_old: &[],
                },
                &mut PointResponse {
                    cauchy_stress: &mut one,
                    state_new: &mut [],
                    tangent: None,
                },
            )
            .unwrap();
        assert_eq!(fields.cauchy_stress.len(), 2);
        assert!((fields.cauchy_stress[0] - one[0]).norm() <= 1e-12 * one[0].norm());
        assert!((fields.cauchy_stress[1] - 0.5 * one[0]).norm() <= 1e-12 * one[0].norm());
        assert_eq!(fields.fiber_direction[0], Vector3::x());
        // The fiber stretch: 1.2 at both points of element 0, the mean of 1.2 and 1 in 1.
        assert!((fields.fiber_stretch[0] - 1.2).abs() < 1e-15);
        assert!((fields.fiber_stretch[1] - 1.1).abs() < 1e-15);
        assert_eq!(fields.activation, None);
        let von_mises = fields.von_mises();
        assert!(
            von_mises[0] > 0.0 && (von_mises[0] - 2.0 * von_mises[1]).abs() < 1e-9 * von_mises[0]
        );
    }
}
