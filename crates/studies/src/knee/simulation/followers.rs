//! The knee's follower kinds for scene files (`motion = { follower = "KIND", ... }` on a
//! `[[rigid_ties]]` or `[[rigid_bodies]]` entry), registered with `inventory`:
//!
//! - `knee-closed-chain`: a bone of the leg in the squat's closed chain
//!   ([`super::super::anatomy::closed_chain`]): its pose at time t is the chain's at the
//!   knee flexion θ(t) = θ_peak (1 − cos 2πt/T)/2. Parameters: `bone` ("femur", "tibia",
//!   "pelvis", or "pelvis-pin" with `pin` [m], a point carried with the pelvis without
//!   turning), `duration` T [s], `peak_flexion` θ_peak [rad], `ankle` (the pin at the
//!   tibia's distal end) and `hip` (the hip centre in the femur's frame) [m], both
//!   defaulting to the procedural knee's (they set the segment lengths), and the femur's
//!   rollback on the tibia ([`crate::knee::anatomy::rollback`]): `rollback_rate` k R_c
//!   [m/rad] and `rollback_end` θ_end [rad] (default: none, a fixed flexion axis).
//! - `knee-patella`: the patella held by the patellar tendon against the pull of the ties
//!   it moves (or of the ties `pulled_by` names) ([`TendonPatella`]), posed from the
//!   equilibrium table `table` (a CSV file beside the scene, [`PatellaTable::read_csv`]).
//!   Parameters: `table`, `duration`, `peak_flexion`, `ankle`, `hip` as above, the tendon
//!   `tendon_slack_length` [m], `tendon_stiffness` [N/m], `tendon_toe_strain` (defaults:
//!   the procedural knee's), and `pulled_by` (tie names).
//!
//! [`closed_chain_motion`] and [`patella_motion`] write the `motion` tables a scene takes.

use std::fmt::Write as _;
use std::sync::Arc;

use nalgebra::Vector3;

use musclefem_core::solver::PoseFollower;
use musclefem_io::csv::format_number;
use musclefem_io::scene::SceneError;
use musclefem_io::scene::{FollowerParameter, FollowerParameters, FollowerRegistration};

use super::patella::{PatellaTable, TendonPatella};
use crate::knee::anatomy::squat::{Bone, LegBone};
use crate::knee::anatomy::{ClosedChain, Rollback, Squat, TendonSpring};

/// The kind of a leg bone in the closed chain.
pub const CLOSED_CHAIN_KIND: &str = "knee-closed-chain";
/// The kind of the patella held by its tendon.
pub const PATELLA_KIND: &str = "knee-patella";

/// The parameters of the squat and the chain, shared by both kinds.
const SQUAT_PARAMETERS: [FollowerParameter; 6] = [
    FollowerParameter {
        name: "duration",
        description: "duration T of the squat 0 → peak → 0 [s]",
    },
    FollowerParameter {
        name: "peak_flexion",
        description: "peak knee flexion θ_peak [rad], in (0, 150°]",
    },
    FollowerParameter {
        name: "ankle",
        description: "the pin at the tibia's distal end [m]; default the procedural knee's",
    },
    FollowerParameter {
        name: "hip",
        description: "the hip centre in the femur's frame [m]; default the procedural knee's",
    },
    FollowerParameter {
        name: "rollback_rate",
        description: "the femur's rollback rate over the tibia at full extension [m/rad]; \
                      default 0 (a fixed flexion axis)",
    },
    FollowerParameter {
        name: "rollback_end",
        description: "the knee flexion at which rolling has given way to sliding [rad]",
    },
];

const CLOSED_CHAIN_PARAMETERS: [FollowerParameter; 8] = [
    FollowerParameter {
        name: "bone",
        description: "\"femur\", \"tibia\", \"pelvis\" or \"pelvis-pin\"",
    },
    FollowerParameter {
        name: "pin",
        description: "with \"pelvis-pin\": the point carried with the pelvis [m]",
    },
    SQUAT_PARAMETERS[0],
    SQUAT_PARAMETERS[1],
    SQUAT_PARAMETERS[2],
    SQUAT_PARAMETERS[3],
    SQUAT_PARAMETERS[4],
    SQUAT_PARAMETERS[5],
];

