//! Checked conversion of a plugin's C table into owned Rust values: the material's name
//! and description, [`ParameterSpec`]s (so that `ParameterSet::resolve` checks user values
//! exactly as for a built-in), [`StateVariable`]s and the update function.
//!
//! Errors are plain messages; the loader adds the plugin path.

use std::borrow::Cow;
use std::collections::BTreeSet;
use std::ffi::{CStr, c_char};

use super::abi;
use crate::material::StateVariable;
use crate::parameters::{Bound, ParameterSpec};

/// Everything the host keeps from a plugin's table (all owned, copied at load).
#[derive(Debug, Clone)]
pub(crate) struct Description {
    pub name: String,
    pub description: String,
    pub parameters: Vec<ParameterSpec>,
    pub states: Vec<StateVariable>,
    pub provides_tangent: bool,
    pub update: unsafe extern "C" fn(*const abi::PointBlock, *mut c_char, u64) -> i32,
}

/// Read and check a full-size table.
///
/// # Safety
/// Every non-null pointer in `table` must point to what the header says (a NUL-terminated
/// string, or an array of the declared count), valid for the duration of the call.
pub(crate) unsafe fn describe(table: &abi::MaterialPlugin) -> Result<Description, String> {
    // SAFETY: forwarded from the caller.
    let name =
        unsafe { c_string(table.name, "the material name") }?.ok_or("the material name is NULL")?;
    check_name(&name).map_err(|e| format!("the material name {e}"))?;
    // SAFETY: as above.
    let description =
        unsafe { c_string(table.description, "the description") }?.unwrap_or_default();
    let update = table
        .update
        .ok_or_else(|| format!("material '{name}': the update function pointer is NULL"))?;

    // SAFETY: as above.
    let infos =
        unsafe { table_slice(table.parameters, table.parameter_count) }.ok_or_else(|| {
            format!(
                "material '{name}': parameter_count is {} but the parameter table is NULL",
                table.parameter_count
            )
        })?;
    let mut parameters = Vec::with_capacity(infos.len());
    for (index, info) in infos.iter().enumerate() {
        // SAFETY: as above.
        let spec = unsafe { parameter_spec(info) }
            .map_err(|e| format!("material '{name}', parameter {index}{e}"))?;
        if parameters
            .iter()
            .any(|p: &ParameterSpec| p.name == spec.name)
        {
            return Err(format!(
                "material '{name}': parameter '{}' is declared twice",
                spec.name
            ));
        }
        parameters.push(spec);
    }

    // SAFETY: as above.
    let state_infos = unsafe { table_slice(table.states, table.state_count) }.ok_or_else(|| {
        format!(
            "material '{name}': state_count is {} but the state table is NULL",
            table.state_count
        )
    })?;
    let mut states = Vec::with_capacity(state_infos.len());
    let mut seen = BTreeSet::new();
    for (index, info) in state_infos.iter().enumerate() {
        // SAFETY: as above.
        let state = unsafe { state_variable(info) }
            .map_err(|e| format!("material '{name}', state variable {index}{e}"))?;
        if !seen.insert(state.name.clone()) {
            return Err(format!(
                "material '{name}': state variable '{}' is declared twice",
                state.name
            ));
        }
        states.push(state);
    }

    Ok(Description {
        name,
        description,
        parameters,
        states,
        provides_tangent: table.provides_tangent != 0,
        update,
    })
}

/// One parameter declaration as a [`ParameterSpec`]. The error starts with the
/// parameter's name in parentheses when it is known, e.g. " ('D'): ...".
///
/// # Safety
/// The string pointers of `info` must be null or NUL-terminated strings.
pub(crate) unsafe fn parameter_spec(info: &abi::ParameterInfo) -> Result<ParameterSpec, String> {
    // SAFETY: forwarded from the caller.
    let name = unsafe { c_string(info.name, "the name") }
        .map_err(|e| format!(": {e}"))?
        .ok_or(": the name is NULL")?;
    let located = |e: String| format!(" ('{name}'): {e}");
    check_name(&name).map_err(|e| located(format!("the name {e}")))?;
    // SAFETY: as above.
    let unit = unsafe { c_string(info.unit, "the unit") }
        .map_err(located)?
        .ok_or_else(|| located("the unit is NULL (use \"1\" for dimensionless)".into()))?;
    // SAFETY: as above.
    let description = unsafe { c_string(info.description, "the description") }
        .map_err(located)?
        .unwrap_or_default();
    spec_from_parts(
        name.clone(),
        unit,
        description,
        info.default_value,
        (info.lower, info.lower_inclusive != 0),
        (info.upper, info.upper_inclusive != 0),
    )
    .map_err(located)
}

