//! Standard verification problems, set up once for the tests that check them and the
//! table tools (`examples/`) that chart them.
//!
//! - [`cooks_membrane`]: the nearly incompressible plane-strain panel, the locking
//!   benchmark of element technologies.

pub mod cooks_membrane;