const PATELLA_PARAMETERS: [FollowerParameter; 11] = [
    FollowerParameter {
        name: "table",
        description: "the equilibrium table, a CSV file relative to the scene",
    },
    SQUAT_PARAMETERS[0],
    SQUAT_PARAMETERS[1],
    SQUAT_PARAMETERS[2],
    SQUAT_PARAMETERS[3],
    SQUAT_PARAMETERS[4],
    SQUAT_PARAMETERS[5],
    FollowerParameter {
        name: "tendon_slack_length",
        description: "the patellar tendon's slack length [m]; default the procedural knee's",
    },
    FollowerParameter {
        name: "tendon_stiffness",
        description: "its linear-region stiffness [N/m]; default the procedural knee's",
    },
    FollowerParameter {
        name: "tendon_toe_strain",
        description: "its toe region's spread strain; default the procedural knee's",
    },
    FollowerParameter {
        name: "pulled_by",
        description: "the ties whose reactions pull the patella; default the ties it moves",
    },
];

inventory::submit! {
    FollowerRegistration {
        kind: CLOSED_CHAIN_KIND,
        description: "a bone of the knee squat's closed chain (tibia pinned at the ankle, \
                      pelvis lowered), posed at the knee flexion θ(t)",
        parameters: &CLOSED_CHAIN_PARAMETERS,
        build: build_closed_chain,
    }
}

inventory::submit! {
    FollowerRegistration {
        kind: PATELLA_KIND,
        description: "the patella held by the patellar tendon against the pull of its ties, \
                      from an equilibrium table",
        parameters: &PATELLA_PARAMETERS,
        build: build_patella,
    }
}

/// The squat and the chain of a `motion` table.
fn squat_and_chain(p: &FollowerParameters<'_>) -> Result<(Squat, ClosedChain), SceneError> {
    let squat = Squat {
        duration: p.number("duration")?,
        peak_flexion: p.number("peak_flexion")?,
    };
    if squat.duration <= 0.0 {
        return Err(p.error("duration", format!("{} s must be positive", squat.duration)));
    }
    if !(squat.peak_flexion > 0.0 && squat.peak_flexion <= 150f64.to_radians()) {
        return Err(p.error(
            "peak_flexion",
            format!("{} rad must be in (0, 150°]", squat.peak_flexion),
        ));
    }
    let default = ClosedChain::procedural_knee();
    let rollback_rate = p.number_or("rollback_rate", 0.0)?;
    if rollback_rate < 0.0 || rollback_rate.is_nan() {
        return Err(p.error(
            "rollback_rate",
            format!("{rollback_rate} m/rad must be zero or positive"),
        ));
    }
    let rollback = if rollback_rate == 0.0 {
        Rollback::FIXED_AXIS
    } else {
        let end = p.number("rollback_end")?;
        if end <= 0.0 || end.is_nan() {
            return Err(p.error("rollback_end", format!("{end} rad must be positive")));
        }
        Rollback {
            rate: rollback_rate,
            end,
        }
    };
    let chain = ClosedChain {
        ankle: Vector3::from(p.vector_or("ankle", default.ankle.into())?),
        hip: Vector3::from(p.vector_or("hip", default.hip.into())?),
        rollback,
    };
    if (chain.hip - chain.ankle).norm() == 0.0 {
        return Err(p.whole_error("the ankle and the hip are the same point"));
    }
    Ok((squat, chain))
}

fn build_closed_chain(p: &FollowerParameters<'_>) -> Result<Arc<dyn PoseFollower>, SceneError> {
    let (squat, chain) = squat_and_chain(p)?;
    let bone = match p.text("bone")? {
        "femur" => Bone::Femur,
        "tibia" => Bone::Tibia,
        "pelvis" => Bone::Pelvis,
        "pelvis-pin" => Bone::PelvisPin(Vector3::from(p.vector("pin")?)),
        other => {
            return Err(p.error(
                "bone",
                format!("'{other}' is not a bone of the chain: femur, tibia, pelvis or pelvis-pin"),
            ));
        }
    };
    if p.has("pin") && !matches!(bone, Bone::PelvisPin(_)) {
        return Err(p.error("pin", "only a \"pelvis-pin\" takes a pin"));
    }
    Ok(Arc::new(LegBone { bone, chain, squat }))
}

