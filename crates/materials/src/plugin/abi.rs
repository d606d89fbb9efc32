//! `#[repr(C)]` mirror of `include/musclefem_material.h`, ABI version 1.
//!
//! The header is the normative description; the field comments here are short. The
//! layouts are checked at compile time (on 64-bit targets against the same sizes that
//! the header checks with `_Static_assert`), and so are the nalgebra types whose slices
//! the host hands to a plugin by pointer casts, without copying.

use std::ffi::c_char;
use std::mem::{align_of, size_of};

use nalgebra::{Matrix3, Vector3};

use crate::material::{Tangent, VoigtStress};

/// `MUSCLEFEM_MATERIAL_ABI_VERSION`: the version this host implements.
pub const ABI_VERSION: u32 = 1;

/// Name of the one symbol a plugin exports (NUL-terminated, for `dlsym`).
pub const PLUGIN_SYMBOL: &[u8] = b"musclefem_material_plugin\0";

/// `MusclefemParameterInfo`: declaration of one parameter.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct ParameterInfo {
    pub name: *const c_char,
    pub unit: *const c_char,
    /// May be null.
    pub description: *const c_char,
    /// NaN: required, no default.
    pub default_value: f64,
    /// -∞: unbounded below.
    pub lower: f64,
    /// +∞: unbounded above.
    pub upper: f64,
    pub lower_inclusive: i32,
    pub upper_inclusive: i32,
}

/// `MusclefemStateInfo`: declaration of one state variable.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct StateInfo {
    pub name: *const c_char,
    pub unit: *const c_char,
    pub initial_value: f64,
}

/// `MusclefemPointBlock`: one batch of points (see the header for the layouts).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct PointBlock {
    /// `size_of::<PointBlock>()`, set by the host.
    pub struct_size: u64,
    pub point_count: u64,
    /// Time at the end of the step, in s.
    pub time: f64,
    /// Step, in s.
    pub dt: f64,
    pub properties: *const f64,
    pub property_count: u64,
    /// 9 per point, column-major.
    pub deformation_gradient_old: *const f64,
    pub deformation_gradient_new: *const f64,
    /// 3 per point.
    pub fiber_direction: *const f64,
    pub state_old: *const f64,
    pub state_new: *mut f64,
    /// 6 per point, Voigt (xx, yy, zz, yz, xz, xy).
    pub cauchy_stress: *mut f64,
    /// Null, or 81 per point (∂P/∂F, column-major 9×9).
    pub tangent: *mut f64,
}

/// `MusclefemUpdateFn`; `None` is a null pointer in the table (rejected at load).
pub type UpdateFn = Option<
    unsafe extern "C" fn(block: *const PointBlock, message: *mut c_char, capacity: u64) -> i32,
>;

/// `MusclefemMaterialPlugin`: the table returned by the exported symbol.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct MaterialPlugin {
    pub abi_version: u32,
    pub struct_size: u32,
    pub name: *const c_char,
    /// May be null.
    pub description: *const c_char,
    pub parameter_count: u32,
    pub parameters: *const ParameterInfo,
    pub state_count: u32,
    pub states: *const StateInfo,
    pub provides_tangent: i32,
    pub update: UpdateFn,
}

/// Type of the exported `musclefem_material_plugin` function.
pub type EntryPoint = unsafe extern "C" fn() -> *const MaterialPlugin;

/// The leading fields every ABI version keeps, so the host can read the version and size
/// of a table before it knows the table is as large as its own `MaterialPlugin`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct TableHead {
    pub abi_version: u32,
    pub struct_size: u32,
}

// The blocks are passed zero-copy: a `&[Matrix3<f64>]` is read by the plugin as 9 f64 per
// point (column-major), `&[Vector3<f64>]` as 3, `&[VoigtStress]` as 6, `&[Tangent]` as 81
// (column-major). nalgebra's `Matrix` is `repr(C)` over a `repr(transparent)`
// `ArrayStorage([[T; R]; C])`, i.e. columns one after the other with no padding; these
// assertions fail the build should that ever change.
const _: () = {
    assert!(size_of::<Matrix3<f64>>() == 9 * size_of::<f64>());
    assert!(align_of::<Matrix3<f64>>() == align_of::<f64>());
    assert!(size_of::<Vector3<f64>>() == 3 * size_of::<f64>());
    assert!(align_of::<Vector3<f64>>() == align_of::<f64>());
    assert!(size_of::<VoigtStress>() == 6 * size_of::<f64>());
    assert!(align_of::<VoigtStress>() == align_of::<f64>());
    assert!(size_of::<Tangent>() == 81 * size_of::<f64>());
    assert!(align_of::<Tangent>() == align_of::<f64>());
    assert!(size_of::<TableHead>() == 8);
    assert!(std::mem::offset_of!(MaterialPlugin, struct_size) == 4);
};

// The same sizes as the `_Static_assert`s of the header (64-bit targets).
#[cfg(target_pointer_width = "64")]
const _: () = {
    assert!(size_of::<ParameterInfo>() == 56);
    assert!(size_of::<StateInfo>() == 24);
    assert!(size_of::<PointBlock>() == 104);
    assert!(size_of::<MaterialPlugin>() == 72);
    assert!(size_of::<UpdateFn>() == size_of::<*const ()>());
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrix_memory_is_column_major() {
        let f = Matrix3::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0);
        let flat: &[f64] = f.as_slice();
        // F(i, J) at i + 3J
        let at = |i: usize, j: usize| flat[i + 3 * j];
        assert_eq!(at(1, 0), 4.0);
        assert_eq!(at(0, 1), 2.0);
        assert_eq!(at(2, 1), 8.0);
        let mut t = Tangent::zeros();
        t[(2, 7)] = 1.0;
        assert_eq!(t.as_slice()[2 + 9 * 7], 1.0);
    }
}
