//! The knee's model as the files a scene reads (issue 30, step 4, begun): the muscles'
//! mesh as Abaqus text (`muscles.inp`: every block, belly and tendon, with the node sets
//! of the origins, insertions and belly ends and the `<block>_lateral` surfaces the
//! interactions use), every element's fiber direction (`fibers.csv`, element ids the
//! file's labels) and the patella's equilibrium table (`patella_table.csv`). Each reads
//! back to the same numbers, bit for bit: coordinates, fibers and table entries are
//! written as the shortest decimals that parse back to them
//! ([`musclefem_io::mesh_export`], [`musclefem_io::csv::format_number`]). The node ids,
//! blocks, node sets and surfaces read back as they were (the knee sorts each surface's
//! faces as the Abaqus reader does).
//!
//! Parts take the file's blocks with `shared_nodes = true`, so that a belly and its
//! tendon stay joined (`super::scene_tests` builds the whole model from these files;
//! `musclefem knee` writes them with its `scene.toml`, [`super::scene`]).

use std::path::Path;

use anyhow::{Context, Result};
use nalgebra::Vector3;

use musclefem_core::mesh::Mesh;
use musclefem_io::fiber_csv::{FiberRow, format_fibers_csv};
use musclefem_io::mesh_export::abaqus_text;

use super::patella::PatellaTable;

/// The muscles' mesh file.
pub const MUSCLES_INP: &str = "muscles.inp";
/// The fibers file.
pub const FIBERS_CSV: &str = "fibers.csv";
/// The patella's equilibrium table.
pub const PATELLA_TABLE_CSV: &str = "patella_table.csv";

/// One row per element of `mesh`, in block order, labelled 1, 2, … as
/// [`abaqus_text`] labels them: the element's centroid (the mean of its nodes) [m] and
/// its fiber direction.
pub fn fiber_rows(mesh: &Mesh) -> Vec<FiberRow> {
    let mut rows = Vec::with_capacity(mesh.element_count());
    for block in &mesh.blocks {
        for (nodes, direction) in block.elements().zip(&block.fiber_direction) {
            let centroid = nodes
                .iter()
                .map(|&n| mesh.nodes.position(n as usize))
                .sum::<Vector3<f64>>()
                / nodes.len() as f64;
            rows.push(FiberRow {
                element: rows.len() as i64 + 1,
                centroid,
                direction: *direction,
            });
        }
    }
    rows
}

/// `muscles.inp` and `fibers.csv` of the fibered muscle mesh `mesh`, and
/// `patella_table.csv` of `table`: (file name, text) each.
pub fn model_files(mesh: &Mesh, table: &PatellaTable) -> Vec<(&'static str, String)> {
    vec![
        (
            MUSCLES_INP,
            abaqus_text(mesh, "musclefem knee: the quadriceps, bellies and tendons"),
        ),
        (FIBERS_CSV, format_fibers_csv(&fiber_rows(mesh))),
        (PATELLA_TABLE_CSV, table.csv_text()),
    ]
}

/// Write the [`model_files`] into `directory` (atomically, each).
pub fn write_model_files(directory: &Path, mesh: &Mesh, table: &PatellaTable) -> Result<()> {
    for (name, text) in model_files(mesh, table) {
        let path = directory.join(name);
        musclefem_io::atomic::write_atomically(&path, text.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use musclefem_io::fiber_csv::read_fibers_csv;
    use musclefem_io::mesh_import::read_mesh;

    use super::*;
    use crate::knee::anatomy::{Anatomy, Resolution, Squat};
    use crate::knee::simulation::KneeGeometry;

    #[test]
    fn the_knees_mesh_fibers_and_table_read_back_bit_for_bit() {
        let anatomy = Anatomy::procedural_knee(Resolution::Coarse).unwrap();
        let squat = Squat {
            duration: 0.2,
            peak_flexion: 10f64.to_radians(),
        };
        let geometry = KneeGeometry::procedural_knee(&anatomy, &squat).unwrap();
        let fibers = geometry.fibers().unwrap();
        let mesh = geometry.fibered_mesh(&fibers).unwrap();
        let directory =
            std::env::temp_dir().join(format!("musclefem-knee-files-{}", std::process::id()));
        std::fs::create_dir_all(&directory).unwrap();
        write_model_files(&directory, &mesh, &geometry.patella_table).unwrap();

        let read = read_mesh(directory.join(MUSCLES_INP)).unwrap().mesh;
        assert_eq!(read.node_count(), mesh.node_count());
        for n in 0..mesh.node_count() {
            let (a, b) = (read.nodes.position(n), mesh.nodes.position(n));
            assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "node {n}");
        }
        assert_eq!(read.blocks.len(), mesh.blocks.len());
        for (a, b) in read.blocks.iter().zip(&mesh.blocks) {
            assert_eq!((&a.name, a.shape), (&b.name, b.shape));
            assert_eq!(a.connectivity, b.connectivity, "block {}", b.name);
        }
        assert_eq!(read.node_sets, mesh.node_sets);
        // The same faces in the same order (the knee's are sorted, as the reader sorts).
        assert_eq!(read.surfaces, mesh.surfaces);
        // The sets the squat ties and the surfaces its interactions take.
        for (b, muscle) in geometry.muscles.iter().enumerate() {
            let name = geometry.block_name(b);
            for set in ["origin", "insertion"] {
                assert!(
                    !read.node_sets[&format!("{name}_{set}")].is_empty(),
                    "{muscle:?}"
                );
            }
            assert!(
                !read.surfaces[&format!("{name}_lateral")].is_empty(),
                "{muscle:?}"
            );
        }

        let rows = read_fibers_csv(&directory.join(FIBERS_CSV)).unwrap();
        assert_eq!(rows.len(), mesh.element_count());
        let directions = mesh.blocks.iter().flat_map(|b| b.fiber_direction.iter());
        for ((_, row), direction) in rows.iter().zip(directions) {
            assert_eq!(
                row.direction.map(f64::to_bits),
                direction.map(f64::to_bits),
                "element {}",
                row.element
            );
        }
        let first = mesh.blocks[0].elements().next().unwrap();
        let centroid = first
            .iter()
            .map(|&n| mesh.nodes.position(n as usize))
            .sum::<Vector3<f64>>()
            / 8.0;
        assert_eq!((rows[0].1.element, rows[0].1.centroid), (1, centroid));

        let table = PatellaTable::read_csv(
            &directory.join(PATELLA_TABLE_CSV),
            *geometry.patella_table.tendon(),
        )
        .unwrap();
        for (angle, tension) in [(0.02, 400.0), (0.15, 3000.0)] {
            assert_eq!(
                table.equilibrium(angle, tension),
                geometry.patella_table.equilibrium(angle, tension)
            );
        }
        std::fs::remove_dir_all(&directory).unwrap();
    }
}
