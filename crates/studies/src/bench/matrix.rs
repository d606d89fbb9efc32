//! Which methods each problem runs, and its reference.
//!
//! The reference of a problem is the most trusted method (quasi-static implicit F-bar
//! hex8: locking-free, no inertia) on a mesh finer than any in the matrix and with an
//! increment no larger than the smallest in it: the cube at 1 mm (quick) or 0.625 mm
//! (full) with 0.05 s increments; the elongation at 3 mm with 0.1 s (quick) or 2 mm with
//! 0.05 s (full; the passive muscle is hyperelastic, so the quasi-static increment changes
//! the cost, not the answer: 0.2 s and 0.1 s on 4 mm agree to 1e-6). Its own discretisation error is not zero: errors well below the
//! difference between the two finest meshes of the reference family are not resolved.
//!
//! The knee's reference is the passive squat on the medium mesh with the default 20 ms
//! increment: fine (35 840 muscle elements) would take hours. The knee's matrix is coarse
//! only (F-bar and one-point hex8, 20 and 40 ms increments, and the explicit solver at
//! the default mass scaling), so its error is that of the coarse mesh against medium,
//! and medium's own error is not measured. It has no quick matrix (`quick` is ignored):
//! the reference alone takes about 5 minutes (277 s on 2026-11-24 with the mixed pressure
//! in Newton's tangent; about 15 before).
//!
//! `--quick` keeps each problem under a minute on a loaded 2-core machine: fewer
//! elements and steps, and for the elongation one matrix mesh (4 mm; the fusiform's end
//! radius, 4.5 mm, bounds the coarsest size).

use crate::elongation::ElementChoice::{self, *};
use crate::knee::Resolution;

use super::Problem;
use super::method::{Method, StepSetting};

/// The methods `problem` runs (the reference excluded).
pub fn matrix(problem: Problem, quick: bool) -> Vec<Method> {
    match (problem, quick) {
        (Problem::Cube, true) => combine(
            &[Hex8Fbar, Hex8Full, Tet4, Tet10],
            &[0.005, 0.01 / 3.0, 0.0025],
            &implicit(&[0.25, 0.1]),
        )
        .chain(combine(
            &[Hex8Fbar, Hex8OnePoint, Tet4NodalAverage],
            &[0.005, 0.01 / 3.0, 0.0025],
            &explicit(&[None, Some(1e-3), Some(1e-2)], 0.9),
        ))
        .collect(),
        (Problem::Cube, false) => combine(
            &[Hex8Fbar, Hex8Full, Hex8OnePoint, Tet4, Tet10],
            &[0.005, 0.0025, 0.00125],
            &implicit(&[0.25, 0.1]),
        )
        .chain(combine(
            &[
                Hex8Fbar,
                Hex8Full,
                Hex8OnePoint,
                Tet4,
                Tet4NodalAverage,
                Tet10,
            ],
            &[0.005, 0.0025, 0.00125],
            &[
                explicit(&[None, Some(1e-3), Some(1e-2)], 0.9),
                explicit(&[None], 0.5),
            ]
            .concat(),
        ))
        .collect(),
        (Problem::Elongate, true) => combine(&[Hex8Fbar], &[0.004], &implicit(&[0.4, 0.2]))
            .chain(combine(&[Hex8Full, Tet4], &[0.004], &implicit(&[0.2])))
            .chain(combine(
                &[Hex8OnePoint],
                &[0.004],
                &explicit(&[Some(2e-4), Some(1e-4)], 0.9),
            ))
            .collect(),
        (Problem::Elongate, false) => combine(
            &[Hex8Fbar, Hex8Full, Tet4],
            &[0.004, 0.003, 0.0025],
            &implicit(&[0.2, 0.05]),
        )
        .chain(combine(&[Tet10], &[0.004], &implicit(&[0.2])))
        .chain(combine(
            &[Hex8Fbar],
            &[0.004],
            &explicit(&[Some(1e-5), Some(4e-5), Some(2e-4)], 0.9),
        ))
        .chain(combine(
            &[Hex8OnePoint],
            &[0.004, 0.003],
            &explicit(&[Some(1e-5), Some(4e-5), Some(2e-4)], 0.9),
        ))
        .collect(),
        (Problem::Knee, _) => {
            let coarse = [Resolution::Coarse.mean_element_size()];
            combine(&[Hex8Fbar], &coarse, &implicit(&[0.04, 0.02]))
                .chain(combine(&[Hex8OnePoint], &coarse, &implicit(&[0.02])))
                .chain(combine(&[Hex8Fbar], &coarse, &explicit(&[Some(2e-5)], 0.9)))
                .collect()
        }
    }
}

/// The reference run of `problem` (see the module's documentation).
pub fn reference_method(problem: Problem, quick: bool) -> Method {
    let (mesh_size, increment) = match (problem, quick) {
        (Problem::Cube, true) => (0.001, 0.05),
        (Problem::Cube, false) => (0.000625, 0.05),
        (Problem::Elongate, true) => (0.003, 0.1),
        (Problem::Elongate, false) => (0.002, 0.05),
        (Problem::Knee, _) => (Resolution::Medium.mean_element_size(), 0.02),
    };
    Method {
        element: Hex8Fbar,
        mesh_size,
        step: StepSetting::Implicit { increment },
    }
}

fn implicit(increments: &[f64]) -> Vec<StepSetting> {
    increments
        .iter()
        .map(|&increment| StepSetting::Implicit { increment })
        .collect()
}

fn explicit(mass_scaling: &[Option<f64>], safety: f64) -> Vec<StepSetting> {
    mass_scaling
        .iter()
        .map(|&mass_scaling| StepSetting::Explicit {
            mass_scaling,
            safety,
        })
        .collect()
}

/// Every element × mesh size × step setting, coarse meshes first.
fn combine<'a>(
    elements: &'a [ElementChoice],
    mesh_sizes: &'a [f64],
    steps: &'a [StepSetting],
) -> impl Iterator<Item = Method> + 'a {
    elements.iter().flat_map(move |&element| {
        mesh_sizes.iter().flat_map(move |&mesh_size| {
            steps.iter().map(move |&step| Method {
                element,
                mesh_size,
                step,
            })
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_is_finer_and_smaller_stepped_than_the_matrix() {
        for problem in [Problem::Cube, Problem::Elongate, Problem::Knee] {
            for quick in [true, false] {
                let reference = reference_method(problem, quick);
                let methods = matrix(problem, quick);
                assert!(!methods.is_empty());
                assert!(!methods.contains(&reference));
                for method in &methods {
                    assert!(method.mesh_size > reference.mesh_size, "{method:?}");
                    if let (
                        StepSetting::Implicit { increment },
                        StepSetting::Implicit { increment: finest },
                    ) = (method.step, reference.step)
                    {
                        assert!(increment >= finest, "{method:?}");
                    }
                }
            }
        }
    }
}
