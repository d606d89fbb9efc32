use nalgebra::Vector3;

use super::generate::{TetOrder, box_of_hexes, box_of_tets};
use super::*;

/// A 2×2×1 box of each shape, with the block renamed so that messages can be checked.
fn small(shape: ElementShape) -> Mesh {
    let mut mesh = match shape {
        ElementShape::Hex8 => box_of_hexes([1.0, 1.0, 0.5], [2, 2, 1]),
        ElementShape::Tet4 => box_of_tets([1.0, 1.0, 0.5], [2, 2, 1], TetOrder::Linear),
        ElementShape::Tet10 => box_of_tets([1.0, 1.0, 0.5], [2, 2, 1], TetOrder::Quadratic),
    }
    .unwrap();
    mesh.blocks[0].name = "muscle".to_string();
    mesh
}

#[test]
fn lookups_name_the_missing_set_and_the_known_ones() {
    let mesh = small(ElementShape::Hex8);
    assert_eq!(mesh.node_set("x0").unwrap().len(), 6);
    let e = mesh.node_set("x2").unwrap_err();
    let MeshError::UnknownName { kind, name, known } = &e else {
        panic!("{e}")
    };
    assert_eq!((*kind, name.as_str()), (NameKind::NodeSet, "x2"));
    assert_eq!(known, &["x0", "x1", "y0", "y1", "z0", "z1"]);
    assert!(e.to_string().contains("node set named 'x2'"), "{e}");
    let e = mesh.element_set("tendon").unwrap_err();
    assert!(e.to_string().contains("known: 'all'"), "{e}");
    let e = mesh.surface("inner").unwrap_err();
    assert!(e.to_string().contains("'outer'"), "{e}");
    assert_eq!(mesh.block_by_name("muscle").unwrap().0, 0);
    let e = mesh.block_by_name("bone").unwrap_err();
    assert!(
        e.to_string()
            .contains("no element block named 'bone'; known: 'muscle'"),
        "{e}"
    );
}

#[test]
fn element_and_face_lookups_check_their_ids() {
    let mesh = small(ElementShape::Tet4);
    let e = mesh.element_nodes(ElementRef::new(1, 0)).unwrap_err();
    assert_eq!(e, MeshError::BlockOutOfRange { block: 1, count: 1 });
    let e = mesh.element_volume(ElementRef::new(0, 24)).unwrap_err();
    assert!(
        e.to_string()
            .contains("'muscle' has no element 24: it has 24"),
        "{e}"
    );
    let e = mesh
        .face_nodes(Face::new(ElementRef::new(0, 3), 4))
        .unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::FaceOutOfRange {
                face: 4,
                element: 3,
                ..
            }
        ),
        "{e}"
    );
    // Element 0 is the tet (0,0,0), (1,0,0), (1,1,0), (1,1,1) of the first cell; face S1
    // is its corners 1-3-2 (0-based 0, 2, 1), on z = 0, pointing down.
    let face = Face::new(ElementRef::new(0, 0), 0);
    let ids = face.nodes(&mesh).unwrap();
    let tet = mesh.element_nodes(face.element).unwrap();
    assert_eq!(&*ids, &[tet[0], tet[2], tet[1]]);
    let a = mesh.face_area_vector(face).unwrap();
    assert!((a - Vector3::new(0.0, 0.0, -0.125)).norm() < 1e-15, "{a}");
}

#[test]
fn validate_rejects_an_inverted_element_naming_block_and_element() {
    for shape in ElementShape::ALL {
        let mut mesh = small(shape);
        let n = shape.nodes_per_element();
        mesh.blocks[0].connectivity.swap(3 * n + 1, 3 * n + 2);
        let e = mesh.validate().unwrap_err();
        let MeshError::InvertedElement {
            block,
            element,
            min_jacobian_volume,
            ..
        } = &e
        else {
            panic!("{shape}: {e}")
        };
        assert_eq!((block.as_str(), *element), ("muscle", 3), "{shape}");
        assert!(*min_jacobian_volume < 0.0, "{shape}: {min_jacobian_volume}");
        assert!(
            e.to_string().contains("element block 'muscle', element 3"),
            "{e}"
        );
    }
}

#[test]
fn validate_rejects_a_flat_element() {
    let mut mesh = small(ElementShape::Hex8);
    // Move the top corners of element 0 into its bottom face.
    for local in 4..8 {
        let id = mesh.blocks[0].element_nodes(0)[local] as usize;
        let p = mesh.nodes.position(id);
        mesh.nodes.set_position(id, Vector3::new(p.x, p.y, 0.0));
    }
    let e = mesh.validate().unwrap_err();
    assert!(
        matches!(e, MeshError::InvertedElement { element: 0, .. }),
        "{e}"
    );
}

