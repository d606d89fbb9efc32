//! A bounded Levenberg–Marquardt least-squares solver for a handful of parameters whose
//! residuals are expensive (each evaluation is a finite-element run):
//!
//!   minimise  C(x) = ½ Σ_i r_i(x)²   subject to  lower ≤ x ≤ upper,
//!
//! with the Jacobian J = ∂r/∂x by forward differences (one run per parameter, the runs in
//! parallel), the damped Gauss–Newton step (JᵀJ + μ diag(JᵀJ)) δ = −Jᵀr projected onto
//! the bounds, and Nielsen's update of μ from the ratio ρ of the actual to the predicted
//! decrease of C.
//!
//! Why not the `levenberg-marquardt` crate (0.15, rust-cv): it depends on nalgebra 0.34
//! while the workspace pins 0.35 (a second nalgebra in the build and conversions at the
//! boundary), it has no bounds, and it expects an analytic Jacobian; written here, the
//! solver is short and the bounds and the parallel finite-difference Jacobian are direct.

use anyhow::{Result, bail};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// When to stop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Largest number of accepted steps.
    pub max_iterations: usize,
    /// Stop when a step changes every scaled parameter x_j/|x_j,start| by less than this.
    pub step_tolerance: f64,
    /// Stop when an accepted step lowers C by less than this fraction of C.
    pub cost_tolerance: f64,
    /// Forward-difference step, relative to the parameter's start value.
    pub difference_step: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            max_iterations: 50,
            step_tolerance: 1e-10,
            cost_tolerance: 1e-14,
            difference_step: 1e-6,
        }
    }
}

/// Why the solver stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The last step was below the step tolerance.
    SmallStep,
    /// The last accepted step barely lowered the cost.
    SmallDecrease,
    /// The residuals are zero.
    ZeroResidual,
    /// No step along the projected gradient lowers the cost any more (e.g. every free
    /// direction is blocked by a bound, or the residuals are noise).
    NoDecrease,
    /// The iteration limit was reached.
    IterationLimit,
}

/// The result.
#[derive(Debug, Clone)]
pub struct Solution {
    pub x: Vec<f64>,
    pub residuals: DVector<f64>,
    /// ∂r/∂x at `x`.
    pub jacobian: DMatrix<f64>,
    /// Accepted steps.
    pub iterations: usize,
    /// Residual evaluations, those for the Jacobian included.
    pub evaluations: usize,
    pub stop: Stop,
}

impl Solution {
    /// C = ½ Σ r².
    pub fn cost(&self) -> f64 {
        0.5 * self.residuals.norm_squared()
    }

    /// Standard errors of the parameters not `fixed` (e.g. those that ended on a bound;
    /// `None` for the fixed ones) from the Jacobian, assuming independent residuals of
    /// equal variance s² = Σ r² / (m − k), k the free parameters: the square roots of the
    /// diagonal of s² (JₖᵀJₖ)⁻¹. `None` altogether with no more residuals than free
    /// parameters or a singular JₖᵀJₖ (they are not identifiable together from these data).
    pub fn standard_errors(&self, fixed: &[bool]) -> Option<Vec<Option<f64>>> {
        let free: Vec<usize> = (0..self.x.len()).filter(|&j| !fixed[j]).collect();
        let m = self.residuals.len();
        if m <= free.len() {
            return None;
        }
        let variance = self.residuals.norm_squared() / (m - free.len()) as f64;
        let jacobian = self.jacobian.select_columns(free.iter());
        let inverse = (jacobian.transpose() * &jacobian).try_inverse()?;
        let mut errors = vec![None; self.x.len()];
        for (k, &j) in free.iter().enumerate() {
            errors[j] = Some((variance * inverse[(k, k)]).sqrt());
        }
        Some(errors)
    }
}

