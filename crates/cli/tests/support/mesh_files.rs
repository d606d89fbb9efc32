//! Meshes for the `musclefem fibers` tests, written as Gmsh 4.1 ASCII and Abaqus text the
//! way the importers read them: a box of tets and the annular sector of a torus (a curved
//! tube) of hexes, with named end surfaces.

#![allow(dead_code)]

use std::fmt::Write;

use musclefem_core::mesh::generate;
use musclefem_core::mesh::{ElementShape, Mesh};

/// File tag of node `id` (1-based, in id order).
pub fn node_tag(id: usize) -> i64 {
    id as i64 + 1
}

/// File tag of element `e` of the only block: not contiguous and not from 1, so that a
/// reader or writer that numbers elements itself is caught.
pub fn element_tag(e: usize) -> i64 {
    1001 + 2 * e as i64
}

/// A region of a mesh written under another name: `(name in the file, surface of the
/// mesh)`, e.g. `("origin", "x0")`.
pub type Renamed<'a> = (&'a str, &'a str);

/// Gmsh 4.1 ASCII text of a one-block tet4 or hex8 mesh: the elements in the physical
/// volume "muscle", and each surface of `surfaces` as 2-D elements (corners in the
/// outward order) in a physical surface of its file name.
pub fn gmsh_text(mesh: &Mesh, surfaces: &[Renamed]) -> String {
    let block = &mesh.blocks[0];
    let (volume_type, face_type) = match block.shape {
        ElementShape::Hex8 => (5, 3),
        ElementShape::Tet4 => (4, 2),
        shape => panic!("gmsh_text writes tet4 and hex8, not {shape}"),
    };
    let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    writeln!(s, "$PhysicalNames\n{}", surfaces.len() + 1).unwrap();
    for (k, (name, _)) in surfaces.iter().enumerate() {
        writeln!(s, "2 {} \"{name}\"", k + 1).unwrap();
    }
    s.push_str("3 1 \"muscle\"\n$EndPhysicalNames\n");
    // One surface entity per physical surface, and the volume bounded by them (bounding
    // boxes are not read: zeros).
    writeln!(s, "$Entities\n0 0 {} 1", surfaces.len()).unwrap();
    for k in 1..=surfaces.len() {
        writeln!(s, "{k} 0 0 0 0 0 0 1 {k} 0").unwrap();
    }
    let bounding: Vec<String> = (1..=surfaces.len()).map(|k| k.to_string()).collect();
    writeln!(
        s,
        "1 0 0 0 0 0 0 1 1 {} {}\n$EndEntities",
        surfaces.len(),
        bounding.join(" ")
    )
    .unwrap();
    let n = mesh.node_count();
    writeln!(s, "$Nodes\n1 {n} 1 {n}\n3 1 0 {n}").unwrap();
    for id in 0..n {
        writeln!(s, "{}", node_tag(id)).unwrap();
    }
    for id in 0..n {
        let p = mesh.nodes.position(id);
        writeln!(s, "{:?} {:?} {:?}", p.x, p.y, p.z).unwrap();
    }
    s.push_str("$EndNodes\n");
    let face_count: usize = surfaces
        .iter()
        .map(|(_, from)| mesh.surfaces[*from].len())
        .sum();
    let total = block.len() + face_count;
    let first_face_tag = element_tag(block.len());
    writeln!(
        s,
        "$Elements\n{} {total} {} {}",
        surfaces.len() + 1,
        element_tag(0),
        first_face_tag + 2 * (face_count as i64 - 1)
    )
    .unwrap();
    writeln!(s, "3 1 {volume_type} {}", block.len()).unwrap();
    for (e, nodes) in block.elements().enumerate() {
        let tags: Vec<String> = nodes
            .iter()
            .map(|&n| node_tag(n as usize).to_string())
            .collect();
        writeln!(s, "{} {}", element_tag(e), tags.join(" ")).unwrap();
    }
    let mut tag = first_face_tag;
    for (k, (_, from)) in surfaces.iter().enumerate() {
        let faces = &mesh.surfaces[*from];
        writeln!(s, "2 {} {face_type} {}", k + 1, faces.len()).unwrap();
        for &face in faces {
            let corners: Vec<String> = mesh
                .face_nodes(face)
                .unwrap()
                .iter()
                .map(|&n| node_tag(n as usize).to_string())
                .collect();
            writeln!(s, "{tag} {}", corners.join(" ")).unwrap();
            tag += 2;
        }
    }
    s.push_str("$EndElements\n");
    s
}

