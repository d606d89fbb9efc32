//! The knee's materials as `[[materials]]` entries of a scene (issue 30, step 4): one
//! Hill muscle per belly with its fiber reference (λ_PE, λ_M, λ_opt) and the squat's
//! activation (`n2`, `t0`), every parameter written as the shortest decimal that reads
//! back to the same `f64` (`t1 = inf`: never switched off), and the tendon with the
//! registry's defaults. A scene built from them has the knee's materials, bit for bit.

use std::fmt::Write as _;

use musclefem_io::csv::format_number;
use musclefem_materials::hill::HillParameters;

use super::model::{Activation, FiberReference, muscle_parameters};
use crate::knee::anatomy::Squat;

/// The `[[materials]]` entry `name` of the Hill muscle with `parameters`.
pub fn hill_entry(name: &str, parameters: &HillParameters) -> String {
    let values: Vec<String> = parameters
        .named()
        .iter()
        .map(|(key, value)| format!("{key} = {}", format_number(*value)))
        .collect();
    format!(
        "[[materials]]\nname = {name:?}\nmodel = \"hill\"\nparameters = {{ {} }}\n",
        values.join(", ")
    )
}

/// The `[[materials]]` entries of the squat's muscles, `<name>_muscle` for each
/// (name, fiber reference) of `muscles`, and of the tendon, `tendon`.
pub fn knee_material_entries(
    muscles: &[(&str, FiberReference)],
    activation: Activation,
    squat: &Squat,
) -> String {
    let mut text = String::new();
    for (name, reference) in muscles {
        let parameters = muscle_parameters(activation, squat, reference);
        let _ = writeln!(
            text,
            "{}",
            hill_entry(&format!("{name}_muscle"), &parameters)
        );
    }
    text.push_str("[[materials]]\nname = \"tendon\"\nmodel = \"tendon\"\n");
    text
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use musclefem_io::scene::{build_model, parse_scene};
    use musclefem_materials::MaterialLibrary;

    use super::*;
    use crate::knee::simulation::model::{muscle_material, tendon_material};

    #[test]
    fn the_scenes_materials_are_the_knees_bit_for_bit() {
        let squat = Squat {
            duration: 1.7,
            peak_flexion: 75f64.to_radians(),
        };
        let muscles = [
            ("vastus_lateralis", FiberReference::paper()),
            (
                "rectus_femoris",
                FiberReference::parallel_slack(1.0834117021530126),
            ),
            ("vastus_medialis", FiberReference::rest_at(1.153)),
        ];
        for activation in [Activation::Passive, Activation::Active] {
            let part = |name: &str, material: &str| {
                format!(
                    "[[parts]]\nname = \"{name}\"\nmaterial = \"{material}\"\nelement = \
                     \"hex8-fbar\"\ndensity = 1060.0\nmesh = {{ generator = \"box\", size = \
                     [0.01, 0.01, 0.01], divisions = [1, 1, 1] }}\n\n"
                )
            };
            let text = format!(
                "schema_version = 1\n\n{}{}{}{}{}[step]\nduration = 1.7\n",
                knee_material_entries(&muscles, activation, &squat),
                part("vl", "vastus_lateralis_muscle"),
                part("rf", "rectus_femoris_muscle"),
                part("vm", "vastus_medialis_muscle"),
                part("rf_tendon", "tendon"),
            );
            let (scene, locator) = parse_scene(&text, Path::new("knee.toml")).unwrap();
            let model =
                build_model(&scene, &locator, &mut MaterialLibrary::with_builtins()).unwrap();
            let described = |part: usize| format!("{:?}", model.parts[part].material);
            for (part, (_, reference)) in muscles.iter().enumerate() {
                let expected = muscle_material(activation, &squat, reference).unwrap();
                // `Debug` writes every f64 as its shortest round-trip decimal: equal text
                // is equal bits.
                assert_eq!(described(part), format!("{expected:?}"), "{activation:?}");
            }
            assert_eq!(described(3), format!("{:?}", tendon_material().unwrap()));
        }
        // The muscles are never switched off.
        let entries = knee_material_entries(&muscles, Activation::Active, &squat);
        assert!(entries.contains("t1 = inf"), "{entries}");
    }
}
