//! Failures are caught and named: a VUMAT that writes NaN or never sets stressNew, stops
//! with XPLB_EXIT or STOP or reports with XPLB_ABQERR, a wrong props count (seen by the VUMAT, and
//! by the adapter when a caller breaks the ABI), and the build's own errors — gfortran's
//! messages with file and line, routines nobody defines, a file without VUMAT, an existing
//! output, a missing compiler.

mod support {
    pub mod builds;
    pub mod points;
}

use std::ffi::{CStr, c_char};

use musclefem_materials::plugin::abi;
use musclefem_materials::{
    Material, MaterialError, MaterialLibrary, PointBlock, PointResponse, VoigtStress,
};
use musclefem_vumat::toolchain::Tool;
use musclefem_vumat::{FiberConvention, VumatError, build_plugin};
use nalgebra::{Matrix3, Vector3};

use support::builds::{built, example, fixture, gfortran_or_skip, material, options, params};
use support::points::deformation_gradients;

/// tests/fixtures/faulty_vumat.f with `fault` (see its header), one state variable.
fn faulty(fault: f64) -> std::sync::Arc<dyn Material> {
    let plugin = built(options(
        &fixture("faulty_vumat.f"),
        "faulty-vumat",
        "fault=0",
        1,
        FiberConvention::None,
    ))
    .unwrap();
    material(&plugin, &[("fault", fault)])
}

/// One step of three points from F = I; the error's text.
fn update_three(material: &dyn Material) -> Result<Vec<f64>, String> {
    let f_old = [Matrix3::identity(); 3];
    let f_new: Vec<Matrix3<f64>> = deformation_gradients().into_iter().take(3).collect();
    let state_old = material.initial_state(3);
    let mut stress = [VoigtStress::zeros(); 3];
    let mut state = vec![0.0; state_old.len()];
    let block = PointBlock {
        time: 0.1,
        dt: 0.1,
        deformation_gradient_old: &f_old,
        deformation_gradient_new: &f_new,
        fiber_direction: &[Vector3::x(); 3],
        state_old: &state_old,
    };
    let mut response = PointResponse {
        cauchy_stress: &mut stress,
        state_new: &mut state,
        tangent: None,
    };
    match material.update(&block, &mut response) {
        Ok(()) => Ok(state),
        Err(error) => {
            assert!(matches!(error, MaterialError::Plugin { .. }), "{error:?}");
            Err(error.to_string())
        }
    }
}

fn assert_contains(text: &str, expected: &str) {
    assert!(
        text.contains(expected),
        "{text:?}\n  should contain {expected:?}"
    );
}

#[test]
fn vumat_failures_are_caught_and_named() {
    if !gfortran_or_skip("vumat_failures_are_caught_and_named") {
        return;
    }
    // Fault 0: a valid VUMAT (zero stress, state carried).
    let state = update_three(&*faulty(0.0)).unwrap();
    assert_eq!(state.len(), 3 * 10);
    let prefix = "material 'faulty-vumat' failed on a block of 3 points (error code 1): \
                  VUMAT (cmname 'FAULTY-VUMAT'): ";
    for (fault, expected) in [
        (
            1.0,
            "the VUMAT returned NaN in stressNew(3, 2) (component 22 of point 2 of the block) \
             at stepTime = 0",
        ),
        (
            2.0,
            "the VUMAT never set stressNew(1, 5) (component 23 of point 0 of the block; \
             stressNew is filled with NaN before the call and this entry still holds it)",
        ),
        (
            3.0,
            "the VUMAT stopped on points 0..2 of the block at stepTime = 0: the VUMAT called \
             XPLB_EXIT",
        ),
        (
            4.0,
            "the VUMAT stopped on points 0..2 of the block at stepTime = 0: XPLB_ABQERR \
             (lop = -2): fault 4 on 3 points: value 0.25 from PROBE",
        ),
        (
            5.0,
            "the VUMAT returned a non-finite stateNew(1, 1) (sdv1 of point 0 of the block)",
        ),
        (
            6.0,
            "the VUMAT stopped on points 0..2 of the block at stepTime = 0: the VUMAT \
             executed STOP fault 6",
        ),
        (
            7.0,
            "the VUMAT stopped on points 0..2 of the block at stepTime = 0: the VUMAT \
             executed STOP 7",
        ),
    ] {
        let text = update_three(&*faulty(fault)).unwrap_err();
        assert_contains(&text, &format!("{prefix}{expected}"));
        assert_contains(&text, "libfaulty_vumat.so");
    }
    // After all that, the plugin still works.
    update_three(&*faulty(0.0)).unwrap();
}

