//! Meshes written as Abaqus input text (`.inp`), so that a study can hand a generated
//! mesh to a scene file (`mesh = { file = "specimen.inp" }`) and [`crate::mesh_import`]
//! reads back the same mesh: the same node ids and coordinates (to the last bit: each
//! coordinate is written as the shortest decimal that parses back to it), the same
//! blocks in order (one `*ELEMENT, TYPE=..., ELSET=<block name>` each: C3D8, C3D4 or
//! C3D10, whose node order is the library's), the node sets, element sets and
//! element-face surfaces (`Sn` is local face n − 1, as the reader takes it).
//!
//! Nodes are labelled 1, 2, ... in id order and elements 1, 2, ... in block order. Fiber
//! directions are not part of an Abaqus mesh: a scene gives them (`fibers = ...`).
//!
//! Rigid surfaces (bones) with their vertex normals are written as OBJ text by
//! [`obj_text`] (`mesh_export/obj.rs`).

mod obj;

use std::fmt::Write as _;

use musclefem_mesh::{ElementRef, ElementShape, Mesh};

pub use obj::obj_text;

/// Entries per data line of a set (Abaqus reads at most 16).
const PER_LINE: usize = 16;

/// The Abaqus element type of `shape`.
pub fn abaqus_element_type(shape: ElementShape) -> &'static str {
    match shape {
        ElementShape::Hex8 => "C3D8",
        ElementShape::Tet4 => "C3D4",
        ElementShape::Tet10 => "C3D10",
    }
}

/// `mesh` as the text of an Abaqus input file, with `heading` (one line) under `*HEADING`.
pub fn abaqus_text(mesh: &Mesh, heading: &str) -> String {
    let mut text = format!("*HEADING\n{}\n*NODE\n", heading.replace('\n', " "));
    for id in 0..mesh.node_count() {
        let p = mesh.nodes.position(id);
        // `{:?}` is the shortest representation that reads back to the same f64.
        let _ = writeln!(text, "{}, {:?}, {:?}, {:?}", id + 1, p.x, p.y, p.z);
    }
    // Element labels run on across the blocks.
    let mut first_label = Vec::with_capacity(mesh.blocks.len());
    let mut label = 1usize;
    for block in &mesh.blocks {
        first_label.push(label);
        let _ = writeln!(
            text,
            "*ELEMENT, TYPE={}, ELSET={}",
            abaqus_element_type(block.shape),
            block.name
        );
        for nodes in block.elements() {
            let ids: Vec<String> = nodes.iter().map(|&n| (n + 1).to_string()).collect();
            // C3D10's eleven fields are split after the label and six nodes: a data line
            // ending in a comma continues on the next.
            let (head, tail) = ids.split_at(ids.len().min(7));
            let _ = write!(text, "{label}, {}", head.join(", "));
            if !tail.is_empty() {
                let _ = write!(text, ",\n{}", tail.join(", "));
            }
            text.push('\n');
            label += 1;
        }
    }
    let element_label = |e: &ElementRef| first_label[e.block as usize] + e.element as usize;
    for (name, nodes) in &mesh.node_sets {
        let _ = writeln!(text, "*NSET, NSET={name}");
        write_labels(&mut text, nodes.iter().map(|&n| n as usize + 1));
    }
    for (name, elements) in &mesh.element_sets {
        let _ = writeln!(text, "*ELSET, ELSET={name}");
        write_labels(&mut text, elements.iter().map(element_label));
    }
    for (name, faces) in &mesh.surfaces {
        let _ = writeln!(text, "*SURFACE, NAME={name}, TYPE=ELEMENT");
        for face in faces {
            let _ = writeln!(text, "{}, S{}", element_label(&face.element), face.face + 1);
        }
    }
    text
}

/// Labels, [`PER_LINE`] to a line (an empty set is written as no data line).
fn write_labels(text: &mut String, labels: impl Iterator<Item = usize>) {
    let labels: Vec<String> = labels.map(|l| l.to_string()).collect();
    for line in labels.chunks(PER_LINE) {
        let _ = writeln!(text, "{}", line.join(", "));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh_import::read_mesh;
    use musclefem_mesh::generate::{TetOrder, box_of_hexes, box_of_tets};

    fn round_trip(mesh: &Mesh) -> Mesh {
        let directory = std::env::temp_dir().join(format!(
            "musclefem-mesh-export-{}-{}",
            std::process::id(),
            mesh.element_count()
        ));
        std::fs::create_dir_all(&directory).unwrap();
        let path = directory.join("mesh.inp");
        std::fs::write(&path, abaqus_text(mesh, "round trip")).unwrap();
        let read = read_mesh(&path).unwrap();
        std::fs::remove_dir_all(&directory).unwrap();
        assert!(
            read.skipped_keywords.is_empty(),
            "{:?}",
            read.skipped_keywords
        );
        read.mesh
    }

    /// Everything but the fibers comes back: coordinates bit for bit, connectivity, sets
    /// and surfaces.
    fn assert_same(read: &Mesh, mesh: &Mesh) {
        assert_eq!(read.node_count(), mesh.node_count());
        for id in 0..mesh.node_count() {
            assert_eq!(
                read.nodes.position(id),
                mesh.nodes.position(id),
                "node {id}"
            );
        }
        assert_eq!(read.blocks.len(), mesh.blocks.len());
        for (r, m) in read.blocks.iter().zip(&mesh.blocks) {
            assert_eq!((&r.name, r.shape), (&m.name, m.shape));
            assert_eq!(r.connectivity, m.connectivity);
        }
        for (name, nodes) in &mesh.node_sets {
            let mut read_nodes = read.node_set(name).unwrap().to_vec();
            let mut nodes = nodes.clone();
            read_nodes.sort_unstable();
            nodes.sort_unstable();
            assert_eq!(read_nodes, nodes, "node set {name}");
        }
        for (name, faces) in &mesh.surfaces {
            let mut read_faces = read.surface(name).unwrap().to_vec();
            let mut faces = faces.clone();
            read_faces.sort_unstable_by_key(|f| (f.element.element, f.face));
            faces.sort_unstable_by_key(|f| (f.element.element, f.face));
            assert_eq!(read_faces, faces, "surface {name}");
        }
    }

    #[test]
    fn a_box_of_hexes_reads_back_the_same() {
        let mut mesh = box_of_hexes([0.013, 0.1 / 3.0, 7e-3], [3, 2, 4]).unwrap();
        mesh.blocks[0].name = "muscle".to_string();
        assert_same(&round_trip(&mesh), &mesh);
    }

    #[test]
    fn quadratic_tets_read_back_the_same() {
        let mut mesh = box_of_tets([0.02, 0.01, 0.03], [2, 1, 3], TetOrder::Quadratic).unwrap();
        mesh.blocks[0].name = "muscle".to_string();
        assert_same(&round_trip(&mesh), &mesh);
    }
}
