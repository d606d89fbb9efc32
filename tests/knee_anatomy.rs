//! The procedural knee anatomy against the reference data of `../shared/data/knee_reference/`:
//! the quadriceps' knee-extensor moment arms and musculotendon excursions against the
//! Rajagopal–Lai–Uhlrich 2023 OpenSim model, their volumes against the Visible Human
//! Male (Andreassen et al. 2023), and the geometric soundness of bones, muscles and
//! kinematics (closed bones, no overlaps, the patella on its groove, the squat's drive).

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::OnceLock;

use nalgebra::Vector3;

use musclefem_studies::knee::anatomy::ClosedChain;
use musclefem_studies::knee::anatomy::bones::{femur_distance, tibia_distance};
use musclefem_studies::knee::anatomy::dimensions::{APEX, MM, PATELLAR_TENDON_LENGTH};
use musclefem_studies::knee::anatomy::moment_arms::{
    hip_length_change, lengths_at, moment_arms_at,
};
use musclefem_studies::knee::{Anatomy, Quadriceps, Resolution, Squat};

fn data_file(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data/knee_reference")
        .join(name)
}

/// The rows of a CSV with a header line, as maps from column name to field.
fn read_csv(name: &str) -> Vec<HashMap<String, String>> {
    let path = data_file(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "reference data {} is missing ({e}); it lives in ../shared/data beside the checkout",
            path.display()
        )
    });
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|h| h.trim().to_string())
        .collect();
    lines
        .map(|line| {
            header
                .iter()
                .cloned()
                .zip(line.split(',').map(|f| f.trim().to_string()))
                .collect()
        })
        .collect()
}

/// The Rajagopal–Lai–Uhlrich column prefix of a muscle.
fn rajagopal_name(muscle: Quadriceps) -> &'static str {
    match muscle {
        Quadriceps::VastusIntermedius => "vasint_r",
        Quadriceps::VastusLateralis => "vaslat_r",
        Quadriceps::VastusMedialis => "vasmed_r",
        Quadriceps::RectusFemoris => "recfem_r",
    }
}

/// (knee flexion [deg], musculotendon length [m], moment arm [m]) of `muscle` in the
/// Rajagopal–Lai–Uhlrich table.
fn rajagopal(muscle: Quadriceps) -> Vec<(f64, f64, f64)> {
    let prefix = rajagopal_name(muscle);
    read_csv("rajagopal_lai_uhlrich2023_quadriceps_vs_knee.csv")
        .iter()
        .map(|row| {
            let get = |column: &str| -> f64 { row[column].parse().unwrap() };
            (
                get("knee_flexion_deg"),
                get(&format!("{prefix}_mtu_length_m")),
                get(&format!("{prefix}_knee_extensor_moment_arm_m")),
            )
        })
        .collect()
}

fn anatomy() -> &'static Anatomy {
    static ANATOMY: OnceLock<Anatomy> = OnceLock::new();
    ANATOMY.get_or_init(|| Anatomy::procedural_knee(Resolution::Coarse).unwrap())
}

#[test]
fn moment_arms_match_rajagopal_lai_uhlrich() {
    let anatomy = anatomy();
    let angles = [0.0, 30.0, 60.0, 90.0];
    let ours: Vec<Vec<f64>> = angles
        .iter()
        .map(|a: &f64| {
            moment_arms_at(&anatomy.kinematics, &anatomy.muscles, a.to_radians()).unwrap()
        })
        .collect();
    println!(
        "knee-extensor moment arm r = dL/dθ [mm]: ours / Rajagopal–Lai–Uhlrich 2023 / difference"
    );
    println!(
        "{:>6} {:>26} {:>26} {:>26} {:>26}",
        "θ [°]", "VI", "VL", "VM", "RF"
    );
    let mut worst: f64 = 0.0;
    for (k, &angle) in angles.iter().enumerate() {
        let mut line = format!("{angle:>6.0}");
        for (m, muscle) in anatomy.muscles.iter().enumerate() {
            let reference = rajagopal(muscle.muscle)
                .into_iter()
                .find(|row| row.0 == angle)
                .unwrap()
                .2;
            let difference = ours[k][m] / reference - 1.0;
            worst = worst.max(difference.abs());
            line += &format!(
                " {:>8.1} / {:>5.1} / {:>+5.1}%",
                ours[k][m] / MM,
                reference / MM,
                100.0 * difference
            );
        }
        println!("{line}");
    }
    println!("largest difference: {:.1} %", 100.0 * worst);
    // The aim: every muscle within 15 % at 0°, 30°, 60° and 90°.
    assert!(
        worst <= 0.15,
        "a moment arm differs by {:.1} %",
        100.0 * worst
    );
}

