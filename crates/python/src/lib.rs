//! musclefem from Python: `import musclefem`.
//!
//! The extension module `musclefem._musclefem` (re-exported by the package
//! `python/musclefem`): the material library ([`material_point::materials`]) with the
//! materials defined in Python ([`library::register_material`],
//! [`python_material::PythonMaterial`]), a material point in uniaxial stress
//! ([`material_point::MaterialPoint`]), scenes from files or dicts ([`scene::Scene`],
//! [`scene_source`], [`toml_text`]) run into a [`run_result::RunResult`] ([`scene_run`],
//! [`frames`]), the single-muscle elongation tests ([`elongation::elongate`]), fits
//! ([`fit::fit`]), the knee ([`knee::knee`]) and fiber directions from the flow solver
//! ([`fibers::fibers`]). Results come back as NumPy arrays (named with their units as in
//! the CSV files); every error is a `musclefem.MusclefemError` whose message is the
//! command line's (file, line, element, time). Long calls run on a thread of their own
//! ([`background`]) with the GIL released and stop on Ctrl-C (KeyboardInterrupt) with
//! their files consistent; [`progress`] shows them when asked. Built with maturin
//! (`pip install ./crates/python`); see `docs/python.md`.

use pyo3::prelude::*;

mod background;
mod columns;
mod elongation;
mod fibers;
mod fit;
mod frames;
mod knee;
mod library;
mod material_point;
mod progress;
mod python_material;
mod run_result;
mod scene;
mod scene_run;
mod scene_source;
mod toml_text;

pyo3::create_exception!(
    musclefem,
    MusclefemError,
    pyo3::exceptions::PyException,
    "A musclefem error: the message names the file, line, key, element or time where it can."
);

/// An error of the library as a `MusclefemError` with its whole chain ("context: cause").
pub(crate) fn python_error(error: anyhow::Error) -> PyErr {
    MusclefemError::new_err(format!("{error:#}"))
}

#[pymodule]
#[pyo3(name = "_musclefem")]
fn musclefem_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("MusclefemError", m.py().get_type::<MusclefemError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(material_point::materials, m)?)?;
    m.add_class::<material_point::MaterialPoint>()?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<run_result::RunResult>()?;
    m.add_function(wrap_pyfunction!(elongation::elongate, m)?)?;
    m.add_function(wrap_pyfunction!(fibers::fibers, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit, m)?)?;
    m.add_function(wrap_pyfunction!(knee::knee, m)?)?;
    m.add_function(wrap_pyfunction!(library::register_material, m)?)?;
    Ok(())
}
