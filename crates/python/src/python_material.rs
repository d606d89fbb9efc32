//! A material whose update is a Python function (`musclefem.register_material`), called
//! once per block of points (the solvers' batches) with NumPy arrays. The slow path:
//! every call takes the GIL and copies the block into and out of NumPy.
//!
//! The function is called with keyword arguments
//!
//! - `F` (n, 3, 3): the deformation gradient at the end of the step, `F[p, i, J]` = F_iJ;
//! - `F_old` (n, 3, 3): at the start of the step;
//! - `fiber` (n, 3): the fiber direction in the reference configuration (not normalised);
//! - `state` (n, k): the state variables at the start of the step (k may be 0);
//! - `dt` [s], `time` [s] (at the end of the step);
//! - `params`: {name: value} of the material's parameters (SI units),
//!
//! and returns the **Cauchy stress** σ (n, 3, 3) [Pa] (its symmetric part is used), or a
//! pair (σ, new state (n, k)). When a solver needs the tangent ∂P/∂F, the block is
//! evaluated once more with every F perturbed by ±h (h = 1e-6) in each of its nine
//! entries (18 n points, one call) and the tangent is the central difference of
//! P = J σ F⁻ᵀ, as for a plugin without a tangent.

use numpy::{IntoPyArray, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use nalgebra::{Matrix3, Vector3};

use musclefem_materials::material::TANGENT_PERTURBATION;
use musclefem_materials::tensor::first_piola_from_cauchy;
use musclefem_materials::{
    Material, MaterialError, PointBlock, PointResponse, StateVariable, VoigtStress,
};

/// A material defined in Python with its parameter values.
#[derive(Debug)]
pub(crate) struct PythonMaterial {
    pub name: String,
    pub update: Py<PyAny>,
    /// (name, value) of every parameter, in declared order.
    pub parameters: Vec<(String, f64)>,
    pub states: Vec<StateVariable>,
}

/// One call's points: F, F_old, fiber and state, point after point.
struct Points<'a> {
    f_new: Vec<Matrix3<f64>>,
    block: &'a PointBlock<'a>,
    /// The block's point each evaluated point belongs to.
    of: Vec<usize>,
}

impl Material for PythonMaterial {
    fn name(&self) -> &str {
        &self.name
    }

    fn state_variables(&self) -> &[StateVariable] {
        &self.states
    }

    /// The tangent comes from the batched central differences of `compute`.
    fn provides_tangent(&self) -> bool {
        true
    }

    fn compute(
        &self,
        block: &PointBlock,
        response: &mut PointResponse,
    ) -> Result<(), MaterialError> {
        let n = block.len();
        if n == 0 {
            return Ok(());
        }
        let mut points = Points {
            f_new: block.deformation_gradient_new.to_vec(),
            block,
            of: (0..n).collect(),
        };
        let wants_tangent = response.tangent.is_some();
        let h = TANGENT_PERTURBATION;
        if wants_tangent {
            for p in 0..n {
                for entry in 0..9 {
                    for sign in [1.0, -1.0] {
                        let mut f = block.deformation_gradient_new[p];
                        f[entry] += sign * h;
                        points.f_new.push(f);
                        points.of.push(p);
                    }
                }
            }
        }
        let (stress, state) = self.call(&points).map_err(|message| MaterialError::Host {
            material: self.name.clone(),
            message,
        })?;
        response.cauchy_stress.copy_from_slice(&stress[..n]);
        let k = self.states.len();
        response.state_new.copy_from_slice(&state[..n * k]);
        if let Some(tangent) = response.tangent.as_deref_mut() {
            for (p, tangent) in tangent.iter_mut().enumerate() {
                for entry in 0..9 {
                    let at = n + 18 * p + 2 * entry;
                    let plus = first_piola_from_cauchy(&points.f_new[at], &stress[at]);
                    let minus = first_piola_from_cauchy(&points.f_new[at + 1], &stress[at + 1]);
                    let dp = (plus - minus) / (2.0 * h);
                    for row in 0..9 {
                        tangent[(row, entry)] = dp[row];
                    }
                }
            }
        }
        Ok(())
    }
}

