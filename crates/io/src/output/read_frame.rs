//! Reading our own frames back: a part frame (`frames/frame_NNNNN.vtu`, written by
//! [`super::vtu`]) as its mesh, displacements and cell arrays, and a rigid-body frame
//! (`frames/rigid_NNNNN.vtu`, [`super::rigid_frames`]) as its triangles; and finding the
//! frame of a run nearest a time in its `result.pvd` (and `rigid.pvd`).
//!
//! The mesh read back has the frame's reference points and one block per `block_id`
//! (named `block_<id>`, the shape from the cell type), in the order of the cells; block
//! names, sets and fibers are not restored. Errors name the file and what is missing.

use std::path::{Path, PathBuf};

use musclefem_core::mesh::{ElementBlock, ElementShape, Mesh, Nodes};
use nalgebra::Vector3;
use vtkio::model::{Attribute, CellType, DataSet, Piece, UnstructuredGridPiece, VertexNumbers};

use super::pvd::{PvdEntry, read_pvd};
use crate::OutputError;

/// A part frame read back.
#[derive(Debug, Clone)]
pub struct FrameData {
    /// The file read.
    pub path: PathBuf,
    /// The reference mesh (blocks by `block_id`).
    pub mesh: Mesh,
    /// Displacement of each node [m].
    pub displacement: Vec<Vector3<f64>>,
    /// Every cell array with a number type: (name, components, values item-major, in
    /// the order of the cells).
    pub cell_arrays: Vec<(String, usize, Vec<f64>)>,
}

impl FrameData {
    /// The one-component cell array `name` (one value per cell, in block order). Errors
    /// name the file and list the cell arrays of one component it has.
    pub fn cell_scalar(&self, name: &str) -> Result<&[f64], OutputError> {
        match self.cell_arrays.iter().find(|(n, _, _)| n == name) {
            Some((_, 1, values)) => Ok(values),
            Some((_, components, _)) => Err(self.missing(format!(
                "the cell array '{name}' has {components} components, not one"
            ))),
            None => {
                let scalars: Vec<&str> = self
                    .cell_arrays
                    .iter()
                    .filter(|(_, c, _)| *c == 1)
                    .map(|(n, _, _)| n.as_str())
                    .collect();
                Err(self.missing(format!(
                    "no cell array '{name}'; its cell arrays of one component: {}",
                    scalars.join(", ")
                )))
            }
        }
    }

    fn missing(&self, message: String) -> OutputError {
        OutputError::Read {
            path: self.path.clone(),
            message,
        }
    }
}

/// The rigid bodies of a rigid-body frame, at their pose in it.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidFrameData {
    /// Vertices at the bodies' current pose [m], body after body.
    pub vertices: Vec<Vector3<f64>>,
    /// Triangles by vertex index.
    pub triangles: Vec<[u32; 3]>,
}

/// The frame of a run to show at a time: the part frame listed in `result.pvd` nearest
/// the time, and the rigid-body frame of the same time in `rigid.pvd` if the run has one.
#[derive(Debug, Clone, PartialEq)]
pub struct RunFrame {
    /// Time of the frame [s].
    pub time: f64,
    pub frame: PathBuf,
    pub rigid: Option<PathBuf>,
}

/// Read the part frame `path`.
pub fn read_frame(path: &Path) -> Result<FrameData, OutputError> {
    let bad = |message: String| OutputError::Read {
        path: path.to_path_buf(),
        message,
    };
    let piece = read_piece(path)?;
    let points = point_coordinates(path, &piece)?;
    let node_count = points.len();
    let displacement = piece
        .data
        .point
        .iter()
        .find(|a| a.name() == "displacement")
        .ok_or_else(|| bad("no point array 'displacement'".to_string()))
        .and_then(|a| numbers(path, a))?;
    if displacement.1 != 3 || displacement.2.len() != 3 * node_count {
        return Err(bad(format!(
            "the point array 'displacement' has {} numbers in {} components for {node_count} points",
            displacement.2.len(),
            displacement.1
        )));
    }
    let cell_arrays: Vec<(String, usize, Vec<f64>)> = piece
        .data
        .cell
        .iter()
        .filter_map(|a| numbers(path, a).ok())
        .collect();
    let block_id = match cell_arrays.iter().find(|(n, _, _)| n == "block_id") {
        Some((_, 1, ids)) => ids.clone(),
        _ => return Err(bad("no cell array 'block_id' of one component".to_string())),
    };
    let mesh = mesh_of_cells(path, &piece, points, &block_id)?;
    let cells = mesh.element_count();
    if let Some((name, components, values)) =
        cell_arrays.iter().find(|(_, c, v)| v.len() != c * cells)
    {
        return Err(bad(format!(
            "the cell array '{name}' has {} numbers for {cells} cells of {components} components",
            values.len()
        )));
    }
    Ok(FrameData {
        path: path.to_path_buf(),
        mesh,
        displacement: displacement
            .2
            .chunks_exact(3)
            .map(|u| Vector3::new(u[0], u[1], u[2]))
            .collect(),
        cell_arrays,
    })
}

