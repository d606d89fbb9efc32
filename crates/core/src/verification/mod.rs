//! Standard verification problems, set up once for the tests that check them and the
//! table tools (`examples/`) that chart them.
//!
//! - [`cooks_membrane`]: the nearly incompressible plane-strain panel, the locking
//!   benchmark of element technologies.
//! - [`uniaxial_cube`]: the neo-Hookean cube pulled to stretch 1.5 between symmetry
//!   planes, the scaling benchmark of the implicit solver (issue #36).

pub mod cooks_membrane;
pub mod uniaxial_cube;
