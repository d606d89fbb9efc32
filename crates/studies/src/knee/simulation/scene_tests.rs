//! The knee's scene files together (issue 30, step 4): the coarse knee's mesh, fibers
//! and patella table, its materials, parts, ties and step written as a scene and built
//! back give the squat's model — the same elements at the same places, fibers,
//! materials, densities, element technology, tie nodes and motions (the patella's after
//! the same pull), bones (surfaces, the femur's vertex normals, poses) and analysis, bit
//! for bit, on the knee's nodes by the knee's ids (the parts share `muscles.inp`'s
//! nodes) — and its interactions, each as the knee builds it (bonds, penalties,
//! surfaces), for both interface laws.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use nalgebra::Vector3;

use musclefem_contact::{ContactTarget, DeformableSurface, PenaltyContact};
use musclefem_core::solver::{PoseFollower, RigidMotion, RigidReaction};
use musclefem_io::scene::{InteractionModel, load_scene};
use musclefem_materials::MaterialLibrary;

use super::interactions::{InterfaceLaw, knee_interactions};
use super::model::{Activation, KneeGeometry, KneeModel};
use super::run::{SquatSettings, squat_analysis};
use super::scene::SquatScene;
use super::scene_interactions::knee_interaction_entries;
use super::visible_human::visible_human_geometry;
use crate::elongation::{ElementChoice, Solver};
use crate::knee::anatomy::{Anatomy, Resolution, Squat};

/// The coarse knee of a 10° squat for the scene tests: its geometry, its model (active),
/// the squat's settings (implicit).
fn coarse_knee() -> (KneeGeometry, KneeModel, SquatSettings) {
    let anatomy = Anatomy::procedural_knee(Resolution::Coarse).unwrap();
    let squat = Squat {
        duration: 0.2,
        peak_flexion: 10f64.to_radians(),
    };
    let geometry = KneeGeometry::procedural_knee(&anatomy, &squat).unwrap();
    let fibers = geometry.fibers().unwrap();
    let knee = KneeModel::new(
        &geometry,
        &fibers,
        Activation::Active,
        &squat,
        ElementChoice::Hex8Fbar,
    )
    .unwrap();
    let mut settings = SquatSettings::recommended(Solver::Implicit);
    settings.squat = squat;
    (geometry, knee, settings)
}

/// Write the knee's scene into `directory`: its files and `scene.toml` with
/// `interactions` (entries, or nothing); returns the scene file's path.
fn write_knee_scene(
    directory: &Path,
    geometry: &KneeGeometry,
    knee: &KneeModel,
    settings: &SquatSettings,
    interactions: &str,
) -> PathBuf {
    std::fs::create_dir_all(directory).unwrap();
    let scene = SquatScene {
        geometry,
        mesh: &knee.mesh,
        activation: Activation::Active,
        settings,
        interactions: interactions.to_string(),
    };
    scene.write_files(directory).unwrap();
    let path = directory.join("scene.toml");
    std::fs::write(&path, scene.text(0.05).unwrap()).unwrap();
    path
}

