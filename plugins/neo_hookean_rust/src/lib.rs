//! Example third-party material plugin for musclefem, written in Rust with no
//! dependencies: the compressible neo-Hookean solid, as material
//! `neo-hookean-rust-plugin`.
//!
//! W = μ/2 (Ī₁ − 3) + (J − 1)²/D, Ī₁ = tr(J^(-2/3) F Fᵀ),
//! σ = (μ/J) dev(B̄) + 2(J − 1)/D I.
//!
//! It is the same model as musclefem's built-in `neo-hookean` (and the C plugin
//! `plugins/neo_hookean_c`); the three agree to round-off (the built-in takes J^(-1/3) by
//! a Taylor series and Newton steps, this plugin by `cbrt`); musclefem's tests check that. It supplies no tangent
//! (`provides_tangent = 0`): the host differentiates the stress numerically.
//!
//! Build: `cargo build --release -p musclefem-plugin-neo-hookean`, then load
//! `target/release/libmusclefem_plugin_neo_hookean.so`. See README.md for how to write
//! your own plugin.

mod abi;

use std::ffi::c_char;
use std::panic::{AssertUnwindSafe, catch_unwind};

use abi::{MaterialPlugin, ParameterInfo, PointBlock, Static};

const NAME: &std::ffi::CStr = c"neo-hookean-rust-plugin";

/// Declared parameters, in the order `properties` arrives in each block.
static PARAMETERS: Static<[ParameterInfo; 2]> = Static([
    ParameterInfo {
        name: c"mu".as_ptr(),
        unit: c"Pa".as_ptr(),
        description: c"shear modulus".as_ptr(),
        default_value: 11_370.0,
        lower: 0.0,
        upper: f64::INFINITY,
        lower_inclusive: 0, // mu > 0
        upper_inclusive: 0,
    },
    ParameterInfo {
        name: c"D".as_ptr(),
        unit: c"1/Pa".as_ptr(),
        description: c"compressibility, bulk modulus = 2/D".as_ptr(),
        default_value: 5.0e-9,
        lower: 0.0,
        upper: f64::INFINITY,
        lower_inclusive: 0, // D > 0
        upper_inclusive: 0,
    },
]);

static PLUGIN: Static<MaterialPlugin> = Static(MaterialPlugin {
    abi_version: abi::ABI_VERSION,
    struct_size: size_of::<MaterialPlugin>() as u32,
    name: NAME.as_ptr(),
    description: c"compressible neo-Hookean solid (Rust plugin example): W = mu/2 (I1bar - 3) + (J - 1)^2 / D".as_ptr(),
    parameter_count: 2,
    parameters: PARAMETERS.0.as_ptr(),
    state_count: 0,
    states: std::ptr::null(),
    provides_tangent: 0,
    update: Some(update),
});

/// The one exported symbol. Like every function the host calls, it must not unwind into
/// the host (a panic crossing `extern "C"` aborts the whole process): it catches panics
/// and returns NULL, which the host reports.
#[unsafe(no_mangle)]
pub extern "C" fn musclefem_material_plugin() -> *const MaterialPlugin {
    catch_unwind(|| &PLUGIN.0 as *const MaterialPlugin).unwrap_or(std::ptr::null())
}

/// `update`: returns 0, or 1 with a message for a bad block, or 2 with a message for a
/// panic caught here.
unsafe extern "C" fn update(block: *const PointBlock, message: *mut c_char, capacity: u64) -> i32 {
    // SAFETY (of the closure's body): the host guarantees the block's pointers as the
    // header describes; `update_block` checks what it can.
    let outcome = catch_unwind(AssertUnwindSafe(|| unsafe { update_block(block) }));
    let (code, text) = match outcome {
        Ok(Ok(())) => return 0,
        Ok(Err(text)) => (1, text),
        Err(payload) => (
            2,
            format!("panic in update: {}", abi::panic_text(&*payload)),
        ),
    };
    // SAFETY: the host passes a buffer of `capacity` bytes.
    unsafe { abi::write_message(message, capacity, &text) };
    code
}

/// A 3×3 matrix as rows: `m[i][j]` is entry (i, j).
type M3 = [[f64; 3]; 3];

