//! Cohesive contact (seed §2.4): surfaces bonded by a linear traction–separation law with
//! damage, which resists opening under tension and (in [`TangentialMode::FreeSlide`])
//! lets the surfaces slide.
//!
//! - [`law`]: the traction–separation law t(δ) with damage and its consistent tangent;
//! - [`settings`]: its parameters ([`CohesiveSettings`], the paper's values by default).

mod error;
pub mod law;
pub mod settings;

pub use error::CohesiveError;
pub use law::{CohesiveLaw, TractionResponse};
pub use settings::{CohesiveSettings, TangentialMode};