#[test]
fn the_knees_scene_builds_the_squats_model() {
    let (geometry, knee, settings) = coarse_knee();
    let directory =
        std::env::temp_dir().join(format!("musclefem-knee-scene-{}", std::process::id()));
    let path = write_knee_scene(&directory, &geometry, &knee, &settings, "");
    let scene =
        load_scene(&path, &mut MaterialLibrary::with_builtins()).unwrap_or_else(|e| panic!("{e}"));

    // Parts: the same materials, densities and technologies.
    assert_eq!(scene.parts.len(), knee.parts.len());
    for (a, b) in scene.parts.iter().zip(&knee.parts) {
        assert_eq!(format!("{:?}", a.material), format!("{:?}", b.material));
        assert_eq!(a.density, b.density);
        assert_eq!(format!("{:?}", a.technology), format!("{:?}", b.technology));
    }
    // Elements: the same corners at the same places, the same fibers.
    let bits = |v: &[Vector3<f64>]| v.iter().map(|x| x.map(f64::to_bits)).collect::<Vec<_>>();
    let corners = |mesh: &musclefem_core::mesh::Mesh, b: usize| -> Vec<[u64; 3]> {
        mesh.blocks[b]
            .connectivity
            .iter()
            .map(|&n| mesh.nodes.position(n as usize).map(f64::to_bits).into())
            .collect()
    };
    for b in 0..knee.mesh.blocks.len() {
        assert_eq!(corners(&scene.mesh, b), corners(&knee.mesh, b), "block {b}");
        assert_eq!(
            bits(&scene.mesh.blocks[b].fiber_direction),
            bits(&knee.mesh.blocks[b].fiber_direction),
            "block {b}"
        );
    }
    // The parts share the file's nodes: the knee's nodes, by the knee's ids.
    assert_eq!(scene.mesh.node_count(), knee.mesh.node_count());
    for b in 0..knee.mesh.blocks.len() {
        assert_eq!(
            scene.mesh.blocks[b].connectivity,
            knee.mesh.blocks[b].connectivity
        );
    }

    // Ties: the same names, nodes at the same places, the same motions.
    let ties = (&scene.loads.rigid_ties, &knee.loads.rigid_ties);
    assert_eq!(ties.0.len(), ties.1.len());
    let places = |mesh: &musclefem_core::mesh::Mesh, nodes: &[u32]| -> Vec<[u64; 3]> {
        nodes
            .iter()
            .map(|&n| mesh.nodes.position(n as usize).map(f64::to_bits).into())
            .collect()
    };
    let reactions: Vec<RigidReaction> = (0..ties.1.len())
        .map(|i| RigidReaction {
            force: Vector3::new(100.0 * i as f64, -30.0, 5.0),
            moment: Vector3::zeros(),
        })
        .collect();
    for (a, b) in ties.0.iter().zip(ties.1) {
        assert_eq!(a.name, b.name);
        assert_eq!(
            places(&scene.mesh, &a.nodes),
            places(&knee.mesh, &b.nodes),
            "{}",
            a.name
        );
    }
    // The patella hears the same pull (its insertions') in both.
    ties.0[1]
        .motion
        .follower
        .as_ref()
        .unwrap()
        .observe(0.05, &reactions);
    knee.patella.observe(0.05, &reactions);
    for (a, b) in ties.0.iter().zip(ties.1) {
        for time in [0.0, 0.05, 0.08, 0.1, 0.17] {
            assert_eq!(
                a.motion.isometry_at(time),
                b.motion.isometry_at(time),
                "{} {time}",
                a.name
            );
        }
    }
    assert!(knee.patella.tension_at(0.1) > 100.0);

    // Bones: the knee's surfaces (the femur with its normals), in the order of its
    // frames, moving as its bones do; the patella's surface with its insertions.
    let bones = [
        ("femur", &geometry.femur, geometry.motions.femur.clone()),
        ("tibia", &geometry.tibia, geometry.motions.tibia.clone()),
        (
            "patella",
            &geometry.patella,
            RigidMotion::followed(knee.patella.clone()),
        ),
    ];
    assert_eq!(scene.rigid_bodies.len(), bones.len());
    for (body, (name, bone, motion)) in scene.rigid_bodies.iter().zip(&bones) {
        assert_eq!(body.name, *name);
        assert_eq!(bits(&body.vertices), bits(&bone.vertices), "{name}");
        assert_eq!(body.triangles, bone.triangles, "{name}");
        for time in [0.0, 0.05, 0.1, 0.17] {
            assert_eq!(
                body.motion.isometry_at(time),
                motion.isometry_at(time),
                "{name} {time}"
            );
        }
    }
    assert_eq!(
        bits(scene.rigid_bodies[0].vertex_normals.as_deref().unwrap()),
        bits(geometry.femur_normals.as_deref().unwrap())
    );
    assert!(Arc::ptr_eq(
        scene.rigid_bodies[2].motion.follower.as_ref().unwrap(),
        ties.0[1].motion.follower.as_ref().unwrap()
    ));

    // The analysis.
    assert_eq!(
        format!("{:?}", scene.analysis),
        format!("{:?}", squat_analysis(&settings, &geometry.motions.femur))
    );
    std::fs::remove_dir_all(&directory).unwrap();
}

