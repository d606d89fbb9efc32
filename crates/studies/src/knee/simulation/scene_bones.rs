//! The knee's bones as a scene's `[[rigid_bodies]]` (issue 30, step 4): the femur, the
//! tibia and the patella written beside the scene as OBJ files (`femur.obj` with the
//! femur's vertex normals from its implicit shape, which its contact and bonds slide
//! along; `tibia.obj` and `patella.obj` without, as the knee has none), each moving with
//! its follower: the femur and the tibia with `knee-closed-chain`, the patella with
//! `knee-patella` on the same table as the insertions' ties ([`super::scene_ties`]), so
//! that one patella moves the insertions and the patella's surface.
//!
//! The bodies come in the order of the knee's own frames (`rigid.pvd`: femur, tibia,
//! patella), and the femur is the implicit step's predictor frame
//! ([`super::scene_step::squat_step_entry`] with [`FEMUR_BODY`]). A scene built from them
//! has the knee's bone surfaces and poses bit for bit (the test below and
//! `super::scene_tests`).

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};

use musclefem_io::mesh_export::obj_text;

use super::followers::closed_chain_motion;
use super::model::KneeGeometry;
use super::scene_ties::knee_patella_motion;
use crate::knee::anatomy::squat::Bone;
use crate::knee::anatomy::surface::TriangleSurface;

/// The femur's rigid body: the implicit step's predictor frame and the main surface of
/// the muscles' contact and bonds on the bone.
pub const FEMUR_BODY: &str = "femur";
/// The femur's surface file.
pub const FEMUR_OBJ: &str = "femur.obj";
/// The tibia's surface file.
pub const TIBIA_OBJ: &str = "tibia.obj";
/// The patella's surface file (in the patella's own frame, placed by its follower).
pub const PATELLA_OBJ: &str = "patella.obj";

/// `femur.obj` (with `geometry.femur_normals` when it has them), `tibia.obj` and
/// `patella.obj` of `geometry`'s bones, coordinates in metres: (file name, text) each.
pub fn bone_files(geometry: &KneeGeometry) -> Vec<(&'static str, String)> {
    let obj = |comment: &str, bone: &TriangleSurface, normals| {
        obj_text(comment, &bone.vertices, &bone.triangles, normals)
    };
    vec![
        (
            FEMUR_OBJ,
            obj(
                "musclefem knee: the femur at 0° of flexion [m], normals from its implicit shape",
                &geometry.femur,
                geometry.femur_normals.as_deref(),
            ),
        ),
        (
            TIBIA_OBJ,
            obj(
                "musclefem knee: the tibia at 0° of flexion [m]",
                &geometry.tibia,
                None,
            ),
        ),
        (
            PATELLA_OBJ,
            obj(
                "musclefem knee: the patella in its own frame [m]",
                &geometry.patella,
                None,
            ),
        ),
    ]
}