/// Build and check a spec from plain values: infinite bounds are unbounded sides, the
/// range must not be empty, a NaN default makes the parameter required, any other
/// default must be finite and inside its own range. Plugin parameters are always finite
/// (`allow_infinite` false).
pub(crate) fn spec_from_parts(
    name: String,
    unit: String,
    description: String,
    default: f64,
    (lower, lower_inclusive): (f64, bool),
    (upper, upper_inclusive): (f64, bool),
) -> Result<ParameterSpec, String> {
    let lower_bound = match lower {
        l if l.is_nan() => return Err("the lower bound is NaN (use -INFINITY for none)".into()),
        f64::NEG_INFINITY => Bound::Unbounded,
        f64::INFINITY => return Err("the lower bound is +infinity: no value is valid".into()),
        l if lower_inclusive => Bound::Inclusive(l),
        l => Bound::Exclusive(l),
    };
    let upper_bound = match upper {
        u if u.is_nan() => return Err("the upper bound is NaN (use INFINITY for none)".into()),
        f64::INFINITY => Bound::Unbounded,
        f64::NEG_INFINITY => return Err("the upper bound is -infinity: no value is valid".into()),
        u if upper_inclusive => Bound::Inclusive(u),
        u => Bound::Exclusive(u),
    };
    let spec = ParameterSpec {
        name: Cow::Owned(name),
        unit: Cow::Owned(unit),
        default: None,
        lower: lower_bound,
        upper: upper_bound,
        allow_infinite: false,
        description: Cow::Owned(description),
    };
    let empty = match (lower_bound, upper_bound) {
        (Bound::Inclusive(l), Bound::Inclusive(u)) => l > u,
        (Bound::Unbounded, _) | (_, Bound::Unbounded) => false,
        _ => lower >= upper,
    };
    if empty {
        let kind = |inclusive: bool| if inclusive { "inclusive" } else { "exclusive" };
        return Err(format!(
            "the bounds leave no valid value: lower {lower} ({}), upper {upper} ({})",
            kind(lower_inclusive),
            kind(upper_inclusive)
        ));
    }
    if default.is_nan() {
        return Ok(spec);
    }
    if !spec.accepts(default) {
        return Err(format!(
            "the default {default} is outside its own range {} (use NaN for a required \
             parameter without default)",
            spec.range_text()
        ));
    }
    Ok(ParameterSpec {
        default: Some(default),
        ..spec
    })
}

/// One state-variable declaration. The error starts like [`parameter_spec`]'s.
///
/// # Safety
/// The string pointers of `info` must be null or NUL-terminated strings.
unsafe fn state_variable(info: &abi::StateInfo) -> Result<StateVariable, String> {
    // SAFETY: forwarded from the caller.
    let name = unsafe { c_string(info.name, "the name") }
        .map_err(|e| format!(": {e}"))?
        .ok_or(": the name is NULL")?;
    let located = |e: String| format!(" ('{name}'): {e}");
    check_name(&name).map_err(|e| located(format!("the name {e}")))?;
    // SAFETY: as above.
    let unit = unsafe { c_string(info.unit, "the unit") }
        .map_err(located)?
        .ok_or_else(|| located("the unit is NULL (use \"1\" for dimensionless)".into()))?;
    if !info.initial_value.is_finite() {
        return Err(located(format!(
            "the initial value {} is not finite",
            info.initial_value
        )));
    }
    Ok(StateVariable {
        name,
        unit,
        initial: info.initial_value,
    })
}

/// A name must be non-empty and free of whitespace, control characters and '=' (it is
/// written as `name = value` in scene files and on the command line).
fn check_name(name: &str) -> Result<(), String> {
    if name.is_empty() {
        return Err("is empty".into());
    }
    if name
        .chars()
        .any(|c| c.is_whitespace() || c.is_control() || c == '=')
    {
        return Err(format!(
            "{name:?} contains whitespace, a control character or '='"
        ));
    }
    Ok(())
}