/// Read the rigid-body frame `path`: its points and triangles.
pub fn read_rigid_frame(path: &Path) -> Result<RigidFrameData, OutputError> {
    let bad = |message: String| OutputError::Read {
        path: path.to_path_buf(),
        message,
    };
    let piece = read_piece(path)?;
    let vertices = point_coordinates(path, &piece)?;
    let (connectivity, offsets) = cell_vertices(path, &piece)?;
    let mut triangles = Vec::with_capacity(offsets.len());
    let mut start = 0;
    for (c, (&end, kind)) in offsets.iter().zip(&piece.cells.types).enumerate() {
        let ids = &connectivity[start..end as usize];
        start = end as usize;
        if *kind != CellType::Triangle || ids.len() != 3 {
            return Err(bad(format!(
                "cell {c} is a {kind:?} of {} points, not a triangle",
                ids.len()
            )));
        }
        if let Some(&v) = ids.iter().find(|&&v| v as usize >= vertices.len()) {
            return Err(bad(format!(
                "triangle {c} refers to point {v} of {}",
                vertices.len()
            )));
        }
        triangles.push([ids[0] as u32, ids[1] as u32, ids[2] as u32]);
    }
    Ok(RigidFrameData {
        vertices,
        triangles,
    })
}

/// The frame of the run in `run_dir` nearest `time` [s] (the earlier of two equally
/// near): from `result.pvd`, with the rigid-body frame of the same time from `rigid.pvd`
/// when that file exists. Errors name the file that lists no frame or not that time.
pub fn run_frame_at(run_dir: &Path, time: f64) -> Result<RunFrame, OutputError> {
    let result = run_dir.join("result.pvd");
    let entries = read_pvd(&result)?;
    let nearest = nearest_entry(&entries, time).ok_or_else(|| OutputError::Read {
        path: result.clone(),
        message: "it lists no frame".to_string(),
    })?;
    let rigid_index = run_dir.join("rigid.pvd");
    let rigid = if rigid_index.exists() {
        let rigid_entries = read_pvd(&rigid_index)?;
        let same = rigid_entries
            .iter()
            .find(|e| e.time == nearest.time)
            .ok_or_else(|| OutputError::Read {
                path: rigid_index.clone(),
                message: format!(
                    "no rigid frame at t = {} s, the time of {}",
                    nearest.time, nearest.file
                ),
            })?;
        Some(run_dir.join(&same.file))
    } else {
        None
    };
    Ok(RunFrame {
        time: nearest.time,
        frame: run_dir.join(&nearest.file),
        rigid,
    })
}

/// The time of the part frame `frame` [s] if the `result.pvd` of its run (two folders
/// up: `RUN/frames/frame_NNNNN.vtu`) lists it; `None` otherwise.
pub fn frame_time(frame: &Path) -> Option<f64> {
    let run_dir = frame.parent()?.parent()?;
    let entries = read_pvd(&run_dir.join("result.pvd")).ok()?;
    let wanted = frame.canonicalize().ok()?;
    entries
        .iter()
        .find(|e| run_dir.join(&e.file).canonicalize().ok().as_ref() == Some(&wanted))
        .map(|e| e.time)
}

/// The entry whose time is nearest `time` (the first of equally near ones).
pub fn nearest_entry(entries: &[PvdEntry], time: f64) -> Option<&PvdEntry> {
    entries
        .iter()
        .min_by(|a, b| (a.time - time).abs().total_cmp(&(b.time - time).abs()))
}