#[test]
fn a_wrong_props_count_is_refused_by_the_vumat_and_by_the_adapter() {
    if !gfortran_or_skip("a_wrong_props_count_is_refused_by_the_vumat_and_by_the_adapter") {
        return;
    }
    // Built with one prop where the VUMAT needs two: its own check (XPLB_ABQERR, -3).
    let one_prop = built(options(
        &example("neo_hookean_vumat.f"),
        "nh-vumat-one-prop",
        "mu=1e4:Pa",
        0,
        FiberConvention::None,
    ))
    .unwrap();
    let text = update_three(&*material(&one_prop, &[])).unwrap_err();
    assert_contains(
        &text,
        "XPLB_ABQERR (lop = -3): neo_hookean_vumat needs 2 props (mu, D), got 1",
    );
    // The props are named parameters: the host refuses a name the build did not declare.
    let mut library = MaterialLibrary::with_builtins();
    let info = library.load_plugin(&one_prop.library).unwrap();
    let names: Vec<&str> = info.parameters.iter().map(|p| p.name.as_ref()).collect();
    assert_eq!(
        names,
        [
            "mu",
            "vumat_density",
            "vumat_char_length",
            "vumat_temperature"
        ]
    );
    let error = library
        .create(&info.name, &params(&[("D", 5e-9)]))
        .unwrap_err()
        .to_string();
    assert_contains(&error, "'D'");

    // A caller that breaks the ABI and passes 2 properties instead of 4.
    // SAFETY: the library is a plugin built above; its table and update function follow
    // musclefem_material.h, and the block below points to arrays of the promised sizes.
    unsafe {
        let library = libloading::Library::new(&one_prop.library).unwrap();
        let entry = library.get::<abi::EntryPoint>(abi::PLUGIN_SYMBOL).unwrap();
        let table = &*entry();
        let update = table.update.unwrap();
        let f = Matrix3::<f64>::identity();
        let fiber = Vector3::x();
        let state_old = vec![0.0; table.state_count as usize];
        let mut state_new = state_old.clone();
        let mut stress = [0.0; 6];
        let properties = [1e4, 1000.0];
        let block = abi::PointBlock {
            struct_size: size_of::<abi::PointBlock>() as u64,
            point_count: 1,
            time: 0.1,
            dt: 0.1,
            properties: properties.as_ptr(),
            property_count: 2,
            deformation_gradient_old: f.as_ptr(),
            deformation_gradient_new: f.as_ptr(),
            fiber_direction: fiber.as_ptr(),
            state_old: state_old.as_ptr(),
            state_new: state_new.as_mut_ptr(),
            cauchy_stress: stress.as_mut_ptr(),
            tangent: std::ptr::null_mut(),
        };
        let mut message = [0 as c_char; 512];
        let code = update(&block, message.as_mut_ptr(), message.len() as u64);
        assert_ne!(code, 0);
        let text = CStr::from_ptr(message.as_ptr()).to_string_lossy();
        assert_contains(
            &text,
            "expected 4 properties (the VUMAT's nprops = 1, then vumat_density, \
             vumat_char_length, vumat_temperature), got 2",
        );
    }
}

fn build_error(source: &str, name: &str) -> VumatError {
    build_plugin(&options(
        &fixture(source),
        name,
        "",
        0,
        FiberConvention::None,
    ))
    .unwrap_err()
}

#[test]
fn build_errors_name_the_file_and_the_line() {
    if !gfortran_or_skip("build_errors_name_the_file_and_the_line") {
        return;
    }
    let error = build_error("broken_vumat.f", "broken");
    assert!(matches!(error, VumatError::Compile { .. }), "{error:?}");
    let text = error.to_string();
    assert_contains(&text, "gfortran could not compile ");
    assert_contains(&text, "broken_vumat.f:5:21:");
    assert_contains(&text, "Error: Invalid form of array reference");

    let text = build_error("unknown_routine_vumat.f", "unknown-routine").to_string();
    assert_contains(
        &text,
        "unknown_routine_vumat.f calls routines that neither it nor musclefem defines: \
         VGETJOBNAME (musclefem provides the Abaqus utilities XPLB_ABQERR and XPLB_EXIT)",
    );
    assert_contains(&text, "undefined reference to `vgetjobname_'");

    let text = build_error("umat_only.f", "umat-only").to_string();
    assert_contains(&text, "umat_only.f does not define SUBROUTINE VUMAT");

    let text = build_error("no_such_file.f", "missing").to_string();
    assert_contains(&text, "cannot read the Fortran file ");
    assert_contains(&text, "no_such_file.f: No such file");
}

#[test]
fn an_existing_output_is_kept_unless_replacing_is_asked_for() {
    if !gfortran_or_skip("an_existing_output_is_kept_unless_replacing_is_asked_for") {
        return;
    }
    let mut build = options(
        &example("neo_hookean_vumat.f"),
        "nh-vumat-twice",
        "mu=1e4:Pa,D=5e-9:1/Pa",
        0,
        FiberConvention::None,
    );
    build_plugin(&build).unwrap();
    build.replace = false;
    let text = build_plugin(&build).unwrap_err().to_string();
    assert_contains(
        &text,
        "libnh_vumat_twice.so exists; give --force to replace it",
    );
}

#[test]
fn a_missing_compiler_is_named_with_the_way_to_install_it() {
    let tool = Tool {
        program: "musclefem-no-such-gfortran".into(),
        variable: "FC",
    };
    assert!(!tool.is_available());
    let text = tool.run(&[]).unwrap_err().to_string();
    assert_contains(
        &text,
        "the compiler 'musclefem-no-such-gfortran' was not found: install it (Debian/Ubuntu: \
         scripts/setup-fortran.sh, or apt-get install gfortran) or name another one with the \
         environment variable FC",
    );
}
