//! The fit's numbers for the terminal, fit.txt and fit.csv: the fitted values, their
//! standard errors and asymptotic 95 % confidence intervals, the residual.

use musclefem_io::csv::format_number;

use super::Z_95;
use super::levenberg_marquardt::Solution;
use super::unknowns::Unknown;

/// The fit's numbers for the terminal, fit.txt and fit.csv.
pub(super) struct Report<'a> {
    pub(super) unknowns: &'a [Unknown],
    pub(super) solution: &'a Solution,
    pub(super) measured_stress: &'a [f64],
    /// The unit of the fitted values (of the residual).
    pub(super) unit: &'a str,
    /// What they are, e.g. "stress".
    pub(super) quantity: &'a str,
}

impl Report<'_> {
    /// RMS residual [Pa] and coefficient of determination R² = 1 − Σr² / Σ(y − ȳ)².
    pub(super) fn residual(&self) -> (f64, f64) {
        let m = self.measured_stress.len() as f64;
        let squares = self.solution.residuals.norm_squared();
        let mean = self.measured_stress.iter().sum::<f64>() / m;
        let spread: f64 = self
            .measured_stress
            .iter()
            .map(|y| (y - mean).powi(2))
            .sum();
        ((squares / m).sqrt(), 1.0 - squares / spread)
    }

    /// Whether fitted parameter `j` ended on one of its bounds.
    pub(super) fn at_bound(&self, j: usize) -> bool {
        let x = self.solution.x[j];
        x == self.unknowns[j].lower || x == self.unknowns[j].upper
    }

    /// Standard errors of the parameters not on a bound.
    pub(super) fn standard_errors(&self) -> Option<Vec<Option<f64>>> {
        let fixed: Vec<bool> = (0..self.unknowns.len()).map(|j| self.at_bound(j)).collect();
        self.solution.standard_errors(&fixed)
    }

    pub(super) fn text(&self) -> String {
        let (rms, r2) = self.residual();
        let errors = self.standard_errors();
        let mut text = String::new();
        for (j, unknown) in self.unknowns.iter().enumerate() {
            let x = self.solution.x[j];
            let interval = match errors.as_ref().map(|e| e[j]) {
                Some(Some(e)) => format!("95 % CI [{}, {}]", x - Z_95 * e, x + Z_95 * e),
                Some(None) => "at its bound: no confidence interval".to_string(),
                None => "no confidence interval (the parameters are not identifiable together: JᵀJ singular)".to_string(),
            };
            text.push_str(&format!(
                "{} = {x} (start {}), {interval}\n",
                unknown.name, unknown.start
            ));
        }
        let largest = self
            .measured_stress
            .iter()
            .copied()
            .fold(0.0, |a: f64, y| a.max(y.abs()));
        text.push_str(&format!(
            "RMS residual = {rms:.4e} {} ({:.3} % of the largest measured {}), R² = {r2:.5}\n\
             iterations = {}, runs = {}, stop = {:?}\n",
            self.unit,
            100.0 * rms / largest,
            self.quantity,
            self.solution.iterations,
            self.solution.evaluations,
            self.solution.stop
        ));
        text
    }

    /// fit.csv: parameter,start,fitted,standard_error,ci95_low,ci95_high,at_bound.
    pub(super) fn csv(&self) -> String {
        let errors = self.standard_errors();
        let mut text =
            String::from("parameter,start,fitted,standard_error,ci95_low,ci95_high,at_bound\n");
        for (j, unknown) in self.unknowns.iter().enumerate() {
            let x = self.solution.x[j];
            let error = errors.as_ref().and_then(|e| e[j]);
            let cell = |v: Option<f64>| v.map_or_else(String::new, format_number);
            text.push_str(&format!(
                "{},{},{},{},{},{},{}\n",
                unknown.name,
                format_number(unknown.start),
                format_number(x),
                cell(error),
                cell(error.map(|e| x - Z_95 * e)),
                cell(error.map(|e| x + Z_95 * e)),
                self.at_bound(j)
            ));
        }
        text
    }
}
