//! The squat's analysis as a scene's `[step]` (issue 30, step 4): the implicit solver
//! with the knee's Newton settings ([`super::run`]: its tolerances, three line-search
//! halvings, no factor reuse, Newmark with α = 0.1 when the muscles' inertia is on, the
//! femur as the predictor frame) or the explicit solver with mass scaling (its added mass
//! carried by the femur) and the knee's shear viscosity. A scene built
//! from it has the knee's [`Analysis`], bit for bit.

use musclefem_io::csv::format_number;

use super::run::{
    KNEE_LINE_SEARCH_CUTS, KNEE_NEWMARK_DISSIPATION, KNEE_SHEAR_VISCOSITY, SquatSettings,
};
use crate::elongation::Solver;

/// The `[step]` table of a squat with `settings`; `femur` names the rigid body whose
/// motion is the implicit solver's predictor frame and carries the explicit solver's
/// added mass.
pub fn squat_step_entry(settings: &SquatSettings, femur: &str) -> String {
    let duration = settings.squat.duration;
    match settings.solver {
        Solver::Implicit => {
            let increments = (duration / settings.time_step).round().max(1.0) as usize;
            let dynamics = if settings.inertia {
                format!(
                    "dynamic = true\nnumerical_dissipation = {}\n",
                    format_number(KNEE_NEWMARK_DISSIPATION)
                )
            } else {
                String::new()
            };
            format!(
                "[step]\nsolver = \"implicit\"\nduration = {}\n\n[step.implicit]\nincrements = \
                 {increments}\n{dynamics}residual_tolerance = {}\ncorrection_tolerance = {}\n\
                 line_search_cuts = {KNEE_LINE_SEARCH_CUTS}\nfactor_reuse = false\n\
                 predictor_frame = {femur:?}\n",
                format_number(duration),
                format_number(settings.residual_tolerance),
                format_number(settings.correction_tolerance),
            )
        }
        Solver::Explicit => format!(
            "[step]\nsolver = \"explicit\"\nduration = {}\noutput_interval = {}\n\n\
             [step.explicit]\nmass_scaling_time_step = {}\nshear_viscosity = {}\n\
             mass_scaling_frame = {femur:?}\n",
            format_number(duration),
            format_number(settings.record_interval),
            format_number(settings.time_step),
            format_number(KNEE_SHEAR_VISCOSITY),
        ),
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use musclefem_io::scene::{build_model, parse_scene};
    use musclefem_materials::MaterialLibrary;

    use super::*;
    use crate::knee::anatomy::squat::Bone;
    use crate::knee::anatomy::{ClosedChain, Squat};
    use crate::knee::simulation::followers::closed_chain_motion;
    use crate::knee::simulation::run::squat_analysis;

    #[test]
    fn the_scenes_analysis_is_the_squats_bit_for_bit() {
        let chain = ClosedChain::procedural_knee();
        for solver in [Solver::Implicit, Solver::Explicit] {
            for inertia in [true, false] {
                let mut settings = SquatSettings::recommended(solver);
                settings.squat = Squat {
                    duration: 0.7,
                    peak_flexion: 40f64.to_radians(),
                };
                settings.inertia = inertia;
                settings.time_step = match solver {
                    Solver::Implicit => 0.015,
                    Solver::Explicit => 3e-5,
                };
                let motion = closed_chain_motion(Bone::Femur, &chain, &settings.squat);
                let text = format!(
                    "schema_version = 1\n\n[[materials]]\nname = \"m\"\nmodel = \"neo-hookean\"\n\n\
                     [[parts]]\nname = \"p\"\nmaterial = \"m\"\nelement = \"hex8-fbar\"\n\
                     density = 1060.0\nmesh = {{ generator = \"box\", size = [0.01, 0.01, \
                     0.01], divisions = [1, 1, 1] }}\n\n[[rigid_bodies]]\nname = \"femur\"\n\
                     surface = {{ shape = \"sphere\", center = [0.0, 0.2, 0.0], radius = 0.01 \
                     }}\nmotion = {motion}\n\n{}",
                    squat_step_entry(&settings, "femur")
                );
                let (scene, locator) = parse_scene(&text, Path::new("knee.toml")).unwrap();
                let model =
                    build_model(&scene, &locator, &mut MaterialLibrary::with_builtins()).unwrap();
                let femur = settings.squat.motions(&chain).unwrap().femur;
                // `Debug` writes every f64 as its shortest round-trip decimal and the
                // predictor frame's follower with its chain and squat.
                assert_eq!(
                    format!("{:?}", model.analysis),
                    format!("{:?}", squat_analysis(&settings, &femur)),
                    "{solver:?}, inertia {inertia}"
                );
            }
        }
    }
}
