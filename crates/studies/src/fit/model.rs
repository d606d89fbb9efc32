//! The fitted model: the elongation test or a scene run with trial values of the fitted
//! parameters, read off (linearly between its recorded points) at the measured abscissae.

use anyhow::{Context, Result, bail};

use crate::elongation::{Curve, ElongationTest, Unwatched, run_elongation};
use crate::scene_study::SceneStudy;

/// The model a fit adjusts: its curve y(x) for trial parameter values.
pub enum FitModel<'a> {
    /// Engineering stress [Pa] against engineering strain [1] of an elongation test.
    Elongation(ElongationModel<'a>),
    /// One history column against another of a scene.
    Scene(SceneModel<'a>),
}

impl FitModel<'_> {
    /// The model's y at each of `xs` with the fitted parameters at `values`.
    pub fn predict(&self, values: &[f64], xs: &[f64]) -> Result<Vec<f64>> {
        match self {
            FitModel::Elongation(model) => model.stresses(values, xs),
            FitModel::Scene(model) => model.predict(values, xs),
        }
    }

    /// The model's whole curve, (x, y) points in the units of the data [SI].
    pub fn curve(&self, values: &[f64]) -> Result<Vec<(f64, f64)>> {
        match self {
            FitModel::Elongation(model) => Ok(model
                .curve(values)?
                .stretching()
                .iter()
                .map(|p| (p.strain, p.stress))
                .collect()),
            FitModel::Scene(model) => model.curve(values),
        }
    }
}

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
            .with_context(|| format!("the run with {}", describe(self.names, values)))?;
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
                        describe(self.names, values),
                        100.0 * strain
                    )
                })
            })
            .collect()
    }
}

/// A scene, the parameters the fit varies and the history columns fitted.
pub struct SceneModel<'a> {
    pub study: &'a SceneStudy,
    /// Material parameter names (`KEY` or `MATERIAL.KEY`), in the order of the values.
    pub names: &'a [String],
    /// The history column of the abscissa (it must increase along the run).
    pub x: &'a str,
    /// The history column fitted to the data.
    pub y: &'a str,
}

impl SceneModel<'_> {
    /// (x, y) of every recorded row of the run with `names[j] = values[j]`; an error if x
    /// decreases somewhere.
    pub fn curve(&self, values: &[f64]) -> Result<Vec<(f64, f64)>> {
        let history = self
            .study
            .history(self.names, values)
            .with_context(|| format!("the run with {}", describe(self.names, values)))?;
        let xs = history.column(self.x)?;
        let ys = history.column(self.y)?;
        if let Some(k) = (1..xs.len()).find(|&k| xs[k] < xs[k - 1]) {
            bail!(
                "the run with {}: its history column '{}' decreases from {} to {} (row {}); \
                 the abscissa of a fit must increase along the run (time_s always does)",
                describe(self.names, values),
                self.x,
                xs[k - 1],
                xs[k],
                k + 1
            );
        }
        Ok(xs.into_iter().zip(ys).collect())
    }

    /// y at each of `xs`, linear between the recorded rows.
    pub fn predict(&self, values: &[f64], xs: &[f64]) -> Result<Vec<f64>> {
        let curve = self.curve(values)?;
        xs.iter()
            .map(|&x| {
                interpolate(&curve, x).with_context(|| {
                    format!(
                        "the run with {} did not reach {} = {x}",
                        describe(self.names, values),
                        self.x
                    )
                })
            })
            .collect()
    }
}

/// y at `x` on the piecewise-linear `curve` (x non-decreasing); `None` outside it.
fn interpolate(curve: &[(f64, f64)], x: f64) -> Option<f64> {
    let after = curve.iter().position(|p| p.0 >= x)?;
    let (x1, y1) = curve[after];
    if x1 == x {
        return Some(y1);
    }
    let (x0, y0) = *curve.get(after.checked_sub(1)?)?;
    Some(y0 + (y1 - y0) * (x - x0) / (x1 - x0))
}

/// "b = 15, c = 379".
pub fn describe(names: &[String], values: &[f64]) -> String {
    names
        .iter()
        .zip(values)
        .map(|(n, v)| format!("{n} = {v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_is_linear_inside_and_none_outside() {
        let curve = [(0.0, 0.0), (1.0, 10.0), (1.0, 10.0), (3.0, 30.0)];
        assert_eq!(interpolate(&curve, 0.5), Some(5.0));
        assert_eq!(interpolate(&curve, 1.0), Some(10.0));
        assert_eq!(interpolate(&curve, 2.0), Some(20.0));
        assert_eq!(interpolate(&curve, 3.5), None);
        assert_eq!(interpolate(&curve[1..], 0.5), None);
    }
}
