//! [`FlowSettings`]: tolerances and limits of the flow solve.

use crate::error::FiberError;

/// The preconditioner of the CG solves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preconditioner {
    /// The inverse diagonal: no setup, iterations grow with the mesh size.
    Jacobi,
    /// One aggregation multigrid V-cycle: a setup of about a tenth of the solve, then
    /// iterations that grow slowly with the mesh size.
    AggregationMultigrid,
}

/// Tolerances and limits of the potential-flow solve. The defaults suit meshes of up to
/// millions of cells; a bad mesh that needs more sweeps fails with
/// [`FiberError::NotConverged`] rather than returning a field that is not converged.
#[derive(Clone, Debug, PartialEq)]
pub struct FlowSettings {
    /// Relative residual ‖b + c(φ) − Aφ‖₂ / ‖b‖₂ at which the solve stops (dimensionless):
    /// A the orthogonal part of the discrete Laplacian, b its fixed-potential terms, c(φ)
    /// the explicit non-orthogonal correction of the final potential. Default 1e-10.
    pub tolerance: f64,
    /// Most non-orthogonal correction sweeps (each a CG solve of the orthogonal part with
    /// the correction of the previous sweep on the right-hand side). Default 50.
    pub max_correction_sweeps: usize,
    /// Most CG iterations in one sweep. Default 20 000.
    pub max_linear_iterations: usize,
    /// Preconditioner of the CG solves. Default aggregation multigrid.
    pub preconditioner: Preconditioner,
}

impl Default for FlowSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_correction_sweeps: 50,
            max_linear_iterations: 20_000,
            preconditioner: Preconditioner::AggregationMultigrid,
        }
    }
}

impl FlowSettings {
    /// Errors if the tolerance is not in (0, 1) or a limit is zero.
    pub fn check(&self) -> Result<(), FiberError> {
        let invalid = |reason: String| Err(FiberError::InvalidSettings { reason });
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            return invalid(format!("tolerance {} must be in (0, 1)", self.tolerance));
        }
        if self.max_correction_sweeps == 0 {
            return invalid("max_correction_sweeps must be at least 1".to_string());
        }
        if self.max_linear_iterations == 0 {
            return invalid("max_linear_iterations must be at least 1".to_string());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_pass_and_nonsense_fails() {
        assert!(FlowSettings::default().check().is_ok());
        for tolerance in [0.0, -1e-3, 1.0, f64::NAN] {
            let settings = FlowSettings {
                tolerance,
                ..FlowSettings::default()
            };
            let err = settings.check().unwrap_err();
            assert!(err.to_string().contains("tolerance"), "{err}");
        }
        let settings = FlowSettings {
            max_correction_sweeps: 0,
            ..FlowSettings::default()
        };
        assert!(settings.check().is_err());
    }
}