#[test]
fn musculotendon_excursions_match_rajagopal_lai_uhlrich() {
    let anatomy = anatomy();
    let extended = lengths_at(&anatomy.kinematics, &anatomy.muscles, 0.0).unwrap();
    let flexed = lengths_at(&anatomy.kinematics, &anatomy.muscles, 90f64.to_radians()).unwrap();
    println!(
        "musculotendon length L(0°) and excursion L(90°) − L(0°) [mm]: ours / Rajagopal–Lai–Uhlrich"
    );
    let mut worst: f64 = 0.0;
    for (m, muscle) in anatomy.muscles.iter().enumerate() {
        let table = rajagopal(muscle.muscle);
        let (l0, l90) = (table[0].1, table.iter().find(|r| r.0 == 90.0).unwrap().1);
        let excursion = flexed[m].total - extended[m].total;
        let difference = excursion / (l90 - l0) - 1.0;
        worst = worst.max(difference.abs());
        println!(
            "{}: L(0°) {:6.1} / {:6.1}   ΔL {:5.1} / {:5.1} ({:+5.1} %){}",
            muscle.muscle.abbreviation(),
            extended[m].total / MM,
            l0 / MM,
            excursion / MM,
            (l90 - l0) / MM,
            100.0 * difference,
            if flexed[m].wrapped {
                "   wraps at 90°"
            } else {
                ""
            }
        );
    }
    assert!(
        worst <= 0.15,
        "an excursion differs by {:.1} %",
        100.0 * worst
    );
}

/// The Visible Human Male's volume [m³] of the mesh-statistics row whose file name
/// contains `needle`.
fn visible_human_volume(needle: &str) -> f64 {
    let rows = read_csv("visible_human_andreassen2023_quadriceps_mesh_stats.csv");
    let row = rows
        .iter()
        .find(|r| r["file"].contains(needle) && r["status"] == "ok")
        .unwrap_or_else(|| panic!("no row for {needle}"));
    1e-6 * row["volume_cm3"].parse::<f64>().unwrap()
}

fn visible_human_file(muscle: Quadriceps) -> &'static str {
    match muscle {
        Quadriceps::VastusIntermedius => "VHM_Right_Muscle_VastusIntermedius",
        Quadriceps::VastusLateralis => "VHM_Right_Muscle_VastusLateralis",
        Quadriceps::VastusMedialis => "VHM_Right_Muscle_VastusMedialis",
        // The VHM's right rectus femoris is absent from the data: its left one.
        Quadriceps::RectusFemoris => "VHM_Left_Muscle_RectusFemoris",
    }
}