/// Abaqus text of the same mesh with the same tags: C3D4 or C3D8 elements in the element
/// set "muscle", each of `surfaces` as a `*SURFACE` of element-face sets (S1…S6), each of
/// `node_sets` as an `*NSET` of the nodes of that surface of the mesh.
pub fn abaqus_text(mesh: &Mesh, surfaces: &[Renamed], node_sets: &[Renamed]) -> String {
    let block = &mesh.blocks[0];
    let type_name = match block.shape {
        ElementShape::Hex8 => "C3D8",
        ElementShape::Tet4 => "C3D4",
        shape => panic!("abaqus_text writes tet4 and hex8, not {shape}"),
    };
    let mut s = String::from("*Heading\n musclefem fibers test mesh\n*Node\n");
    for id in 0..mesh.node_count() {
        let p = mesh.nodes.position(id);
        writeln!(s, "{}, {:?}, {:?}, {:?}", node_tag(id), p.x, p.y, p.z).unwrap();
    }
    writeln!(s, "*Element, type={type_name}, elset=muscle").unwrap();
    for (e, nodes) in block.elements().enumerate() {
        let tags: Vec<String> = nodes
            .iter()
            .map(|&n| node_tag(n as usize).to_string())
            .collect();
        writeln!(s, "{}, {}", element_tag(e), tags.join(", ")).unwrap();
    }
    let data_lines = |s: &mut String, tags: Vec<i64>| {
        for chunk in tags.chunks(16) {
            let chunk: Vec<String> = chunk.iter().map(i64::to_string).collect();
            writeln!(s, "{}", chunk.join(", ")).unwrap();
        }
    };
    for (name, from) in surfaces {
        let faces = &mesh.surfaces[*from];
        let mut lines = String::new();
        for local in 0..6u8 {
            let elements: Vec<i64> = faces
                .iter()
                .filter(|f| f.face == local)
                .map(|f| element_tag(f.element.element as usize))
                .collect();
            if !elements.is_empty() {
                writeln!(s, "*Elset, elset=_{name}_S{}, internal", local + 1).unwrap();
                data_lines(&mut s, elements);
                writeln!(lines, "_{name}_S{0}, S{0}", local + 1).unwrap();
            }
        }
        write!(s, "*Surface, type=ELEMENT, name={name}\n{lines}").unwrap();
    }
    for (name, from) in node_sets {
        writeln!(s, "*Nset, nset={name}").unwrap();
        let tags = mesh.node_sets[*from]
            .iter()
            .map(|&n| node_tag(n as usize))
            .collect();
        data_lines(&mut s, tags);
    }
    s
}

/// Inner and outer radius of the curved tube [m].
pub const TUBE_RADII: [f64; 2] = [0.02, 0.04];
/// Height of the curved tube [m].
pub const TUBE_HEIGHT: f64 = 0.01;

/// Divisions (radial, angular, axial) of the curved tube of the tests and of the docs'
/// picture: 1024 hexes.
pub const CURVED_TUBE_DIVISIONS: [usize; 3] = [8, 32, 4];

/// The curved tube of the tests (see `musclefem_core::mesh::generate::curved_tube`).
pub fn curved_tube(divisions: [usize; 3]) -> Mesh {
    generate::curved_tube(TUBE_RADII, TUBE_HEIGHT, divisions).expect("a valid tube")
}
