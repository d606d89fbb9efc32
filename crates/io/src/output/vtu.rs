//! VTU (VTK XML unstructured grid) files of one [`Frame`], written atomically.
//!
//! The file is encoded by vtkio in memory (XML, `version="1.0"`, little endian, every
//! array base64-encoded inline with a UInt64 size header, uncompressed, all floats as
//! Float64 so nothing is rounded), then staged and renamed onto its target
//! ([`PendingFile`]): a reader never sees a half-written frame.
//!
//! # Geometry
//! Points are the **reference** node positions [m], in node-id order; the point array
//! `displacement` [m] gives the current configuration through ParaView's *Warp By
//! Vector* (scale 1). Cells are the elements in block order.
//!
//! # Cell types and node orders
//! | mesh shape | VTK cell type            | node order                                   |
//! |------------|--------------------------|----------------------------------------------|
//! | hex8       | 12 `VTK_HEXAHEDRON`      | Abaqus C3D8 order unchanged: 0–3 the bottom face, counter-clockwise seen from the top face 4–7 |
//! | tet4       | 10 `VTK_TETRA`           | Abaqus C3D4 order unchanged: (0,1,2) counter-clockwise seen from 3 |
//! | tet10      | 24 `VTK_QUADRATIC_TETRA` | Abaqus C3D10 order unchanged: mid-edge nodes 4–9 on edges (0,1), (1,2), (2,0), (0,3), (1,3), (2,3) |
//!
//! VTK documents the same orders (vtkHexahedron: "(0,1,2,3) is the base ... whose normal
//! points in the direction of the opposite face (4,5,6,7)"; vtkTetra: "(0,1,2) ... forms
//! a triangle whose normal points in the direction of the fourth point";
//! vtkQuadraticTetra: mid-edge nodes "between (0,1), (1,2), (2,0), (0,3), (1,3), and
//! (2,3)"), so the connectivity is copied as is. The integration tests check these three
//! rules on the cells read back.
//!
//! # Arrays
//! Point data: `displacement` (3, [m]); `velocity` (3, [m/s]) if given; named point
//! fields.
//!
//! Cell data, in this order:
//! - `block_id` (Int32): index of the element's block in `mesh.blocks`;
//! - `element_in_block` (Int32): index of the element in its block;
//! - `set_<name>` (UInt8, 0 or 1): one per element set, 1 for its members;
//! - `fiber_direction_reference` (3): the mesh's fiber direction, reference
//!   configuration, as stored (unit by convention);
//! - `fiber_direction_current` (3) if given: the direction in the current configuration;
//! - `cauchy_stress` (6, [Pa]) if given, in VTK's symmetric-tensor order
//!   **XX, YY, ZZ, XY, YZ, XZ** (converted from the solvers' Voigt xx, yy, zz, yz, xz, xy);
//! - `von_mises` (1, [Pa]) if the stress is given: √(3/2 s:s);
//! - the named cell fields, in the frame's order.
//!
//! The active point vectors are `displacement` (ready for Warp By Vector) and the active
//! cell scalars `von_mises` (when the stress is given).

use std::path::Path;

use musclefem_core::mesh::ElementShape;
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType, IOBuffer,
    UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};

use super::frame::{Field, Frame, voigt_to_vtk_symmetric, von_mises};
use crate::OutputError;
use crate::atomic::PendingFile;

/// The VTK cell type of a mesh shape (the node order is the same: see the module
/// documentation).
pub fn vtk_cell_type(shape: ElementShape) -> CellType {
    match shape {
        ElementShape::Hex8 => CellType::Hexahedron,
        ElementShape::Tet4 => CellType::Tetra,
        ElementShape::Tet10 => CellType::QuadraticTetra,
    }
}

/// Write `frame` to `path` (a `.vtu` file) atomically.
pub fn write_vtu(path: &Path, frame: &Frame<'_>) -> Result<(), OutputError> {
    stage_vtu(path, frame)?.commit()
}

/// Encode `frame` and stage it for `path` (commit it with [`PendingFile::commit`]).
pub fn stage_vtu(path: &Path, frame: &Frame<'_>) -> Result<PendingFile, OutputError> {
    let bytes = encode_vtu(path, frame)?;
    PendingFile::stage_bytes(path, &bytes)
}

