//! A run's frames kept in memory (those `musclefem run` writes as VTU files), as Python
//! sees them and as they are written out again.
//!
//! A frame's dict holds the arrays of its VTU file, named as there: `displacement`
//! (N, 3) [m] and the interactions' per-node fields, one row per node in node-id order;
//! `cauchy_stress` (E, 6) [Pa] in VTK's order XX, YY, ZZ, XY, YZ, XZ, `von_mises` (E,)
//! [Pa], `fiber_direction_current` (E, 3), `fiber_stretch` (E,) [1], `activation` and
//! `state_NAME` (E,), one row per element in block order (the VTU cell order); and
//! `time_s` [s]. What does not change from frame to frame (reference positions, blocks,
//! reference fibers) is in `Result.mesh`.

use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use nalgebra::Vector3;

use musclefem_core::mesh::Mesh;
use musclefem_core::solver::{NodalField, Snapshot, SolverError};
use musclefem_io::OutputError;
use musclefem_io::output::{
    ElementFieldArrays, FieldValues, Frame, RunDirectory, state_frame, voigt_to_vtk_symmetric,
    von_mises,
};

/// One frame of a run: the state a VTU file is written from.
#[derive(Debug, Clone)]
pub(crate) struct CapturedFrame {
    /// Time [s].
    pub time: f64,
    /// Displacement of every node [m].
    pub displacement: Vec<Vector3<f64>>,
    pub fields: ElementFieldArrays,
    pub nodal: Vec<NodalField>,
}

impl CapturedFrame {
    /// The frame of `snapshot` (its element fields evaluated now).
    pub fn capture(mesh: &Mesh, snapshot: &Snapshot) -> Result<Self, SolverError> {
        let parts = snapshot.element_fields()?;
        Ok(CapturedFrame {
            time: snapshot.time,
            displacement: snapshot.displacement.to_vec(),
            fields: ElementFieldArrays::gather(mesh, &parts),
            nodal: snapshot.nodal_fields(),
        })
    }

    /// The frame as the VTU writer sees it.
    pub fn frame<'a>(&'a self, mesh: &'a Mesh) -> Frame<'a> {
        state_frame(
            mesh,
            self.time,
            &self.displacement,
            &self.fields,
            &self.nodal,
        )
    }

    /// The frame's dict (see the module documentation).
    pub fn to_dict<'py>(&self, py: Python<'py>, mesh: &Mesh) -> PyResult<Bound<'py, PyDict>> {
        let frame = self.frame(mesh);
        let dict = PyDict::new(py);
        dict.set_item("time_s", frame.time)?;
        dict.set_item("displacement", rows(py, flatten3(frame.displacement), 3)?)?;
        if let Some(direction) = frame.current_fiber_direction {
            dict.set_item("fiber_direction_current", rows(py, flatten3(direction), 3)?)?;
        }
        if let Some(stress) = frame.cauchy_stress {
            let tensor: Vec<f64> = stress.iter().flat_map(voigt_to_vtk_symmetric).collect();
            dict.set_item("cauchy_stress", rows(py, tensor, 6)?)?;
            let mises: Vec<f64> = stress.iter().map(von_mises).collect();
            dict.set_item("von_mises", mises.into_pyarray(py))?;
        }
        for fields in [&frame.cell_fields, &frame.point_fields] {
            for field in fields {
                let values = field.values.flatten();
                let array = match field.values {
                    FieldValues::Scalar(_) => values.into_pyarray(py).into_any(),
                    _ => rows(py, values, field.values.components())?.into_any(),
                };
                dict.set_item(&field.name, array)?;
            }
        }
        Ok(dict)
    }
}

/// `values` as an array of rows of `width`.
fn rows<'py>(
    py: Python<'py>,
    values: Vec<f64>,
    width: usize,
) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
    let count = values.len() / width;
    values.into_pyarray(py).reshape([count, width])
}

fn flatten3(v: &[Vector3<f64>]) -> Vec<f64> {
    v.iter().flat_map(|x| [x.x, x.y, x.z]).collect()
}

/// The frames as a list of dicts.
pub(crate) fn frame_list<'py>(
    py: Python<'py>,
    frames: &[CapturedFrame],
    mesh: &Mesh,
) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for frame in frames {
        list.append(frame.to_dict(py, mesh)?)?;
    }
    Ok(list)
}

/// What does not change from frame to frame: `points` (N, 3) reference node positions
/// [m], `block` (E,) and `element_in_block` (E,) of every element (VTU cell order),
/// `fiber_direction_reference` (E, 3), and `blocks`, the blocks' names.
pub(crate) fn mesh_dict<'py>(py: Python<'py>, mesh: &Mesh) -> PyResult<Bound<'py, PyDict>> {
    let nodes = &mesh.nodes;
    let points: Vec<f64> = (0..nodes.len())
        .flat_map(|i| [nodes.x[i], nodes.y[i], nodes.z[i]])
        .collect();
    let mut block = Vec::new();
    let mut element_in_block = Vec::new();
    let mut fibers = Vec::new();
    for (b, items) in mesh.blocks.iter().enumerate() {
        for e in 0..items.len() {
            block.push(b as i64);
            element_in_block.push(e as i64);
        }
        fibers.extend(flatten3(&items.fiber_direction));
    }
    let dict = PyDict::new(py);
    dict.set_item("points", rows(py, points, 3)?)?;
    dict.set_item("block", block.into_pyarray(py))?;
    dict.set_item("element_in_block", element_in_block.into_pyarray(py))?;
    dict.set_item("fiber_direction_reference", rows(py, fibers, 3)?)?;
    let names: Vec<&str> = mesh.blocks.iter().map(|b| b.name.as_str()).collect();
    dict.set_item("blocks", names)?;
    Ok(dict)
}

/// Write `frames` into `directory` as `musclefem run` writes them: `frames/frame_NNNNN.vtu`
/// each and `result.pvd` listing them.
pub(crate) fn write_frames(
    directory: &mut RunDirectory,
    frames: &[CapturedFrame],
    mesh: &Mesh,
) -> Result<(), OutputError> {
    for frame in frames {
        directory.write_frame(&frame.frame(mesh))?;
    }
    Ok(())
}
