//! `vumat_config.h`: what the adapter (plugins/abaqus_vumat/adapter.c or umat_adapter.c)
//! needs to know about one VUMAT or UMAT — the material name and description, cmname, the
//! props as parameters, the user's state variables, the fiber convention and the UMAT's
//! tangent source — as C macros.

use std::fmt::Write;

use crate::kind::Subroutine;
use crate::options::VumatBuild;

/// A C string literal of `text` (quotes and backslashes escaped, other bytes outside
/// printable ASCII as octal escapes).
pub fn c_string(text: &str) -> String {
    let mut literal = String::from("\"");
    for byte in text.bytes() {
        match byte {
            b'"' => literal.push_str("\\\""),
            b'\\' => literal.push_str("\\\\"),
            b' '..=b'~' => literal.push(byte as char),
            _ => {
                let _ = write!(literal, "\\{byte:03o}");
            }
        }
    }
    literal.push('"');
    literal
}

/// A double as C source that reads back exactly (`NAN` for a required value).
fn c_double(value: Option<f64>) -> String {
    match value {
        // `{:?}` prints the shortest text that parses back to the same double.
        Some(v) => format!("{v:?}"),
        None => "NAN".to_string(),
    }
}

/// The header's text for `build`, whose options were checked.
pub fn render(build: &VumatBuild) -> String {
    let file_name = build
        .source
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tangent = match build.subroutine {
        Subroutine::Vumat => String::new(),
        Subroutine::Umat => format!(", tangent {}", build.tangent),
    };
    let description = format!(
        "{} {} from {file_name} (cmname {}, nstatev {}, fiber convention {}{tangent})",
        build.subroutine.solver(),
        build.subroutine,
        build.cmname(),
        build.nstatev,
        build.fiber
    );
    let mut text = String::from(
        "/* vumat_config.h, written by `musclefem vumat build` or `musclefem umat build`: the \
         subroutine this plugin runs (the macros are named VUMAT_ for both). */\n",
    );
    let _ = writeln!(text, "#define VUMAT_NAME {}", c_string(&build.name));
    let _ = writeln!(text, "#define VUMAT_DESCRIPTION {}", c_string(&description));
    let _ = writeln!(text, "#define VUMAT_CMNAME {}", c_string(&build.cmname()));
    let _ = writeln!(text, "#define VUMAT_NPROPS {}", build.props.len());
    let _ = writeln!(text, "#define VUMAT_NSTATEV {}", build.nstatev);
    let _ = writeln!(text, "#define VUMAT_FIBER {}", build.fiber.c_macro());
    let _ = writeln!(text, "#define UMAT_TANGENT {}", build.tangent.c_value());
    text.push_str("#define VUMAT_PROPS_TABLE");
    for (i, prop) in build.props.iter().enumerate() {
        let _ = write!(
            text,
            " \\\n    {{{}, {}, {}, {}, -INFINITY, INFINITY, 0, 0}},",
            c_string(&prop.name),
            c_string(&prop.unit),
            c_string(&format!("props({}) of the {}", i + 1, build.subroutine)),
            c_double(prop.default)
        );
    }
    text.push_str("\n#define VUMAT_USER_STATES_TABLE");
    for i in 1..=build.nstatev {
        let initial = build.statev_initial.get(i - 1).copied().unwrap_or(0.0);
        let _ = write!(text, " \\\n    {{\"sdv{i}\", \"1\", {initial:?}}},");
    }
    text.push('\n');
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kind::TangentSource;
    use crate::options::{FiberConvention, Prop};

    #[test]
    fn strings_are_escaped_for_c() {
        assert_eq!(c_string("a\"b\\c"), "\"a\\\"b\\\\c\"");
        assert_eq!(c_string("é"), "\"\\303\\251\"");
    }

    #[test]
    fn header_lists_props_states_and_convention() {
        let build = VumatBuild {
            source: "dir/muscle.f".into(),
            name: "muscle".into(),
            cmname: None,
            props: Prop::parse_list("mu=11370:Pa,k").unwrap(),
            nstatev: 2,
            statev_initial: vec![1.5],
            fiber: FiberConvention::State,
            out: "libmuscle.so".into(),
            replace: false,
            subroutine: Subroutine::Vumat,
            tangent: TangentSource::Ddsdde,
        };
        let text = render(&build);
        for expected in [
            "#define VUMAT_NAME \"muscle\"\n",
            "#define VUMAT_CMNAME \"MUSCLE\"\n",
            "from muscle.f (cmname MUSCLE, nstatev 2, fiber convention state)",
            "#define VUMAT_NPROPS 2\n",
            "#define VUMAT_NSTATEV 2\n",
            "#define VUMAT_FIBER VUMAT_FIBER_STATE\n",
            "{\"mu\", \"Pa\", \"props(1) of the VUMAT\", 11370.0, -INFINITY, INFINITY, 0, 0},",
            "{\"k\", \"1\", \"props(2) of the VUMAT\", NAN, -INFINITY, INFINITY, 0, 0},",
            "{\"sdv1\", \"1\", 1.5}, \\\n    {\"sdv2\", \"1\", 0.0},\n",
        ] {
            assert!(text.contains(expected), "{expected}\nnot in\n{text}");
        }
        let umat = render(&VumatBuild {
            subroutine: Subroutine::Umat,
            tangent: TangentSource::FiniteDifference,
            ..build
        });
        for expected in [
            "Abaqus/Standard UMAT from muscle.f (cmname MUSCLE, nstatev 2, fiber convention \
             state, tangent finite-difference)",
            "#define UMAT_TANGENT 0\n",
            "\"props(1) of the UMAT\"",
        ] {
            assert!(umat.contains(expected), "{expected}\nnot in\n{umat}");
        }
    }
}