#[test]
fn muscle_volumes_match_the_visible_human_at_every_resolution() {
    for resolution in [Resolution::Coarse, Resolution::Medium, Resolution::Fine] {
        let anatomy = if resolution == Resolution::Coarse {
            anatomy().clone()
        } else {
            Anatomy::procedural_knee(resolution).unwrap()
        };
        let (n, m, axial) = resolution.muscle_divisions();
        for muscle in &anatomy.muscles {
            let reference = visible_human_volume(visible_human_file(muscle.muscle));
            // The belly: its block's mesh volume against its solid's and the VHM's.
            let belly = muscle.belly_block();
            let volume = muscle.mesh.block_volume(belly).expect("the belly's volume");
            let solid = muscle.solid.volume_between(muscle.belly.0, muscle.belly.1);
            let tendon = muscle.mesh.total_volume().unwrap() - volume;
            println!(
                "{resolution:?} {}: belly {} hex8, mesh {:.1} cm³, solid {:.1} cm³, VHM {:.1} \
                 cm³ ({:+.2} %); tendons {} hex8, {:.1} cm³",
                muscle.muscle.abbreviation(),
                muscle.mesh.blocks[belly].len(),
                volume * 1e6,
                solid * 1e6,
                reference * 1e6,
                100.0 * (volume / reference - 1.0),
                muscle.mesh.element_count() - muscle.mesh.blocks[belly].len(),
                tendon * 1e6,
            );
            assert_eq!(muscle.mesh.blocks[belly].len(), (n * n + 4 * n * m) * axial);
            muscle.mesh.validate().unwrap();
            assert!(
                (volume / reference - 1.0).abs() < 0.10,
                "{:?}",
                muscle.muscle
            );
            assert!((solid / reference - 1.0).abs() < 1e-4);
            // Tendons: a few percent of the muscle, not a second muscle.
            assert!(tendon > 0.0 && tendon < 0.1 * volume, "{:?}", muscle.muscle);
        }
    }
}

#[test]
fn the_rectus_femoris_stays_nearly_isometric_when_the_hip_flexes_with_the_knee() {
    // Rajagopal–Lai–Uhlrich 2023: the rectus with hip flexion = knee flexion (the
    // closed-chain squat's pelvis tilts with the tibia, see `closed_chain`).
    let anatomy = anatomy();
    let rectus = anatomy.muscle(Quadriceps::RectusFemoris);
    let index = anatomy
        .muscles
        .iter()
        .position(|m| m.muscle == Quadriceps::RectusFemoris)
        .unwrap();
    let rows = read_csv("rajagopal_lai_uhlrich2023_recfem_hip_knee.csv");
    let reference = |knee: f64, hip: f64| -> f64 {
        rows.iter()
            .find(|r| {
                r["knee_flexion_deg"].parse::<f64>().unwrap() == knee
                    && r["hip_flexion_deg"].parse::<f64>().unwrap() == hip
            })
            .unwrap()["recfem_r_mtu_length_m"]
            .parse()
            .unwrap()
    };
    let ours = |degrees: f64, hip: f64| -> f64 {
        let knee = lengths_at(&anatomy.kinematics, &anatomy.muscles, degrees.to_radians()).unwrap()
            [index]
            .total;
        knee + hip_length_change(rectus, hip.to_radians())
    };
    println!("rectus femoris length change from 0° [mm]: ours / Rajagopal–Lai–Uhlrich");
    for degrees in [30.0, 60.0, 90.0] {
        let squat = (ours(degrees, degrees) - ours(0.0, 0.0)) / MM;
        let squat_reference = (reference(degrees, degrees) - reference(0.0, 0.0)) / MM;
        let knee_only = (ours(degrees, 0.0) - ours(0.0, 0.0)) / MM;
        let knee_only_reference = (reference(degrees, 0.0) - reference(0.0, 0.0)) / MM;
        println!(
            "  {degrees:.0}°: hip = knee {squat:+6.1} / {squat_reference:+6.1}, hip at 0° \
             {knee_only:+6.1} / {knee_only_reference:+6.1}"
        );
        // Nearly isometric in the squat: within a sixth of the knee-only excursion of the
        // reference (11 mm at 90°), and far from the knee-only stretch.
        assert!(
            (squat - squat_reference).abs() < knee_only_reference / 6.0,
            "{degrees}°: {squat:.1} mm against {squat_reference:.1} mm"
        );
    }
}

