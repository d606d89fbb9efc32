//! Mesh import: Abaqus and Gmsh files against the generator meshes, hand-written
//! fixtures, and malformed inputs (tests/mesh_import_errors.rs).

mod common;

use common::{elem_label, node_label, to_inp, to_msh};
use musclefem_io::mesh_import::{ImportedMesh, parse_abaqus, parse_gmsh, read_mesh};
use musclefem_mesh::generate::{TetOrder, box_of_hexes, box_of_tets};
use musclefem_mesh::{ElementRef, Face, Mesh};

fn fixture(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/meshes")
        .join(name)
}

/// The imported element with file label `label`.
fn by_label(imported: &ImportedMesh, label: i64) -> ElementRef {
    for (b, labels) in imported.element_labels.iter().enumerate() {
        if let Some(e) = labels.iter().position(|&l| l == label) {
            return ElementRef::new(b as u32, e as u32);
        }
    }
    panic!("no element {label}");
}

/// Same node positions, connectivity (through labels), volumes and surfaces as `reference`.
fn assert_same(imported: &ImportedMesh, reference: &Mesh) {
    let mesh = &imported.mesh;
    assert_eq!(mesh.node_count(), reference.node_count());
    assert_eq!(mesh.element_count(), reference.element_count());
    for id in 0..reference.node_count() {
        let at = imported
            .node_labels
            .iter()
            .position(|&l| l == node_label(id))
            .expect("every label is imported");
        assert_eq!(mesh.nodes.position(at), reference.nodes.position(id));
    }
    let block = &reference.blocks[0];
    for e in 0..block.len() {
        let r = by_label(imported, elem_label(e));
        let labels: Vec<i64> = mesh
            .element_nodes(r)
            .unwrap()
            .iter()
            .map(|&n| imported.node_labels[n as usize])
            .collect();
        let expected: Vec<i64> = block
            .element_nodes(e)
            .iter()
            .map(|&n| node_label(n as usize))
            .collect();
        assert_eq!(labels, expected, "element {}", elem_label(e));
        let v = mesh.element_volume(r).unwrap();
        let v_ref = reference
            .element_volume(ElementRef::new(0, e as u32))
            .unwrap();
        assert!((v - v_ref).abs() <= 1e-12 * v_ref, "{v} vs {v_ref}");
    }
    let total = mesh.total_volume().unwrap();
    assert!((total - reference.total_volume().unwrap()).abs() < 1e-12);
}

/// The surface holds the reference surface's faces, and their normals point along `normal`.
fn assert_surface(imported: &ImportedMesh, name: &str, reference: &[Face], normal: [f64; 3]) {
    let faces = imported.mesh.surface(name).unwrap();
    assert_eq!(faces.len(), reference.len(), "surface {name}");
    let mut expected: Vec<Face> = reference
        .iter()
        .map(|f| {
            Face::new(
                by_label(imported, elem_label(f.element.element as usize)),
                f.face,
            )
        })
        .collect();
    expected.sort();
    assert_eq!(faces, expected.as_slice(), "surface {name}");
    for &face in faces {
        let a = imported.mesh.face_area_vector(face).unwrap();
        let along = a.x * normal[0] + a.y * normal[1] + a.z * normal[2];
        assert!(along > 0.99 * a.norm() && a.norm() > 0.0, "{name}: {a:?}");
    }
}

#[test]
fn abaqus_hexes_c3d8r_with_generate_sets_and_surface() {
    let reference = box_of_hexes([1.0, 2.0, 0.5], [3, 2, 2]).unwrap();
    let text = to_inp(&reference, "C3D8R", false);
    let imported = parse_abaqus(&text, "hexes.inp").unwrap();
    assert_same(&imported, &reference);
    assert_eq!(imported.element_types, vec!["C3D8R"]);
    assert_eq!(imported.mesh.blocks[0].name, "EALL");
    assert_surface(&imported, "x1", &reference.surfaces["x1"], [1.0, 0.0, 0.0]);
    assert_surface(&imported, "z0", &reference.surfaces["z0"], [0.0, 0.0, -1.0]);
    // GENERATE over every element label (step 3).
    assert_eq!(
        imported.mesh.element_set("EVERY").unwrap().len(),
        reference.element_count()
    );
    assert_eq!(
        imported.mesh.node_set("X0").unwrap().len(),
        reference.node_sets["x0"].len()
    );
    let skipped: Vec<&str> = imported
        .skipped_keywords
        .iter()
        .map(|s| s.keyword.as_str())
        .collect();
    assert_eq!(
        skipped,
        ["MATERIAL", "ELASTIC", "STEP", "STATIC", "END STEP"]
    );
}