/// Write the [`bone_files`] into `directory` (atomically, each).
pub fn write_bone_files(directory: &Path, geometry: &KneeGeometry) -> Result<()> {
    for (name, text) in bone_files(geometry) {
        let path = directory.join(name);
        musclefem_io::atomic::write_atomically(&path, text.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

/// The `[[rigid_bodies]]` entries of `geometry`'s bones, femur, tibia and patella, on
/// the files [`write_bone_files`] writes, with the squat's follower motions.
pub fn knee_bone_entries(geometry: &KneeGeometry) -> String {
    let (chain, squat) = (&geometry.motions.chain, &geometry.motions.squat);
    let bodies = [
        (
            FEMUR_BODY,
            FEMUR_OBJ,
            closed_chain_motion(Bone::Femur, chain, squat),
        ),
        (
            "tibia",
            TIBIA_OBJ,
            closed_chain_motion(Bone::Tibia, chain, squat),
        ),
        ("patella", PATELLA_OBJ, knee_patella_motion(geometry)),
    ];
    let mut text = String::new();
    for (name, file, motion) in bodies {
        let _ = writeln!(
            text,
            "[[rigid_bodies]]\nname = {name:?}\nsurface = {{ file = {file:?} }}\nmotion = \
             {motion}\n"
        );
    }
    text
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use std::sync::Arc;

    use musclefem_core::solver::RigidMotion;
    use musclefem_io::scene::load_scene;
    use musclefem_materials::MaterialLibrary;

    use super::*;
    use crate::knee::anatomy::{Anatomy, Resolution, Squat};
    use crate::knee::simulation::patella::TendonPatella;
    use crate::knee::simulation::scene_files::PATELLA_TABLE_CSV;

    fn bits(v: &[Vector3<f64>]) -> Vec<[u64; 3]> {
        v.iter().map(|x| x.map(f64::to_bits).into()).collect()
    }

    #[test]
    fn the_knees_bones_read_back_as_rigid_bodies_bit_for_bit() {
        let anatomy = Anatomy::procedural_knee(Resolution::Coarse).unwrap();
        let squat = Squat::to_ninety_degrees(2.0);
        let geometry = KneeGeometry::procedural_knee(&anatomy, &squat).unwrap();
        let directory =
            std::env::temp_dir().join(format!("musclefem-knee-bones-{}", std::process::id()));
        std::fs::create_dir_all(&directory).unwrap();
        write_bone_files(&directory, &geometry).unwrap();
        geometry
            .patella_table
            .write_csv(&directory.join(PATELLA_TABLE_CSV))
            .unwrap();
        // A scene of one block and the bones.
        let text = format!(
            "schema_version = 1\n\n[[materials]]\nname = \"m\"\nmodel = \"neo-hookean\"\n\n\
             [[parts]]\nname = \"p\"\nmaterial = \"m\"\nelement = \"hex8-fbar\"\n\
             density = 1060.0\nmesh = {{ generator = \"box\", size = [0.01, 0.01, 0.01], \
             divisions = [1, 1, 1] }}\n\n{}[step]\nsolver = \"implicit\"\nduration = 2.0\n",
            knee_bone_entries(&geometry)
        );
        let path = directory.join("scene.toml");
        std::fs::write(&path, text).unwrap();
        let scene = load_scene(&path, &mut MaterialLibrary::with_builtins())
            .unwrap_or_else(|e| panic!("{e}"));

        // The surfaces, vertex by vertex and triangle by triangle; the femur's normals.
        let bones = [&geometry.femur, &geometry.tibia, &geometry.patella];
        let names = ["femur", "tibia", "patella"];
        assert_eq!(scene.rigid_bodies.len(), 3);
        for ((body, bone), name) in scene.rigid_bodies.iter().zip(bones).zip(names) {
            assert_eq!(body.name, name);
            assert_eq!(bits(&body.vertices), bits(&bone.vertices), "{name}");
            assert_eq!(body.triangles, bone.triangles, "{name}");
        }
        let femur_normals = geometry.femur_normals.as_deref().unwrap();
        assert_eq!(
            bits(scene.rigid_bodies[0].vertex_normals.as_deref().unwrap()),
            bits(femur_normals)
        );
        assert!(scene.rigid_bodies[1].vertex_normals.is_none());
        assert!(scene.rigid_bodies[2].vertex_normals.is_none());

        // The poses: at rest, half way down (45°), at 90° and half way up.
        let patella = TendonPatella::new(
            geometry.patella_table.clone(),
            squat,
            geometry.motions.chain,
        );
        let motions = [
            geometry.motions.femur.clone(),
            geometry.motions.tibia.clone(),
            RigidMotion::followed(Arc::new(patella)),
        ];
        for time in [0.0, 0.5, 1.0, 1.5] {
            for ((body, motion), name) in scene.rigid_bodies.iter().zip(&motions).zip(names) {
                assert_eq!(
                    body.motion.isometry_at(time),
                    motion.isometry_at(time),
                    "{name} at {time} s"
                );
            }
        }
        assert_eq!(squat.flexion_at(1.0), std::f64::consts::FRAC_PI_2);
        std::fs::remove_dir_all(&directory).unwrap();
    }
}