#[test]
fn bones_are_closed_outward_surfaces() {
    let bones = &anatomy().bones;
    for (name, bone) in [
        ("femur", &bones.femur),
        ("tibia", &bones.tibia),
        ("patella", &bones.patella),
    ] {
        bone.check_closed()
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let (lower, upper) = bone.bounds();
        println!(
            "{name}: {} triangles, {:.1} cm³, {:.0} cm², extent {:.0} × {:.0} × {:.0} mm",
            bone.triangles.len(),
            bone.volume() * 1e6,
            bone.area() * 1e4,
            (upper - lower).x / MM,
            (upper - lower).y / MM,
            (upper - lower).z / MM
        );
        assert!(bone.volume() > 0.0, "{name} is inside out");
    }
    // The tibia swings about the condyles without touching the femur (the 2 mm left
    // for cartilage): its vertices stay outside the femur from 0° to 120°.
    for degrees in [0.0, 20.0, 45.0, 70.0, 90.0, 120.0] {
        let motion = anatomy()
            .kinematics
            .tibia_isometry(f64::to_radians(degrees));
        let clearance = bones
            .tibia
            .vertices
            .iter()
            .map(|v| femur_distance(&(motion * nalgebra::Point3::from(*v)).coords))
            .fold(f64::INFINITY, f64::min);
        println!(
            "tibia–femur clearance at {degrees:.0}°: {:.2} mm",
            clearance / MM
        );
        assert!(clearance > 0.5 * MM, "{degrees}°: {clearance}");
    }
    // The patella's 25 cm³ is the VHM's right patella's.
    let patella = visible_human_volume("VHM_Right_Bone_Patella");
    assert!((bones.patella.volume() / patella - 1.0).abs() < 0.01);
    // Adult femur (about 490 mm) and tibia (about 400 mm) lengths.
    let (low, high) = bones.femur.bounds();
    assert!(((high - low).y - 0.490).abs() < 0.005);
    let (low, high) = bones.tibia.bounds();
    assert!(((high - low).y - 0.389).abs() < 0.005);
}

/// The muscles' lateral surfaces: every node of the `lateral` set of each mesh.
fn lateral_nodes(anatomy: &Anatomy, index: usize) -> Vec<Vector3<f64>> {
    let mesh = &anatomy.muscles[index].mesh;
    mesh.node_set("lateral")
        .unwrap()
        .iter()
        .map(|&id| mesh.nodes.position(id as usize))
        .collect()
}

#[test]
fn muscles_neither_overlap_each_other_nor_the_femur_and_neighbours_touch() {
    let anatomy = anatomy();
    // Signed distances [mm] from each muscle's lateral surface nodes to the femur and to
    // every other muscle's solid: the smallest is the deepest overlap if negative, the
    // narrowest gap if positive.
    let mut closest = HashMap::new();
    for (i, muscle) in anatomy.muscles.iter().enumerate() {
        let nodes = lateral_nodes(anatomy, i);
        let femur = nodes
            .iter()
            .map(femur_distance)
            .fold(f64::INFINITY, f64::min);
        closest.insert((muscle.muscle.abbreviation(), "femur"), femur / MM);
        for other in &anatomy.muscles {
            if other.muscle != muscle.muscle {
                let d = nodes
                    .iter()
                    .map(|p| other.solid.signed_distance(p))
                    .fold(f64::INFINITY, f64::min);
                closest.insert(
                    (muscle.muscle.abbreviation(), other.muscle.abbreviation()),
                    d / MM,
                );
            }
        }
    }
    let mut pairs: Vec<_> = closest.iter().collect();
    pairs.sort_by(|a, b| a.0.cmp(b.0));
    for ((a, b), d) in &pairs {
        println!("{a} → {b}: {d:+.2} mm");
    }
    // The coarse mesh's corners lie 1.3 % outside the ellipses (area-preserving
    // sections): allow 1 mm of overlap.
    for ((a, b), d) in &pairs {
        assert!(**d > -1.0, "{a} overlaps {b} by {:.2} mm", -**d);
    }
    // Neighbours to be bonded by cohesive contact are within 2 mm (touching, or
    // nearly).
    for (a, b) in [
        ("VI", "femur"),
        ("VL", "femur"),
        ("VM", "femur"),
        ("VI", "RF"),
        ("VI", "VL"),
        ("VI", "VM"),
    ] {
        assert!(
            closest[&(a, b)] < 2.0,
            "{a} and {b} are {:.2} mm apart",
            closest[&(a, b)]
        );
    }
}

