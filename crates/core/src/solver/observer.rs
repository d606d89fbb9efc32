//! What a caller sees of a run while it goes: every recorded history row with the nodal
//! displacements at that instant (for frames and live histories), and the progress of the
//! steps (for a progress bar). Either may stop the run cleanly (Ctrl-C): the solver then
//! returns [`super::SolverError::Interrupted`] after the last recorded row.

use std::ops::ControlFlow;

use nalgebra::Vector3;

/// Watches a run whose history rows are `Row`s.
pub trait Observer<Row> {
    /// A history row was recorded, with the displacements at its time [m].
    fn record(&mut self, row: &Row, displacement: &[Vector3<f64>]) -> ControlFlow<()>;

    /// A step ended at `time` [s], the `steps`-th; called every step, keep it cheap.
    fn progress(&mut self, _time: f64, _steps: usize) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// An observer that watches nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoObserver;

impl<Row> Observer<Row> for NoObserver {
    fn record(&mut self, _row: &Row, _displacement: &[Vector3<f64>]) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}
