//! Registered follower kinds in scene files (`motion = { follower = "KIND", ... }`): a
//! kind registered here (a body turning about z at a rate, which counts the pulls it
//! hears) builds from its parameters, ties with the same table share one follower that
//! knows them, a rigid body with that table moves with them, and every mistake names the
//! file, the line and the key.

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use musclefem_core::solver::{PoseFollower, RigidReaction, tie_followers};
use musclefem_io::scene::{
    FollowerParameter, FollowerParameters, FollowerRegistration, Model, SceneError, build_model,
    follower_kinds, parse_scene,
};
use musclefem_materials::MaterialLibrary;

/// Turns about the z axis through `center` at `rate` [rad/s]; remembers the ties it
/// moves (its `Debug` text shows them) and how many observations it heard.
#[derive(Debug)]
#[allow(dead_code)]
struct Turning {
    center: Vector3<f64>,
    rate: f64,
    followed_by: Vec<usize>,
    observed: AtomicUsize,
}

impl PoseFollower for Turning {
    fn isometry_at(&self, time: f64) -> Isometry3<f64> {
        let rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), self.rate * time);
        Isometry3::from_parts(
            Translation3::from(self.center - rotation * self.center),
            rotation,
        )
    }
    fn reference_point(&self) -> Vector3<f64> {
        self.center
    }
    fn observe(&self, _time: f64, _tie_reactions: &[RigidReaction]) {
        self.observed.fetch_add(1, Ordering::Relaxed);
    }
}

fn build_turning(p: &FollowerParameters<'_>) -> Result<Arc<dyn PoseFollower>, SceneError> {
    let rate = p.number("rate")?;
    if rate < 0.0 {
        return Err(p.error("rate", "must not be negative"));
    }
    Ok(Arc::new(Turning {
        center: Vector3::from(p.vector_or("center", [0.0; 3])?),
        rate,
        followed_by: p
            .ties("pulled_by")?
            .unwrap_or_else(|| p.followed_by().to_vec()),
        observed: AtomicUsize::new(0),
    }))
}

inventory::submit! {
    FollowerRegistration {
        kind: "test-turning",
        description: "turns about z through `center` at `rate`",
        parameters: &[
            FollowerParameter { name: "rate", description: "[rad/s]" },
            FollowerParameter { name: "center", description: "[m], default the origin" },
            FollowerParameter { name: "pulled_by", description: "tie names" },
        ],
        build: build_turning,
    }
}

const SCENE: &str = r#"schema_version = 1

[[materials]]
name = "rubber"
model = "neo-hookean"

[[parts]]
name = "cube"
material = "rubber"
element = "hex8-full"
density = 1000.0
mesh = { generator = "box", size = [0.01, 0.01, 0.01], divisions = [1, 1, 1] }

[[rigid_ties]]
name = "left"
part = "cube"
nodes = "x0"
motion = { follower = "test-turning", rate = 2, center = [0.01, 0.0, 0.0] }

[[rigid_ties]]
name = "right"
part = "cube"
nodes = "x1"
motion = { follower = "test-turning", rate = 2, center = [0.01, 0.0, 0.0] }

[[rigid_ties]]
name = "bottom"
part = "cube"
nodes = "y0"
motion = { follower = "test-turning", rate = 3.0 }

[[rigid_bodies]]
name = "wall"
surface = { shape = "plane", point = [0.02, 0.0, 0.0], normal = [-1.0, 0.0, 0.0], half_size = 0.01 }
motion = { follower = "test-turning", rate = 2, center = [0.01, 0.0, 0.0] }

[step]
solver = "implicit"
duration = 1.0
"#;

fn build(text: &str) -> Result<Model, String> {
    let (scene, locator) = parse_scene(text, Path::new("s.toml")).map_err(|e| e.to_string())?;
    build_model(&scene, &locator, &mut MaterialLibrary::with_builtins()).map_err(|e| e.to_string())
}

/// What a follower built here was built with (its `Debug` text: `Turning { .. }`).
fn described(follower: &Arc<dyn PoseFollower>) -> String {
    format!("{follower:?}")
}

#[test]
fn the_kind_is_registered() {
    let kinds: Vec<&str> = follower_kinds().iter().map(|k| k.kind).collect();
    assert_eq!(kinds, vec!["test-turning"]);
}