#[test]
fn the_patella_rides_the_groove_on_an_inextensible_tendon() {
    let anatomy = anatomy();
    let kinematics = &anatomy.kinematics;
    let reference = anatomy.patella_reference.isometry().inverse();
    println!(
        "θ [°]  patellar flexion [°]  tendon angle [°] (van Eijden et al. 1985)  clearance [mm]"
    );
    let van_eijden = [(0.0, 20.6), (30.0, 13.7), (60.0, 5.0), (90.0, -6.6)];
    let mut previous = f64::NEG_INFINITY;
    for degrees in [0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0] {
        let angle = f64::to_radians(degrees);
        let pose = kinematics.patella_pose(angle).unwrap();
        // The tendon keeps its length.
        let tendon = (pose.to_world(&APEX) - kinematics.tuberosity(angle)).norm();
        assert!((tendon - PATELLAR_TENDON_LENGTH).abs() < 1e-9 * PATELLAR_TENDON_LENGTH);
        // The patella touches the femur without entering it.
        let patella = anatomy
            .bones
            .patella
            .transformed(&(pose.isometry() * reference));
        let clearance = patella
            .vertices
            .iter()
            .map(femur_distance)
            .fold(f64::INFINITY, f64::min);
        // and stays clear of the tibia.
        let tibia = anatomy.kinematics.tibia_isometry(angle).inverse();
        let tibia_clearance = patella
            .vertices
            .iter()
            .map(|v| tibia_distance(&(tibia * nalgebra::Point3::from(*v)).coords))
            .fold(f64::INFINITY, f64::min);
        let tendon_angle = kinematics.patellar_tendon_angle(angle, &pose).to_degrees();
        let measured = van_eijden.iter().find(|r| r.0 == degrees).map(|r| r.1);
        println!(
            "{degrees:5.0} {:12.1} {:14.1} {:>12} {:14.2}",
            pose.flexion.to_degrees(),
            tendon_angle,
            measured.map_or(String::new(), |m| format!("({m:.1})")),
            clearance / MM
        );
        assert!(clearance.abs() < MM, "{degrees}°: {clearance}");
        assert!(
            tibia_clearance > 0.0,
            "{degrees}°: the patella enters the tibia"
        );
        // The tendon's angle to the tibia within 12° of van Eijden's cadaver data.
        if let Some(m) = measured {
            assert!(
                (tendon_angle - m).abs() < 12.0,
                "{degrees}°: {tendon_angle} against {m}"
            );
        }
        // The quadriceps' lever: the tendon's force over the quadriceps' (volume-weighted
        // moment arm over the tendon's moment arm about the flexion axis).
        let arms = moment_arms_at(kinematics, &anatomy.muscles, angle).unwrap();
        let weights: Vec<f64> = anatomy
            .muscles
            .iter()
            .map(|m| m.muscle.visible_human_volume())
            .collect();
        let lever = arms.iter().zip(&weights).map(|(r, w)| r * w).sum::<f64>()
            / weights.iter().sum::<f64>();
        let tuberosity = kinematics.tuberosity(angle);
        let direction = (pose.to_world(&APEX) - tuberosity).normalize();
        let tendon_arm = tuberosity.cross(&direction).z.abs();
        let ratio = lever / tendon_arm;
        println!(
            "      force ratio tendon / quadriceps {ratio:.2} (tendon moment arm {:.1} mm)",
            tendon_arm / MM
        );
        if degrees == 0.0 {
            assert!((0.85..1.2).contains(&ratio), "{ratio}");
        }
        if degrees == 90.0 {
            assert!((0.4..0.8).contains(&ratio), "{ratio}");
        }
        // Patellar flexion grows with knee flexion, lagging it.
        assert!(
            pose.flexion > previous && pose.flexion < angle,
            "{degrees}°"
        );
        previous = pose.flexion;
    }
    // About 50–70° of patellar flexion at 90° of knee flexion (0.57 θ here; the
    // Rajagopal model's patella, from Delp et al. 1990's data, is at 72°).
    assert!(
        (45.0..75.0).contains(&previous.to_degrees()),
        "{}",
        previous.to_degrees()
    );
}

