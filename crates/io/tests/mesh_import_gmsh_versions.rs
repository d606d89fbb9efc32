//! Gmsh 2.2 ASCII and 4.1 binary against 4.1 ASCII, and an Abaqus deck with triangles,
//! all written by meshio 5.3.5 (tests/meshes/write_gmsh_versions.py), checked against
//! the hand-known mesh: two unit hexes along x, physical volume "muscle", physical
//! surface "top" on z = 1.

use std::collections::BTreeMap;

use musclefem_io::mesh_import::{ImportedMesh, parse_gmsh_bytes, read_mesh};
use musclefem_mesh::Face;

fn fixture(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/meshes")
        .join(name)
}

/// The mesh in file labels: node positions, element node labels, sets as label lists
/// and surfaces as (element label, face), all sorted.
#[derive(Debug, PartialEq)]
struct Labelled {
    nodes: BTreeMap<i64, [f64; 3]>,
    elements: BTreeMap<i64, Vec<i64>>,
    node_sets: BTreeMap<String, Vec<i64>>,
    element_sets: BTreeMap<String, Vec<i64>>,
    surfaces: BTreeMap<String, Vec<(i64, u8)>>,
    blocks: Vec<(String, String)>,
}

fn labelled(imported: &ImportedMesh) -> Labelled {
    let mesh = &imported.mesh;
    let node = |id: u32| imported.node_labels[id as usize];
    let element = |b: u32, e: u32| imported.element_labels[b as usize][e as usize];
    let mut out = Labelled {
        nodes: BTreeMap::new(),
        elements: BTreeMap::new(),
        node_sets: BTreeMap::new(),
        element_sets: BTreeMap::new(),
        surfaces: BTreeMap::new(),
        blocks: Vec::new(),
    };
    for id in 0..mesh.node_count() {
        let p = mesh.nodes.position(id);
        out.nodes.insert(node(id as u32), [p.x, p.y, p.z]);
    }
    for (b, block) in mesh.blocks.iter().enumerate() {
        out.blocks
            .push((block.name.clone(), imported.element_types[b].clone()));
        for (e, nodes) in block.elements().enumerate() {
            let labels = nodes.iter().map(|&n| node(n)).collect();
            out.elements.insert(element(b as u32, e as u32), labels);
        }
    }
    for (name, ids) in &mesh.node_sets {
        let mut labels: Vec<i64> = ids.iter().map(|&n| node(n)).collect();
        labels.sort_unstable();
        out.node_sets.insert(name.clone(), labels);
    }
    for (name, refs) in &mesh.element_sets {
        let mut labels: Vec<i64> = refs.iter().map(|r| element(r.block, r.element)).collect();
        labels.sort_unstable();
        out.element_sets.insert(name.clone(), labels);
    }
    for (name, faces) in &mesh.surfaces {
        let mut labels: Vec<(i64, u8)> = faces
            .iter()
            .map(|f| (element(f.element.block, f.element.element), f.face))
            .collect();
        labels.sort_unstable();
        out.surfaces.insert(name.clone(), labels);
    }
    out
}

#[test]
fn gmsh_22_ascii_and_41_binary_read_as_41_ascii_and_as_the_known_mesh() {
    let ascii = read_mesh(fixture("two_hexes_41.msh")).unwrap();
    let binary = read_mesh(fixture("two_hexes_41_binary.msh")).unwrap();
    let v2 = read_mesh(fixture("two_hexes_22.msh")).unwrap();
    let reference = labelled(&ascii);
    assert_eq!(labelled(&binary), reference);
    assert_eq!(labelled(&v2), reference);

    // The known mesh: node label 1 + i + 3j + 6k at (i, j, k).
    for (&label, x) in &reference.nodes {
        let i = label - 1;
        assert_eq!(*x, [(i % 3) as f64, (i / 3 % 2) as f64, (i / 6) as f64]);
    }
    assert_eq!(reference.nodes.len(), 12);
    assert_eq!(reference.elements[&1], [1, 2, 5, 4, 7, 8, 11, 10]);
    assert_eq!(reference.elements[&2], [2, 3, 6, 5, 8, 9, 12, 11]);
    assert_eq!(reference.blocks, [("muscle".into(), "hex8".into())]);
    assert_eq!(reference.element_sets["muscle"], [1, 2]);
    assert_eq!(reference.node_sets["top"], [7, 8, 9, 10, 11, 12]);
    assert_eq!(reference.node_sets["muscle"].len(), 12);
    // The top quads are face S2 (nodes 5 6 7 8, z = 1) of each hex, outward +z.
    assert_eq!(reference.surfaces["top"], [(1, 1), (2, 1)]);
    for &face in v2.mesh.surface("top").unwrap() {
        let area = v2.mesh.face_area_vector(face).unwrap();
        assert!((area - nalgebra::Vector3::new(0.0, 0.0, 1.0)).norm() < 1e-15);
    }
    assert!((binary.mesh.total_volume().unwrap() - 2.0).abs() < 1e-15);
}