/// A deformable surface's nodes, triangles, areas and rim, bit for bit (the shortest
/// decimals print distinct numbers distinctly), without its name.
fn surface_bits(surface: &DeformableSurface) -> String {
    format!(
        "{:?} {:?} {:?} {:?} {:?}",
        surface.nodes,
        surface.triangles,
        surface.triangle_area,
        surface.node_area,
        surface.boundary_edges
    )
}

/// A main surface bit for bit: a rigid body's name, vertices, triangles and vertex
/// normals, or a deformable surface's [`surface_bits`].
fn main_bits(target: &ContactTarget) -> String {
    match target {
        ContactTarget::Rigid(body) => format!(
            "{} {:?} {:?} {:?}",
            body.name, body.vertices, body.triangles, body.vertex_normals
        ),
        ContactTarget::Deformable(surface) => surface_bits(surface),
    }
}

#[test]
fn the_knees_interactions_read_back_as_scene_interactions() {
    let (geometry, knee, settings) = coarse_knee();
    for law in [InterfaceLaw::Sliding, InterfaceLaw::ElasticShear] {
        let built = knee_interactions(&geometry, &knee.mesh, knee.material.as_ref(), law).unwrap();
        let entries = knee_interaction_entries(&geometry, &built, law).unwrap();
        let directory = std::env::temp_dir().join(format!(
            "musclefem-knee-interactions-{}-{}",
            law.name(),
            std::process::id()
        ));
        let path = write_knee_scene(&directory, &geometry, &knee, &settings, &entries);
        let scene = load_scene(&path, &mut MaterialLibrary::with_builtins())
            .unwrap_or_else(|e| panic!("{e}"));

        let names = |list: &[InteractionModel]| -> Vec<String> {
            list.iter().map(|i| i.name().to_string()).collect()
        };
        assert_eq!(names(&scene.interactions), names(&built.interactions));
        let mut kinds = (0, 0);
        for (a, b) in scene.interactions.iter().zip(&built.interactions) {
            let name = b.name();
            match (a, b) {
                (InteractionModel::Cohesive(a), InteractionModel::Cohesive(b)) => {
                    // The same bonds: nodes, areas, triangles, bonded points, normals and
                    // rest separations; the same law, on the same main surface.
                    assert_eq!(
                        format!("{:?}", a.bonds()),
                        format!("{:?}", b.bonds()),
                        "{name}"
                    );
                    assert_eq!(a.bonded_reference_area(), b.bonded_reference_area());
                    assert_eq!(format!("{:?}", a.law()), format!("{:?}", b.law()), "{name}");
                    assert_eq!(a.law().tangential(), law.tangential());
                    assert_eq!(main_bits(a.main()), main_bits(b.main()), "{name}");
                    kinds.0 += 1;
                }
                (InteractionModel::Contact(a), InteractionModel::Contact(b)) => {
                    // The same secondary nodes and triangles, each node's penalty, the
                    // same main surface, along its smooth normals.
                    assert_eq!(
                        surface_bits(a.secondary()),
                        surface_bits(b.secondary()),
                        "{name}"
                    );
                    let penalties = |c: &PenaltyContact| -> Vec<u64> {
                        (0..c.secondary().nodes.len())
                            .map(|i| c.node_penalty(i).to_bits())
                            .collect()
                    };
                    assert_eq!(penalties(a), penalties(b), "{name}");
                    assert_eq!(a.penalty().to_bits(), b.penalty().to_bits(), "{name}");
                    assert_eq!(main_bits(a.target()), main_bits(b.target()), "{name}");
                    assert!(a.smooth_normals() && b.smooth_normals(), "{name}");
                    kinds.1 += 1;
                }
                _ => panic!("{name}: the scene's is of another kind"),
            }
        }
        // Bonds between the vasti and the rectus and on the femur; contact of every
        // muscle with every other, both ways, and with the femur.
        let muscles = geometry.muscles.len();
        assert_eq!(
            kinds,
            (
                built.muscle_interfaces.len() + built.femur_interfaces.len(),
                muscles * (muscles - 1) + muscles
            )
        );
        assert!(built.muscle_interfaces.len() >= 3 && built.femur_interfaces.len() >= 3);
        // Tendon nodes press harder than belly nodes.
        let InteractionModel::Contact(contact) = &scene.interactions[kinds.0] else {
            panic!("a contact follows the bonds");
        };
        let nodes = contact.secondary().nodes.len();
        let lowest = (0..nodes)
            .map(|i| contact.node_penalty(i))
            .fold(f64::INFINITY, f64::min);
        let highest = (0..nodes)
            .map(|i| contact.node_penalty(i))
            .fold(0.0, f64::max);
        assert!(highest > 10.0 * lowest, "{lowest} {highest}");
        std::fs::remove_dir_all(&directory).unwrap();
    }
}

