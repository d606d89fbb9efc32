//! The rigid bodies of a run (bones, tools) in its frames: a second time series,
//! `rigid.pvd`, beside the deformable parts' `result.pvd`, so that ParaView animates the
//! bones with the muscles (open both).
//!
//! One VTU file per frame, `frames/rigid_NNNNN.vtu`, numbered as the part frame of the
//! same instant (`frames/frame_NNNNN.vtu`), holds every rigid body of the run:
//!
//! - points: each body's vertices at its **current** pose, x = iso(t) · X [m] (the rigid
//!   motion's isometry, c + R(t)(X − c) + T(t), or the pose a follower sets as the run
//!   goes), body after body, in the order the bodies were given (the scene's
//!   `[[rigid_bodies]]`);
//! - cells: the bodies' triangles (5 `VTK_TRIANGLE`), right-hand normal out of the body;
//! - cell data `body_id` (Int32): the index of the triangle's body;
//! - point data `displacement` [m]: x − X, the vertex's displacement from the body frame.
//!
//! Unlike the part frames (reference points plus a displacement to warp by), the points
//! are already where the bodies are: no *Warp By Vector* is needed.

use std::path::Path;

use musclefem_core::solver::RigidMotion;
use nalgebra::{Point3, Vector3};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType, IOBuffer,
    UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};

use crate::OutputError;

/// One rigid body as the frames show it: its triangles in the body frame (borrowed from
/// the model for the length of the run) and its motion (a copy: a follower's pose is
/// shared, so the copy follows it).
#[derive(Clone, Debug)]
pub struct RigidBodyFrame<'a> {
    /// The body's name (messages).
    pub name: &'a str,
    /// Vertices in the body frame [m] (where they are at a motion's rest pose).
    pub vertices: &'a [Vector3<f64>],
    /// Triangles by vertex index.
    pub triangles: &'a [[u32; 3]],
    /// The body's motion: its pose at time t is `motion.isometry_at(t)`.
    pub motion: RigidMotion,
}

