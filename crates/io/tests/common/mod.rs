//! Writers of Abaqus and Gmsh text from generator meshes, with non-contiguous labels.

#![allow(dead_code)]

use std::fmt::Write;

use musclefem_mesh::Mesh;

/// File label of node id `id`: not contiguous, not starting at 1.
pub fn node_label(id: usize) -> i64 {
    1000 + 7 * id as i64
}

/// File label of element `e` of the first block.
pub fn elem_label(e: usize) -> i64 {
    50 + 3 * e as i64
}

/// Abaqus text of a one-block mesh: elements before nodes, element sets per surface face
/// (as Abaqus/CAE writes them), a GENERATE set, a node set, and skipped keywords. With
/// `wrap`, element lines break after six entries with a trailing comma.
pub fn to_inp(mesh: &Mesh, type_name: &str, wrap: bool) -> String {
    let mut s = String::from("*Heading\n test mesh\n** comment\n");
    let block = &mesh.blocks[0];
    writeln!(s, "*Element, Type={type_name}, ELSET=EALL").unwrap();
    for (e, nodes) in block.elements().enumerate() {
        let mut fields = vec![elem_label(e).to_string()];
        fields.extend(nodes.iter().map(|&n| node_label(n as usize).to_string()));
        if wrap && fields.len() > 6 {
            writeln!(s, "{},\n{}", fields[..6].join(", "), fields[6..].join(", ")).unwrap();
        } else {
            writeln!(s, "{}", fields.join(", ")).unwrap();
        }
    }
    s.push_str("*NODE\n");
    for id in 0..mesh.node_count() {
        let p = mesh.nodes.position(id);
        writeln!(s, "{}, {:?}, {:?}, {:?}", node_label(id), p.x, p.y, p.z).unwrap();
    }
    writeln!(
        s,
        "*Elset, elset=EVERY, generate\n{}, {}, 3",
        elem_label(0),
        elem_label(block.len() - 1)
    )
    .unwrap();
    s.push_str("*nset, nset=X0\n");
    for chunk in mesh.node_sets["x0"].chunks(16) {
        let labels: Vec<String> = chunk
            .iter()
            .map(|&n| node_label(n as usize).to_string())
            .collect();
        writeln!(s, "{},", labels.join(", ")).unwrap();
    }
    for (name, faces) in &mesh.surfaces {
        let mut lines = String::new();
        for face in 0..6u8 {
            let elements: Vec<String> = faces
                .iter()
                .filter(|f| f.face == face)
                .map(|f| elem_label(f.element.element as usize).to_string())
                .collect();
            if elements.is_empty() {
                continue;
            }
            writeln!(s, "*Elset, elset=_{name}_S{}, internal", face + 1).unwrap();
            for chunk in elements.chunks(16) {
                writeln!(s, "{}", chunk.join(", ")).unwrap();
            }
            writeln!(lines, "_{name}_S{}, S{}", face + 1, face + 1).unwrap();
        }
        write!(s, "*Surface, type=ELEMENT, name={name}\n{lines}").unwrap();
    }
    s.push_str("*Material, name=M\n*Elastic\n1e3, 0.3\n*Step\n*Static\n0.1, 1.\n*End Step\n");
    s
}

/// Gmsh 4.1 ASCII text of a one-block mesh: one volume in the physical group "muscle",
/// the faces of the surface "z1" as 2-D elements of the physical surface "top".
pub fn to_msh(mesh: &Mesh) -> String {
    let block = &mesh.blocks[0];
    let (volume_type, face_type) = match block.shape.name() {
        "hex8" => (5, 3),
        "tet4" => (4, 2),
        _ => (11, 9),
    };
    let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    s.push_str("$PhysicalNames\n2\n2 2 \"top\"\n3 1 \"muscle\"\n$EndPhysicalNames\n");
    s.push_str("$Entities\n0 0 1 1\n1 0 0 0 1 1 1 1 2 0\n1 0 0 0 1 1 1 1 1 1 1\n$EndEntities\n");
    let n = mesh.node_count();
    writeln!(
        s,
        "$Nodes\n1 {n} {} {}\n3 1 0 {n}",
        node_label(0),
        node_label(n - 1)
    )
    .unwrap();
    for id in 0..n {
        writeln!(s, "{}", node_label(id)).unwrap();
    }
    for id in 0..n {
        let p = mesh.nodes.position(id);
        writeln!(s, "{:?} {:?} {:?}", p.x, p.y, p.z).unwrap();
    }
    s.push_str("$EndNodes\n");
    let faces = &mesh.surfaces["z1"];
    let total = block.len() + faces.len();
    writeln!(
        s,
        "$Elements\n2 {total} 1 {total}\n3 1 {volume_type} {}",
        block.len()
    )
    .unwrap();
    for (e, nodes) in block.elements().enumerate() {
        let mut labels: Vec<i64> = nodes.iter().map(|&n| node_label(n as usize)).collect();
        if labels.len() == 10 {
            labels.swap(8, 9); // Abaqus → Gmsh mid-edge order
        }
        let labels: Vec<String> = labels.iter().map(i64::to_string).collect();
        writeln!(s, "{} {}", elem_label(e), labels.join(" ")).unwrap();
    }
    writeln!(s, "2 1 {face_type} {}", faces.len()).unwrap();
    for (k, &face) in faces.iter().enumerate() {
        let nodes = mesh.face_nodes(face).unwrap();
        let labels: Vec<String> = nodes
            .iter()
            .map(|&n| node_label(n as usize).to_string())
            .collect();
        writeln!(s, "{} {}", 1_000_000 + k, labels.join(" ")).unwrap();
    }
    s.push_str("$EndElements\n");
    s
}
