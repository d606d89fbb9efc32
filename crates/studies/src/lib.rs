//! musclefem's studies: the scenarios behind the `musclefem` command's subcommands, as a
//! library for tests, benchmarks, notebooks and other programs. The command
//! (`crates/cli`) parses arguments, shows progress and prints; the physics of each study
//! lives here, over the library crates (materials, core, contact, fibers, io).
//!
//! - [`activation`]: the one passive/active choice of every study.
//! - [`bench`]: the work–precision matrix (`musclefem bench`).
//! - [`elongation`]: the single-muscle uniaxial elongation tests (`musclefem elongate`).
//! - [`fit`]: least-squares calibration of material parameters to a measured curve, through
//!   the elongation tests or a scene (`musclefem fit`).
//! - [`frame_interval`]: the `--frame-interval` option of the commands that write frames.
//! - [`inertia`]: whether an explicit run stayed quasi-static (kinetic/internal energy).
//! - [`knee`]: the knee scene's procedural anatomy, kinematics and squat drive.
//! - [`material_point`]: a material point driven in uniaxial stress (`musclefem point`).
//! - [`progress`]: a run's progress over simulated time (bar or plain lines).
//! - [`scene_check`]: what `musclefem check` says of a scene, and the free-body check of
//!   `run`.
//! - [`scene_study`]: a scene file as the base of a sweep or a fit.
//! - [`solver`]: the one solver choice of every study and command.
//! - [`sweep`]: parametric studies of the elongation tests or of a scene (`musclefem sweep`).
//! - [`threads`]: how many worker threads a run may use.

pub mod activation;
pub mod bench;
pub mod elongation;
pub mod fit;
pub mod frame_interval;
pub mod inertia;
pub mod interrupted;
pub mod knee;
pub mod material_point;
pub mod progress;
pub mod run_directory;
pub mod scene_check;
pub mod scene_study;
pub mod solver;
pub mod sweep;
pub mod threads;

/// The README's examples, compiled and run by `cargo test --doc`.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
