//! # musclefem-fibers
//!
//! The in-house finite-volume flow solver that turns origin (inlet) and insertion (outlet)
//! surfaces into a fiber direction per element.
//!
//! Not built yet: the fibers issue fills this crate. It exposes no API until then.