#[test]
fn a_meshio_deck_with_triangles_reads_them_as_a_surface() {
    let imported = read_mesh(fixture("tet_triangles.inp")).unwrap();
    let mesh = &imported.mesh;
    assert_eq!(imported.element_types, ["C3D4"]);
    let tet = musclefem_mesh::ElementRef::new(0, 0);
    // (1, 3, 2) is S1 (outward −z), (2, 3, 4) is S3.
    assert_eq!(
        mesh.surface("R3D3").unwrap(),
        &[Face::new(tet, 0), Face::new(tet, 2)]
    );
    assert_eq!(mesh.node_set("R3D3").unwrap(), &[0, 1, 2, 3]);
    assert!(imported.warnings.is_empty(), "{:?}", imported.warnings);
}

#[test]
fn unreadable_gmsh_variants_say_what_to_do() {
    let directory = std::env::temp_dir().join(format!("musclefem-gmsh-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    let binary = std::fs::read(fixture("two_hexes_41_binary.msh")).unwrap();
    let write = |name: &str, bytes: &[u8]| {
        let path = directory.join(name);
        std::fs::write(&path, bytes).unwrap();
        read_mesh(&path).unwrap_err().to_string()
    };
    // 2.2 binary.
    let text = write(
        "v22b.msh",
        b"$MeshFormat\n2.2 1 8\n\x01\x00\x00\x00\n$EndMeshFormat\n",
    );
    assert!(text.ends_with("v22b.msh:2: $MeshFormat: binary 2.2 files are not supported: save as 4.1 (Mesh.MshFileVersion = 4.1) or as ASCII (Mesh.Binary = 0)"), "{text}");
    // Big-endian: the integer 1 written 00 00 00 01.
    let mut big = binary.clone();
    let at = big.windows(4).position(|w| w == [1, 0, 0, 0]).unwrap();
    big[at..at + 4].copy_from_slice(&[0, 0, 0, 1]);
    let text = write("big.msh", &big);
    assert!(
        text.contains("big-endian files are not supported"),
        "{text}"
    );
    // Cut within the node coordinates: the section and byte are named.
    let nodes = binary.windows(7).position(|w| w == b"$Nodes\n").unwrap();
    let text = write("cut.msh", &binary[..nodes + 200]);
    assert!(text.contains("$Nodes (binary, byte"), "{text}");
    assert!(
        text.contains("6 items cannot fit in the 141 bytes left"),
        "{text}"
    );
    // 4.0 is not read.
    let text = write("v40.msh", b"$MeshFormat\n4 0 8\n$EndMeshFormat\n");
    assert!(text.contains("version 4 is not supported"), "{text}");
    std::fs::remove_dir_all(&directory).unwrap();
}

/// Random byte changes of the binary fixture (a fixed linear congruential sequence):
/// every one gives a mesh or an error, never a panic.
#[test]
fn mutated_binary_files_never_panic() {
    let binary = std::fs::read(fixture("two_hexes_41_binary.msh")).unwrap();
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 33) as usize
    };
    let (mut read, mut refused) = (0, 0);
    for _ in 0..3000 {
        let mut bytes = binary.clone();
        for _ in 0..1 + next() % 4 {
            let at = next() % bytes.len();
            match next() % 3 {
                0 => bytes[at] = next() as u8,
                1 => bytes.truncate(at.max(1)),
                _ => bytes[at] ^= 0x80,
            }
        }
        let outcome = std::panic::catch_unwind(|| parse_gmsh_bytes(bytes, "m.msh").is_ok());
        match outcome.expect("a mutated binary file made the reader panic") {
            true => read += 1,
            false => refused += 1,
        }
    }
    // Both outcomes occur: the mutations reach the data, not only the header.
    assert!(read > 0 && refused > 0, "{read} read, {refused} refused");
}