/// The one inline unstructured-grid piece of the VTU file `path`.
fn read_piece(path: &Path) -> Result<UnstructuredGridPiece, OutputError> {
    let bad = |message: String| OutputError::Read {
        path: path.to_path_buf(),
        message,
    };
    let vtk = vtkio::Vtk::import(path).map_err(|e| OutputError::Vtk {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let DataSet::UnstructuredGrid { mut pieces, .. } = vtk.data else {
        return Err(bad("not an unstructured grid (.vtu)".to_string()));
    };
    if pieces.len() != 1 {
        return Err(bad(format!("{} pieces, not one", pieces.len())));
    }
    match pieces.remove(0) {
        Piece::Inline(piece) => Ok(*piece),
        _ => Err(bad("the piece is not inline".to_string())),
    }
}

/// The points of `piece` [m].
fn point_coordinates(
    path: &Path,
    piece: &UnstructuredGridPiece,
) -> Result<Vec<Vector3<f64>>, OutputError> {
    let coordinates = piece
        .points
        .clone()
        .cast_into::<f64>()
        .ok_or_else(|| OutputError::Read {
            path: path.to_path_buf(),
            message: "the points are not numbers".to_string(),
        })?;
    if coordinates.len() % 3 != 0 {
        return Err(OutputError::Read {
            path: path.to_path_buf(),
            message: format!(
                "{} point coordinates, not a multiple of 3",
                coordinates.len()
            ),
        });
    }
    Ok(coordinates
        .chunks_exact(3)
        .map(|x| Vector3::new(x[0], x[1], x[2]))
        .collect())
}

/// (connectivity, offsets) of the cells of `piece`.
fn cell_vertices(
    path: &Path,
    piece: &UnstructuredGridPiece,
) -> Result<(Vec<u64>, Vec<u64>), OutputError> {
    match &piece.cells.cell_verts {
        VertexNumbers::XML {
            connectivity,
            offsets,
        } if offsets.len() == piece.cells.types.len()
            && offsets.windows(2).all(|w| w[0] <= w[1])
            && offsets
                .last()
                .is_none_or(|&l| l as usize <= connectivity.len()) =>
        {
            Ok((connectivity.clone(), offsets.clone()))
        }
        _ => Err(OutputError::Read {
            path: path.to_path_buf(),
            message: "the cells' connectivity and offsets do not match their types".to_string(),
        }),
    }
}

/// A number array's (name, components, values); an error for one of another type.
fn numbers(path: &Path, attribute: &Attribute) -> Result<(String, usize, Vec<f64>), OutputError> {
    match attribute {
        Attribute::DataArray(array) => {
            let values =
                array
                    .data
                    .clone()
                    .cast_into::<f64>()
                    .ok_or_else(|| OutputError::Read {
                        path: path.to_path_buf(),
                        message: format!("the array '{}' does not hold numbers", array.name),
                    })?;
            Ok((array.name.clone(), array.num_comp(), values))
        }
        Attribute::Field { name, .. } => Err(OutputError::Read {
            path: path.to_path_buf(),
            message: format!("'{name}' is a field, not an array"),
        }),
    }
}

/// The mesh of `piece`'s cells: a block per `block_id`, which must not decrease from cell
/// to cell nor change shape within a block.
fn mesh_of_cells(
    path: &Path,
    piece: &UnstructuredGridPiece,
    points: Vec<Vector3<f64>>,
    block_id: &[f64],
) -> Result<Mesh, OutputError> {
    let bad = |message: String| OutputError::Read {
        path: path.to_path_buf(),
        message,
    };
    let (connectivity, offsets) = cell_vertices(path, piece)?;
    if block_id.len() != offsets.len() {
        return Err(bad(format!(
            "{} block ids for {} cells",
            block_id.len(),
            offsets.len()
        )));
    }
    let mut nodes = Nodes::with_capacity(points.len());
    for x in &points {
        nodes.push(*x);
    }
    let mut blocks: Vec<ElementBlock> = Vec::new();
    let mut start = 0;
    for (c, ((&end, kind), &id)) in offsets
        .iter()
        .zip(&piece.cells.types)
        .zip(block_id)
        .enumerate()
    {
        let ids = &connectivity[start..end as usize];
        start = end as usize;
        let shape = match kind {
            CellType::Hexahedron => ElementShape::Hex8,
            CellType::Tetra => ElementShape::Tet4,
            CellType::QuadraticTetra => ElementShape::Tet10,
            other => {
                return Err(bad(format!(
                    "cell {c} is a {other:?}, not a hex8, tet4 or tet10"
                )));
            }
        };
        if ids.len() != shape.nodes_per_element() {
            return Err(bad(format!(
                "cell {c}, a {shape}, has {} points",
                ids.len()
            )));
        }
        if let Some(&v) = ids.iter().find(|&&v| v as usize >= points.len()) {
            return Err(bad(format!(
                "cell {c} refers to point {v} of {}",
                points.len()
            )));
        }
        let id = id as usize;
        if id + 1 < blocks.len() || id > blocks.len() {
            return Err(bad(format!(
                "cell {c} has block_id {id} after block {}: the cells are not in block order",
                blocks.len().saturating_sub(1)
            )));
        }
        if id == blocks.len() {
            blocks.push(ElementBlock {
                name: format!("block_{id}"),
                shape,
                connectivity: Vec::new(),
                fiber_direction: Vec::new(),
            });
        }
        let block = &mut blocks[id];
        if block.shape != shape {
            return Err(bad(format!(
                "cell {c} is a {shape} in block {id} of {}",
                block.shape
            )));
        }
        block.connectivity.extend(ids.iter().map(|&v| v as u32));
        block.fiber_direction.push(Vector3::x());
    }
    Ok(Mesh::new(nodes, blocks))
}
