//! `musclefem.fibers`: fiber directions of a muscle mesh from the flow solver
//! (`musclefem fibers`, seed §2.3): origin = inlet, insertion = outlet, walls
//! impermeable.

use std::path::PathBuf;

use anyhow::Context;
use nalgebra::Vector3;
use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use musclefem_fibers::{FlowBoundary, FlowSettings, compute_fibers};
use musclefem_io::mesh_import::read_mesh;

use crate::python_error;

/// The fiber direction of every element of the mesh `mesh` (Abaqus .inp or Gmsh .msh 2.2/4.1,
/// metres) from a potential flow entering at the surfaces or node sets `inlet` (the
/// origin, potential 1) and leaving at `outlet` (the insertion, potential 0), solved to
/// the relative residual `tolerance`. Returns a dict: `element` (labels as in the file),
/// `centroid` [m] and `direction` (unit vectors) as (N, 3) arrays, `potential` [1] per
/// element, and the flow's `inlet_flux` and `outlet_flux` [m] and `iterations`.
#[pyfunction]
#[pyo3(signature = (mesh, inlet, outlet, tolerance = 1e-10))]
pub fn fibers<'py>(
    py: Python<'py>,
    mesh: PathBuf,
    inlet: Vec<String>,
    outlet: Vec<String>,
    tolerance: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let solved = py
        .detach(|| -> anyhow::Result<_> {
            let imported = read_mesh(&mesh)?;
            let mut grid = imported.mesh;
            let boundary = FlowBoundary::from_names(&grid, &inlet, &outlet)
                .with_context(|| format!("the inlet and outlet of {}", mesh.display()))?;
            let settings = FlowSettings {
                tolerance,
                ..FlowSettings::default()
            };
            let field = compute_fibers(&grid, &boundary, &settings)
                .with_context(|| format!("the flow through {}", mesh.display()))?;
            field.assign_to(&mut grid)?;
            let mut labels: Vec<i64> = Vec::new();
            let mut centroids: Vec<f64> = Vec::new();
            let mut directions: Vec<f64> = Vec::new();
            for (b, block) in grid.blocks.iter().enumerate() {
                let corners = block.shape.corner_count();
                for (e, nodes) in block.elements().enumerate() {
                    let centroid = nodes[..corners]
                        .iter()
                        .map(|&n| grid.nodes.position(n as usize))
                        .sum::<Vector3<f64>>()
                        / corners as f64;
                    labels.push(imported.element_labels[b][e]);
                    centroids.extend(centroid.iter());
                    directions.extend(block.fiber_direction[e].iter());
                }
            }
            Ok((labels, centroids, directions, field))
        })
        .map_err(python_error)?;
    let (labels, centroids, directions, field) = solved;
    let count = labels.len();
    let dict = PyDict::new(py);
    dict.set_item("element", labels.into_pyarray(py))?;
    dict.set_item("centroid", centroids.into_pyarray(py).reshape([count, 3])?)?;
    dict.set_item(
        "direction",
        directions.into_pyarray(py).reshape([count, 3])?,
    )?;
    dict.set_item("potential", field.potential.clone().into_pyarray(py))?;
    dict.set_item("inlet_flux", field.inlet_flux)?;
    dict.set_item("outlet_flux", field.outlet_flux)?;
    dict.set_item("iterations", field.linear_iterations)?;
    Ok(dict)
}