impl PythonMaterial {
    /// The stresses (Voigt) and new states of `points`, or what went wrong.
    fn call(&self, points: &Points<'_>) -> Result<(Vec<VoigtStress>, Vec<f64>), String> {
        Python::attach(|py| {
            self.call_with(py, points).map_err(|error| {
                let function = self
                    .update
                    .bind(py)
                    .getattr("__qualname__")
                    .map_or_else(|_| "update".to_string(), |n| n.to_string());
                format!(
                    "its Python function {function} failed: {}",
                    describe(py, &error)
                )
            })
        })
    }

    fn call_with(
        &self,
        py: Python<'_>,
        points: &Points<'_>,
    ) -> PyResult<(Vec<VoigtStress>, Vec<f64>)> {
        let m = points.of.len();
        let k = self.states.len();
        let block = points.block;
        let tensors = |fs: &mut dyn Iterator<Item = Matrix3<f64>>| -> Vec<f64> {
            fs.flat_map(|f| (0..3).flat_map(move |i| (0..3).map(move |j| f[(i, j)])))
                .collect()
        };
        let f_new = tensors(&mut points.f_new.iter().copied());
        let f_old = tensors(&mut points.of.iter().map(|&p| block.deformation_gradient_old[p]));
        let fiber: Vec<f64> = points
            .of
            .iter()
            .flat_map(|&p| {
                let a: Vector3<f64> = block.fiber_direction[p];
                [a.x, a.y, a.z]
            })
            .collect();
        let state: Vec<f64> = points
            .of
            .iter()
            .flat_map(|&p| block.state_old[p * k..(p + 1) * k].iter().copied())
            .collect();
        let kwargs = PyDict::new(py);
        kwargs.set_item("F", f_new.into_pyarray(py).reshape([m, 3, 3])?)?;
        kwargs.set_item("F_old", f_old.into_pyarray(py).reshape([m, 3, 3])?)?;
        kwargs.set_item("fiber", fiber.into_pyarray(py).reshape([m, 3])?)?;
        kwargs.set_item("state", state.into_pyarray(py).reshape([m, k])?)?;
        kwargs.set_item("dt", block.dt)?;
        kwargs.set_item("time", block.time)?;
        let params = PyDict::new(py);
        for (name, value) in &self.parameters {
            params.set_item(name, value)?;
        }
        kwargs.set_item("params", params)?;
        let returned = self.update.bind(py).call((), Some(&kwargs))?;
        let (stress, state) = match returned.cast::<PyTuple>() {
            Ok(pair) if pair.len() == 2 => (pair.get_item(0)?, Some(pair.get_item(1)?)),
            _ => (returned, None),
        };
        let stress = float_array(py, &stress, &[m, 3, 3], "the stress")?;
        let voigt = stress
            .chunks_exact(9)
            .map(|s| {
                let at = |i: usize, j: usize| 0.5 * (s[3 * i + j] + s[3 * j + i]);
                VoigtStress::new(at(0, 0), at(1, 1), at(2, 2), at(1, 2), at(0, 2), at(0, 1))
            })
            .collect();
        let state = match (state, k) {
            (None, 0) => Vec::new(),
            (None, _) => {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "it returned no state: return (stress, state) with state of shape ({m}, {k})"
                )));
            }
            (Some(state), _) => float_array(py, &state, &[m, k], "the state")?,
        };
        Ok((voigt, state))
    }
}

/// `value` as float64 numbers of `shape` (a NumPy array or anything `numpy.asarray`
/// takes), row-major.
fn float_array(
    py: Python<'_>,
    value: &Bound<'_, PyAny>,
    shape: &[usize],
    what: &str,
) -> PyResult<Vec<f64>> {
    let numpy = py.import("numpy")?;
    let array = numpy.call_method1("asarray", (value, "float64"))?;
    let array = array.cast_into::<numpy::PyArrayDyn<f64>>()?;
    if array.shape() != shape {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "{what} has shape {:?}, expected {shape:?}",
            array.shape()
        )));
    }
    // In logical (row-major) order, whatever the array's memory layout.
    Ok(array.readonly().as_array().iter().copied().collect())
}

/// "ValueError: message" of a Python exception.
fn describe(py: Python<'_>, error: &PyErr) -> String {
    let kind = error
        .get_type(py)
        .name()
        .map_or_else(|_| "exception".to_string(), |n| n.to_string());
    format!("{kind}: {}", error.value(py))
}