/// The string a C pointer points to: `Ok(None)` for NULL, an error naming `what` when it
/// is not UTF-8.
///
/// # Safety
/// `ptr` must be null or point to a NUL-terminated string.
pub(crate) unsafe fn c_string(ptr: *const c_char, what: &str) -> Result<Option<String>, String> {
    if ptr.is_null() {
        return Ok(None);
    }
    // SAFETY: non-null and NUL-terminated by the caller's contract.
    let c = unsafe { CStr::from_ptr(ptr) };
    c.to_str()
        .map(|s| Some(s.to_owned()))
        .map_err(|e| format!("{what} is not valid UTF-8 ({e}): {:?}", c.to_string_lossy()))
}

/// A slice of `count` entries; `None` when `count > 0` and `ptr` is null.
///
/// # Safety
/// When `count > 0` and `ptr` is non-null, `ptr` must point to `count` initialised entries.
unsafe fn table_slice<'a, T>(ptr: *const T, count: u32) -> Option<&'a [T]> {
    if count == 0 {
        return Some(&[]);
    }
    if ptr.is_null() || !ptr.is_aligned() {
        return None;
    }
    // SAFETY: non-null, aligned, and `count` entries by the caller's contract.
    Some(unsafe { std::slice::from_raw_parts(ptr, count as usize) })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ptr;

    const INF: f64 = f64::INFINITY;

    fn info(name: &CStr, default: f64, lower: f64, upper: f64) -> abi::ParameterInfo {
        abi::ParameterInfo {
            name: name.as_ptr(),
            unit: c"Pa".as_ptr(),
            description: ptr::null(),
            default_value: default,
            lower,
            upper,
            lower_inclusive: 0,
            upper_inclusive: 1,
        }
    }

    unsafe extern "C" fn no_op(_: *const abi::PointBlock, _: *mut c_char, _: u64) -> i32 {
        0
    }

    fn table(name: *const c_char, parameters: &[abi::ParameterInfo]) -> abi::MaterialPlugin {
        abi::MaterialPlugin {
            abi_version: abi::ABI_VERSION,
            struct_size: size_of::<abi::MaterialPlugin>() as u32,
            name,
            description: ptr::null(),
            parameter_count: parameters.len() as u32,
            parameters: parameters.as_ptr(),
            state_count: 0,
            states: ptr::null(),
            provides_tangent: 0,
            update: Some(no_op),
        }
    }

    #[test]
    fn parameter_table_becomes_the_same_specs_as_a_builtin() {
        let infos = [
            info(c"mu", 11_370.0, 0.0, INF),
            abi::ParameterInfo {
                unit: c"1/Pa".as_ptr(),
                ..info(c"D", 5e-9, 0.0, INF)
            },
        ];
        // SAFETY: every pointer is a static C string or the live array above.
        let d = unsafe { describe(&table(c"nh".as_ptr(), &infos)) }.unwrap();
        assert_eq!(d.name, "nh");
        assert_eq!(d.description, "");
        assert!(!d.provides_tangent);
        let builtin = &crate::neo_hookean::NEO_HOOKEAN_PARAMETERS;
        assert_eq!(d.parameters.len(), 2);
        for (p, b) in d.parameters.iter().zip(builtin) {
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
                )
            );
            assert_eq!(p.range_text(), b.range_text());
        }
    }

    #[test]
    fn bounds_map_to_bound_kinds_and_nan_default_means_required() {
        let spec = spec_from_parts(
            "n".into(),
            "1".into(),
            "activation".into(),
            f64::NAN,
            (0.0, true),
            (1.0, false),
        )
        .unwrap();
        assert_eq!(spec.default, None);
        assert_eq!(spec.lower, Bound::Inclusive(0.0));
        assert_eq!(spec.upper, Bound::Exclusive(1.0));
        assert!(!spec.allow_infinite);
        let spec = spec_from_parts(
            "x".into(),
            "m".into(),
            String::new(),
            -3.0,
            (-INF, false),
            (INF, true),
        )
        .unwrap();
        assert_eq!(
            (spec.lower, spec.upper),
            (Bound::Unbounded, Bound::Unbounded)
        );
        assert_eq!(spec.default, Some(-3.0));
        assert!(!spec.accepts(INF), "plugin parameters are finite");
    }

    #[test]
    fn inconsistent_parameter_tables_are_rejected_with_a_reason() {
        let check = |infos: &[abi::ParameterInfo], expected: &str| {
            // SAFETY: static strings and a live array.
            let err = unsafe { describe(&table(c"m".as_ptr(), infos)) }.unwrap_err();
            assert!(err.contains(expected), "{err:?} lacks {expected:?}");
        };
        check(
            &[info(c"D", 0.0, 0.0, INF)],
            "parameter 0 ('D'): the default 0 is outside its own range (0, inf), finite",
        );
        check(&[info(c"D", INF, 0.0, INF)], "the default inf is outside");
        check(
            &[info(c"a", 1.0, 2.0, 1.0)],
            "('a'): the bounds leave no valid value: lower 2 (exclusive), upper 1 (inclusive)",
        );
        check(
            &[info(c"a", 1.0, 1.0, 1.0)],
            "lower 1 (exclusive), upper 1 (inclusive)",
        );
        check(&[info(c"a", 1.0, f64::NAN, 2.0)], "lower bound is NaN");
        check(&[info(c"a", 1.0, INF, INF)], "lower bound is +infinity");
        check(
            &[info(c"a", 1.0, 0.0, 2.0), info(c"a", 1.0, 0.0, 2.0)],
            "parameter 'a' is declared twice",
        );
        check(
            &[info(c"", 1.0, 0.0, 2.0)],
            "parameter 0 (''): the name is empty",
        );
        check(&[info(c"a b", 1.0, 0.0, 2.0)], "contains whitespace");
        let no_unit = abi::ParameterInfo {
            unit: ptr::null(),
            ..info(c"a", 1.0, 0.0, 2.0)
        };
        check(&[no_unit], "('a'): the unit is NULL");
        let mut t = table(c"m".as_ptr(), &[]);
        t.parameter_count = 2;
        t.parameters = ptr::null();
        // SAFETY: the null parameter pointer is what is being tested; nothing else is read.
        let err = unsafe { describe(&t) }.unwrap_err();
        assert!(
            err.contains("parameter_count is 2 but the parameter table is NULL"),
            "{err}"
        );
        // An inclusive range of a single value is fine.
        let one = abi::ParameterInfo {
            lower_inclusive: 1,
            ..info(c"a", 1.0, 1.0, 1.0)
        };
        // SAFETY: as above.
        assert!(unsafe { describe(&table(c"m".as_ptr(), &[one])) }.is_ok());
    }

    #[test]
    fn material_name_must_be_present_and_utf8() {
        // SAFETY: null name, no parameters.
        let err = unsafe { describe(&table(ptr::null(), &[])) }.unwrap_err();
        assert_eq!(err, "the material name is NULL");
        let bad = c"caf\xe9";
        // SAFETY: a static C string.
        let err = unsafe { describe(&table(bad.as_ptr(), &[])) }.unwrap_err();
        assert!(
            err.contains("the material name is not valid UTF-8"),
            "{err}"
        );
        let mut t = table(c"m".as_ptr(), &[]);
        t.update = None;
        // SAFETY: static strings.
        let err = unsafe { describe(&t) }.unwrap_err();
        assert!(err.contains("update function pointer is NULL"), "{err}");
    }

    #[test]
    fn state_table_is_checked() {
        let states = [
            abi::StateInfo {
                name: c"lambda_m".as_ptr(),
                unit: c"1".as_ptr(),
                initial_value: 1.0,
            },
            abi::StateInfo {
                name: c"sigma_s".as_ptr(),
                unit: c"Pa".as_ptr(),
                initial_value: f64::NAN,
            },
        ];
        let mut t = table(c"m".as_ptr(), &[]);
        t.states = states.as_ptr();
        t.state_count = 1;
        // SAFETY: static strings and a live array of at least `state_count` entries.
        let d = unsafe { describe(&t) }.unwrap();
        assert_eq!(
            d.states,
            vec![StateVariable {
                name: "lambda_m".into(),
                unit: "1".into(),
                initial: 1.0
            }]
        );
        t.state_count = 2;
        // SAFETY: as above.
        let err = unsafe { describe(&t) }.unwrap_err();
        assert!(
            err.contains("state variable 1 ('sigma_s'): the initial value NaN is not finite"),
            "{err}"
        );
    }
}
