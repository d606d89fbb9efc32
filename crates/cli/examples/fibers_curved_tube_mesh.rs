//! Writes the curved tube of the `musclefem fibers` tests (a quarter torus of rectangular
//! section, r ∈ [20, 40] mm, 10 mm high, 8 × 32 × 4 hex8) as a Gmsh 4.1 file with the
//! physical surfaces "origin" (cut θ = 0) and "insertion" (cut θ = π/2), to run
//! `musclefem fibers` on it. docs/images/README.md has the commands that draw
//! docs/images/fibers_curved_tube.png.
//!
//! ```sh
//! cargo run --release -p musclefem --example fibers_curved_tube_mesh -- target/curved_tube.msh
//! ```

#[path = "../tests/support/mesh_files.rs"]
mod mesh_files;

use std::path::PathBuf;

fn main() -> std::io::Result<()> {
    let path = std::env::args_os()
        .nth(1)
        .map_or_else(|| PathBuf::from("curved_tube.msh"), PathBuf::from);
    let mesh = mesh_files::curved_tube(mesh_files::CURVED_TUBE_DIVISIONS);
    let text = mesh_files::gmsh_text(&mesh, &[("origin", "y0"), ("insertion", "y1")]);
    std::fs::write(&path, text)?;
    println!(
        "wrote {} ({} hex8, physical surfaces 'origin' and 'insertion')",
        path.display(),
        mesh.element_count()
    );
    Ok(())
}
