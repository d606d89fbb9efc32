//! The fitted model: the elongation test run with trial values of the fitted parameters,
//! read off (linearly between its recorded points) at the measured strains.

use anyhow::{Context, Result};

use crate::elongation::{Curve, ElongationTest, Unwatched, run_elongation};

/// The base test and the parameters the fit varies.
pub struct ElongationModel<'a> {
    pub base: &'a ElongationTest,
    /// Hill parameter names, in the order of the value vectors.
    pub names: &'a [String],
}

impl ElongationModel<'_> {
    /// The test's curve with `names[j] = values[j]`.
    pub fn curve(&self, values: &[f64]) -> Result<Curve> {
        let mut test = self.base.clone();
        for (name, &value) in self.names.iter().zip(values) {
            test.parameters.insert(name.clone(), value);
        }
        let run = run_elongation(&test, &mut Unwatched)
            .with_context(|| format!("the run with {}", self.describe(values)))?;
        Ok(run.curve)
    }

    /// Engineering stress [Pa] at each of `strains` with `names[j] = values[j]`.
    pub fn stresses(&self, values: &[f64], strains: &[f64]) -> Result<Vec<f64>> {
        let curve = self.curve(values)?;
        strains
            .iter()
            .map(|&strain| {
                curve.stress_at_strain(strain).with_context(|| {
                    format!(
                        "the run with {} did not reach {:.4} % strain",
                        self.describe(values),
                        100.0 * strain
                    )
                })
            })
            .collect()
    }

    /// "b = 15, c = 379".
    pub fn describe(&self, values: &[f64]) -> String {
        self.names
            .iter()
            .zip(values)
            .map(|(n, v)| format!("{n} = {v}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}
