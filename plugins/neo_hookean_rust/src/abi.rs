//! This plugin's own `#[repr(C)]` mirror of `musclefem_material.h`, ABI version 1.
//!
//! A third-party plugin does not depend on musclefem: it copies these few declarations
//! (or generates them from the header with bindgen). Keep the field order and types
//! exactly as in the header.

use std::ffi::c_char;

/// `MUSCLEFEM_MATERIAL_ABI_VERSION`.
pub const ABI_VERSION: u32 = 1;

/// `MusclefemParameterInfo`.
#[repr(C)]
pub struct ParameterInfo {
    pub name: *const c_char,
    pub unit: *const c_char,
    pub description: *const c_char,
    /// NaN: required, no default.
    pub default_value: f64,
    /// `f64::NEG_INFINITY` / `f64::INFINITY`: unbounded.
    pub lower: f64,
    pub upper: f64,
    pub lower_inclusive: i32,
    pub upper_inclusive: i32,
}

/// `MusclefemStateInfo`.
#[repr(C)]
pub struct StateInfo {
    pub name: *const c_char,
    pub unit: *const c_char,
    pub initial_value: f64,
}

/// `MusclefemPointBlock`.
#[repr(C)]
pub struct PointBlock {
    pub struct_size: u64,
    pub point_count: u64,
    pub time: f64,
    pub dt: f64,
    pub properties: *const f64,
    pub property_count: u64,
    pub deformation_gradient_old: *const f64,
    pub deformation_gradient_new: *const f64,
    pub fiber_direction: *const f64,
    pub state_old: *const f64,
    pub state_new: *mut f64,
    pub cauchy_stress: *mut f64,
    pub tangent: *mut f64,
}

/// `MusclefemUpdateFn`.
pub type UpdateFn =
    unsafe extern "C" fn(block: *const PointBlock, message: *mut c_char, capacity: u64) -> i32;

/// `MusclefemMaterialPlugin`.
#[repr(C)]
pub struct MaterialPlugin {
    pub abi_version: u32,
    pub struct_size: u32,
    pub name: *const c_char,
    pub description: *const c_char,
    pub parameter_count: u32,
    pub parameters: *const ParameterInfo,
    pub state_count: u32,
    pub states: *const StateInfo,
    pub provides_tangent: i32,
    pub update: Option<UpdateFn>,
}

/// A `static` table holds raw pointers, which are not `Sync`; this wrapper makes the
/// table usable as a `static`.
#[repr(transparent)]
pub struct Static<T>(pub T);

// SAFETY: the wrapped tables are immutable and only point to immutable `'static` data
// (string literals and other statics), so sharing them between threads is sound.
unsafe impl<T> Sync for Static<T> {}

/// Write `text` as a NUL-terminated message into the host's buffer, cut to fit.
///
/// # Safety
/// `message` must be null or valid for writes of `capacity` bytes.
pub unsafe fn write_message(message: *mut c_char, capacity: u64, text: &str) {
    if message.is_null() || capacity == 0 {
        return;
    }
    let bytes = text.as_bytes();
    let len = bytes.len().min(capacity as usize - 1);
    // SAFETY: `len + 1 <= capacity` bytes, valid for writes by the caller's contract.
    unsafe {
        std::ptr::copy_nonoverlapping(bytes.as_ptr(), message.cast::<u8>(), len);
        *message.add(len) = 0;
    }
}

/// The text of a caught panic.
pub fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "(non-text panic payload)".to_string()
    }
}

// The sizes the header checks on 64-bit targets.
#[cfg(target_pointer_width = "64")]
const _: () = {
    assert!(size_of::<ParameterInfo>() == 56);
    assert!(size_of::<StateInfo>() == 24);
    assert!(size_of::<PointBlock>() == 104);
    assert!(size_of::<MaterialPlugin>() == 72);
};
