//! Every way the input can be wrong gives its own error, naming the region, block,
//! element or face concerned.

mod common;

use common::{Cells, box_mesh};
use musclefem_fibers::{
    BoundaryRegion, FiberError, FlowBoundary, FlowSettings, MissingEnd, Side, compute_fibers,
};
use musclefem_mesh::{ElementBlock, ElementShape, Mesh};
use musclefem_mesh::{ElementRef, Face, MeshError};
use nalgebra::Vector3;

fn tube(cells: Cells) -> Mesh {
    box_mesh(cells, [1.0, 0.3, 0.2], [5, 2, 2])
}

fn run(mesh: &Mesh, boundary: &FlowBoundary) -> FiberError {
    compute_fibers(mesh, boundary, &FlowSettings::default()).expect_err("an error")
}

#[test]
fn empty_inlet_or_outlet() {
    let mesh = tube(Cells::Hex8);
    let x1 = BoundaryRegion::surface(&mesh, "x1").unwrap();
    let no_faces = BoundaryRegion::Faces {
        name: "origin".into(),
        faces: vec![],
    };
    let err = run(&mesh, &FlowBoundary::new(no_faces, x1.clone()));
    assert_eq!(
        err,
        FiberError::EmptyRegion {
            side: Side::Inlet,
            name: "origin".into()
        }
    );
    assert_eq!(err.to_string(), "inlet 'origin' is empty");
    let no_nodes = BoundaryRegion::Nodes {
        name: "insertion".into(),
        nodes: vec![],
    };
    let x0 = BoundaryRegion::surface(&mesh, "x0").unwrap();
    let err = run(&mesh, &FlowBoundary::new(x0.clone(), no_nodes));
    assert_eq!(err.to_string(), "outlet 'insertion' is empty");
    let err = run(
        &mesh,
        &FlowBoundary {
            inlet: vec![x0],
            outlet: vec![],
        },
    );
    assert_eq!(err, FiberError::NoRegion { side: Side::Outlet });
}

#[test]
fn a_set_without_boundary_face() {
    let mesh = tube(Cells::Tet4);
    let x1 = BoundaryRegion::surface(&mesh, "x1").unwrap();
    // Three corners of the box: no face has all its corners among them.
    let corners = BoundaryRegion::Nodes {
        name: "corners".into(),
        nodes: vec![0, 5, 17],
    };
    let err = run(&mesh, &FlowBoundary::new(corners, x1.clone()));
    assert_eq!(
        err,
        FiberError::NoBoundaryFace {
            side: Side::Inlet,
            name: "corners".into()
        }
    );
    assert_eq!(
        err.to_string(),
        "inlet 'corners' has no face on the boundary of the mesh"
    );

    // A surface with a face inside the mesh: tet 0's faces are not all on the boundary.
    let inner = (0..4)
        .map(|f| Face::new(ElementRef::new(0, 0), f))
        .collect();
    let inner = BoundaryRegion::Faces {
        name: "inner".into(),
        faces: inner,
    };
    let err = run(&mesh, &FlowBoundary::new(inner, x1.clone()));
    let FiberError::InteriorFace { side, name, face } = &err else {
        panic!("{err}");
    };
    assert_eq!(
        (*side, name.as_str(), face.block.as_str(), face.element),
        (Side::Inlet, "inner", "tets", 0)
    );
    assert!(err.to_string().contains("is not on the boundary"), "{err}");

    // A face of an element that does not exist.
    let missing = BoundaryRegion::Faces {
        name: "ghost".into(),
        faces: vec![Face::new(ElementRef::new(0, 100_000), 0)],
    };
    let err = run(&mesh, &FlowBoundary::new(missing, x1));
    assert!(
        matches!(&err, FiberError::InvalidRegion { name, error, .. } if name == "ghost" && matches!(**error, MeshError::ElementOutOfRange { .. })),
        "{err}"
    );
}

#[test]
fn inlet_and_outlet_sharing_a_face() {
    let mesh = tube(Cells::Tet10);
    let boundary = FlowBoundary::from_names(&mesh, &["x0"], &["y0", "outer"]).unwrap();
    let err = run(&mesh, &boundary);
    let FiberError::InletOutletOverlap {
        inlet,
        outlet,
        face,
    } = &err
    else {
        panic!("{err}");
    };
    assert_eq!((inlet.as_str(), outlet.as_str()), ("x0", "outer"));
    assert!(mesh.surface("x0").unwrap().contains(&Face::new(
        ElementRef::new(0, face.element as u32),
        face.face
    )));
    assert!(
        err.to_string().starts_with(
            "inlet 'x0' and outlet 'outer' share the boundary face element block 'tets'"
        ),
        "{err}"
    );
}

