//! Tables as Python sees them: a dict of NumPy arrays, one per column.

use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// `{name: array}` for every column `names[k]` of `rows` (rows of equal length).
pub(crate) fn column_dict<'py>(
    py: Python<'py>,
    names: &[String],
    rows: &[Vec<f64>],
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (k, name) in names.iter().enumerate() {
        let column: Vec<f64> = rows.iter().map(|row| row[k]).collect();
        dict.set_item(name, column.into_pyarray(py))?;
    }
    Ok(dict)
}