#[test]
fn abaqus_tets_c3d4_and_wrapped_c3d10() {
    let linear = box_of_tets([1.0, 1.0, 2.0], [2, 1, 2], TetOrder::Linear).unwrap();
    let imported = parse_abaqus(&to_inp(&linear, "C3D4", false), "tets.inp").unwrap();
    assert_same(&imported, &linear);
    assert_surface(&imported, "y0", &linear.surfaces["y0"], [0.0, -1.0, 0.0]);

    let quadratic = box_of_tets([1.0, 1.0, 2.0], [2, 1, 2], TetOrder::Quadratic).unwrap();
    let text = to_inp(&quadratic, "C3D10", true);
    assert!(
        text.lines()
            .any(|l| l.ends_with(',') && l.split(',').count() == 7),
        "wrapped"
    );
    let imported = parse_abaqus(&text, "tet10.inp").unwrap();
    assert_same(&imported, &quadratic);
    assert_eq!(imported.element_types, vec!["C3D10"]);
    assert_surface(&imported, "z1", &quadratic.surfaces["z1"], [0.0, 0.0, 1.0]);
}

#[test]
fn abaqus_part_instance_translation_sets_and_surfaces() {
    let imported = read_mesh(fixture("part_instance.inp")).unwrap();
    let mesh = &imported.mesh;
    assert_eq!(imported.element_types, vec!["C3D8R"]);
    assert_eq!(imported.element_labels, vec![vec![11, 12]]);
    // Node 101 was at the origin: translated by (10, 0, 0).
    let at = |label: i64| {
        let id = imported
            .node_labels
            .iter()
            .position(|&l| l == label)
            .unwrap();
        mesh.nodes.position(id)
    };
    assert_eq!(at(101).as_slice(), &[10.0, 0.0, 0.0]);
    assert_eq!(at(112).as_slice(), &[12.0, 1.0, 1.0]);
    assert!((mesh.total_volume().unwrap() - 2.0).abs() < 1e-12);
    let labels = |ids: &[u32]| -> Vec<i64> {
        ids.iter()
            .map(|&i| imported.node_labels[i as usize])
            .collect()
    };
    assert_eq!(labels(mesh.node_set("left").unwrap()), [101, 104, 107, 110]);
    assert_eq!(
        labels(mesh.node_set("left_again").unwrap()),
        [101, 104, 107, 110]
    );
    assert_eq!(labels(mesh.node_set("corner").unwrap()), [112]);
    assert_eq!(mesh.element_set("both").unwrap().len(), 2);
    assert_eq!(mesh.element_set("first").unwrap(), &[ElementRef::new(0, 0)]);
    let right = mesh.surface("right").unwrap();
    assert_eq!(right, &[Face::new(ElementRef::new(0, 1), 3)]);
    assert!(mesh.face_area_vector(right[0]).unwrap().x > 0.99);
    let bottom = mesh.surface("bottom").unwrap();
    assert_eq!(bottom.len(), 2);
    for &f in bottom {
        assert!(mesh.face_area_vector(f).unwrap().z < -0.99);
    }
    let skipped: Vec<&str> = imported
        .skipped_keywords
        .iter()
        .map(|s| s.keyword.as_str())
        .collect();
    assert_eq!(
        skipped,
        [
            "PREPRINT",
            "SOLID SECTION",
            "MATERIAL",
            "DENSITY",
            "HYPERELASTIC",
            "STEP",
            "DYNAMIC",
            "BOUNDARY",
            "END STEP"
        ]
    );
    assert_eq!(imported.skipped_keywords[0].line, 4);
}