/// # Safety
/// `block` must be null or a block laid out as the header describes.
unsafe fn update_block(block: *const PointBlock) -> Result<(), String> {
    // SAFETY: null checked; the host owns the block for the duration of the call.
    let b = unsafe { block.as_ref() }.ok_or("the block pointer is NULL")?;
    if (b.struct_size as usize) < size_of::<PointBlock>() {
        return Err(format!(
            "block struct_size {} < {}",
            b.struct_size,
            size_of::<PointBlock>()
        ));
    }
    if b.property_count != 2 || b.properties.is_null() {
        return Err(format!(
            "expected 2 properties (mu, D), got {}",
            b.property_count
        ));
    }
    let n = b.point_count as usize;
    if n == 0 {
        return Ok(());
    }
    // SAFETY: array lengths as the header promises for `n` points and 2 properties.
    let (properties, f_new, stress) = unsafe {
        (
            std::slice::from_raw_parts(b.properties, 2),
            std::slice::from_raw_parts(b.deformation_gradient_new, 9 * n),
            std::slice::from_raw_parts_mut(b.cauchy_stress, 6 * n),
        )
    };
    let (mu, d) = (properties[0], properties[1]);
    for p in 0..n {
        // Column-major input: F(i, J) at 9p + i + 3J.
        let f: M3 = std::array::from_fn(|i| std::array::from_fn(|j| f_new[9 * p + i + 3 * j]));
        let sigma = cauchy_stress(&f, mu, d);
        let out = &mut stress[6 * p..6 * p + 6];
        out.copy_from_slice(&[
            sigma[0][0],
            sigma[1][1],
            sigma[2][2],
            sigma[1][2],
            sigma[0][2],
            sigma[0][1],
        ]);
    }
    Ok(())
}

/// σ = (μ/J) dev(B̄) + 2(J − 1)/D I, with B̄ = F̄ F̄ᵀ, F̄ = J^(-1/3) F.
fn cauchy_stress(f: &M3, mu: f64, d: f64) -> M3 {
    let j = determinant(f);
    let j_minus_third = 1.0 / j.cbrt();
    let f_bar: M3 = std::array::from_fn(|r| std::array::from_fn(|c| f[r][c] * j_minus_third));
    let b_bar: M3 = std::array::from_fn(|r| {
        std::array::from_fn(|c| {
            f_bar[r][0] * f_bar[c][0] + f_bar[r][1] * f_bar[c][1] + f_bar[r][2] * f_bar[c][2]
        })
    });
    let third_trace = (b_bar[0][0] + b_bar[1][1] + b_bar[2][2]) / 3.0;
    let pressure = 2.0 * (j - 1.0) / d;
    let scale = mu / j;
    std::array::from_fn(|r| {
        std::array::from_fn(|c| {
            let dev = if r == c {
                b_bar[r][c] - third_trace
            } else {
                b_bar[r][c]
            };
            dev * scale + if r == c { pressure } else { 0.0 }
        })
    })
}

/// det F by cofactors along the first row.
fn determinant(m: &M3) -> f64 {
    let minor_12_23 = m[1][1] * m[2][2] - m[2][1] * m[1][2];
    let minor_11_23 = m[1][0] * m[2][2] - m[2][0] * m[1][2];
    let minor_11_22 = m[1][0] * m[2][1] - m[2][0] * m[1][1];
    m[0][0] * minor_12_23 - m[0][1] * minor_11_23 + m[0][2] * minor_11_22
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stress_free_at_identity_and_hydrostatic_under_dilatation() {
        let identity: M3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let s = cauchy_stress(&identity, 1e4, 1e-6);
        assert!(s.iter().flatten().all(|x| x.abs() < 1e-9), "{s:?}");
        let a = 1.01_f64;
        let dilated: M3 = [[a, 0.0, 0.0], [0.0, a, 0.0], [0.0, 0.0, a]];
        let s = cauchy_stress(&dilated, 1e4, 1e-6);
        let p = 2.0 * (a * a * a - 1.0) / 1e-6;
        for i in 0..3 {
            assert!((s[i][i] - p).abs() < 1e-9 * p, "{s:?}");
        }
    }

    #[test]
    fn the_table_is_exported() {
        let t = musclefem_material_plugin();
        assert!(!t.is_null());
        // SAFETY: the static table.
        let t = unsafe { &*t };
        assert_eq!(t.abi_version, 1);
        assert_eq!(t.parameter_count, 2);
    }

    #[test]
    fn a_bad_block_is_an_error_code_with_a_message() {
        let mut message = [0 as c_char; 64];
        // SAFETY: a null block is what is tested; the buffer is 64 bytes.
        let code = unsafe { update(std::ptr::null(), message.as_mut_ptr(), 64) };
        assert_eq!(code, 1);
        // SAFETY: write_message NUL-terminates within the buffer.
        let text = unsafe { std::ffi::CStr::from_ptr(message.as_ptr()) };
        assert_eq!(text.to_str().unwrap(), "the block pointer is NULL");
    }
}
