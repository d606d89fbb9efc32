//! One point of the work–precision matrix: solver, element, mesh size and step setting.

use crate::elongation::{ElementChoice, Solver};

/// How the time step of a run is set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepSetting {
    /// Quasi-static Newton with this (initial and largest) increment [s], with automatic
    /// cutting.
    Implicit { increment: f64 },
    /// Central differences at `safety` × the stable step, with mass scaling to the target
    /// step `mass_scaling` [s] (`None`: the physical mass).
    Explicit {
        mass_scaling: Option<f64>,
        safety: f64,
    },
}

impl StepSetting {
    /// The solver this setting belongs to.
    pub fn solver(self) -> Solver {
        match self {
            StepSetting::Implicit { .. } => Solver::Implicit,
            StepSetting::Explicit { .. } => Solver::Explicit,
        }
    }

    /// As in the CSV's `step_setting` column (no commas), e.g. `increment=0.05s` or
    /// `mass_scaling=1e-4s;safety=0.9`.
    pub fn label(self) -> String {
        match self {
            StepSetting::Implicit { increment } => format!("increment={increment}s"),
            StepSetting::Explicit {
                mass_scaling: Some(target),
                safety,
            } => format!("mass_scaling={target:e}s;safety={safety}"),
            StepSetting::Explicit {
                mass_scaling: None,
                safety,
            } => format!("no_mass_scaling;safety={safety}"),
        }
    }
}

/// One run of a problem.
#[derive(Debug, Clone, PartialEq)]
pub struct Method {
    pub element: ElementChoice,
    /// Target element edge length [m].
    pub mesh_size: f64,
    pub step: StepSetting,
}

impl Method {
    pub fn solver(&self) -> Solver {
        self.step.solver()
    }

    /// The method family: solver and element (one line on the chart), e.g.
    /// `implicit hex8-fbar`.
    pub fn family(&self) -> String {
        format!("{} {}", self.solver().name(), self.element.name())
    }

    /// One line for progress and logs.
    pub fn describe(&self) -> String {
        format!(
            "{}, {} mm, {}",
            self.family(),
            millimetres(self.mesh_size),
            self.step.label()
        )
    }
}

/// A length [m] in millimetres with at most three decimals, e.g. `3.333`, `2.5`.
pub fn millimetres(length: f64) -> String {
    let text = format!("{:.3}", 1e3 * length);
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_labels_have_no_commas() {
        let implicit = StepSetting::Implicit { increment: 0.05 };
        assert_eq!(implicit.label(), "increment=0.05s");
        let explicit = StepSetting::Explicit {
            mass_scaling: Some(1e-4),
            safety: 0.9,
        };
        assert_eq!(explicit.label(), "mass_scaling=1e-4s;safety=0.9");
        let method = Method {
            element: ElementChoice::Tet10,
            mesh_size: 0.0025,
            step: explicit,
        };
        assert_eq!(method.family(), "explicit tet10");
        assert_eq!(
            method.describe(),
            "explicit tet10, 2.5 mm, mass_scaling=1e-4s;safety=0.9"
        );
        assert_eq!(millimetres(0.01 / 3.0), "3.333");
    }
}