/// The VTU file of `frame` as bytes; `path` only names the file in errors.
pub fn encode_vtu(path: &Path, frame: &Frame<'_>) -> Result<Vec<u8>, OutputError> {
    frame.check(path)?;
    let vtk = Vtk {
        version: Version::new((1, 0)),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        data: DataSet::inline(unstructured_grid(frame)),
        file_path: None,
    };
    let mut bytes = Vec::new();
    vtk.write_xml(&mut bytes).map_err(|e| OutputError::Vtk {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    Ok(bytes)
}

/// The grid of a checked frame.
fn unstructured_grid(frame: &Frame<'_>) -> UnstructuredGridPiece {
    let mesh = frame.mesh;
    let nodes = &mesh.nodes;
    let points: Vec<f64> = (0..nodes.len())
        .flat_map(|i| [nodes.x[i], nodes.y[i], nodes.z[i]])
        .collect();
    let elements = mesh.element_count();
    let mut connectivity =
        Vec::with_capacity(mesh.blocks.iter().map(|b| b.connectivity.len()).sum());
    let mut offsets = Vec::with_capacity(elements);
    let mut types = Vec::with_capacity(elements);
    let mut block_id = Vec::with_capacity(elements);
    let mut element_in_block = Vec::with_capacity(elements);
    let mut fibers = Vec::with_capacity(3 * elements);
    for (b, block) in mesh.blocks.iter().enumerate() {
        let cell_type = vtk_cell_type(block.shape);
        for (e, ids) in block.elements().enumerate() {
            connectivity.extend(ids.iter().map(|&id| u64::from(id)));
            offsets.push(connectivity.len() as u64);
            types.push(cell_type);
            block_id.push(b as i32);
            element_in_block.push(e as i32);
        }
        fibers.extend(block.fiber_direction.iter().flat_map(|f| [f.x, f.y, f.z]));
    }

    let mut point = vec![vector("displacement", flatten3(frame.displacement))];
    if let Some(v) = frame.velocity {
        point.push(array("velocity", 3, IOBuffer::F64(flatten3(v))));
    }
    point.extend(frame.point_fields.iter().map(named));

    let mut cell = vec![
        array("block_id", 1, IOBuffer::I32(block_id)),
        array("element_in_block", 1, IOBuffer::I32(element_in_block)),
    ];
    // Running offset of each block's first element among all cells.
    let mut first = Vec::with_capacity(mesh.blocks.len());
    let mut start = 0;
    for block in &mesh.blocks {
        first.push(start);
        start += block.len();
    }
    for (name, set) in &mesh.element_sets {
        let mut flags = vec![0u8; elements];
        for e in set {
            flags[first[e.block as usize] + e.element as usize] = 1;
        }
        cell.push(array(&format!("set_{name}"), 1, IOBuffer::U8(flags)));
    }
    cell.push(array("fiber_direction_reference", 3, IOBuffer::F64(fibers)));
    if let Some(f) = frame.current_fiber_direction {
        cell.push(array(
            "fiber_direction_current",
            3,
            IOBuffer::F64(flatten3(f)),
        ));
    }
    if let Some(stress) = frame.cauchy_stress {
        let tensor: Vec<f64> = stress.iter().flat_map(voigt_to_vtk_symmetric).collect();
        cell.push(array("cauchy_stress", 6, IOBuffer::F64(tensor)));
        let mises: Vec<f64> = stress.iter().map(von_mises).collect();
        cell.push(array("von_mises", 1, IOBuffer::F64(mises)));
    }
    cell.extend(frame.cell_fields.iter().map(named));

    UnstructuredGridPiece {
        points: IOBuffer::F64(points),
        cells: Cells {
            cell_verts: VertexNumbers::XML {
                connectivity,
                offsets,
            },
            types,
        },
        data: Attributes { point, cell },
    }
}

fn flatten3(v: &[nalgebra::Vector3<f64>]) -> Vec<f64> {
    v.iter().flat_map(|x| [x.x, x.y, x.z]).collect()
}

/// A data array of `components` numbers per item. Only `von_mises` is marked as the
/// active scalars and `displacement` as the active vectors (`vector`), so ParaView colours
/// by them first.
fn array(name: &str, components: u32, data: IOBuffer) -> Attribute {
    let elem = if name == "von_mises" {
        ElementType::Scalars {
            num_comp: 1,
            lookup_table: None,
        }
    } else {
        ElementType::Generic(components)
    };
    Attribute::DataArray(DataArray {
        name: name.to_string(),
        elem,
        data,
    })
}

/// A 3-component vector array.
fn vector(name: &str, values: Vec<f64>) -> Attribute {
    Attribute::DataArray(DataArray {
        name: name.to_string(),
        elem: ElementType::Vectors,
        data: IOBuffer::F64(values),
    })
}

/// The array of a named field.
fn named(field: &Field<'_>) -> Attribute {
    let components = field.values.components() as u32;
    array(
        &field.name,
        components,
        IOBuffer::F64(field.values.flatten()),
    )
}
