//! Writes the procedural knee anatomy at 0°, 45° and 90° of flexion for a look in ParaView,
//! and prints its moment arms.
//!
//! ```text
//! cargo run --release -p musclefem-studies --example knee_anatomy -- [directory] [coarse|medium|fine]
//! ```
//!
//! Open `femur.stl`, the four `<muscle>.stl` (or `muscles.vtu`), then `tibia_*deg.stl`,
//! `patella_*deg.stl` and `paths_*deg.vtk` of one angle: the patella rides the groove on
//! its tendon, and the paths (coloured by `muscle`) wrap over the trochlea at 90°.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::ValueEnum;

use musclefem_studies::knee::anatomy::export::write_anatomy;
use musclefem_studies::knee::anatomy::moment_arms::moment_arms_at;
use musclefem_studies::knee::{Anatomy, Resolution};

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let directory = PathBuf::from(args.next().unwrap_or_else(|| "knee_anatomy".to_string()));
    let resolution = match args.next() {
        Some(name) => Resolution::from_str(&name, true)
            .map_err(anyhow::Error::msg)
            .context("the resolution is coarse, medium or fine")?,
        None => Resolution::Coarse,
    };
    let anatomy = Anatomy::procedural_knee(resolution)?;
    write_anatomy(&anatomy, &directory, &[0.0, 45.0, 90.0])?;
    println!(
        "wrote the anatomy at 0°, 45°, 90° to {}",
        directory.display()
    );
    println!("knee-extensor moment arms [mm]:   VI     VL     VM     RF");
    for degrees in [0.0f64, 30.0, 60.0, 90.0] {
        let arms = moment_arms_at(&anatomy.kinematics, &anatomy.muscles, degrees.to_radians())?;
        let cells: Vec<String> = arms.iter().map(|r| format!("{:6.1}", r * 1e3)).collect();
        println!("  {degrees:5.0}°                      {}", cells.join(" "));
    }
    Ok(())
}
