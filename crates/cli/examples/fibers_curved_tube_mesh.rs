//! Writes the curved tube of the `musclefem fibers` tests (a quarter torus of rectangular
//! section, r ∈ [20, 40] mm, 10 mm high, 8 × 32 × 4 hex8) as an Abaqus input file with the
//! surfaces "origin" (cut θ = 0) and "insertion" (cut θ = π/2), to run `musclefem fibers`
//! on it. docs/images/README.md has the commands that draw
//! docs/images/fibers_curved_tube.png.
//!
//! ```sh
//! cargo run --release -p musclefem --example fibers_curved_tube_mesh -- target/curved_tube.inp
//! ```

use std::path::PathBuf;

use musclefem_core::mesh::generate::curved_tube;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args_os()
        .nth(1)
        .map_or_else(|| PathBuf::from("curved_tube.inp"), PathBuf::from);
    let mut mesh = curved_tube([0.02, 0.04], 0.01, [8, 32, 4])?;
    for (name, face) in [("origin", "y0"), ("insertion", "y1")] {
        let faces = mesh.surfaces[face].clone();
        mesh.surfaces.insert(name.to_string(), faces);
    }
    let text = musclefem_io::mesh_export::abaqus_text(&mesh, "curved tube (quarter torus)");
    std::fs::write(&path, text)?;
    println!(
        "wrote {} ({} hex8, surfaces 'origin' and 'insertion')",
        path.display(),
        mesh.element_count()
    );
    Ok(())
}
