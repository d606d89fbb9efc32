//! `musclefem.materials()` and `musclefem.MaterialPoint`: the material library and one
//! material point driven in uniaxial stress along its fiber (`musclefem point`).

use std::collections::BTreeMap;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use musclefem_materials::Bound as Limit;
use musclefem_studies::material_point::run_point;

use crate::columns::column_dict;
use crate::library::material_library;
use crate::{MusclefemError, python_error};

/// The built-in materials: a list of dicts with `name`, `description` and `parameters`
/// (each a dict: `name`, `unit` (SI, "1" for none), `default` (None: required), `lower`,
/// `upper` (None: unbounded), `inclusive` (lower, upper) and `description`).
#[pyfunction]
pub fn materials(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for info in material_library().materials() {
        let parameters = PyList::empty(py);
        for spec in &info.parameters {
            let parameter = PyDict::new(py);
            parameter.set_item("name", spec.name.as_ref())?;
            parameter.set_item("unit", spec.unit.as_ref())?;
            parameter.set_item("default", spec.default)?;
            let (lower, lower_inclusive) = limit(&spec.lower);
            let (upper, upper_inclusive) = limit(&spec.upper);
            parameter.set_item("lower", lower)?;
            parameter.set_item("upper", upper)?;
            parameter.set_item("inclusive", (lower_inclusive, upper_inclusive))?;
            parameter.set_item("description", spec.description.as_ref())?;
            parameters.append(parameter)?;
        }
        let material = PyDict::new(py);
        material.set_item("name", info.name.as_str())?;
        material.set_item("description", info.description.as_str())?;
        material.set_item("parameters", parameters)?;
        list.append(material)?;
    }
    Ok(list)
}

/// A bound as (value, inclusive): (None, false) when unbounded.
fn limit(bound: &Limit) -> (Option<f64>, bool) {
    match *bound {
        Limit::Unbounded => (None, false),
        Limit::Inclusive(x) => (Some(x), true),
        Limit::Exclusive(x) => (Some(x), false),
    }
}

/// A material point of material `name` with parameters `**params` (SI units, defaults
/// for the others; `musclefem.materials()` lists them), e.g.
/// `MaterialPoint("hill", n2=1.0)`. The material is built at once: an unknown name or a
/// parameter out of range raises `MusclefemError`.
#[pyclass(module = "musclefem", frozen)]
pub struct MaterialPoint {
    name: String,
    parameters: BTreeMap<String, f64>,
}

#[pymethods]
impl MaterialPoint {
    #[new]
    #[pyo3(signature = (name, **params))]
    fn new(name: String, params: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let mut parameters = BTreeMap::new();
        if let Some(params) = params {
            for (key, value) in params.iter() {
                parameters.insert(key.extract::<String>()?, value.extract::<f64>()?);
            }
        }
        material_library()
            .create(&name, &parameters)
            .map_err(|e| MusclefemError::new_err(e.to_string()))?;
        Ok(MaterialPoint { name, parameters })
    }

    /// Drive the point in uniaxial stress along its fiber through the piecewise-linear
    /// stretch history (`times` [s], increasing from 0; `stretches` [1], the first 1) with
    /// step `dt` [s]. Returns a dict of arrays `time_s`, `stretch`,
    /// `engineering_stress_pa` (P₁₁), `cauchy_stress_pa` (σ₁₁) and `volume_ratio` (J).
    /// Refused (MusclefemError) when halving `dt` changes the answer by more than 1 % of
    /// its largest stress.
    #[pyo3(signature = (times, stretches, dt = 1e-3))]
    fn uniaxial<'py>(
        &self,
        py: Python<'py>,
        times: Vec<f64>,
        stretches: Vec<f64>,
        dt: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        if times.len() != stretches.len() {
            return Err(MusclefemError::new_err(format!(
                "{} times and {} stretches: give one stretch per time",
                times.len(),
                stretches.len()
            )));
        }
        let history: Vec<String> = times
            .iter()
            .zip(&stretches)
            .map(|(t, l)| format!("{t}:{l}"))
            .collect();
        let history = history.join(",");
        let (name, parameters) = (&self.name, &self.parameters);
        let run = py
            .detach(|| run_point(&material_library(), name, parameters, &history, dt))
            .map_err(python_error)?;
        let names = [
            "time_s",
            "stretch",
            "engineering_stress_pa",
            "cauchy_stress_pa",
            "volume_ratio",
        ]
        .map(String::from);
        let rows: Vec<Vec<f64>> = run
            .rows
            .iter()
            .map(|r| {
                vec![
                    r.time,
                    r.stretch,
                    r.engineering_stress,
                    r.cauchy_stress,
                    r.jacobian,
                ]
            })
            .collect();
        column_dict(py, &names, &rows)
    }

    fn __repr__(&self) -> String {
        let parameters: Vec<String> = self
            .parameters
            .iter()
            .map(|(k, v)| format!(", {k}={v}"))
            .collect();
        format!("MaterialPoint({:?}{})", self.name, parameters.join(""))
    }
}
