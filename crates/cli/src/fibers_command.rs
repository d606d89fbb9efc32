//! `musclefem fibers`: fiber directions of a muscle mesh from a potential flow between its
//! origin (inlet) and insertion (outlet) surfaces (seed §2.3), written as fibers.csv
//! (element, centroid, unit direction), fibers.vtu (cell vectors for ParaView) and
//! fibers.png (arrows at the centroids, in the plane of their two principal axes).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use nalgebra::Vector3;

use musclefem_fibers::{FlowBoundary, FlowSettings, Side, compute_fibers};
use musclefem_io::PendingFile;
use musclefem_io::fiber_csv::{FiberRow, format_fibers_csv};
use musclefem_io::mesh_import::read_mesh;
use musclefem_io::output::{Frame, stage_vtu};
use musclefem_io::plot::{GlyphView, stage_glyph_png};

/// Length of the arrows in fibers.png as a fraction of the mean element size, the cube
/// root of the mean element volume.
const ARROW_LENGTH_PER_ELEMENT_SIZE: f64 = 0.6;

/// Most arrows in fibers.png (a larger mesh shows every k-th element).
const MAX_ARROWS: usize = 3000;

#[derive(Debug, Args)]
pub struct FibersArgs {
    /// The muscle mesh: Abaqus .inp or Gmsh .msh (2.2 ASCII, 4.1 ASCII or binary; coordinates in m).
    #[arg(long, value_name = "FILE")]
    pub mesh: PathBuf,
    /// Origin: a surface (element faces) or node set of the mesh, where the flow enters
    /// (potential 1); repeatable for several origins.
    #[arg(long, value_name = "SURFACE_OR_NODESET", required = true)]
    pub inlet: Vec<String>,
    /// Insertion: a surface or node set where the flow leaves (potential 0); repeatable.
    #[arg(long, value_name = "SURFACE_OR_NODESET", required = true)]
    pub outlet: Vec<String>,
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "out/fibers")]
    pub out: PathBuf,
    /// Relative residual of the flow solve [1].
    #[arg(long, value_name = "TOL", default_value_t = 1e-10)]
    pub tolerance: f64,
    /// Replace the results of an earlier run in the output place.
    #[arg(long)]
    pub force: bool,
}

pub fn fibers(args: &FibersArgs) -> Result<()> {
    crate::commands::refuse_existing(
        &["fibers.csv", "fibers.vtu", "fibers.png"].map(|f| args.out.join(f)),
        args.force,
    )?;
    let imported = read_mesh(&args.mesh)?;
    let mut mesh = imported.mesh;
    let boundary = FlowBoundary::from_names(&mesh, &args.inlet, &args.outlet)
        .with_context(|| format!("the inlet and outlet of {}", args.mesh.display()))?;
    let settings = FlowSettings {
        tolerance: args.tolerance,
        ..FlowSettings::default()
    };
    let field = compute_fibers(&mesh, &boundary, &settings)
        .with_context(|| format!("the flow through {}", args.mesh.display()))?;
    field.assign_to(&mut mesh)?;

    let mut rows = Vec::with_capacity(mesh.element_count());
    for (b, block) in mesh.blocks.iter().enumerate() {
        for (e, nodes) in block.elements().enumerate() {
            let corners = block.shape.corner_count();
            let centroid = nodes[..corners]
                .iter()
                .map(|&n| mesh.nodes.position(n as usize))
                .sum::<Vector3<f64>>()
                / corners as f64;
            rows.push(FiberRow {
                element: imported.element_labels[b][e],
                centroid,
                direction: block.fiber_direction[e],
            });
        }
    }
    // Creates the directory; a second `fibers` into it is refused while this one runs.
    let _lock = musclefem_io::output::OutputLock::acquire(&args.out)?;
    let csv_path = args.out.join("fibers.csv");
    let vtu_path = args.out.join("fibers.vtu");
    let png_path = args.out.join("fibers.png");
    let displacement = vec![Vector3::zeros(); mesh.node_count()];
    let frame =
        Frame::new(0.0, &mesh, &displacement).with_cell_scalar("potential", &field.potential);
    let element_size = (mesh.total_volume()? / mesh.element_count() as f64).cbrt();
    let centroids: Vec<Vector3<f64>> = rows.iter().map(|r| r.centroid).collect();
    let directions: Vec<Vector3<f64>> = rows.iter().map(|r| r.direction).collect();
    let mesh_name = args.mesh.file_name().unwrap_or(args.mesh.as_os_str());
    let view = GlyphView {
        title: format!("Fiber directions of {}", mesh_name.to_string_lossy()),
        points: &centroids,
        directions: &directions,
        colour_values: &field.potential,
        colour_label: "potential φ [1]".to_string(),
        arrow_length: ARROW_LENGTH_PER_ELEMENT_SIZE * element_size,
        max_glyphs: MAX_ARROWS,
    };
    let staged = [
        PendingFile::stage_bytes(&csv_path, format_fibers_csv(&rows).as_bytes())?,
        stage_vtu(&vtu_path, &frame)?,
        stage_glyph_png(&png_path, &view)?,
    ];
    for file in staged {
        file.commit()?;
    }
    println!(
        "{}: {} elements, {} inlet and {} outlet faces; flux in {:.6e} m, out {:.6e} m \
         (imbalance {:.1e}); {} CG iterations, residual {:.1e}, {:.2?}",
        args.mesh.display(),
        mesh.element_count(),
        field.inlet_faces,
        field.outlet_faces,
        field.inlet_flux,
        field.outlet_flux,
        (field.inlet_flux - field.outlet_flux).abs() / field.inlet_flux,
        field.linear_iterations,
        field.residual,
        field.setup_time + field.solve_time
    );
    for region in &field.region_fluxes {
        let total = match region.side {
            Side::Inlet => field.inlet_flux,
            Side::Outlet => field.outlet_flux,
        };
        println!(
            "  {} '{}': {} faces, flux {:.6e} m ({:.2} % of the {} flux)",
            region.side,
            region.name,
            region.faces,
            region.flux,
            100.0 * region.flux / total,
            region.side
        );
    }
    println!(
        "wrote {}, {} (cell vector fiber_direction_reference) and {} (arrows coloured by \
         the potential: 1 at the inlet, 0 at the outlet)",
        csv_path.display(),
        vtu_path.display(),
        png_path.display()
    );
    Ok(())
}
