//! How the implicit solve grows with the mesh (`musclefem bench --problem scaling`, issue
//! #36): the cube of [`musclefem_core::verification::uniaxial_cube`] at n³ elements for
//! several n, Poisson's ratios and linear solvers (and the same cubes through felupe, a
//! Python FE package, when it is installed), timed in one run.
//!
//! - [`case`]: one case ([`ScalingCase`]), run and measured ([`ScalingRun`]), and the
//!   one-line form in which a child process reports it;
//! - [`memory`]: the peak resident memory of the process;
//! - [`felupe`]: the same cube through `scripts/felupe_cube.py`;
//! - [`slope`]: the least-squares slope of log time against log unknowns;
//! - [`report`]: the table, the fitted slopes, the time ratios and the end-force
//!   differences, as text;
//! - [`csv`], [`chart`]: `scaling.csv` and `scaling.png`.

pub mod case;
pub mod chart;
pub mod csv;
pub mod felupe;
pub mod memory;
pub mod report;
pub mod slope;

pub use case::{ScalingCase, ScalingRun, ScalingSolver};
