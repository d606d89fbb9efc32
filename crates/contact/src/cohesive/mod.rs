//! Cohesive contact (seed §2.4): a secondary surface bonded to a main surface (deformable,
//! or a rigid bone) by a linear traction–separation law with damage, which resists
//! opening under tension and, in [`TangentialMode::FreeSlide`] and
//! [`TangentialMode::SmoothSlide`], lets the surfaces slide.
//!
//! - [`law`]: the traction–separation law t(δ) with damage and its consistent tangent;
//! - [`settings`]: its parameters ([`CohesiveSettings`], the paper's values by default);
//! - `interface.rs`: [`CohesiveInterface`], the [`musclefem_core::solver::Interaction`]
//!   the solvers call; `bonds.rs`: the bonds, their formation and material-point forces;
//!   `slide.rs` and `slide_tangent.rs`: sliding bonds and their linearization;
//!   `smooth_slide.rs`: bonds sliding along the smooth normal field of the main surface
//!   (`crate::normal_field`); `frame.rs`: the local frames of the main triangles (their
//!   corners at an instant: `crate::main_side`).
//!
//! Use:
//!
//! ```text
//! let vastus = DeformableSurface::from_mesh_surface(&mesh, "vastus_deep")?;
//! let femur = RigidSurface::from_stl("femur.stl")?.with_motion(motion);
//! let settings = CohesiveSettings { tangential: TangentialMode::FreeSlide, ..Default::default() };
//! let glue = CohesiveInterface::new("vastus on femur", &vastus, femur, &mesh, &settings)?;
//! let mut interactions: Vec<Box<dyn Interaction>> = vec![Box::new(glue)];
//! ```

mod bond_checkpoint;
mod bonds;
mod error;
mod frame;
mod interface;
pub mod law;
pub mod settings;
mod slide;
mod slide_tangent;
mod smooth_slide;

pub use bonds::Bond;
pub use error::CohesiveError;
pub use interface::CohesiveInterface;
pub use law::{CohesiveLaw, TractionResponse};
pub use settings::{CohesiveSettings, TangentialMode};