/// The VTU file of `bodies` at `time` [s] as bytes (see the module documentation);
/// `path` only names the file in errors.
pub fn encode_rigid_vtu(
    path: &Path,
    time: f64,
    bodies: &[RigidBodyFrame<'_>],
) -> Result<Vec<u8>, OutputError> {
    let bad = |message: String| OutputError::Data {
        path: path.to_path_buf(),
        message,
    };
    if !time.is_finite() {
        return Err(bad(format!("rigid frame time {time} is not finite")));
    }
    let vertices: usize = bodies.iter().map(|b| b.vertices.len()).sum();
    let triangles: usize = bodies.iter().map(|b| b.triangles.len()).sum();
    let mut points = Vec::with_capacity(3 * vertices);
    let mut displacement = Vec::with_capacity(3 * vertices);
    let mut connectivity = Vec::with_capacity(3 * triangles);
    let mut body_id = Vec::with_capacity(triangles);
    let mut first = 0u64;
    for (b, body) in bodies.iter().enumerate() {
        let count = body.vertices.len();
        if let Some(t) = body
            .triangles
            .iter()
            .position(|t| t.iter().any(|&v| v as usize >= count))
        {
            return Err(bad(format!(
                "rigid body '{}': triangle {t} refers to a missing vertex ({count} vertices)",
                body.name
            )));
        }
        let pose = body.motion.isometry_at(time);
        for reference in body.vertices {
            let x = pose.transform_point(&Point3::from(*reference)).coords;
            if !x.iter().all(|c| c.is_finite()) {
                return Err(bad(format!(
                    "rigid body '{}' is not at a finite pose at t = {time} s",
                    body.name
                )));
            }
            points.extend([x.x, x.y, x.z]);
            let u = x - reference;
            displacement.extend([u.x, u.y, u.z]);
        }
        for triangle in body.triangles {
            connectivity.extend(triangle.iter().map(|&v| first + u64::from(v)));
            body_id.push(b as i32);
        }
        first += count as u64;
    }
    let offsets = (1..=triangles as u64).map(|t| 3 * t).collect();
    let piece = UnstructuredGridPiece {
        points: IOBuffer::F64(points),
        cells: Cells {
            cell_verts: VertexNumbers::XML {
                connectivity,
                offsets,
            },
            types: vec![CellType::Triangle; triangles],
        },
        data: Attributes {
            point: vec![Attribute::DataArray(DataArray {
                name: "displacement".into(),
                elem: ElementType::Vectors,
                data: IOBuffer::F64(displacement),
            })],
            cell: vec![Attribute::DataArray(DataArray {
                name: "body_id".into(),
                elem: ElementType::Generic(1),
                data: IOBuffer::I32(body_id),
            })],
        },
    };
    let vtk = Vtk {
        version: Version::new((1, 0)),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        data: DataSet::inline(piece),
        file_path: None,
    };
    let mut bytes = Vec::new();
    vtk.write_xml(&mut bytes).map_err(|e| OutputError::Vtk {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use musclefem_core::solver::RigidRotation;
    use musclefem_materials::Amplitude;
    use vtkio::model::VertexNumbers;

    /// The points read back are the motion's positions x(X, t), computed by
    /// `RigidMotion::position_at` (c + R(X − c) + T, not the isometry the writer uses);
    /// the second body's triangles point past the first body's vertices.
    #[test]
    fn the_points_are_the_bodies_at_their_pose() {
        let turning = RigidMotion {
            translation: [Some(Amplitude::ramp(1.0, 0.2).unwrap()), None, None],
            rotation: Some(RigidRotation {
                center: Vector3::new(0.0, 1.0, 0.0),
                axis: Vector3::z_axis(),
                angle: Amplitude::ramp(1.0, 0.7).unwrap(),
            }),
            follower: None,
        };
        let fixed = RigidMotion::fixed();
        let a = [Vector3::zeros(), Vector3::x(), Vector3::y()];
        let b = [
            Vector3::new(0.0, 0.0, 1.0),
            Vector3::new(1.0, 0.0, 1.0),
            Vector3::new(0.0, 1.0, 1.0),
            Vector3::new(1.0, 1.0, 1.0),
        ];
        let bodies = [
            RigidBodyFrame {
                name: "a",
                vertices: &a,
                triangles: &[[0, 1, 2]],
                motion: turning.clone(),
            },
            RigidBodyFrame {
                name: "b",
                vertices: &b,
                triangles: &[[0, 1, 2], [1, 3, 2]],
                motion: fixed,
            },
        ];
        let time = 0.4;
        let bytes = encode_rigid_vtu(Path::new("rigid.vtu"), time, &bodies).unwrap();
        let vtk = Vtk::parse_xml(&bytes[..]).unwrap();
        let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
            panic!("not an unstructured grid")
        };
        let vtkio::model::Piece::Inline(piece) = &pieces[0] else {
            panic!("not inline")
        };
        let IOBuffer::F64(points) = &piece.points else {
            panic!("points are not f64")
        };
        let expected: Vec<Vector3<f64>> = a
            .iter()
            .map(|x| turning.position_at(x, time))
            .chain(b.iter().copied())
            .collect();
        assert_eq!(points.len(), 3 * expected.len());
        for (i, x) in expected.iter().enumerate() {
            let written = Vector3::new(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
            assert!((written - x).norm() < 1e-12, "vertex {i}: {written} ≠ {x}");
        }
        let (connectivity, offsets) = match &piece.cells.cell_verts {
            VertexNumbers::XML {
                connectivity,
                offsets,
            } => (connectivity.clone(), offsets.clone()),
            VertexNumbers::Legacy { .. } => panic!("legacy cells"),
        };
        assert_eq!(connectivity, vec![0, 1, 2, 3, 4, 5, 4, 6, 5]);
        assert_eq!(offsets, vec![3, 6, 9]);
        assert!(piece.cells.types.iter().all(|t| *t == CellType::Triangle));

        let broken = [RigidBodyFrame {
            triangles: &[[0, 1, 7]],
            ..bodies[0].clone()
        }];
        let error = encode_rigid_vtu(Path::new("rigid.vtu"), time, &broken)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("'a'") && error.contains("triangle 0"),
            "{error}"
        );
    }
}