#[test]
fn abaqus_instance_rotation_is_applied_after_the_translation() {
    let text = "*PART, NAME=P\n*NODE\n1,0,0,0\n2,1,0,0\n3,0,1,0\n4,0,0,1\n\
                *ELEMENT,TYPE=C3D4\n1,1,2,3,4\n*END PART\n*ASSEMBLY,NAME=A\n\
                *INSTANCE,NAME=I,PART=P\n1.,0.,0.\n0.,0.,0.,0.,0.,1.,90.\n*END INSTANCE\n*END ASSEMBLY\n";
    let imported = parse_abaqus(text, "rotated.inp").unwrap();
    let p = |i: usize| imported.mesh.nodes.position(i);
    // (0,0,0) + (1,0,0) = (1,0,0), then 90° about z: (0,1,0).
    let close = |i: usize, x: [f64; 3]| (0..3).all(|d| (p(i)[d] - x[d]).abs() < 1e-12);
    assert!(close(0, [0.0, 1.0, 0.0]), "{:?}", p(0));
    // (1,0,0) → (2,0,0) → (0,2,0); (0,0,1) → (1,0,1) → (0,1,1).
    assert!(close(1, [0.0, 2.0, 0.0]), "{:?}", p(1));
    assert!(close(3, [0.0, 1.0, 1.0]), "{:?}", p(3));
    assert!((imported.mesh.total_volume().unwrap() - 1.0 / 6.0).abs() < 1e-12);
}

#[test]
fn abaqus_include_is_relative_to_the_including_file() {
    let imported = read_mesh(fixture("include_main.inp")).unwrap();
    assert_eq!(imported.node_labels, vec![1, 2, 3, 4]);
    assert_eq!(imported.element_labels, vec![vec![7]]);
    assert_eq!(imported.mesh.node_set("ALLN").unwrap(), &[0, 1, 2, 3]);
    assert_eq!(imported.mesh.blocks[0].name, "TET");
    assert!((imported.mesh.total_volume().unwrap() - 1.0 / 6.0).abs() < 1e-15);
}

#[test]
fn gmsh_hexes_tets_and_tet10_with_physical_groups() {
    let cases = [
        box_of_hexes([1.0, 2.0, 0.5], [2, 2, 2]).unwrap(),
        box_of_tets([1.0, 1.0, 2.0], [2, 1, 2], TetOrder::Linear).unwrap(),
        box_of_tets([1.0, 1.0, 2.0], [1, 2, 1], TetOrder::Quadratic).unwrap(),
    ];
    for reference in &cases {
        let shape = reference.blocks[0].shape;
        let imported = parse_gmsh(&to_msh(reference), "box.msh").unwrap();
        assert_same(&imported, reference);
        assert_eq!(imported.element_types, vec![shape.name()]);
        assert_eq!(imported.mesh.blocks[0].name, "muscle");
        assert_eq!(
            imported.mesh.element_set("muscle").unwrap().len(),
            reference.element_count()
        );
        assert_surface(&imported, "top", &reference.surfaces["z1"], [0.0, 0.0, 1.0]);
        // The node set of the physical surface: its nodes (all of them for tri6 faces).
        let top: Vec<i64> = imported
            .mesh
            .node_set("top")
            .unwrap()
            .iter()
            .map(|&i| imported.node_labels[i as usize])
            .collect();
        let mut expected: Vec<i64> = reference.node_sets["z1"]
            .iter()
            .map(|&i| node_label(i as usize))
            .collect();
        expected.sort();
        let mut top_sorted = top.clone();
        top_sorted.sort();
        assert_eq!(top_sorted, expected, "{shape}");
    }
}

#[test]
fn gmsh_tet10_mid_nodes_land_on_the_abaqus_edges() {
    let imported = read_mesh(fixture("tet10_gmsh_order.msh")).unwrap();
    let mesh = &imported.mesh;
    assert_eq!(imported.element_types, vec!["tet10"]);
    assert_eq!(mesh.blocks[0].name, "volume_1");
    let nodes = mesh.element_nodes(ElementRef::new(0, 0)).unwrap();
    let shape = mesh.blocks[0].shape;
    for (edge, &[a, b]) in shape.edges().iter().enumerate() {
        let mid = shape.mid_edge_node(edge).unwrap() as usize;
        let pa = mesh.nodes.position(nodes[a as usize] as usize);
        let pb = mesh.nodes.position(nodes[b as usize] as usize);
        let pm = mesh.nodes.position(nodes[mid] as usize);
        assert!((pm - 0.5 * (pa + pb)).norm() < 1e-15, "edge {edge}");
    }
    assert!((mesh.total_volume().unwrap() - 1.0 / 6.0).abs() < 1e-15);
}