#[test]
fn validate_rejects_broken_connectivity() {
    let mut mesh = small(ElementShape::Tet10);
    let count = mesh.node_count() as u32;
    mesh.blocks[0].connectivity[5 * 10 + 7] = count;
    let e = mesh.validate().unwrap_err();
    let expected = MeshError::NodeOutOfRange {
        block: "muscle".into(),
        element: 5,
        local: 7,
        node: count,
        node_count: count as usize,
    };
    assert_eq!(e, expected);
    assert_eq!(mesh.total_volume().unwrap_err(), expected);
    assert_eq!(mesh.node_elements().unwrap_err(), expected);

    let mut mesh = small(ElementShape::Hex8);
    let first = mesh.blocks[0].connectivity[8];
    mesh.blocks[0].connectivity[8 + 6] = first;
    let e = mesh.validate().unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::RepeatedNode {
                element: 1,
                first: 0,
                second: 6,
                ..
            }
        ),
        "{e}"
    );

    let mut mesh = small(ElementShape::Hex8);
    mesh.blocks[0].connectivity.pop();
    assert!(matches!(
        mesh.validate().unwrap_err(),
        MeshError::ConnectivityLength { len: 31, .. }
    ));
}

#[test]
fn validate_rejects_bad_nodes_fibers_and_names() {
    let mut mesh = small(ElementShape::Tet4);
    mesh.nodes.z.pop();
    assert!(matches!(
        mesh.validate().unwrap_err(),
        MeshError::NodeArrayLengths { .. }
    ));

    let mut mesh = small(ElementShape::Tet4);
    mesh.nodes.y[4] = f64::NAN;
    assert!(matches!(
        mesh.validate().unwrap_err(),
        MeshError::NonFiniteNode { node: 4, .. }
    ));

    let mut mesh = small(ElementShape::Tet4);
    mesh.blocks[0].fiber_direction.pop();
    assert!(matches!(
        mesh.validate().unwrap_err(),
        MeshError::FiberCount {
            elements: 24,
            fibers: 23,
            ..
        }
    ));

    let mut mesh = small(ElementShape::Tet4);
    mesh.blocks[0].fiber_direction[9] = Vector3::zeros();
    assert!(matches!(
        mesh.validate().unwrap_err(),
        MeshError::InvalidFiber { element: 9, .. }
    ));

    let mut mesh = small(ElementShape::Tet4);
    let copy = mesh.blocks[0].clone();
    mesh.blocks.push(copy);
    assert!(matches!(
        mesh.validate().unwrap_err(),
        MeshError::DuplicateBlockName { .. }
    ));
}

#[test]
fn validate_rejects_sets_that_refer_to_nothing() {
    let mut mesh = small(ElementShape::Hex8);
    mesh.node_sets.insert("tip".into(), vec![0, 99]);
    let e = mesh.validate().unwrap_err();
    assert_eq!(
        e.to_string(),
        "node set 'tip': there is no node 99: the mesh has 18 nodes"
    );

    let mut mesh = small(ElementShape::Hex8);
    mesh.element_sets
        .get_mut("all")
        .unwrap()
        .push(ElementRef::new(0, 4));
    let e = mesh.validate().unwrap_err();
    assert!(
        e.to_string()
            .starts_with("element set 'all': element block 'muscle' has no element 4"),
        "{e}"
    );

    let mut mesh = small(ElementShape::Hex8);
    mesh.surfaces
        .get_mut("z1")
        .unwrap()
        .push(Face::new(ElementRef::new(0, 0), 6));
    let e = mesh.validate().unwrap_err();
    assert!(
        e.to_string()
            .starts_with("surface 'z1': element block 'muscle', element 0: a hex8 has no face 6"),
        "{e}"
    );
}

#[test]
fn blocks_of_different_shapes_add_up() {
    // A hex block and a tet block side by side, sharing no nodes.
    let hexes = box_of_hexes([1.0, 2.0, 3.0], [1, 2, 1]).unwrap();
    let tets = box_of_tets([0.5, 0.5, 0.5], [1, 1, 1], TetOrder::Quadratic).unwrap();
    let mut mesh = hexes.clone();
    let offset = mesh.node_count() as u32;
    for i in 0..tets.node_count() {
        mesh.nodes
            .push(tets.nodes.position(i) + Vector3::new(5.0, 0.0, 0.0));
    }
    let mut block = tets.blocks[0].clone();
    block.connectivity.iter_mut().for_each(|id| *id += offset);
    mesh.blocks.push(block);
    mesh.validate().unwrap();
    assert_eq!(mesh.element_count(), 2 + 6);
    let total = mesh.total_volume().unwrap();
    assert!((total - (6.0 + 0.125)).abs() < 1e-12 * 6.125, "{total}");
    assert_eq!(mesh.block(1).unwrap().shape, ElementShape::Tet10);
    assert_eq!(mesh.boundary_faces().unwrap().len(), 10 + 12);
}