#[test]
fn ties_with_the_same_table_share_one_follower_which_knows_them() {
    let model = build(SCENE).unwrap();
    let ties = &model.loads.rigid_ties;
    let follower = |i: usize| ties[i].motion.follower.clone().unwrap();
    assert!(Arc::ptr_eq(&follower(0), &follower(1)));
    assert!(!Arc::ptr_eq(&follower(0), &follower(2)));
    assert_eq!(tie_followers(ties).len(), 2);
    assert_eq!(
        described(&follower(0)),
        "Turning { center: [[0.01, 0.0, 0.0]], rate: 2.0, followed_by: [0, 1], observed: 0 }"
    );
    assert_eq!(
        described(&follower(2)),
        "Turning { center: [[0.0, 0.0, 0.0]], rate: 3.0, followed_by: [2], observed: 0 }"
    );
    // The motion is the follower's: a quarter turn about z through (0.01, 0, 0) at
    // t = π/4 s takes (0.02, 0, 0) to (0.01, 0.01, 0).
    let moved = ties[1]
        .motion
        .position_at(&Vector3::new(0.02, 0.0, 0.0), std::f64::consts::FRAC_PI_4);
    assert!(
        (moved - Vector3::new(0.01, 0.01, 0.0)).norm() < 1e-15,
        "{moved}"
    );
    // The wall has the ties' table: it moves with them, and hears nothing of its own.
    let wall = model.rigid_bodies[0].motion.follower.clone().unwrap();
    assert!(Arc::ptr_eq(&wall, &follower(0)));
    wall.observe(0.0, &[]);
    assert!(described(&follower(0)).ends_with("observed: 1 }"));
}

#[test]
fn pulled_by_names_ties() {
    let text = SCENE.replace(
        "rate = 3.0 }",
        "rate = 3.0, pulled_by = [\"right\", \"left\"] }",
    );
    let model = build(&text).unwrap();
    let follower = model.loads.rigid_ties[2].motion.follower.clone().unwrap();
    assert!(described(&follower).contains("followed_by: [1, 0]"));
}

/// Each mistake (what, the edit of [`SCENE`], the start of the message, a fragment of it).
#[test]
fn mistakes_name_the_file_the_line_and_the_key() {
    let cases = [
        (
            "unknown kind",
            "follower = \"test-turning\", rate = 3.0",
            "follower = \"test-turnin\", rate = 3.0",
            "s.toml:30:23: ",
            "`follower`: unknown follower kind 'test-turnin' (did you mean `test-turning`?); known: test-turning",
        ),
        (
            "unknown parameter",
            "rate = 3.0 }",
            "rate = 3.0, rte = 1.0 }",
            "s.toml:30:57: ",
            "follower 'test-turning' has no parameter `rte` (did you mean `rate`?); it takes: rate, center, pulled_by",
        ),
        (
            "missing parameter",
            "motion = { follower = \"test-turning\", rate = 3.0 }",
            "motion = { follower = \"test-turning\" }",
            "s.toml:30:10: ",
            "follower 'test-turning': `rate` is missing",
        ),
        (
            "a string for a number",
            "rate = 3.0 }",
            "rate = \"fast\" }",
            "s.toml:30:46: ",
            "follower 'test-turning', `rate`: expected a number, found \"fast\"",
        ),
        (
            "a value the kind refuses",
            "rate = 3.0 }",
            "rate = -1.0 }",
            "s.toml:30:46: ",
            "follower 'test-turning', `rate`: must not be negative",
        ),
        (
            "a short vector",
            "rate = 3.0 }",
            "rate = 3.0, center = [1.0, 2.0] }",
            "s.toml:30:60: ",
            "follower 'test-turning', `center`: expected [x, y, z]",
        ),
        (
            "an unknown tie",
            "rate = 3.0 }",
            "rate = 3.0, pulled_by = [\"rigt\"] }",
            "s.toml:30:63: ",
            "`pulled_by`: no rigid tie 'rigt' (did you mean `right`?)",
        ),
        (
            "no kind",
            "follower = \"test-turning\", rate = 3.0",
            "rate = 3.0",
            "s.toml:30:10: ",
            "`motion` needs `follower = \"KIND\"`",
        ),
        (
            "a prescribed motion beside",
            "nodes = \"y0\"\nmotion",
            "nodes = \"y0\"\ntranslation = [0.0, 0.001, 0.0]\nmotion",
            "s.toml:31:10: ",
            "`motion` sets the whole pose",
        ),
    ];
    for (what, from, to, location, fragment) in cases {
        assert!(SCENE.contains(from), "{what}: the edit does not apply");
        let message = build(&SCENE.replacen(from, to, 1))
            .err()
            .unwrap_or_default();
        assert!(
            message.starts_with(location) && message.contains(fragment),
            "{what}: got \"{message}\", expected {location} … {fragment}"
        );
    }
}