#[test]
fn the_squat_moves_the_bones_as_the_closed_chain_says() {
    let anatomy = anatomy();
    let squat = Squat::to_ninety_degrees(2.0);
    let chain = ClosedChain::procedural_knee();
    let motions = squat.motions(&chain).unwrap();
    for time in [0.0, 0.25, 0.5, 0.77, 1.0, 1.5, 2.0] {
        let angle = squat.flexion_at(time);
        // In the femur's frame the tibia turns about the flexion axis as the kinematics
        // say: the tuberosity is where the knee's kinematics put it.
        let femur = motions.femur.isometry_at(time);
        let tuberosity = femur.inverse_transform_point(&nalgebra::Point3::from(
            motions
                .tibia
                .position_at(&anatomy.patellar_tendon.tuberosity, time),
        ));
        assert!((tuberosity.coords - anatomy.kinematics.tuberosity(angle)).norm() < 1e-9);
        // The ankle pin stays; the hip centre goes straight down.
        assert!((motions.tibia.position_at(&chain.ankle, time) - chain.ankle).norm() < 1e-12);
        let hip = motions.pelvis.position_at(&chain.hip, time);
        assert!((hip.x - chain.hip.x).abs() < 1e-9 && hip.y <= chain.hip.y + 1e-12);
    }
    assert!((squat.flexion_at(1.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    assert_eq!(squat.flexion_at(2.0), squat.flexion_at(0.0));
    // At 90° the hip has come down by about 30 cm with the tibia 48° forward.
    let deep = chain.pose(std::f64::consts::FRAC_PI_2);
    println!(
        "at 90°: tibia {:.1}° forward, hip {:.1}°, pelvis {:.0} mm lower",
        deep.tibia_tilt.to_degrees(),
        deep.hip_flexion.to_degrees(),
        (chain.pelvis_height(0.0) - chain.pelvis_height(std::f64::consts::FRAC_PI_2)) / MM
    );
}

#[test]
fn the_anatomy_is_written_at_0_45_and_90_degrees() {
    let anatomy = anatomy();
    let directory =
        std::env::temp_dir().join(format!("musclefem_knee_anatomy_{}", std::process::id()));
    musclefem_studies::knee::anatomy::export::write_anatomy(
        anatomy,
        &directory,
        &[0.0, 45.0, 90.0],
    )
    .unwrap();
    for name in [
        "muscles.vtu",
        "femur.stl",
        "tibia_45deg.stl",
        "patella_90deg.stl",
        "paths_0deg.vtk",
        "paths_90deg.vtk",
    ] {
        let text = std::fs::read_to_string(directory.join(name)).unwrap();
        assert!(text.len() > 100, "{name}");
    }
    let paths = std::fs::read_to_string(directory.join("paths_90deg.vtk")).unwrap();
    assert!(paths.contains("LINES 5 "));
    std::fs::remove_dir_all(&directory).unwrap();
}
