//! Running the `musclefem` binary from a test: a fresh directory per test, the example
//! scenes, and the process output as text.

// Each test binary includes this file and uses a part of it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The flags of a cheap elongation model for `sweep` and `fit` tests: a cylinder with
/// sliding grips (homogeneous deformation), 8.75 mm elements (72 hex8), 0.2 s increments.
pub const CHEAP_ELONGATION: [&str; 8] = [
    "--shape",
    "cylinder",
    "--grips",
    "sliding",
    "--mesh-size",
    "8.75",
    "--time-step",
    "0.2",
];

/// A fresh, empty directory `group/name-PID` for one test (per process, so concurrent
/// runs do not clash).
pub fn test_dir(group: &str, name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(group)
        .join(format!("{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The path of the example scene `name` (in `examples/`).
pub fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

/// Runs `musclefem ARGS` in `dir` and waits for it.
pub fn musclefem(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_musclefem"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the musclefem binary runs")
}

/// Process output as text.
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}
