//! # musclefem-fibers
//!
//! Fiber directions from a potential flow through the muscle (seed §2.3): the flow enters
//! through the origin (the inlet), leaves through the insertion (the outlet), and cannot
//! cross the other boundary faces (impermeable walls). The unit flow velocity in each
//! element is its fiber direction.
//!
//! ```text
//! ∇²φ = 0 in the muscle,   φ = 1 on the inlet,   φ = 0 on the outlet,   ∇φ·n = 0 on walls,
//! fiber direction = −∇φ / |∇φ|   (from inlet to outlet).
//! ```
//!
//! ```no_run
//! # fn main() -> Result<(), musclefem_fibers::FiberError> {
//! use musclefem_mesh::generate::box_of_hexes;
//! use musclefem_fibers::{FlowBoundary, FlowSettings, compute_fibers};
//!
//! let mut mesh = box_of_hexes([0.1, 0.02, 0.02], [20, 4, 4])?;
//! let boundary = FlowBoundary::from_names(&mesh, &["x0"], &["x1"])?;
//! let fibers = compute_fibers(&mesh, &boundary, &FlowSettings::default())?;
//! fibers.assign_to(&mut mesh)?;
//! # Ok(())
//! # }
//! ```
//!
//! The method is a cell-centred finite-volume scheme on the elements of the mesh (hex8,
//! tet4, and tet10 through its four corners; several blocks form one mesh when their
//! faces share corner nodes):
//!
//! 1. [`fv_mesh`]: cells, faces matched across blocks by their corner nodes, and the check
//!    for inverted elements and non-manifold faces;
//! 2. [`boundary`]: inlet and outlet regions (surfaces or node sets, several per end) onto
//!    boundary faces, and the check that every connected part of the mesh has both ends;
//! 3. [`discretisation`]: over-relaxed face fluxes with an explicit non-orthogonal
//!    correction from weighted least-squares cell gradients;
//! 4. [`solve`]: deferred correction sweeps (Anderson-mixed) around preconditioned CG on
//!    the symmetric orthogonal part ([`linear`]: sprs matrix, parallel allocation-free
//!    kernels, aggregation multigrid or Jacobi preconditioner), until the corrected
//!    system's relative residual is 1e-10 (default);
//! 5. [`field`]: the directions and the inlet and outlet fluxes, in total and per region.
//!
//! A linear potential with its gradient along the walls (a straight tube) is reproduced to
//! the solver tolerance on any mesh; on curved domains the direction error falls with the
//! mesh size (see `tests/`).

mod boundary;
mod discretisation;
mod error;
mod field;
mod fv_mesh;
mod linear;
mod settings;
mod solve;

use std::time::Instant;

use musclefem_mesh::Mesh;

pub use boundary::{BoundaryRegion, FlowBoundary};
pub use error::{FaceLabel, FiberError, MissingEnd, Side};
pub use field::{FiberField, RegionFlux};
pub use settings::{FlowSettings, Preconditioner};

/// Solves the potential flow through `mesh` from `boundary.inlet` to `boundary.outlet`
/// and returns the fiber direction of every element.
///
/// Errors, each naming what it concerns: settings out of range; a malformed, empty,
/// inverted or non-manifold mesh; an end without region, an empty region, a region
/// without boundary face, a face in both ends; a part of the mesh without an inlet or
/// an outlet; and a solve that does not converge.
pub fn compute_fibers(
    mesh: &Mesh,
    boundary: &FlowBoundary,
    settings: &FlowSettings,
) -> Result<FiberField, FiberError> {
    let start = Instant::now();
    settings.check()?;
    let fv = fv_mesh::FvMesh::new(mesh)?;
    let classified = boundary::classify_boundary(mesh, &fv, boundary)?;
    let kinds = &classified.kinds;
    let coefficients = discretisation::coefficients::Coefficients::new(mesh, &fv)?;
    let least_squares = discretisation::gradient::LeastSquaresGradient::new(mesh, &fv, kinds)?;
    let setup_time = start.elapsed();

    let solution = solve::solve_potential(&fv, &coefficients, kinds, &least_squares, settings)?;
    let mut field = FiberField::new(mesh, &fv, &coefficients, &classified, solution)?;
    field.setup_time = setup_time;
    field.solve_time = start.elapsed() - setup_time;
    Ok(field)
}

/// The README's examples, compiled and run by `cargo test --doc`.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
