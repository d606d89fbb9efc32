//! A UMAT's failures are caught and named: NaN in STRESS, a DDSDDE set only in part, XIT,
//! STDB_ABQERR, PNEWDT < 1, a non-finite STATEV, a wrong props count (seen by the UMAT, by
//! the host's parameter check and by the adapter when a caller breaks the ABI), and the
//! build's errors — gfortran's file and line, a file without UMAT, `--fiber orientation`.

mod support {
    pub mod builds;
    pub mod points;
}

use std::ffi::{CStr, c_char};

use musclefem_materials::plugin::abi;
use musclefem_materials::{
    Material, MaterialError, MaterialLibrary, PointBlock, PointResponse, Tangent, VoigtStress,
};
use musclefem_vumat::{FiberConvention, Subroutine, TangentSource, VumatBuild, VumatError};
use nalgebra::{Matrix3, Vector3};

use support::builds::{built, example, fixture, gfortran_or_skip, material, params, umat_options};
use support::points::deformation_gradients;

/// tests/fixtures/faulty_umat.f with `fault` (see its header), one state variable.
fn faulty(fault: f64) -> std::sync::Arc<dyn Material> {
    let plugin = built(umat_options(
        &fixture("faulty_umat.f"),
        "faulty-umat",
        "fault=0,mu=1e4:Pa,D=1e-5:1/Pa",
        1,
        TangentSource::Ddsdde,
    ))
    .unwrap();
    material(&plugin, &[("fault", fault)])
}

/// One step of three points from F = I, with the tangent; the error's text.
fn update_three(material: &dyn Material) -> Result<(), String> {
    let f_old = [Matrix3::identity(); 3];
    let f_new: Vec<Matrix3<f64>> = deformation_gradients().into_iter().take(3).collect();
    let state_old = material.initial_state(3);
    let mut stress = [VoigtStress::zeros(); 3];
    let mut state = vec![0.0; state_old.len()];
    let mut tangent = [Tangent::zeros(); 3];
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
        tangent: Some(&mut tangent),
    };
    material.update(&block, &mut response).map_err(|error| {
        assert!(matches!(error, MaterialError::Plugin { .. }), "{error:?}");
        error.to_string()
    })
}

fn assert_contains(text: &str, expected: &str) {
    assert!(
        text.contains(expected),
        "{text:?}\n  should contain {expected:?}"
    );
}

#[test]
fn umat_failures_are_caught_and_named() {
    if !gfortran_or_skip("umat_failures_are_caught_and_named") {
        return;
    }
    update_three(&*faulty(0.0)).unwrap();
    let prefix = "material 'faulty-umat' failed on a block of 3 points (error code 1): UMAT \
                  (cmname 'FAULTY-UMAT'): ";
    for (fault, expected) in [
        (
            1.0,
            "the UMAT returned NaN in STRESS(2) (component 22 of point 1 of the block) at \
             TIME(2) = 0",
        ),
        (
            2.0,
            "the UMAT set DDSDDE only in part: DDSDDE(1, 1) was set but DDSDDE(1, 2) was not \
             (point 0 of the block; DDSDDE is filled with NaN before the call and 30 of its 36 \
             entries still hold it",
        ),
        (
            3.0,
            "the UMAT stopped on point 0 of the block at TIME(2) = 0: the UMAT called XIT",
        ),
        (
            4.0,
            "the UMAT stopped on point 0 of the block at TIME(2) = 0: STDB_ABQERR (lop = -3): \
             fault 4: value 0.25 from PROBE",
        ),
        (
            5.0,
            "the UMAT asked for a shorter increment (PNEWDT = 0.5) at point 0 of the block",
        ),
        (
            6.0,
            "the UMAT returned a non-finite STATEV(1) (sdv1 of point 0 of the block)",
        ),
    ] {
        let text = update_three(&*faulty(fault)).unwrap_err();
        assert_contains(&text, &format!("{prefix}{expected}"));
        assert_contains(&text, "libfaulty_umat.so");
    }
    update_three(&*faulty(0.0)).unwrap();
}

#[test]
fn a_wrong_props_count_is_refused_by_the_umat_the_host_and_the_adapter() {
    if !gfortran_or_skip("a_wrong_props_count_is_refused_by_the_umat_the_host_and_the_adapter") {
        return;
    }
    let one_prop = built(umat_options(
        &example("neo_hookean_umat.f"),
        "nh-umat-one-prop",
        "mu=1e4:Pa",
        0,
        TangentSource::Ddsdde,
    ))
    .unwrap();
    let text = update_three(&*material(&one_prop, &[])).unwrap_err();
    assert_contains(
        &text,
        "STDB_ABQERR (lop = -3): neo_hookean_umat needs 2 props (mu, D), got 1",
    );
    let mut library = MaterialLibrary::with_builtins();
    let info = library.load_plugin(&one_prop.library).unwrap();
    let names: Vec<&str> = info.parameters.iter().map(|p| p.name.as_ref()).collect();
    assert_eq!(names, ["mu", "umat_char_length", "umat_temperature"]);
    let error = library
        .create(&info.name, &params(&[("D", 5e-9)]))
        .unwrap_err()
        .to_string();
    assert_contains(&error, "'D'");

    // A caller that breaks the ABI and passes 2 properties instead of 3.
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
        let properties = [1e4, 1e-3];
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
            "expected 3 properties (the UMAT's nprops = 1, then umat_char_length, \
             umat_temperature), got 2",
        );
    }
}

fn umat_build_error(source: &str, name: &str, fiber: FiberConvention) -> VumatError {
    let options = VumatBuild {
        fiber,
        ..umat_options(&fixture(source), name, "", 0, TangentSource::Ddsdde)
    };
    assert_eq!(options.subroutine, Subroutine::Umat);
    musclefem_vumat::build_plugin(&options).unwrap_err()
}

#[test]
fn umat_build_errors_name_the_file_and_the_line() {
    if !gfortran_or_skip("umat_build_errors_name_the_file_and_the_line") {
        return;
    }
    let error = umat_build_error("broken_umat.f", "broken-umat", FiberConvention::None);
    assert!(matches!(error, VumatError::Compile { .. }), "{error:?}");
    let text = error.to_string();
    assert_contains(&text, "gfortran could not compile ");
    assert_contains(&text, "broken_umat.f:6:");

    let text = umat_build_error("vumat_only.f", "vumat-only", FiberConvention::None).to_string();
    assert_contains(
        &text,
        "vumat_only.f does not define SUBROUTINE UMAT (the linker found no symbol umat_)",
    );

    let text =
        umat_build_error("faulty_umat.f", "oriented", FiberConvention::Orientation).to_string();
    assert_contains(&text, "--fiber orientation is for VUMATs");
}