fn build_patella(p: &FollowerParameters<'_>) -> Result<Arc<dyn PoseFollower>, SceneError> {
    let (squat, chain) = squat_and_chain(p)?;
    let default = TendonSpring::procedural_knee();
    let tendon = TendonSpring {
        slack_length: p.number_or("tendon_slack_length", default.slack_length)?,
        stiffness: p.number_or("tendon_stiffness", default.stiffness)?,
        toe_strain: p.number_or("tendon_toe_strain", default.toe_strain)?,
    };
    for (key, value) in [
        ("tendon_slack_length", tendon.slack_length),
        ("tendon_stiffness", tendon.stiffness),
    ] {
        if value <= 0.0 {
            return Err(p.error(key, format!("{value} must be positive")));
        }
    }
    let path = p.file("table")?;
    let table =
        PatellaTable::read_csv(&path, tendon).map_err(|e| p.error("table", format!("{e:#}")))?;
    let patella = TendonPatella::new(Arc::new(table), squat, chain);
    patella.pulled_by(
        p.ties("pulled_by")?
            .unwrap_or_else(|| p.followed_by().to_vec()),
    );
    Ok(Arc::new(patella))
}

/// `[f64; 3]` as a TOML list of round-trip numbers.
fn point(v: &Vector3<f64>) -> String {
    format!(
        "[{}, {}, {}]",
        format_number(v.x),
        format_number(v.y),
        format_number(v.z)
    )
}

/// The squat's and the chain's parameters as TOML key–value pairs (the rollback's only
/// when the chain has one).
fn squat_keys(squat: &Squat, chain: &ClosedChain) -> String {
    let mut keys = format!(
        "duration = {}, peak_flexion = {}, ankle = {}, hip = {}",
        format_number(squat.duration),
        format_number(squat.peak_flexion),
        point(&chain.ankle),
        point(&chain.hip)
    );
    if !chain.rollback.is_fixed_axis() {
        let _ = write!(
            keys,
            ", rollback_rate = {}, rollback_end = {}",
            format_number(chain.rollback.rate),
            format_number(chain.rollback.end)
        );
    }
    keys
}

/// The `motion` table (inline TOML) of `bone` in the closed `chain` over `squat`.
pub fn closed_chain_motion(bone: Bone, chain: &ClosedChain, squat: &Squat) -> String {
    let mut text = format!("{{ follower = \"{CLOSED_CHAIN_KIND}\", bone = ");
    let _ = match bone {
        Bone::Femur => write!(text, "\"femur\""),
        Bone::Tibia => write!(text, "\"tibia\""),
        Bone::Pelvis => write!(text, "\"pelvis\""),
        Bone::PelvisPin(pin) => write!(text, "\"pelvis-pin\", pin = {}", point(&pin)),
    };
    let _ = write!(text, ", {} }}", squat_keys(squat, chain));
    text
}

/// The `motion` table (inline TOML) of the patella on the table file `table` (relative
/// to the scene) with `tendon`, over `squat` with the femur placed by `chain`, pulled by
/// the ties it moves.
pub fn patella_motion(
    table: &str,
    tendon: &TendonSpring,
    chain: &ClosedChain,
    squat: &Squat,
) -> String {
    format!(
        "{{ follower = \"{PATELLA_KIND}\", table = {table:?}, {}, tendon_slack_length = {}, \
         tendon_stiffness = {}, tendon_toe_strain = {} }}",
        squat_keys(squat, chain),
        format_number(tendon.slack_length),
        format_number(tendon.stiffness),
        format_number(tendon.toe_strain)
    )
}

#[cfg(test)]
mod tests {
    use std::path::{Path, PathBuf};

    use nalgebra::Vector3;

    use musclefem_core::solver::{RigidReaction, tie_followers};
    use musclefem_io::scene::load_scene;
    use musclefem_materials::MaterialLibrary;

    use super::*;
    use crate::knee::anatomy::{KneeKinematics, Quadriceps};

