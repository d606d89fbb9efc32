//! Building the plugins the material tests load: the example plugins (Rust with cargo, C
//! with the system compiler) and deliberately broken C ones, once per test binary, into
//! `$CARGO_TARGET_TMPDIR/plugins`.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

pub const RUST_PLUGIN: &str = "neo-hookean-rust-plugin";
pub const C_PLUGIN: &str = "neo-hookean-c-plugin";

/// Paths of every plugin library the tests load.
pub struct Plugins {
    pub rust: PathBuf,
    pub c: PathBuf,
    pub faulty: PathBuf,
    pub wrong_abi: PathBuf,
    pub missing_symbol: PathBuf,
    pub null_table: PathBuf,
    pub small_table: PathBuf,
    pub bad_default: PathBuf,
    pub unresolved: PathBuf,
    pub not_a_library: PathBuf,
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

pub fn out_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("plugins")
}

fn library_file(dir: &Path, stem: &str) -> PathBuf {
    dir.join(format!(
        "{}{stem}{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    ))
}

fn run(command: &mut Command) {
    let output = command
        .output()
        .unwrap_or_else(|e| panic!("cannot run {command:?}: {e}"));
    assert!(
        output.status.success(),
        "{command:?} failed ({}):\n{}\n{}",
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}

/// Build a Rust plugin crate (no dependencies, so this takes seconds).
fn build_rust_plugin(crate_dir: &str, lib_stem: &str) -> PathBuf {
    let manifest = workspace_root().join(crate_dir).join("Cargo.toml");
    let target_dir = out_dir();
    run(Command::new(env!("CARGO"))
        .args(["build", "--release", "--manifest-path"])
        .arg(&manifest)
        .arg("--target-dir")
        .arg(&target_dir));
    let path = library_file(&target_dir.join("release"), lib_stem);
    assert!(path.is_file(), "cargo did not produce {}", path.display());
    path
}

/// Compile one C file into a shared library with the system compiler ($CC or cc).
fn compile_c(source: &Path, stem: &str) -> PathBuf {
    let dir = out_dir().join("c");
    std::fs::create_dir_all(&dir).unwrap();
    let output = library_file(&dir, stem);
    let compiler = std::env::var("CC").unwrap_or_else(|_| "cc".to_string());
    run(Command::new(compiler)
        .args(["-shared", "-fPIC", "-O2", "-ffp-contract=off", "-std=c11"])
        .arg("-I")
        .arg(workspace_root().join("crates/materials/include"))
        .arg(source)
        .arg("-o")
        .arg(&output)
        .arg("-lm"));
    output
}

/// Write a small C plugin source and compile it.
fn compile_c_text(stem: &str, text: &str) -> PathBuf {
    let dir = out_dir().join("c");
    std::fs::create_dir_all(&dir).unwrap();
    let source = dir.join(format!("{stem}.c"));
    std::fs::write(&source, text).unwrap();
    compile_c(&source, stem)
}

/// A minimal valid plugin table in C, with `{ABI}`, `{SIZE}`, `{RETURN}`, `{DEFAULT}` to
/// be replaced to break it in one way.
const TEMPLATE: &str = r#"
#include <math.h>
#include <stddef.h>
#include "musclefem_material.h"
static const MusclefemParameterInfo parameters[1] = {
    {"k", "Pa", "stiffness", {DEFAULT}, 0.0, INFINITY, 0, 0},
};
static int32_t update(const MusclefemPointBlock* b, char* m, uint64_t c) {
    (void)b; (void)m; (void)c;
    {EXTRA}
    return 0;
}
static const MusclefemMaterialPlugin plugin = {
    {ABI}, {SIZE}, "broken", NULL, 1, parameters, 0, NULL, 0, update,
};
{EXTERN}
MUSCLEFEM_EXPORT const MusclefemMaterialPlugin* {SYMBOL}(void) { return {RETURN}; }
"#;

fn broken_plugin(stem: &str, replacements: &[(&str, &str)]) -> PathBuf {
    let defaults = [
        ("{ABI}", "MUSCLEFEM_MATERIAL_ABI_VERSION"),
        ("{SIZE}", "sizeof(MusclefemMaterialPlugin)"),
        ("{DEFAULT}", "1.0"),
        ("{RETURN}", "&plugin"),
        ("{SYMBOL}", "musclefem_material_plugin"),
        ("{EXTRA}", ""),
        ("{EXTERN}", ""),
    ];
    let mut text = TEMPLATE.to_string();
    for (key, default) in defaults {
        let value = replacements
            .iter()
            .find(|(k, _)| *k == key)
            .map_or(default, |(_, v)| *v);
        text = text.replace(key, value);
    }
    compile_c_text(stem, &text)
}

pub fn plugins() -> &'static Plugins {
    static PLUGINS: OnceLock<Plugins> = OnceLock::new();
    PLUGINS.get_or_init(|| {
        let not_a_library = out_dir().join("not_a_library.so");
        std::fs::create_dir_all(out_dir()).unwrap();
        std::fs::write(
            &not_a_library,
            "This is a text file, not a shared library.\n".repeat(4),
        )
        .unwrap();
        Plugins {
            rust: build_rust_plugin("plugins/neo_hookean_rust", "musclefem_plugin_neo_hookean"),
            faulty: build_rust_plugin(
                "crates/materials/tests/faulty_plugin",
                "musclefem_test_faulty_plugin",
            ),
            c: compile_c(
                &workspace_root().join("plugins/neo_hookean_c/neo_hookean.c"),
                "neo_hookean_c",
            ),
            wrong_abi: broken_plugin("wrong_abi", &[("{ABI}", "99u")]),
            missing_symbol: broken_plugin(
                "missing_symbol",
                &[("{SYMBOL}", "musclefem_material_plugin_v0")],
            ),
            null_table: broken_plugin("null_table", &[("{RETURN}", "NULL")]),
            small_table: broken_plugin("small_table", &[("{SIZE}", "16u")]),
            bad_default: broken_plugin("bad_default", &[("{DEFAULT}", "-1.0")]),
            unresolved: broken_plugin(
                "unresolved",
                &[
                    ("{EXTERN}", "void musclefem_no_such_function(void);"),
                    ("{EXTRA}", "musclefem_no_such_function();"),
                ],
            ),
            not_a_library,
        }
    })
}