/// Minimise ½‖r(x)‖² from `start` within [`lower`, `upper`]. `residuals` may fail for a
/// trial point (e.g. the solver diverges): that trial counts as a rejected step.
/// `progress` sees each accepted step's number and cost.
pub fn minimise(
    residuals: &(dyn Fn(&[f64]) -> Result<DVector<f64>> + Sync),
    start: &[f64],
    lower: &[f64],
    upper: &[f64],
    settings: &Settings,
    progress: &mut dyn FnMut(usize, f64),
) -> Result<Solution> {
    let n = start.len();
    // Steps and tolerances are measured on x_j / scale_j, scale_j = |start_j| (or 1).
    let scale: Vec<f64> = start
        .iter()
        .map(|&s| if s != 0.0 { s.abs() } else { 1.0 })
        .collect();
    let project = |x: &mut [f64]| {
        for j in 0..n {
            x[j] = x[j].clamp(lower[j], upper[j]);
        }
    };
    let mut x = start.to_vec();
    project(&mut x);
    let mut r = residuals(&x)?;
    let mut evaluations = 1;
    let mut cost = 0.5 * r.norm_squared();
    let mut mu: Option<f64> = None;
    let mut nu = 2.0;
    let mut iterations = 0;
    let stop = loop {
        if cost == 0.0 {
            break Stop::ZeroResidual;
        }
        if iterations == settings.max_iterations {
            break Stop::IterationLimit;
        }
        let jacobian = forward_differences(residuals, &x, &r, &scale, upper, settings)?;
        evaluations += n;
        let gradient = jacobian.transpose() * &r;
        let normal = jacobian.transpose() * &jacobian;
        let damping: Vec<f64> = (0..n).map(|j| normal[(j, j)].max(1e-300)).collect();
        // μ multiplies diag(JᵀJ): dimensionless, starting small (close to Gauss–Newton).
        let mut damping_factor = mu.unwrap_or(1e-3);
        // A parameter on a bound that the descent direction −g pushes further out is held
        // there for this step (its row and column of the system become the identity).
        let held: Vec<bool> = (0..n)
            .map(|j| {
                (x[j] <= lower[j] && gradient[j] > 0.0) || (x[j] >= upper[j] && gradient[j] < 0.0)
            })
            .collect();
        let free_gradient = DVector::from_fn(n, |j, _| if held[j] { 0.0 } else { gradient[j] });
        let mut accepted = None;
        let mut small_step = false;
        for _attempt in 0..40 {
            let mut system = normal.clone();
            for j in 0..n {
                if held[j] {
                    system.row_mut(j).fill(0.0);
                    system.column_mut(j).fill(0.0);
                    system[(j, j)] = 1.0;
                } else {
                    system[(j, j)] += damping_factor * damping[j];
                }
            }
            let Some(delta) = system.cholesky().map(|c| c.solve(&(-&free_gradient))) else {
                damping_factor *= nu;
                nu *= 2.0;
                continue;
            };
            let mut trial: Vec<f64> = (0..n).map(|j| x[j] + delta[j]).collect();
            project(&mut trial);
            let step = DVector::from_fn(n, |j, _| trial[j] - x[j]);
            if (0..n).all(|j| step[j].abs() <= settings.step_tolerance * scale[j]) {
                small_step = true;
                break;
            }
            let predicted = -(gradient.dot(&step) + 0.5 * step.dot(&(&normal * &step)));
            evaluations += 1;
            let trial_cost = residuals(&trial).map(|r| (0.5 * r.norm_squared(), r));
            match trial_cost {
                Ok((trial_cost, trial_r)) if trial_cost < cost && predicted > 0.0 => {
                    let rho = (cost - trial_cost) / predicted;
                    damping_factor *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                    nu = 2.0;
                    accepted = Some((trial, trial_r, trial_cost));
                    break;
                }
                _ => {
                    damping_factor *= nu;
                    nu *= 2.0;
                }
            }
        }
        mu = Some(damping_factor);
        if small_step {
            break Stop::SmallStep;
        }
        let Some((trial, trial_r, trial_cost)) = accepted else {
            break Stop::NoDecrease;
        };
        let decrease = cost - trial_cost;
        x = trial;
        r = trial_r;
        cost = trial_cost;
        iterations += 1;
        progress(iterations, cost);
        if decrease <= settings.cost_tolerance * (cost + decrease) {
            break Stop::SmallDecrease;
        }
    };
    let jacobian = forward_differences(residuals, &x, &r, &scale, upper, settings)?;
    evaluations += n;
    Ok(Solution {
        x,
        residuals: r,
        jacobian,
        iterations,
        evaluations,
        stop,
    })
}

