//! The rigid bodies in a run's frames: a scene with a rigid sphere that moves (a
//! translation and a rotation about an axis off its centre) run through the run writer
//! gives `rigid.pvd` with one `frames/rigid_NNNNN.vtu` per frame, at the frames' times,
//! whose points are the sphere's vertices where the prescribed motion puts them,
//! x = c + R(t)(X − c) + T(t) (computed here from the axis, angle and translation, not
//! by the program's motion), to 1e-12 m.

use std::ops::ControlFlow;
use std::path::PathBuf;

use nalgebra::{Rotation3, Vector3};
use vtkio::model::{Attribute, DataSet, IOBuffer, Piece};

use musclefem_io::output::{
    ExistingResults, FrameSchedule, HistoryWriter, RunProgress, RunStart, RunWriter, read_pvd,
};
use musclefem_io::scene::load_scene;
use musclefem_materials::MaterialLibrary;

const SCENE: &str = r#"schema_version = 1

[[materials]]
name = "rubber"
model = "neo-hookean"
parameters = { mu = 1e4, D = 2e-5 }

[[parts]]
name = "cube"
material = "rubber"
element = "hex8-fbar"
density = 1000.0
mesh = { generator = "box", size = [0.01, 0.01, 0.01], divisions = [1, 1, 1] }

[[amplitudes]]
name = "ramp"
points = [[0.0, 0.0], [1.0, 1.0]]

[[displacements]]
part = "cube"
nodes = "x0"
components = ["x", "y", "z"]

[[rigid_bodies]]
name = "ball"
surface = { shape = "sphere", center = [0.03, 0.0, 0.0], radius = 0.01, divisions = 4 }
translation = [0.0, 0.02, -0.01]
translation_amplitude = "ramp"
rotation = { center = [0.03, 0.005, 0.0], axis = [0.0, 0.0, 2.0], angle_degrees = 90.0, amplitude = "ramp" }

[step]
solver = "implicit"
duration = 1.0
output_interval = 0.25

[step.implicit]
increments = 4
"#;

struct Quiet;
impl RunProgress for Quiet {
    fn reached(&mut self, _time: f64) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

fn test_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("musclefem_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn a_moving_rigid_sphere_is_written_at_its_prescribed_pose_in_every_frame() {
    let dir = test_dir("rigid_frames");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let model = load_scene(&scene, &mut MaterialLibrary::with_builtins()).unwrap();
    assert_eq!(model.rigid_bodies.len(), 1);
    let out = dir.join("run");
    let history = HistoryWriter::for_analysis(
        &out.join("history.csv"),
        &model.history_columns(),
        &model.analysis,
    )
    .unwrap();
    let frames = FrameSchedule::new(model.frame_interval, model.analysis.end_time(), &[]);
    let mut quiet = Quiet;
    let (writer, _) = RunWriter::open(
        &out,
        RunStart::Fresh(ExistingResults::Refuse),
        &model.mesh,
        history,
        (frames, true),
        1,
        &mut quiet,
    )
    .unwrap();
    let mut writer = writer.with_rigid_bodies(model.rigid_body_frames());
    model.run(&mut writer).unwrap();
    let written = writer.finish().unwrap();
    assert!(written.write_error.is_none(), "{:?}", written.write_error);

    let parts = read_pvd(&out.join("result.pvd")).unwrap();
    let rigid = read_pvd(&out.join("rigid.pvd")).unwrap();
    assert_eq!(parts.len(), 5, "frames at 0, 0.25, …, 1 s");
    assert_eq!(rigid.len(), parts.len());
    let reference = &model.rigid_bodies[0].vertices;
    let (center, pivot) = (Vector3::new(0.03, 0.0, 0.0), Vector3::new(0.03, 0.005, 0.0));
    let mut largest_move: f64 = 0.0;
    for (k, (frame, bodies)) in parts.iter().zip(&rigid).enumerate() {
        assert_eq!(bodies.time, frame.time);
        assert_eq!(bodies.file, format!("frames/rigid_{k:05}.vtu"));
        let vtk = vtkio::Vtk::import(out.join(&bodies.file)).unwrap();
        let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
            panic!("not an unstructured grid")
        };
        let Piece::Inline(piece) = &pieces[0] else {
            panic!("not inline")
        };
        let IOBuffer::F64(points) = &piece.points else {
            panic!("points are not Float64")
        };
        assert_eq!(points.len(), 3 * reference.len());
        assert_eq!(
            piece.cells.types.len(),
            model.rigid_bodies[0].triangles.len()
        );
        assert!(
            piece
                .data
                .cell
                .iter()
                .any(|a| matches!(a, Attribute::DataArray(d) if d.name == "body_id"))
        );
        // x = c + R(t)(X − c) + T(t), R a quarter turn about z times t, T t (0, 0.02, −0.01).
        let t = frame.time;
        let rotation = Rotation3::from_axis_angle(&Vector3::z_axis(), t * 90f64.to_radians());
        let translation = t * Vector3::new(0.0, 0.02, -0.01);
        for (i, x) in reference.iter().enumerate() {
            let expected = pivot + rotation * (x - pivot) + translation;
            let written = Vector3::new(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
            assert!(
                (written - expected).norm() < 1e-12,
                "t = {t}, vertex {i}: {written} ≠ {expected}"
            );
            // Every vertex stays on the moved sphere.
            let moved_center = pivot + rotation * (center - pivot) + translation;
            assert!(((written - moved_center).norm() - 0.01).abs() < 1e-12);
            largest_move = largest_move.max((written - x).norm());
        }
    }
    assert!(largest_move > 0.01, "the sphere moved {largest_move} m");
}
