//! The passive knee squat (see [`crate::knee`]): the procedural anatomy, knee flexion
//! 0° → 90° → 0° in 2 s, at a resolution chosen by the method's mesh size (the
//! resolution's [`Resolution::mean_element_size`]).
//!
//! Response: the 32 passive vm95 entries of the peak-stress table (VI, VL, VM, RF × 30°,
//! 45°, 60°, 90° × flexion, extension) [Pa]. The passive squat is the one measured: the
//! active one costs about twice as much and its vm95 differ from the passive ones at the
//! same angles by the activation, which every resolution and solver models alike.

use std::sync::atomic::{AtomicUsize, Ordering};

use anyhow::{Context, Result, bail};

use super::Response;
use super::method::{Method, StepSetting};
use crate::knee::simulation::peak_stress::TABLE_ANGLES_DEGREES;
use crate::knee::simulation::{Activation, KneeGeometry, Phase, SquatSettings, run_squat_in};
use crate::knee::{Anatomy, Quadriceps, Resolution};

/// The `error_metric` column.
pub const ERROR_METRIC: &str =
    "max_passive_vm95_error_4_muscles_at_30_45_60_90deg_flexion_and_extension";

/// The explicit knee runs at the solver's default safety factor.
pub const KNEE_SAFETY: f64 = 0.9;

/// The squat settings of `method` (its solver's recommended ones, with its element and
/// step) and the resolution its mesh size names.
pub fn squat_of(method: &Method) -> Result<(SquatSettings, Resolution)> {
    let resolution = Resolution::with_mean_element_size(method.mesh_size).with_context(|| {
        format!(
            "the knee has no resolution with {:.1} mm elements (coarse {:.1}, medium {:.1}, \
             fine {:.1} mm)",
            1e3 * method.mesh_size,
            1e3 * Resolution::Coarse.mean_element_size(),
            1e3 * Resolution::Medium.mean_element_size(),
            1e3 * Resolution::Fine.mean_element_size()
        )
    })?;
    if !method.element.is_hex() {
        bail!(
            "the knee's muscles are meshed with hex8, not {}",
            method.element.name()
        );
    }
    let mut settings = SquatSettings::recommended(method.solver());
    settings.element = method.element;
    settings.time_step = match method.step {
        StepSetting::Implicit { increment } => increment,
        StepSetting::Explicit {
            mass_scaling,
            safety,
        } => {
            if safety != KNEE_SAFETY {
                bail!("the knee runs the explicit solver at safety factor {KNEE_SAFETY}");
            }
            mass_scaling.context(
                "the knee needs mass scaling (its physical stable step would take millions \
                 of steps)",
            )?
        }
    };
    Ok((settings, resolution))
}

/// Run the passive squat of `method` as its scene (in a scratch directory, removed
/// afterwards) and return its 32 vm95 entries, muscle by muscle, angle by angle, flexion
/// before extension.
pub fn run_knee(method: &Method) -> Result<Response> {
    let (settings, resolution) = squat_of(method)?;
    let anatomy = Anatomy::procedural_knee(resolution)?;
    let geometry = KneeGeometry::procedural_knee(&anatomy, &settings.squat)?;
    let fibers = geometry.fibers()?;
    // One scratch directory per run: the bench may run several at once.
    static RUNS: AtomicUsize = AtomicUsize::new(0);
    let scratch = std::env::temp_dir().join(format!(
        "musclefem-bench-knee-{}-{}",
        std::process::id(),
        RUNS.fetch_add(1, Ordering::Relaxed)
    ));
    let run = run_squat_in(&geometry, &fibers, Activation::Passive, &settings, &scratch);
    let _ = std::fs::remove_dir_all(&scratch);
    let run = run?;
    let mut samples = Vec::with_capacity(32);
    for muscle in Quadriceps::ALL {
        for angle in TABLE_ANGLES_DEGREES {
            for phase in [Phase::Flexion, Phase::Extension] {
                let row = run
                    .rows
                    .iter()
                    .find(|r| r.muscle == muscle && r.angle_degrees == angle && r.phase == phase)
                    .with_context(|| {
                        format!(
                            "the squat has no vm95 of {} at {angle}° in {}",
                            muscle.abbreviation(),
                            phase.name()
                        )
                    })?;
                samples.push(row.vm95);
            }
        }
    }
    Ok(Response {
        samples,
        warning: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elongation::ElementChoice;

    #[test]
    fn a_resolution_is_named_by_its_mean_element_size() {
        for resolution in [Resolution::Coarse, Resolution::Medium, Resolution::Fine] {
            let size = resolution.mean_element_size();
            assert_eq!(Resolution::with_mean_element_size(size), Some(resolution));
        }
        assert!((Resolution::Coarse.mean_element_size() - 0.01275).abs() < 1e-5);
        assert_eq!(Resolution::with_mean_element_size(0.010), None);
        // The coarse anatomy's bellies (volume-matched to the Visible Human; the tendons
        // are meshed apart): as many elements as the formula says, and the mean element
        // volume of the formula within 1 %.
        let anatomy = Anatomy::procedural_knee(Resolution::Coarse).unwrap();
        let mut volume = 0.0;
        let mut elements = 0;
        for muscle in &anatomy.muscles {
            let b = muscle.belly_block();
            let block = &muscle.mesh.blocks[b];
            assert_eq!(block.len(), Resolution::Coarse.elements_per_muscle());
            for e in 0..block.len() {
                let element = musclefem_core::mesh::ElementRef {
                    block: b as u32,
                    element: e as u32,
                };
                volume += muscle.mesh.element_volume(element).unwrap();
                elements += 1;
            }
        }
        let size = (volume / elements as f64).cbrt();
        let expected = Resolution::Coarse.mean_element_size();
        assert!(
            (size - expected).abs() < 0.01 * expected,
            "{size} vs {expected}"
        );
    }

    #[test]
    fn a_method_without_a_knee_resolution_or_with_tetrahedra_is_refused() {
        let method = |element, mesh_size| Method {
            element,
            mesh_size,
            step: StepSetting::Implicit { increment: 0.02 },
        };
        let size = Resolution::Medium.mean_element_size();
        let (settings, resolution) = squat_of(&method(ElementChoice::Hex8Fbar, size)).unwrap();
        assert_eq!(resolution, Resolution::Medium);
        assert_eq!(settings.time_step, 0.02);
        let error = squat_of(&method(ElementChoice::Hex8Fbar, 0.01)).unwrap_err();
        assert!(error.to_string().contains("no resolution"), "{error}");
        let error = squat_of(&method(ElementChoice::Tet4, size)).unwrap_err();
        assert!(error.to_string().contains("hex8"), "{error}");
    }
}
