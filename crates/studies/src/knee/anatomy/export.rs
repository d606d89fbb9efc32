//! The anatomy at a knee flexion angle as files for a visual check in ParaView:
//!
//! - `femur.stl`, `tibia_<θ>deg.stl`, `patella_<θ>deg.stl`: the bones (ASCII STL, metres);
//! - `muscles.vtu`: the four quadriceps' meshes at 0° (one block each; `block_id` tells
//!   them apart, `fiber_direction_reference` shows the fibers), and each one's outer
//!   surface as `<muscle>.stl`;
//! - `paths_<θ>deg.vtk`: the musculotendon paths (centreline to the release station,
//!   free path, patellar tendon) as VTK legacy polylines, one cell per muscle and one
//!   for the patellar tendon, with a `muscle` cell field (0–3 in the order VI, VL, VM,
//!   RF; 4 the tendon).
//!
//! The muscles are not deformed here (that is the finite-element run's job): open the
//! bones and paths of several angles over the 0° muscles to see the patella track the
//! groove and the paths wrap over the trochlea.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};
use nalgebra::Vector3;

use musclefem_io::output::{Frame, write_vtu};

use super::path::free_path_points;
use super::{Anatomy, TriangleSurface};

/// Writes `muscles.vtu`, the muscles' and the femur's STL, and for each knee flexion angle of
/// `angles_degrees` the tibia, the patella and the paths (see the module documentation),
/// into `directory` (created if missing).
pub fn write_anatomy(anatomy: &Anatomy, directory: &Path, angles_degrees: &[f64]) -> Result<()> {
    std::fs::create_dir_all(directory)
        .with_context(|| format!("creating {}", directory.display()))?;
    let (mesh, _) = anatomy.muscle_mesh();
    let displacement = vec![Vector3::zeros(); mesh.node_count()];
    write_vtu(
        &directory.join("muscles.vtu"),
        &Frame::new(0.0, &mesh, &displacement),
    )
    .context("writing muscles.vtu")?;
    anatomy
        .bones
        .femur
        .write_stl(&directory.join("femur.stl"), "femur")?;
    for muscle in &anatomy.muscles {
        let name = muscle.muscle.name();
        TriangleSurface::from_mesh_surface(&muscle.mesh, "outer")?
            .write_stl(&directory.join(format!("{name}.stl")), name)?;
    }
    let reference = anatomy.patella_reference.isometry().inverse();
    for &degrees in angles_degrees {
        let angle = degrees.to_radians();
        let pose = anatomy.kinematics.patella_pose(angle)?;
        let tag = format!("{degrees:.0}deg");
        anatomy
            .bones
            .tibia
            .transformed(&anatomy.kinematics.tibia_isometry(angle))
            .write_stl(&directory.join(format!("tibia_{tag}.stl")), "tibia")?;
        anatomy
            .bones
            .patella
            .transformed(&(pose.isometry() * reference))
            .write_stl(&directory.join(format!("patella_{tag}.stl")), "patella")?;
        let mut lines: Vec<Vec<Vector3<f64>>> = Vec::new();
        for muscle in &anatomy.muscles {
            let lengths = muscle.solid.station_arclengths();
            let release = lengths[muscle.release];
            let samples = 40;
            let mut points: Vec<Vector3<f64>> = (0..samples)
                .map(|k| {
                    muscle
                        .solid
                        .section(release * k as f64 / samples as f64)
                        .centre
                })
                .collect();
            let pull = muscle.pull();
            points.extend(free_path_points(
                &pull.release,
                &pose.to_world(&pull.insertion),
                &anatomy.kinematics.trochlea,
                24,
            ));
            lines.push(points);
        }
        lines.push(vec![
            pose.to_world(&anatomy.dimensions().apex),
            anatomy.kinematics.tuberosity(angle),
        ]);
        write_polylines(&directory.join(format!("paths_{tag}.vtk")), &lines)?;
    }
    Ok(())
}

/// Writes `lines` as a VTK legacy ASCII polydata file, cell field `muscle` = line index.
fn write_polylines(path: &Path, lines: &[Vec<Vector3<f64>>]) -> Result<()> {
    let count: usize = lines.iter().map(Vec::len).sum();
    let mut text =
        String::from("# vtk DataFile Version 3.0\nmusculotendon paths\nASCII\nDATASET POLYDATA\n");
    let _ = writeln!(text, "POINTS {count} double");
    for p in lines.iter().flatten() {
        let _ = writeln!(text, "{:e} {:e} {:e}", p.x, p.y, p.z);
    }
    let _ = writeln!(text, "LINES {} {}", lines.len(), count + lines.len());
    let mut first = 0;
    for line in lines {
        let ids: Vec<String> = (first..first + line.len()).map(|i| i.to_string()).collect();
        let _ = writeln!(text, "{} {}", line.len(), ids.join(" "));
        first += line.len();
    }
    let _ = writeln!(
        text,
        "CELL_DATA {}\nSCALARS muscle int 1\nLOOKUP_TABLE default",
        lines.len()
    );
    for k in 0..lines.len() {
        let _ = writeln!(text, "{k}");
    }
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}