/// ∂r/∂x_j ≈ (r(x + h_j e_j) − r(x)) / h_j with h_j = step × scale_j, taken backwards
/// where the forward point would pass the upper bound. The columns run in parallel.
fn forward_differences(
    residuals: &(dyn Fn(&[f64]) -> Result<DVector<f64>> + Sync),
    x: &[f64],
    r: &DVector<f64>,
    scale: &[f64],
    upper: &[f64],
    settings: &Settings,
) -> Result<DMatrix<f64>> {
    let columns: Vec<Result<DVector<f64>>> = (0..x.len())
        .into_par_iter()
        .with_max_len(1)
        .map(|j| {
            let mut h = settings.difference_step * scale[j];
            if x[j] + h > upper[j] {
                h = -h;
            }
            let mut shifted = x.to_vec();
            shifted[j] += h;
            let r_shifted = residuals(&shifted)?;
            Ok((r_shifted - r) / h)
        })
        .collect();
    let columns = columns.into_iter().collect::<Result<Vec<_>>>()?;
    if columns.iter().any(|c| c.len() != r.len()) {
        bail!("the residuals changed length between evaluations");
    }
    Ok(DMatrix::from_columns(&columns))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// r_i = a exp(b t_i) − y_i, with y from a = 2, b = −1.5 (zero residual at the
    /// answer).
    fn exponential(x: &[f64]) -> Result<DVector<f64>> {
        let t: Vec<f64> = (0..12).map(|i| 0.25 * i as f64).collect();
        Ok(DVector::from_fn(t.len(), |i, _| {
            x[0] * (x[1] * t[i]).exp() - 2.0 * (-1.5 * t[i]).exp()
        }))
    }

    #[test]
    fn recovers_the_parameters_of_a_zero_residual_problem() {
        let solution = minimise(
            &exponential,
            &[1.0, -0.5],
            &[0.0, -10.0],
            &[10.0, 10.0],
            &Settings::default(),
            &mut |_, _| {},
        )
        .unwrap();
        assert_relative_eq!(solution.x[0], 2.0, max_relative = 1e-8);
        assert_relative_eq!(solution.x[1], -1.5, max_relative = 1e-8);
        assert!(solution.cost() < 1e-20, "{}", solution.cost());
    }

    #[test]
    fn a_bound_holds_and_the_other_parameter_fits_given_it() {
        // With a ≤ 1.5 the best a is the bound.
        let solution = minimise(
            &exponential,
            &[1.0, -0.5],
            &[0.0, -10.0],
            &[1.5, 10.0],
            &Settings::default(),
            &mut |_, _| {},
        )
        .unwrap();
        assert_eq!(solution.x[0], 1.5);
        assert!(solution.x[1] < -0.5);
        assert_ne!(solution.stop, Stop::IterationLimit);
        // There b is the 1-D least-squares optimum: the gradient along b vanishes.
        let gradient_b = solution.jacobian.column(1).dot(&solution.residuals);
        assert!(gradient_b.abs() < 1e-8, "{gradient_b}");
    }

    #[test]
    fn standard_errors_match_the_linear_regression_formula() {
        // r = x0 + x1 t − y: straight-line fit, where the formula is exact:
        // var(slope) = s² / Σ (t − t̄)².
        let t = [0.0, 1.0, 2.0, 3.0, 4.0];
        let y = [0.1, 0.9, 2.2, 2.8, 4.1];
        let line = |x: &[f64]| -> Result<DVector<f64>> {
            Ok(DVector::from_fn(5, |i, _| x[0] + x[1] * t[i] - y[i]))
        };
        let solution = minimise(
            &line,
            &[1.0, 1.0],
            &[-10.0, -10.0],
            &[10.0, 10.0],
            &Settings::default(),
            &mut |_, _| {},
        )
        .unwrap();
        let t_mean = 2.0;
        let sxx: f64 = t.iter().map(|ti| (ti - t_mean).powi(2)).sum();
        let slope = t
            .iter()
            .zip(&y)
            .map(|(ti, yi)| (ti - t_mean) * yi)
            .sum::<f64>()
            / sxx;
        assert_relative_eq!(solution.x[1], slope, max_relative = 1e-7);
        let s2 = solution.residuals.norm_squared() / 3.0;
        let errors = solution.standard_errors(&[false, false]).unwrap();
        assert_relative_eq!(errors[1].unwrap(), (s2 / sxx).sqrt(), max_relative = 1e-5);
        // With the intercept fixed, the slope's error is that of a line through a point.
        let slope_only = solution.standard_errors(&[true, false]).unwrap();
        assert_eq!(slope_only[0], None);
        let sxx_origin: f64 = t.iter().map(|ti| ti * ti).sum();
        let s2_slope = solution.residuals.norm_squared() / 4.0;
        assert_relative_eq!(
            slope_only[1].unwrap(),
            (s2_slope / sxx_origin).sqrt(),
            max_relative = 1e-5
        );
    }
}
