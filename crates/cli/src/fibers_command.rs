//! `musclefem fibers`: fiber directions of a muscle mesh from a potential flow between its
//! origin (inlet) and insertion (outlet) surfaces (seed §2.3), written as fibers.csv
//! (element, centroid, unit direction) and fibers.vtu (cell vectors for ParaView).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use nalgebra::Vector3;

use musclefem_fibers::{FlowBoundary, FlowSettings, Side, compute_fibers};
use musclefem_io::PendingFile;
use musclefem_io::fiber_csv::{FiberRow, format_fibers_csv};
use musclefem_io::mesh_import::read_mesh;
use musclefem_io::output::{Frame, stage_vtu};

#[derive(Debug, Args)]
pub struct FibersArgs {
    /// The muscle mesh: Abaqus .inp or Gmsh .msh 4.1 (coordinates in m).
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
}

pub fn fibers(args: &FibersArgs) -> Result<()> {
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
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let csv_path = args.out.join("fibers.csv");
    let vtu_path = args.out.join("fibers.vtu");
    let displacement = vec![Vector3::zeros(); mesh.node_count()];
    let frame =
        Frame::new(0.0, &mesh, &displacement).with_cell_scalar("potential", &field.potential);
    let staged = [
        PendingFile::stage_bytes(&csv_path, format_fibers_csv(&rows).as_bytes())?,
        stage_vtu(&vtu_path, &frame)?,
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
        "wrote {} and {} (cell vector fiber_direction_reference)",
        csv_path.display(),
        vtu_path.display()
    );
    Ok(())
}
