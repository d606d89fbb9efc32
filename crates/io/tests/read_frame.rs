//! Frames read back: a written part frame gives back its mesh, displacements and cell
//! arrays; a rigid frame its triangles; a run's frame nearest a time is found through its
//! .pvd files; what is missing is named with the file.

use std::path::{Path, PathBuf};

use musclefem_core::mesh::generate::{TetOrder, box_of_hexes, box_of_tets};
use musclefem_core::mesh::{ElementShape, Mesh};
use musclefem_core::solver::RigidMotion;
use musclefem_io::output::{
    Frame, PvdEntry, RigidBodyFrame, encode_rigid_vtu, frame_time, nearest_entry, read_frame,
    read_rigid_frame, run_frame_at, von_mises, write_pvd, write_vtu,
};
use musclefem_materials::VoigtStress;
use nalgebra::Vector3;

fn test_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join("musclefem-io-read-frame-tests")
        .join(format!("{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Two hex8 cells, then a cube of six tet10 beside them (their own nodes).
fn mixed_mesh() -> Mesh {
    let mut mesh = box_of_hexes([2.0, 1.0, 1.0], [2, 1, 1]).unwrap();
    let tets = box_of_tets([1.0, 1.0, 1.0], [1, 1, 1], TetOrder::Quadratic).unwrap();
    let offset = mesh.node_count() as u32;
    for i in 0..tets.node_count() {
        mesh.nodes
            .push(tets.nodes.position(i) + Vector3::new(3.0, 0.0, 0.0));
    }
    let mut block = tets.blocks[0].clone();
    block.connectivity.iter_mut().for_each(|n| *n += offset);
    mesh.blocks.push(block);
    mesh
}

fn write_mixed_frame(path: &Path) -> (Mesh, Vec<Vector3<f64>>, Vec<VoigtStress>, Vec<f64>) {
    let mesh = mixed_mesh();
    let u: Vec<Vector3<f64>> = (0..mesh.node_count())
        .map(|i| Vector3::new(1e-3 * i as f64, 0.5, -(i as f64).sqrt()))
        .collect();
    let stress: Vec<VoigtStress> = (0..mesh.element_count())
        .map(|e| VoigtStress::new(e as f64, 2.0, -3.0 * e as f64, 0.1, 0.0, 7.0))
        .collect();
    let stretch: Vec<f64> = (0..mesh.element_count())
        .map(|e| 1.0 + 0.01 * e as f64)
        .collect();
    let frame = Frame::new(0.5, &mesh, &u)
        .with_cauchy_stress(&stress)
        .with_cell_scalar("fiber_stretch", &stretch);
    write_vtu(path, &frame).unwrap();
    (mesh, u, stress, stretch)
}

#[test]
fn a_part_frame_reads_back_as_written() {
    let dir = test_dir("part");
    let path = dir.join("frame_00000.vtu");
    let (mesh, u, stress, stretch) = write_mixed_frame(&path);
    let read = read_frame(&path).unwrap();
    assert_eq!(read.mesh.node_count(), mesh.node_count());
    for i in 0..mesh.node_count() {
        assert_eq!(read.mesh.nodes.position(i), mesh.nodes.position(i));
    }
    assert_eq!(read.displacement, u);
    let shapes: Vec<ElementShape> = read.mesh.blocks.iter().map(|b| b.shape).collect();
    assert_eq!(shapes, vec![ElementShape::Hex8, ElementShape::Tet10]);
    for (a, b) in read.mesh.blocks.iter().zip(&mesh.blocks) {
        assert_eq!(a.connectivity, b.connectivity);
    }
    let mises: Vec<f64> = stress.iter().map(von_mises).collect();
    assert_eq!(read.cell_scalar("von_mises").unwrap(), &mises[..]);
    assert_eq!(read.cell_scalar("fiber_stretch").unwrap(), &stretch[..]);

    let error = read.cell_scalar("cauchy_stress").unwrap_err().to_string();
    assert!(
        error.contains("frame_00000.vtu") && error.contains("6 components"),
        "{error}"
    );
    let error = read.cell_scalar("activation").unwrap_err().to_string();
    assert!(
        error.contains("no cell array 'activation'") && error.contains("von_mises, fiber_stretch"),
        "{error}"
    );
}

#[test]
fn what_a_frame_lacks_is_named_with_the_file() {
    let dir = test_dir("lacks");
    let path = dir.join("frame.vtu");
    write_mixed_frame(&path);
    let text = std::fs::read_to_string(&path).unwrap();
    for (array, expected) in [
        ("Name=\"displacement\"", "no point array 'displacement'"),
        ("Name=\"block_id\"", "no cell array 'block_id'"),
    ] {
        let broken = dir.join("broken.vtu");
        std::fs::write(&broken, text.replacen(array, "Name=\"renamed\"", 1)).unwrap();
        let error = read_frame(&broken).unwrap_err().to_string();
        assert!(
            error.contains("broken.vtu") && error.contains(expected),
            "{error}"
        );
    }
    let error = read_frame(&dir.join("absent.vtu")).unwrap_err().to_string();
    assert!(error.contains("absent.vtu"), "{error}");
}

#[test]
fn a_rigid_frame_reads_back_as_its_triangles_at_their_pose() {
    let dir = test_dir("rigid");
    let path = dir.join("rigid_00000.vtu");
    let a = [Vector3::zeros(), Vector3::x(), Vector3::y()];
    let b = [
        Vector3::z(),
        Vector3::new(1.0, 0.0, 1.0),
        Vector3::new(0.0, 1.0, 1.0),
    ];
    let bodies = [
        RigidBodyFrame {
            name: "a",
            vertices: &a,
            triangles: &[[0, 1, 2]],
            motion: RigidMotion::fixed(),
        },
        RigidBodyFrame {
            name: "b",
            vertices: &b,
            triangles: &[[0, 2, 1]],
            motion: RigidMotion::fixed(),
        },
    ];
    std::fs::write(&path, encode_rigid_vtu(&path, 0.0, &bodies).unwrap()).unwrap();
    let read = read_rigid_frame(&path).unwrap();
    let all: Vec<Vector3<f64>> = a.iter().chain(&b).copied().collect();
    assert_eq!(read.vertices, all);
    assert_eq!(read.triangles, vec![[0, 1, 2], [3, 5, 4]]);
    // A part frame is not a rigid frame.
    let part = dir.join("frame.vtu");
    write_mixed_frame(&part);
    let error = read_rigid_frame(&part).unwrap_err().to_string();
    assert!(
        error.contains("frame.vtu") && error.contains("not a triangle"),
        "{error}"
    );
}

/// result.pvd at t = 0, 0.4, 1.1 s: t = 0.7 s picks 0.4 s (the nearer), 0.75 s the
/// earlier of two equally near (0.4 s), 5 s the last; the rigid frame is that of the
/// same time in rigid.pvd, and a frame knows its time from its run's result.pvd.
#[test]
fn the_frame_nearest_a_time() {
    let dir = test_dir("nearest");
    let entries: Vec<PvdEntry> = [0.0, 0.4, 1.1]
        .iter()
        .enumerate()
        .map(|(k, &time)| PvdEntry {
            time,
            file: format!("frames/frame_{k:05}.vtu"),
        })
        .collect();
    assert_eq!(nearest_entry(&entries, 0.7).unwrap().time, 0.4);
    assert_eq!(nearest_entry(&entries, 0.75).unwrap().time, 0.4);
    assert_eq!(nearest_entry(&entries, 5.0).unwrap().time, 1.1);
    assert!(nearest_entry(&[], 1.0).is_none());

    write_pvd(&dir.join("result.pvd"), &entries).unwrap();
    let found = run_frame_at(&dir, 1.0).unwrap();
    assert_eq!(found.time, 1.1);
    assert_eq!(found.frame, dir.join("frames/frame_00002.vtu"));
    assert_eq!(found.rigid, None);
    let rigid: Vec<PvdEntry> = entries
        .iter()
        .map(|e| PvdEntry {
            file: e.file.replace("frame_", "rigid_"),
            ..e.clone()
        })
        .collect();
    write_pvd(&dir.join("rigid.pvd"), &rigid[..2]).unwrap();
    let found = run_frame_at(&dir, 0.3).unwrap();
    assert_eq!(found.rigid, Some(dir.join("frames/rigid_00001.vtu")));
    let error = run_frame_at(&dir, 1.0).unwrap_err().to_string();
    assert!(
        error.contains("rigid.pvd") && error.contains("t = 1.1 s"),
        "{error}"
    );

    std::fs::create_dir_all(dir.join("frames")).unwrap();
    write_mixed_frame(&dir.join("frames/frame_00001.vtu"));
    assert_eq!(frame_time(&dir.join("frames/frame_00001.vtu")), Some(0.4));
    write_mixed_frame(&dir.join("frames/unlisted.vtu"));
    assert_eq!(frame_time(&dir.join("frames/unlisted.vtu")), None);
}
