//! Material plugins end to end: the test builds the example plugins (Rust with cargo, C with
//! the system compiler) and a few deliberately broken ones (`support/plugin_builds.rs`),
//! loads them through `MaterialLibrary`, and checks results and error messages.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use musclefem_materials::{
    Material, MaterialError, MaterialLibrary, MaterialOrigin, PointBlock, PointResponse, Tangent,
    VoigtStress,
};
use nalgebra::{Matrix3, Vector3};

mod support {
    pub mod plugin_builds;
}

use support::plugin_builds::{C_PLUGIN, RUST_PLUGIN, out_dir, plugins};

/// A library with both neo-Hookean plugins loaded.
fn library_with_neo_hookean_plugins() -> MaterialLibrary {
    let mut library = MaterialLibrary::with_builtins();
    library.load_plugin(&plugins().rust).unwrap();
    library.load_plugin(&plugins().c).unwrap();
    library
}

fn params(pairs: &[(&str, f64)]) -> BTreeMap<String, f64> {
    pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

/// Varied deformation gradients: identity, pure dilatation and compression (J != 1),
/// isochoric stretch, simple shear, and pseudo-random general ones with J from ~0.6 to ~1.5.
fn deformation_gradients() -> Vec<Matrix3<f64>> {
    let mut fs = vec![
        Matrix3::identity(),
        Matrix3::identity() * 1.05,
        Matrix3::identity() * 0.97,
        Matrix3::from_diagonal(&Vector3::new(1.2, 1.0 / 1.2f64.sqrt(), 1.0 / 1.2f64.sqrt())),
        Matrix3::new(1.0, 0.4, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
    ];
    let mut seed: u64 = 0x2545_F491_4F6C_DD1D;
    let mut next = move || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    while fs.len() < 64 {
        let f = Matrix3::identity() + Matrix3::from_fn(|_, _| 0.25 * next());
        if f.determinant() > 0.3 {
            fs.push(f);
        }
    }
    let js: Vec<f64> = fs.iter().map(|f| f.determinant()).collect();
    assert!(
        js.iter().any(|j| *j < 0.8) && js.iter().any(|j| *j > 1.2),
        "{js:?}"
    );
    fs
}

#[derive(Debug)]
struct Output {
    stress: Vec<VoigtStress>,
    state: Vec<f64>,
    tangent: Option<Vec<Tangent>>,
}

/// One `update` of `material` on a block with F_old = I, F_new = `fs`.
fn update(
    material: &dyn Material,
    fs: &[Matrix3<f64>],
    time: f64,
    dt: f64,
    with_tangent: bool,
) -> Result<Output, MaterialError> {
    let n = fs.len();
    let f_old = vec![Matrix3::identity(); n];
    let fibers = vec![Vector3::new(0.6, 0.8, 0.0); n];
    let state_old: Vec<f64> = material.initial_state(n);
    let mut stress = vec![VoigtStress::zeros(); n];
    let mut state = vec![0.0; state_old.len()];
    let mut tangent = with_tangent.then(|| vec![Tangent::zeros(); n]);
    let block = PointBlock {
        time,
        dt,
        deformation_gradient_old: &f_old,
        deformation_gradient_new: fs,
        fiber_direction: &fibers,
        state_old: &state_old,
    };
    let mut response = PointResponse {
        cauchy_stress: &mut stress,
        state_new: &mut state,
        tangent: tangent.as_deref_mut(),
    };
    material.update(&block, &mut response)?;
    Ok(Output {
        stress,
        state,
        tangent,
    })
}

#[test]
fn rust_and_c_plugins_match_the_builtin_neo_hookean() {
    let library = library_with_neo_hookean_plugins();
    let fs = deformation_gradients();
    // Non-default values (volumetric and deviatoric parts of similar size), then defaults.
    for given in [params(&[("mu", 2.5e4), ("D", 4e-6)]), params(&[])] {
        let builtin = library.create("neo-hookean", &given).unwrap();
        let reference = update(&*builtin, &fs, 1.0, 0.1, false).unwrap().stress;
        for name in [RUST_PLUGIN, C_PLUGIN] {
            let plugin = library.create(name, &given).unwrap();
            assert_eq!(plugin.name(), name);
            assert!(!plugin.provides_tangent());
            let stress = update(&*plugin, &fs, 1.0, 0.1, false).unwrap().stress;
            let mut worst = 0.0_f64;
            for (p, (s, r)) in stress.iter().zip(&reference).enumerate() {
                let error = (s - r).norm();
                assert!(
                    error <= 1e-12 * r.norm() + 1e-300,
                    "{name} {given:?}, point {p} (J = {}): {s:?} vs built-in {r:?}",
                    fs[p].determinant()
                );
                if r.norm() > 0.0 {
                    worst = worst.max(error / r.norm());
                }
            }
            // The stresses are non-trivial: the comparison means something.
            assert!(
                reference.iter().skip(1).all(|r| r.norm() > 1.0),
                "{reference:?}"
            );
            eprintln!("{name} {given:?}: worst relative stress difference {worst:e}");
        }
    }
}

#[test]
fn plugin_finite_difference_tangent_matches_the_builtin_analytic_tangent() {
    let library = library_with_neo_hookean_plugins();
    let fs = deformation_gradients();
    let given = params(&[("mu", 2.5e4), ("D", 4e-6)]);
    let builtin = library.create("neo-hookean", &given).unwrap();
    let reference = update(&*builtin, &fs, 1.0, 0.1, true)
        .unwrap()
        .tangent
        .unwrap();
    for name in [RUST_PLUGIN, C_PLUGIN] {
        let plugin = library.create(name, &given).unwrap();
        let tangent = update(&*plugin, &fs, 1.0, 0.1, true)
            .unwrap()
            .tangent
            .unwrap();
        let mut worst = 0.0_f64;
        for (p, (t, r)) in tangent.iter().zip(&reference).enumerate() {
            let relative = (t - r).norm() / r.norm();
            assert!(
                relative < 1e-6,
                "{name}, point {p}: relative tangent error {relative:e}"
            );
            worst = worst.max(relative);
        }
        eprintln!("{name}: worst relative tangent difference {worst:e}");
    }
}

#[test]
fn listing_shows_plugins_with_their_origin_and_parameters() {
    let library = library_with_neo_hookean_plugins();
    let materials = library.materials();
    let names: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
    for expected in ["neo-hookean", C_PLUGIN, RUST_PLUGIN] {
        assert!(names.contains(&expected), "{names:?}");
    }
    let mut sorted = names.clone();
    sorted.sort();
    assert_eq!(names, sorted);
    let builtin = library.info("neo-hookean").unwrap();
    assert_eq!(builtin.origin, MaterialOrigin::BuiltIn);
    for (name, path) in [(RUST_PLUGIN, &plugins().rust), (C_PLUGIN, &plugins().c)] {
        let info = materials.iter().find(|m| m.name == name).unwrap();
        assert_eq!(info.origin, MaterialOrigin::Plugin(path.clone()));
        assert!(
            info.description.contains("neo-Hookean"),
            "{}",
            info.description
        );
        assert_eq!(info.parameters.len(), 2);
        for (p, b) in info.parameters.iter().zip(&builtin.parameters) {
            assert_eq!(
                (
                    &p.name,
                    &p.unit,
                    p.default,
                    p.lower,
                    p.upper,
                    p.allow_infinite
                ),
                (
                    &b.name,
                    &b.unit,
                    b.default,
                    b.lower,
                    b.upper,
                    b.allow_infinite
                ),
                "{name}"
            );
        }
    }
}

#[test]
fn parameter_errors_are_the_same_as_for_builtins() {
    let library = library_with_neo_hookean_plugins();
    let cases = [
        params(&[("mu", -1.0)]),
        params(&[("mu", 0.0)]),
        params(&[("D", f64::NAN)]),
        params(&[("mu", f64::INFINITY)]),
        params(&[("nu", 0.3)]),
        params(&[("Mu", 1e4)]),
    ];
    for given in &cases {
        let builtin = library.create("neo-hookean", given).unwrap_err();
        for name in [RUST_PLUGIN, C_PLUGIN] {
            let plugin = library.create(name, given).unwrap_err();
            assert_eq!(
                std::mem::discriminant(&plugin),
                std::mem::discriminant(&builtin),
                "{plugin:?} vs {builtin:?}"
            );
            assert_eq!(
                plugin.to_string().replace(name, "neo-hookean"),
                builtin.to_string(),
                "{given:?}"
            );
        }
    }
    let text = library
        .create(RUST_PLUGIN, &params(&[("mu", -1.0)]))
        .unwrap_err()
        .to_string();
    assert!(
        text.contains("'mu' = -1 is outside its valid range (0, inf)"),
        "{text}"
    );
}

fn load_error(path: &Path) -> String {
    let err = MaterialLibrary::with_builtins()
        .load_plugin(path)
        .unwrap_err();
    assert!(matches!(err, MaterialError::Plugin { .. }), "{err:?}");
    let text = err.to_string();
    assert!(
        text.contains(&path.display().to_string()),
        "the message must name the file: {text}"
    );
    text
}

fn assert_contains(text: &str, expected: &str) {
    assert!(
        text.contains(expected),
        "{text:?}\n  should contain {expected:?}"
    );
}

#[test]
fn load_errors_name_their_cause() {
    let p = plugins();
    let missing = out_dir().join("no_such_plugin.so");
    assert_contains(&load_error(&missing), "file not found");

    let text = load_error(&p.not_a_library);
    assert_contains(
        &text,
        "cannot be loaded as a shared library: dlopen failed: ",
    );
    if cfg!(target_os = "linux") {
        // The reason from the source chain, not only libloading's "dlopen failed".
        assert_contains(&text, "invalid ELF header");
    }

    let text = load_error(&p.missing_symbol);
    assert_contains(
        &text,
        "does not export the symbol 'musclefem_material_plugin'",
    );
    if cfg!(target_os = "linux") {
        assert_contains(&text, "undefined symbol: musclefem_material_plugin");
    }

    assert_contains(
        &load_error(&p.wrong_abi),
        "ABI version mismatch: the plugin was built for material ABI version 99, this \
         musclefem implements version 1",
    );
    assert_contains(
        &load_error(&p.null_table),
        "'musclefem_material_plugin()' returned NULL",
    );
    assert_contains(
        &load_error(&p.small_table),
        "struct_size = 16 bytes, smaller than sizeof(MusclefemMaterialPlugin)",
    );
    assert_contains(
        &load_error(&p.bad_default),
        "material 'broken', parameter 0 ('k'): the default -1 is outside its own range \
         (0, inf), finite",
    );
    if cfg!(target_os = "linux") {
        // Bound eagerly (RTLD_NOW): an unresolved function is a load error, not an abort
        // at the first call.
        assert_contains(
            &load_error(&p.unresolved),
            "undefined symbol: musclefem_no_such_function",
        );
    }
}

#[test]
fn loading_the_same_plugin_twice_is_a_name_clash() {
    let mut library = MaterialLibrary::with_builtins();
    library.load_plugin(&plugins().rust).unwrap();
    let err = library.load_plugin(&plugins().rust).unwrap_err();
    let text = err.to_string();
    assert_contains(&text, "material 'neo-hookean-rust-plugin'");
    assert_contains(&text, "already registered");
    // The first copy is still loaded and usable after the second was refused and dropped.
    let material = library.create(RUST_PLUGIN, &params(&[])).unwrap();
    update(&*material, &deformation_gradients(), 0.0, 0.0, false).unwrap();
    assert_eq!(
        library
            .names()
            .iter()
            .filter(|n| n.as_str() == RUST_PLUGIN)
            .count(),
        1
    );
}

fn faulty(fault: f64) -> Arc<dyn Material> {
    let mut library = MaterialLibrary::with_builtins();
    library.load_plugin(&plugins().faulty).unwrap();
    // The library is dropped here: the material keeps the shared library loaded.
    library
        .create("faulty", &params(&[("fault", fault)]))
        .unwrap()
}

#[test]
fn a_well_behaved_faulty_plugin_passes_state_through_and_outlives_its_library() {
    let material = faulty(0.0);
    assert_eq!(material.state_count(), 1);
    assert_eq!(material.state_variables()[0].name, "elapsed");
    let fs = deformation_gradients();
    let out = update(&*material, &fs, 0.5, 0.25, true).unwrap();
    assert!(out.stress.iter().all(|s| s.norm() == 0.0));
    assert!(out.state.iter().all(|&s| s == 0.25), "{:?}", out.state);
    assert!(out.tangent.unwrap().iter().all(|t| t.norm() == 0.0));
}

#[test]
fn a_panic_inside_the_plugin_is_caught_and_reported() {
    let material = faulty(1.0);
    let err = update(&*material, &deformation_gradients(), 0.5, 0.25, false).unwrap_err();
    assert!(matches!(err, MaterialError::Plugin { .. }), "{err:?}");
    let text = err.to_string();
    assert_contains(
        &text,
        "material 'faulty' failed on a block of 64 points (error code 2)",
    );
    assert_contains(
        &text,
        "caught panic: fault 1 requested: deliberate panic in update",
    );
    assert_contains(&text, &plugins().faulty.display().to_string());
    // The process survived, and the plugin still works.
    update(&*faulty(0.0), &deformation_gradients(), 0.5, 0.25, false).unwrap();
}

#[test]
fn a_nan_stress_from_the_plugin_is_reported_as_non_finite() {
    let material = faulty(2.0);
    let err = update(&*material, &deformation_gradients(), 0.5, 0.25, false).unwrap_err();
    assert_eq!(
        err,
        MaterialError::NonFiniteResult {
            material: "faulty".into(),
            point: 63,
            what: "Cauchy stress",
        }
    );
    assert_contains(
        &err.to_string(),
        "material 'faulty' returned a non-finite Cauchy stress at point 63",
    );
}

#[test]
fn an_error_code_from_the_plugin_carries_its_message() {
    let material = faulty(3.0);
    let err = update(&*material, &deformation_gradients(), 0.5, 0.25, false).unwrap_err();
    let text = err.to_string();
    assert_contains(
        &text,
        "(error code 7): fault 3 requested: deliberate error at t = 0.5",
    );
    // Also when the host builds the tangent by finite differences.
    let err = update(&*material, &deformation_gradients(), 0.5, 0.25, true).unwrap_err();
    assert_contains(&err.to_string(), "error code 7");
}

#[test]
fn plugins_run_concurrently_on_separate_blocks() {
    let library = library_with_neo_hookean_plugins();
    let fs = deformation_gradients();
    for name in [RUST_PLUGIN, C_PLUGIN] {
        let material = library.create(name, &params(&[])).unwrap();
        let serial = update(&*material, &fs, 1.0, 0.1, false).unwrap().stress;
        let chunks: Vec<Vec<VoigtStress>> = std::thread::scope(|scope| {
            let handles: Vec<_> = fs
                .chunks(8)
                .map(|chunk| {
                    let material = Arc::clone(&material);
                    scope.spawn(move || update(&*material, chunk, 1.0, 0.1, false).unwrap().stress)
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        assert_eq!(chunks.concat(), serial, "{name}");
    }
}