/// The tube and, beside it, a second block of hexes that shares no face with it.
fn tube_and_island() -> Mesh {
    let mut mesh = tube(Cells::Hex8);
    let island = box_mesh(Cells::Hex8, [0.2, 0.2, 0.2], [1, 2, 1]);
    let offset = mesh.nodes.len() as u32;
    for i in 0..island.nodes.len() {
        mesh.nodes
            .push(island.nodes.position(i) + Vector3::new(0.0, 1.0, 0.0));
    }
    let connectivity = island.blocks[0]
        .connectivity
        .iter()
        .map(|id| id + offset)
        .collect();
    mesh.blocks
        .push(ElementBlock::new("island", ElementShape::Hex8, connectivity).unwrap());
    let island_x0 = island.node_sets["x0"]
        .iter()
        .map(|id| id + offset)
        .collect();
    mesh.node_sets.insert("island_x0".into(), island_x0);
    mesh
}

#[test]
fn disconnected_parts_are_named() {
    let mesh = tube_and_island();
    let boundary = FlowBoundary::from_names(&mesh, &["x0"], &["x1"]).unwrap();
    let err = run(&mesh, &boundary);
    assert_eq!(
        err,
        FiberError::DisconnectedPart {
            block: "island".into(),
            element: 0,
            cells: 2,
            missing: MissingEnd::Both
        }
    );
    assert!(
        err.to_string().contains(
            "element block 'island', element 0 (2 elements) has neither an inlet nor an outlet face"
        ),
        "{err}"
    );
    // With an inlet on the island, it still lacks an outlet.
    let boundary = FlowBoundary::from_names(&mesh, &["x0", "island_x0"], &["x1"]).unwrap();
    let err = run(&mesh, &boundary);
    assert!(
        matches!(
            err,
            FiberError::DisconnectedPart {
                missing: MissingEnd::Outlet,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn inverted_elements_are_named() {
    let mut mesh = tube(Cells::Tet4);
    let nodes = &mut mesh.blocks[0].connectivity[4 * 5..4 * 6];
    nodes.swap(0, 1);
    let boundary = FlowBoundary::from_names(&mesh, &["x0"], &["x1"]).unwrap();
    let err = run(&mesh, &boundary);
    let FiberError::InvertedElement {
        block,
        element,
        volume,
        ..
    } = &err
    else {
        panic!("{err}");
    };
    assert_eq!((block.as_str(), *element), ("tets", 5));
    assert!(*volume < 0.0);
    assert!(
        err.to_string()
            .starts_with("element block 'tets', element 5 (tet4) is inverted"),
        "{err}"
    );

    let mut mesh = tube(Cells::Hex8);
    let first_hex: Vec<u32> = mesh.blocks[0].connectivity[..8].to_vec();
    // Upside down: the top four nodes first.
    let flipped = [4, 5, 6, 7, 0, 1, 2, 3].map(|l| first_hex[l]);
    mesh.blocks[0].connectivity[..8].copy_from_slice(&flipped);
    let err = run(&mesh, &boundary);
    assert!(
        matches!(&err, FiberError::InvertedElement { element: 0, .. }),
        "{err}"
    );
}

#[test]
fn unknown_names_and_bad_settings() {
    let mesh = tube(Cells::Hex8);
    let err = FlowBoundary::from_names(&mesh, &["origin"], &["x1"]).unwrap_err();
    assert!(
        matches!(&err, FiberError::UnknownRegion { name, .. } if name == "origin"),
        "{err}"
    );
    let boundary = FlowBoundary::from_names(&mesh, &["x0"], &["x1"]).unwrap();
    let settings = FlowSettings {
        tolerance: 2.0,
        ..FlowSettings::default()
    };
    let err = compute_fibers(&mesh, &boundary, &settings).unwrap_err();
    assert!(matches!(err, FiberError::InvalidSettings { .. }), "{err}");
    // A solve that cannot reach its tolerance in the allowed sweeps says so.
    let mut distorted = tube(Cells::Tet4);
    musclefem_mesh::generate::distort(&mut distorted, 0.3, 3).unwrap();
    let settings = FlowSettings {
        max_correction_sweeps: 2,
        ..FlowSettings::default()
    };
    let boundary = FlowBoundary::from_names(&distorted, &["x0"], &["x1"]).unwrap();
    let err = compute_fibers(&distorted, &boundary, &settings).unwrap_err();
    assert!(
        matches!(err, FiberError::NotConverged { sweeps: 2, .. }),
        "{err}"
    );
}
