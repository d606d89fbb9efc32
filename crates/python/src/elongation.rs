//! `musclefem.elongate`: the single-muscle uniaxial elongation test (`musclefem elongate`,
//! seed §2.2), its curve as arrays.

use std::collections::BTreeMap;

use clap::ValueEnum;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use musclefem_studies::elongation::{
    Activation, ElementChoice, ElongationTest, Grips, Shape, Unwatched, run_elongation,
};
use musclefem_studies::solver::Solver;

use crate::columns::column_dict;
use crate::{MusclefemError, python_error};

/// A command-line value (`passive`, `cylinder`, `hex8-fbar`, ...) of `what`.
fn choice<T: ValueEnum>(what: &str, value: &str) -> PyResult<T> {
    T::from_str(value, true).map_err(|_| {
        let names: Vec<String> = T::value_variants()
            .iter()
            .filter_map(|v| v.to_possible_value())
            .map(|v| v.get_name().to_string())
            .collect();
        MusclefemError::new_err(format!(
            "{what} '{value}': expected one of {}",
            names.join(", ")
        ))
    })
}

/// Run the elongation test of `mode` (`passive`, or `active` after a 0.5 s isometric
/// hold) on the `shape` (`fusiform` or `cylinder`) with `grips` (`fixed` or `sliding`),
/// `solver`, `element` and `mesh_size` [mm], the implicit increment or explicit
/// mass-scaling step `time_step` [s] (None: the default), and Hill parameters `**params`
/// overriding Table 1. Returns the curve: arrays `time_s`, `engineering_strain`,
/// `reaction_force_n`, `engineering_stress_pa`, and the stresses at 10 % and 20 % strain
/// (`stress_10pct_pa`, `stress_20pct_pa`, None if not reached).
#[pyfunction]
#[pyo3(signature = (
    mode = "passive",
    shape = "fusiform",
    grips = "fixed",
    solver = "implicit",
    element = "hex8-fbar",
    mesh_size = 4.0,
    time_step = None,
    **params
))]
#[allow(clippy::too_many_arguments)]
pub fn elongate<'py>(
    py: Python<'py>,
    mode: &str,
    shape: &str,
    grips: &str,
    solver: &str,
    element: &str,
    mesh_size: f64,
    time_step: Option<f64>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let mode: Activation = choice("mode", mode)?;
    let mut parameters = BTreeMap::new();
    if let Some(params) = params {
        for (key, value) in params.iter() {
            parameters.insert(key.extract::<String>()?, value.extract::<f64>()?);
        }
    }
    let test = ElongationTest {
        mode,
        solver: choice::<Solver>("solver", solver)?,
        element: choice::<ElementChoice>("element", element)?,
        mesh_size: 1e-3 * mesh_size,
        shape: choice::<Shape>("shape", shape)?,
        grips: choice::<Grips>("grips", grips)?,
        parameters,
        time_step,
        ..ElongationTest::recommended(mode)
    };
    let run = py
        .detach(|| {
            musclefem_studies::elongation::setup::check_time_step(&test)?;
            run_elongation(&test, &mut Unwatched)
        })
        .map_err(python_error)?;
    let names = [
        "time_s",
        "engineering_strain",
        "reaction_force_n",
        "engineering_stress_pa",
    ]
    .map(String::from);
    let rows: Vec<Vec<f64>> = run
        .curve
        .points
        .iter()
        .map(|p| vec![p.time, p.strain, p.force, p.stress])
        .collect();
    let curve = column_dict(py, &names, &rows)?;
    curve.set_item("stress_10pct_pa", run.curve.stress_at_strain(0.10))?;
    curve.set_item("stress_20pct_pa", run.curve.stress_at_strain(0.20))?;
    Ok(curve)
}
