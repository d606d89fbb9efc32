//! The material library every call of the module uses: the built-in materials and those
//! defined in Python with `musclefem.register_material` (kept for the process's life).

use std::borrow::Cow;
use std::sync::{Arc, Mutex};

use pyo3::prelude::*;
use pyo3::types::PyDict;

use musclefem_materials::{
    Bound as Limit, HostedMaterial, MaterialLibrary, ParameterSpec, StateVariable,
};

use crate::MusclefemError;
use crate::python_material::PythonMaterial;

/// The materials registered from Python, in order.
static REGISTERED: Mutex<Vec<HostedMaterial>> = Mutex::new(Vec::new());

/// The library a scene, a material point or `materials()` sees.
pub(crate) fn material_library() -> MaterialLibrary {
    let mut library = MaterialLibrary::with_builtins();
    let registered = REGISTERED.lock().unwrap_or_else(|e| e.into_inner());
    for material in registered.iter() {
        // Names were checked against the built-in ones on registration.
        let _ = library.add_hosted(material.clone());
    }
    library
}

/// Register a material whose update is the Python function `update`, under `name` (the
/// `model` of scene files, the name `MaterialPoint` takes). The slow path, for trying a
/// law out before writing it as a plugin: every block of points is one call holding the
/// GIL (see `docs/python.md`). `update` is called with keyword arguments `F` (n, 3, 3),
/// `F_old` (n, 3, 3), `fiber` (n, 3), `state` (n, k), `dt` [s], `time` [s] and `params`
/// ({name: value}), and returns the **Cauchy** stress (n, 3, 3) [Pa], or (stress, new
/// state (n, k)). `parameters`: {name: default} (None: required) or {name: {"default",
/// "unit", "lower", "upper" (inclusive bounds), "description"}}; `state`: the state
/// variables' names, or {name: initial value} (default 0). Registering a name again
/// replaces the earlier Python material; a built-in name is refused. An exception in
/// `update` stops the run with a `MusclefemError` naming the material.
#[pyfunction]
#[pyo3(signature = (name, update, parameters = None, state = None, description = ""))]
pub fn register_material(
    name: String,
    update: Bound<'_, PyAny>,
    parameters: Option<&Bound<'_, PyDict>>,
    state: Option<&Bound<'_, PyAny>>,
    description: &str,
) -> PyResult<()> {
    if !update.is_callable() {
        return Err(MusclefemError::new_err(format!(
            "register_material('{name}'): update must be a function"
        )));
    }
    if name.trim().is_empty() {
        return Err(MusclefemError::new_err(
            "register_material: the name is empty",
        ));
    }
    let specs = match parameters {
        None => Vec::new(),
        Some(table) => table
            .iter()
            .map(|(key, value)| parameter(&name, key.extract()?, &value))
            .collect::<PyResult<_>>()?,
    };
    let states = state_variables(state)?;
    let update = update.unbind();
    let material_name = name.clone();
    let material = HostedMaterial {
        name: name.clone(),
        description: if description.is_empty() {
            "defined in Python".to_string()
        } else {
            description.to_string()
        },
        parameters: specs,
        host: "Python".into(),
        build: Arc::new(move |values| {
            let parameters = values
                .names()
                .iter()
                .cloned()
                .zip(values.values().iter().copied())
                .collect();
            Ok(Arc::new(PythonMaterial {
                name: material_name.clone(),
                update: Python::attach(|py| update.clone_ref(py)),
                parameters,
                states: states.clone(),
            }))
        }),
    };
    let mut registered = REGISTERED.lock().unwrap_or_else(|e| e.into_inner());
    registered.retain(|m| m.name != name);
    let mut check = MaterialLibrary::with_builtins();
    for other in registered.iter().cloned().chain([material.clone()]) {
        check
            .add_hosted(other)
            .map_err(|e| MusclefemError::new_err(e.to_string()))?;
    }
    registered.push(material);
    Ok(())
}

/// One parameter's declaration from `value`: a default, None, or a dict of its fields.
fn parameter(material: &str, name: String, value: &Bound<'_, PyAny>) -> PyResult<ParameterSpec> {
    let mut spec = ParameterSpec {
        name: Cow::Owned(name.clone()),
        unit: Cow::Borrowed(""),
        default: None,
        lower: Limit::Unbounded,
        upper: Limit::Unbounded,
        allow_infinite: false,
        description: Cow::Borrowed(""),
    };
    match value.cast::<PyDict>() {
        Err(_) => spec.default = value.extract()?,
        Ok(fields) => {
            for (key, field) in fields.iter() {
                let key: String = key.extract()?;
                match key.as_str() {
                    "default" => spec.default = field.extract()?,
                    "unit" => spec.unit = Cow::Owned(field.extract()?),
                    "description" => spec.description = Cow::Owned(field.extract()?),
                    "lower" => spec.lower = Limit::Inclusive(field.extract()?),
                    "upper" => spec.upper = Limit::Inclusive(field.extract()?),
                    other => {
                        return Err(MusclefemError::new_err(format!(
                            "register_material('{material}'): parameter '{name}': unknown \
                             field '{other}' (default, unit, lower, upper, description)"
                        )));
                    }
                }
            }
        }
    }
    if let Some(default) = spec.default
        && !spec.accepts(default)
    {
        return Err(MusclefemError::new_err(format!(
            "register_material('{material}'): parameter '{name}': the default {default} is \
             outside its range {}",
            spec.range_text()
        )));
    }
    Ok(spec)
}

/// The state variables: names (initial value 0) or {name: initial value}.
fn state_variables(state: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<StateVariable>> {
    let Some(state) = state else {
        return Ok(Vec::new());
    };
    let variable = |name: String, initial: f64| StateVariable {
        name,
        unit: String::new(),
        initial,
    };
    if let Ok(table) = state.cast::<PyDict>() {
        return table
            .iter()
            .map(|(k, v)| Ok(variable(k.extract()?, v.extract()?)))
            .collect();
    }
    let names: Vec<String> = state.extract()?;
    Ok(names.into_iter().map(|n| variable(n, 0.0)).collect())
}