/// The Visible Human knee's scene (a 10° passive squat): its tet10 blocks as tet10-fbar
/// parts on the knee's nodes, the strands' attachments (nodes in no element) tied to the
/// patella through the first part, its interactions on the muscles' `_outer` surfaces,
/// and the strands as the knee builds them, bit for bit.
#[test]
fn the_visible_human_scene_carries_its_strands_and_their_attachments() {
    let squat = Squat {
        duration: 0.2,
        peak_flexion: 10f64.to_radians(),
    };
    let geometry = visible_human_geometry(Resolution::Coarse, &squat).unwrap();
    let fibers = geometry.fibers().unwrap();
    let knee = KneeModel::new(
        &geometry,
        &fibers,
        Activation::Passive,
        &squat,
        ElementChoice::Hex8Fbar,
    )
    .unwrap();
    let mut settings = SquatSettings::recommended(Solver::Implicit);
    settings.squat = squat;
    let law = InterfaceLaw::Sliding;
    let built = knee_interactions(&geometry, &knee.mesh, knee.material.as_ref(), law).unwrap();
    let entries = knee_interaction_entries(&geometry, &built, law).unwrap();
    let directory =
        std::env::temp_dir().join(format!("musclefem-knee-vh-scene-{}", std::process::id()));
    let scene_file = SquatScene {
        geometry: &geometry,
        mesh: &knee.mesh,
        activation: Activation::Passive,
        settings: &settings,
        interactions: entries,
    };
    std::fs::create_dir_all(&directory).unwrap();
    scene_file.write_files(&directory).unwrap();
    let path = directory.join("scene.toml");
    std::fs::write(&path, scene_file.text(0.05).unwrap()).unwrap();
    let scene =
        load_scene(&path, &mut MaterialLibrary::with_builtins()).unwrap_or_else(|e| panic!("{e}"));

    // Parts: tet10-fbar, on the knee's nodes (the attachments included).
    assert_eq!(scene.parts.len(), knee.parts.len());
    for (a, b) in scene.parts.iter().zip(&knee.parts) {
        assert_eq!(format!("{:?}", a.technology), format!("{:?}", b.technology));
        assert!(format!("{:?}", a.technology).contains("Tet10"));
    }
    assert_eq!(scene.mesh.node_count(), knee.mesh.node_count());
    // Ties: the insertions hold the attachment nodes, which no element holds.
    for (a, b) in scene.loads.rigid_ties.iter().zip(&knee.loads.rigid_ties) {
        assert_eq!((&a.name, &a.nodes), (&b.name, &b.nodes));
    }
    let attachments: Vec<u32> = geometry.strands.iter().map(|s| s.attachment).collect();
    for tie in scene
        .loads
        .rigid_ties
        .iter()
        .filter(|t| t.name.ends_with("_insertion"))
    {
        assert_eq!(tie.nodes.len(), 1, "{}", tie.name);
        assert!(attachments.contains(&tie.nodes[0]), "{}", tie.name);
    }
    // Interactions: the knee's, in its order, the strands last and the same.
    let names: Vec<String> = scene
        .interactions
        .iter()
        .map(|i| i.name().to_string())
        .collect();
    assert_eq!(names, built.names());
    let Some(InteractionModel::Strands(strands)) = scene.interactions.last() else {
        panic!("the strands come last");
    };
    let knee_strands = built.strands.as_ref().unwrap();
    assert_eq!(strands.strands(), knee_strands.strands());
    assert_eq!(strands.strands().len(), geometry.strands.len());
    std::fs::remove_dir_all(&directory).unwrap();
}
