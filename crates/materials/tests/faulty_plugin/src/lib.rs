//! Test-only material plugin `faulty` that misbehaves on request, to test the host's
//! guards (`crates/materials/tests/plugins.rs`). No dependencies.
//!
//! Parameter `fault` [1] in [0, 3], default 0:
//! - 0: behave — zero stress, state `elapsed` [s] advanced by dt;
//! - 1: panic inside `update` (caught here by `catch_unwind`, reported as error code 2);
//! - 2: return a NaN stress at the last point of the block (return code 0);
//! - 3: return error code 7 with a message.

use std::ffi::c_char;
use std::panic::{AssertUnwindSafe, catch_unwind};

#[repr(C)]
pub struct ParameterInfo {
    name: *const c_char,
    unit: *const c_char,
    description: *const c_char,
    default_value: f64,
    lower: f64,
    upper: f64,
    lower_inclusive: i32,
    upper_inclusive: i32,
}

#[repr(C)]
pub struct StateInfo {
    name: *const c_char,
    unit: *const c_char,
    initial_value: f64,
}

#[repr(C)]
pub struct PointBlock {
    struct_size: u64,
    point_count: u64,
    time: f64,
    dt: f64,
    properties: *const f64,
    property_count: u64,
    deformation_gradient_old: *const f64,
    deformation_gradient_new: *const f64,
    fiber_direction: *const f64,
    state_old: *const f64,
    state_new: *mut f64,
    cauchy_stress: *mut f64,
    tangent: *mut f64,
}

type UpdateFn = unsafe extern "C" fn(*const PointBlock, *mut c_char, u64) -> i32;

#[repr(C)]
pub struct MaterialPlugin {
    abi_version: u32,
    struct_size: u32,
    name: *const c_char,
    description: *const c_char,
    parameter_count: u32,
    parameters: *const ParameterInfo,
    state_count: u32,
    states: *const StateInfo,
    provides_tangent: i32,
    update: Option<UpdateFn>,
}

#[repr(transparent)]
struct Static<T>(T);

// SAFETY: immutable tables pointing only to immutable 'static data.
unsafe impl<T> Sync for Static<T> {}

static PARAMETERS: Static<[ParameterInfo; 1]> = Static([ParameterInfo {
    name: c"fault".as_ptr(),
    unit: c"1".as_ptr(),
    description: c"0 behave, 1 panic, 2 NaN stress, 3 error code".as_ptr(),
    default_value: 0.0,
    lower: 0.0,
    upper: 3.0,
    lower_inclusive: 1,
    upper_inclusive: 1,
}]);

static STATES: Static<[StateInfo; 1]> = Static([StateInfo {
    name: c"elapsed".as_ptr(),
    unit: c"s".as_ptr(),
    initial_value: 0.0,
}]);

static PLUGIN: Static<MaterialPlugin> = Static(MaterialPlugin {
    abi_version: 1,
    struct_size: size_of::<MaterialPlugin>() as u32,
    name: c"faulty".as_ptr(),
    description: c"test plugin that fails on request".as_ptr(),
    parameter_count: 1,
    parameters: PARAMETERS.0.as_ptr(),
    state_count: 1,
    states: STATES.0.as_ptr(),
    provides_tangent: 0,
    update: Some(update),
});

#[unsafe(no_mangle)]
pub extern "C" fn musclefem_material_plugin() -> *const MaterialPlugin {
    catch_unwind(|| &PLUGIN.0 as *const MaterialPlugin).unwrap_or(std::ptr::null())
}

unsafe extern "C" fn update(block: *const PointBlock, message: *mut c_char, capacity: u64) -> i32 {
    // SAFETY (of the closure's body): the host lays out the block as the header says.
    let outcome = catch_unwind(AssertUnwindSafe(|| unsafe { update_block(&*block) }));
    let (code, text) = match outcome {
        Ok(Ok(())) => return 0,
        Ok(Err((code, text))) => (code, text),
        Err(payload) => {
            let text = if let Some(s) = payload.downcast_ref::<&str>() {
                (*s).to_string()
            } else if let Some(s) = payload.downcast_ref::<String>() {
                s.clone()
            } else {
                "(non-text payload)".to_string()
            };
            (2, format!("caught panic: {text}"))
        }
    };
    if !message.is_null() && capacity > 0 {
        let len = text.len().min(capacity as usize - 1);
        // SAFETY: len + 1 <= capacity bytes of the host's buffer.
        unsafe {
            std::ptr::copy_nonoverlapping(text.as_ptr(), message.cast::<u8>(), len);
            *message.add(len) = 0;
        }
    }
    code
}

/// # Safety
/// `b` laid out as the header describes, with 1 property and 1 state variable.
unsafe fn update_block(b: &PointBlock) -> Result<(), (i32, String)> {
    let n = b.point_count as usize;
    if b.property_count != 1 {
        return Err((1, format!("expected 1 property, got {}", b.property_count)));
    }
    // SAFETY: array lengths as the header promises.
    let (fault, stress, state_old, state_new) = unsafe {
        (
            *b.properties,
            std::slice::from_raw_parts_mut(b.cauchy_stress, 6 * n),
            std::slice::from_raw_parts(b.state_old, n),
            std::slice::from_raw_parts_mut(b.state_new, n),
        )
    };
    match fault.round() as i32 {
        1 => panic!("fault 1 requested: deliberate panic in update"),
        3 => {
            return Err((
                7,
                format!("fault 3 requested: deliberate error at t = {}", b.time),
            ));
        }
        _ => {}
    }
    stress.fill(0.0);
    for (new, old) in state_new.iter_mut().zip(state_old) {
        *new = old + b.dt;
    }
    if fault.round() as i32 == 2
        && let Some(last) = stress.chunks_mut(6).last()
    {
        last[0] = f64::NAN;
    }
    Ok(())
}
