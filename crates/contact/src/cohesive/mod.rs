//! Cohesive contact (seed §2.4): a secondary surface bonded to a main surface (deformable,
//! or a rigid bone) by a linear traction–separation law with damage, which resists
//! opening under tension and, in [`TangentialMode::FreeSlide`], lets the surfaces slide.
//!
//! - [`law`]: the traction–separation law t(δ) with damage and its consistent tangent;
//! - [`settings`]: its parameters ([`CohesiveSettings`], the paper's values by default);
//! - `interface.rs`: [`CohesiveInterface`], the [`musclefem_core::solver::Interaction`]
//!   the solvers call; `bonds.rs`: the bonds and their forces; `slide.rs`: sliding bonds;
//!   `main_side.rs`: the main triangles at an instant; `frame.rs`: their local frames.

mod bonds;
mod error;
mod frame;
mod interface;
pub mod law;
mod main_side;
pub mod settings;
mod slide;
mod slide_tangent;

pub use error::CohesiveError;
pub use interface::CohesiveInterface;
pub use law::{CohesiveLaw, TractionResponse};
pub use settings::{CohesiveSettings, TangentialMode};
