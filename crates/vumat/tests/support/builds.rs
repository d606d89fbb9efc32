//! Building the test VUMATs (examples/vumat and tests/fixtures) into plugins, once per test
//! binary and name, in `$CARGO_TARGET_TMPDIR/vumat-plugins`; loading them as materials.
//!
//! Without gfortran a test prints why and returns early, unless MUSCLEFEM_REQUIRE_GFORTRAN
//! is set (scripts/test sets it after scripts/setup-fortran.sh), where it fails instead.

// Each test binary uses a part of this file.
#![allow(dead_code)]

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use musclefem_materials::{Material, MaterialLibrary};
use musclefem_vumat::toolchain::Tool;
use musclefem_vumat::{
    BuiltPlugin, FiberConvention, Prop, Subroutine, TangentSource, VumatBuild, VumatError,
    build_plugin,
};

/// Whether gfortran is there; prints the skip message if not (panics if it is required).
pub fn gfortran_or_skip(test: &str) -> bool {
    if Tool::fortran().is_available() {
        return true;
    }
    assert!(
        std::env::var_os("MUSCLEFEM_REQUIRE_GFORTRAN").is_none(),
        "{test}: gfortran is required (MUSCLEFEM_REQUIRE_GFORTRAN is set) but not found"
    );
    eprintln!("SKIPPED {test}: gfortran is not installed (scripts/setup-fortran.sh installs it)");
    false
}

pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A file of tests/fixtures.
pub fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

/// A file of examples/vumat.
pub fn example(name: &str) -> PathBuf {
    workspace_root().join("examples/vumat").join(name)
}

/// Where the test plugins go: one directory for every run (a build replaces a library by
/// renaming a new file over it, so a process that still has the old one loaded keeps it).
pub fn out_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("vumat-plugins")
}

/// The options of a build of `source` as material `name` into out_dir().
pub fn options(
    source: &Path,
    name: &str,
    props: &str,
    nstatev: usize,
    fiber: FiberConvention,
) -> VumatBuild {
    VumatBuild {
        source: source.to_path_buf(),
        name: name.to_string(),
        cmname: None,
        props: Prop::parse_list(props).unwrap(),
        nstatev,
        statev_initial: Vec::new(),
        fiber,
        out: out_dir().join(format!("lib{}.so", name.replace('-', "_"))),
        replace: true,
        subroutine: Subroutine::Vumat,
        tangent: TangentSource::Ddsdde,
    }
}

/// Build with `options` once per test binary (keyed by the material name).
pub fn built(options: VumatBuild) -> Result<BuiltPlugin, VumatError> {
    static BUILT: Mutex<Option<HashMap<String, BuiltPlugin>>> = Mutex::new(None);
    let mut guard = BUILT.lock().unwrap_or_else(|e| e.into_inner());
    let map = guard.get_or_insert_with(HashMap::new);
    if let Some(plugin) = map.get(&options.name) {
        return Ok(plugin.clone());
    }
    let plugin = build_plugin(&options)?;
    map.insert(options.name.clone(), plugin.clone());
    Ok(plugin)
}

pub fn params(pairs: &[(&str, f64)]) -> BTreeMap<String, f64> {
    pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

/// The material of a built plugin with `given` parameters.
pub fn material(plugin: &BuiltPlugin, given: &[(&str, f64)]) -> Arc<dyn Material> {
    let mut library = MaterialLibrary::with_builtins();
    let info = library.load_plugin(&plugin.library).unwrap();
    library.create(&info.name, &params(given)).unwrap()
}

/// The built-in material `name` with `given` parameters.
pub fn builtin(name: &str, given: &[(&str, f64)]) -> Arc<dyn Material> {
    MaterialLibrary::with_builtins()
        .create(name, &params(given))
        .unwrap()
}

/// examples/vumat/neo_hookean_vumat.f as material `name` with the built-in's parameter
/// names, defaults and units.
pub fn neo_hookean_vumat(name: &str, fiber: FiberConvention) -> BuiltPlugin {
    built(options(
        &example("neo_hookean_vumat.f"),
        name,
        "mu=11370:Pa,D=5e-9:1/Pa",
        0,
        fiber,
    ))
    .unwrap()
}

/// The options of a UMAT build of `source` as material `name` into out_dir(), global basis.
pub fn umat_options(
    source: &Path,
    name: &str,
    props: &str,
    nstatev: usize,
    tangent: TangentSource,
) -> VumatBuild {
    VumatBuild {
        subroutine: Subroutine::Umat,
        tangent,
        ..options(source, name, props, nstatev, FiberConvention::None)
    }
}

/// examples/vumat/neo_hookean_umat.f as material `name` with the built-in's parameter
/// names, defaults and units.
pub fn neo_hookean_umat(name: &str, tangent: TangentSource) -> BuiltPlugin {
    built(umat_options(
        &example("neo_hookean_umat.f"),
        name,
        "mu=11370:Pa,D=5e-9:1/Pa",
        0,
        tangent,
    ))
    .unwrap()
}