    /// A fresh folder for one test's scene.
    fn folder(name: &str) -> PathBuf {
        let path = std::env::temp_dir().join(format!(
            "musclefem-knee-followers-{}-{name}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).unwrap();
        path
    }

    /// A shallow squat's table (0° … 6°).
    fn table() -> PatellaTable {
        let kinematics = KneeKinematics::new(Quadriceps::ALL.iter().map(|m| m.pull()).collect());
        PatellaTable::new(
            &kinematics,
            TendonSpring::procedural_knee(),
            5f64.to_radians(),
        )
        .unwrap()
    }

    fn squat() -> Squat {
        Squat {
            duration: 0.4,
            peak_flexion: 5f64.to_radians(),
        }
    }

    /// A block tied at its x0 face to the femur, at y0 to a pin of the pelvis and at x1
    /// and y1 to the patella; the patella and the tibia as rigid planes.
    fn scene_text(chain: &ClosedChain) -> String {
        let squat = squat();
        let pin = Vector3::new(0.01, 0.3, 0.0);
        let patella = patella_motion(
            "patella_table.csv",
            &TendonSpring::procedural_knee(),
            chain,
            &squat,
        );
        let motion = |bone| closed_chain_motion(bone, chain, &squat);
        let tie = |name: &str, nodes: &str, motion: &str| {
            format!(
                "[[rigid_ties]]\nname = \"{name}\"\npart = \"block\"\nnodes = \"{nodes}\"\nmotion = {motion}\n\n"
            )
        };
        let plane = |name: &str, motion: &str| {
            format!(
                "[[rigid_bodies]]\nname = \"{name}\"\nsurface = {{ shape = \"plane\", point = [0.0, 0.0, 0.0], \
                 normal = [1.0, 0.0, 0.0], half_size = 0.01 }}\nmotion = {motion}\n\n"
            )
        };
        format!(
            "schema_version = 1\n\n[[materials]]\nname = \"muscle\"\nmodel = \"neo-hookean\"\n\n\
             [[parts]]\nname = \"block\"\nmaterial = \"muscle\"\nelement = \"hex8-full\"\ndensity = 1060.0\n\
             mesh = {{ generator = \"box\", size = [0.01, 0.01, 0.01], divisions = [1, 1, 1] }}\n\n{}{}{}{}{}{}\
             [step]\nsolver = \"implicit\"\nduration = 0.4\n",
            tie("femur_origin", "x0", &motion(Bone::Femur)),
            tie("rf_origin", "y0", &motion(Bone::PelvisPin(pin))),
            tie("a_insertion", "x1", &patella),
            tie("b_insertion", "y1", &patella),
            plane("patella", &patella),
            plane("tibia", &motion(Bone::Tibia)),
        )
    }

    /// Write the scene `text` and the table into `folder`; the scene's path.
    fn write(folder: &Path, text: &str) -> PathBuf {
        table()
            .write_csv(&folder.join("patella_table.csv"))
            .unwrap();
        let path = folder.join("scene.toml");
        std::fs::write(&path, text).unwrap();
        path
    }

    fn load(path: &Path) -> Result<musclefem_io::scene::Model, String> {
        load_scene(path, &mut MaterialLibrary::with_builtins()).map_err(|e| e.to_string())
    }

    #[test]
    fn a_scene_with_both_kinds_builds_the_knees_followers() {
        let chain = ClosedChain {
            ankle: Vector3::new(0.001, -0.39, 0.0),
            hip: Vector3::new(0.01, 0.44, -0.005),
            rollback: Rollback::rolling(0.0196, 1.0, 60f64.to_radians()),
        };
        let model = load(&write(&folder("both"), &scene_text(&chain))).unwrap();
        let squat = squat();
        let ties = &model.loads.rigid_ties;
        let bone = |bone| LegBone { bone, chain, squat };
        let pin = Vector3::new(0.01, 0.3, 0.0);
        let times = [0.0, 0.05, 0.2, 0.33];
        for time in times {
            assert_eq!(
                ties[0].motion.isometry_at(time),
                bone(Bone::Femur).isometry_at(time)
            );
            assert_eq!(
                ties[1].motion.isometry_at(time),
                bone(Bone::PelvisPin(pin)).isometry_at(time)
            );
            assert_eq!(
                model.rigid_bodies[1].motion.isometry_at(time),
                bone(Bone::Tibia).isometry_at(time)
            );
        }
        assert_eq!(ties[0].motion.reference_point_at(0.0), Vector3::zeros());
        // One patella for both insertions and the rigid body, pulled by the insertions.
        let patella = ties[2].motion.follower.clone().unwrap();
        assert!(Arc::ptr_eq(
            &patella,
            ties[3].motion.follower.as_ref().unwrap()
        ));
        assert!(Arc::ptr_eq(
            &patella,
            model.rigid_bodies[0].motion.follower.as_ref().unwrap()
        ));
        assert_eq!(tie_followers(ties).len(), 3);
        let reaction = |x: f64| RigidReaction {
            force: Vector3::new(x, 0.0, 0.0),
            moment: Vector3::zeros(),
        };
        patella.observe(
            0.1,
            &[
                reaction(5000.0),
                reaction(-7000.0),
                reaction(300.0),
                reaction(-400.0),
            ],
        );
        // The same patella built in code, told of the insertions' pull 300 + 400 N.
        let expected = TendonPatella::new(Arc::new(table()), squat, chain);
        expected.report(0.1, 700.0);
        assert!(expected.tension_at(0.2) > 100.0);
        for time in [0.1, 0.2, 0.3] {
            assert_eq!(patella.isometry_at(time), expected.isometry_at(time));
        }
        assert_eq!(patella.reference_point(), expected.reference_point());
    }

    #[test]
    fn a_bad_kind_or_parameter_names_the_file_the_line_and_the_key() {
        let chain = ClosedChain::procedural_knee();
        let text = scene_text(&chain);
        let line_of = |fragment: &str| text.lines().position(|l| l.contains(fragment)).unwrap() + 1;
        let folder = folder("bad");
        let cases = [
            (
                "bone = \"femur\"",
                "bone = \"knee\"",
                "`bone`: 'knee' is not a bone of the chain",
            ),
            (
                "bone = \"tibia\"",
                "bone = \"tibia\", pin = [0.0, 0.0, 0.0]",
                "`pin`: only a \"pelvis-pin\" takes a pin",
            ),
            (
                "knee-closed-chain\", bone = \"femur\"",
                "knee-closed-chains\", bone = \"femur\"",
                "unknown follower kind 'knee-closed-chains' (did you mean `knee-closed-chain`?); known: knee-closed-chain, knee-patella",
            ),
            (
                "table = \"patella_table.csv\"",
                "table = \"missing.csv\"",
                "`table`: reading",
            ),
            (
                "tendon_toe_strain",
                "tendon_toe_stran",
                "has no parameter `tendon_toe_stran` (did you mean `tendon_toe_strain`?)",
            ),
            (
                "bone = \"tibia\"",
                "bone = \"tibia\", rollback_rate = -0.02",
                "`rollback_rate`: -0.02 m/rad must be zero or positive",
            ),
            (
                "bone = \"tibia\"",
                "bone = \"tibia\", rollback_rate = 0.02, rollback_end = 0.0",
                "`rollback_end`: 0 rad must be positive",
            ),
        ];
        for (from, to, fragment) in cases {
            let line = line_of(from);
            let path = write(&folder, &text.replacen(from, to, 1));
            let message = load(&path).err().unwrap_or_default();
            let location = format!("{}:{line}:", path.display());
            assert!(
                message.starts_with(&location) && message.contains(fragment),
                "{to}: got \"{message}\", expected {location} … {fragment}"
            );
        }
        // A table off the knee's grid.
        let path = write(&folder, &text);
        let table = std::fs::read_to_string(folder.join("patella_table.csv")).unwrap();
        std::fs::write(
            folder.join("patella_table.csv"),
            table.replacen("\n0,0.01,", "\n0,0.015,", 1),
        )
        .unwrap();
        let message = load(&path).unwrap_err();
        assert!(
            message.contains("`table`")
                && message.contains("line 3: knee flexion 0 rad and strain 0.015"),
            "{message}"
        );
    }
}
