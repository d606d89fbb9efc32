//! Abaqus coverage beyond the mesh itself: `*ORIENTATION`/`*DISTRIBUTION` as fibers
//! (against hand-computed directions), 2-D elements (R3D3, S3, ...) as surfaces, and the
//! warnings for every keyword read over.

use musclefem_io::mesh_import::{parse_abaqus, summarize_warnings};
use musclefem_mesh::{ElementRef, Face};

/// Two unit hexes side by side along x; node label 1 + i + 3j + 6k at (i, j, k).
const TWO_HEXES: &str = "\
*NODE
1, 0, 0, 0
2, 1, 0, 0
3, 2, 0, 0
4, 0, 1, 0
5, 1, 1, 0
6, 2, 1, 0
7, 0, 0, 1
8, 1, 0, 1
9, 2, 0, 1
10, 0, 1, 1
11, 1, 1, 1
12, 2, 1, 1
*ELEMENT, TYPE=C3D8, ELSET=MUSCLE
1, 1, 2, 5, 4, 7, 8, 11, 10
2, 2, 3, 6, 5, 8, 9, 12, 11
";

fn assert_close(actual: nalgebra::Vector3<f64>, expected: [f64; 3]) {
    for d in 0..3 {
        assert!(
            (actual[d] - expected[d]).abs() < 1e-12,
            "{actual:?} != {expected:?}"
        );
    }
}

#[test]
fn an_orientation_from_a_distribution_gives_each_element_its_fiber() {
    let deck = format!(
        "{TWO_HEXES}\
*DISTRIBUTION TABLE, NAME=ORI_TABLE
COORD3D, COORD3D
*DISTRIBUTION, NAME=ORI_DIST, LOCATION=ELEMENT, TABLE=ORI_TABLE
, 1., 0., 0., 0., 1., 0.
1, 0., 2., 0., -1., 0., 0.
*ORIENTATION, NAME=ORI
ORI_DIST
3, 30.
*SOLID SECTION, ELSET=MUSCLE, MATERIAL=M, ORIENTATION=ORI
,
*MATERIAL, NAME=M
*DENSITY
1060.
*STEP
*STATIC
*BOUNDARY
1, 1, 3
*BOUNDARY
2, 1, 3
*END STEP
"
    );
    let imported = parse_abaqus(&deck, "ori.inp").unwrap();
    let fibers = &imported.mesh.blocks[0].fiber_direction;
    // Element 1: e1 = y, e2 = e3 × e1 = −x (b = −x, e3 = z); 30° about e3:
    // cos30 e1 + sin30 e2 = (−1/2, √3/2, 0).
    let (c, s) = (0.75f64.sqrt(), 0.5);
    assert_close(fibers[0], [-s, c, 0.0]);
    // Element 2 takes the default line: e1 = x, e2 = y → (√3/2, 1/2, 0).
    assert_close(fibers[1], [c, s, 0.0]);
    let source = imported.fiber_sources[0].as_deref().unwrap();
    assert!(
        source.starts_with("*ORIENTATION ORI (ori.inp:22)"),
        "{source}"
    );

    let lines = summarize_warnings(&imported.warnings);
    let boundary = lines.iter().find(|l| l.contains("*BOUNDARY")).unwrap();
    assert_eq!(
        boundary,
        "ori.inp:32: *BOUNDARY ignored: musclefem takes loads, boundary conditions and steps \
         from the scene file (and 1 more)"
    );
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("ori.inp:30: *STEP ignored"))
    );
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("ori.inp:25: *SOLID SECTION, ELSET=MUSCLE: material")),
        "{lines:?}"
    );
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("ori.inp:27: *MATERIAL ignored"))
    );
}

#[test]
fn an_orientation_by_points_follows_the_instance_rotation() {
    let deck = format!(
        "*PART, NAME=P\n{TWO_HEXES}\
*ORIENTATION, NAME=ORI, SYSTEM=RECTANGULAR
2., 1., 5., 1., 2., 1., 1., 1., 1.
*SOLID SECTION, ELSET=MUSCLE, MATERIAL=M, ORIENTATION=ORI
*END PART
*ASSEMBLY, NAME=A
*INSTANCE, NAME=I, PART=P
0., 0., 0.
0., 0., 0., 0., 0., 1., 90.
*END INSTANCE
*END ASSEMBLY
"
    );
    let imported = parse_abaqus(&deck, "points.inp").unwrap();
    // a − c = (1, 0, 4): e1 = (1, 0, 4)/√17; turned 90° about z: (0, 1, 4)/√17.
    let r = 17f64.sqrt();
    for fiber in &imported.mesh.blocks[0].fiber_direction {
        assert_close(*fiber, [0.0, 1.0 / r, 4.0 / r]);
    }
}

#[test]
fn unsupported_orientations_and_geometry_keywords_are_errors_at_their_line() {
    let cases = [
        (
            "*ORIENTATION, NAME=O, SYSTEM=CYLINDRICAL\n0,0,0,0,0,1\n",
            17,
            "SYSTEM=CYLINDRICAL is not supported",
        ),
        (
            "*ORIENTATION, NAME=O, DEFINITION=NODES\n1, 2, 3\n",
            17,
            "DEFINITION=NODES is not supported",
        ),
        (
            "*ORIENTATION, NAME=O\n1,0,0,2,0,0\n",
            18,
            "point b lies on the local 1-axis",
        ),
        (
            "*ORIENTATION, NAME=O\n1,0,0,0,1,0\n4, 10.\n",
            19,
            "local axis (1, 2 or 3)",
        ),
        (
            "*SOLID SECTION, ELSET=MUSCLE, MATERIAL=M, ORIENTATION=NONE\n",
            17,
            "no *ORIENTATION named 'NONE'",
        ),
        (
            "*TRANSFORM, NSET=N\n1,0,0,0,1,0\n",
            17,
            "*TRANSFORM is not supported",
        ),
        (
            "*NCOPY, OLD SET=A, CHANGE NUMBER=100\n",
            17,
            "*NCOPY is not supported",
        ),
    ];
    for (tail, line, words) in cases {
        let error = parse_abaqus(&format!("{TWO_HEXES}{tail}"), "bad.inp").unwrap_err();
        let text = error.to_string();
        assert!(text.starts_with(&format!("bad.inp:{line}: ")), "{text}");
        assert!(text.contains(words), "'{words}' missing in: {text}");
    }
    // A distribution without a default line that misses an element of the section.
    let deck = format!(
        "{TWO_HEXES}*DISTRIBUTION, NAME=D, LOCATION=ELEMENT\n1, 1,0,0, 0,1,0\n\
         *ORIENTATION, NAME=O\nD\n*SOLID SECTION, ELSET=MUSCLE, ORIENTATION=O\n"
    );
    let text = parse_abaqus(&deck, "d.inp").unwrap_err().to_string();
    assert!(text.starts_with("d.inp:21: element 2"), "{text}");
    assert!(text.contains("no default line"), "{text}");
}

/// One tet as meshio writes it (no `ELSET=` on the `*ELEMENT` lines, element labels
/// running on across blocks), with triangles on two of its faces and one elsewhere.
const MESHIO_TET: &str = "\
*HEADING
Abaqus DataFile Version 6.14
written by meshio v5.3.5
*NODE
1, 0.0, 0.0, 0.0
2, 1.0, 0.0, 0.0
3, 0.0, 1.0, 0.0
4, 0.0, 0.0, 1.0
5, 5.0, 5.0, 5.0
6, 6.0, 5.0, 5.0
7, 5.0, 6.0, 5.0
*ELEMENT, TYPE=C3D4
1, 1, 2, 3, 4
*ELEMENT, TYPE=R3D3
2, 1, 3, 2
3, 2, 3, 4
*ELEMENT, TYPE=S3
4, 5, 6, 7
*ELSET, ELSET=bottom
2
*ELSET, ELSET=everything
1, 2, 3
";

#[test]
fn two_d_elements_are_read_as_surfaces_and_node_sets() {
    let imported = parse_abaqus(MESHIO_TET, "meshio.inp").unwrap();
    let mesh = &imported.mesh;
    assert_eq!(mesh.blocks.len(), 1);
    assert_eq!(imported.element_types, ["C3D4"]);
    let tet = ElementRef::new(0, 0);
    // Triangle 2 (1, 3, 2) is face S1 (1, 2, 3) with the normal −z; triangle 3 is S3.
    assert_eq!(mesh.surface("bottom").unwrap(), &[Face::new(tet, 0)]);
    let area = mesh.face_area_vector(Face::new(tet, 0)).unwrap();
    assert!((area - nalgebra::Vector3::new(0.0, 0.0, -0.5)).norm() < 1e-15);
    assert_eq!(
        mesh.surface("R3D3").unwrap(),
        &[Face::new(tet, 0), Face::new(tet, 2)]
    );
    let oblique = mesh.face_area_vector(Face::new(tet, 2)).unwrap();
    assert!((oblique - nalgebra::Vector3::new(0.5, 0.5, 0.5)).norm() < 1e-15);
    assert_eq!(mesh.node_set("bottom").unwrap(), &[0, 1, 2]);
    assert_eq!(mesh.node_set("R3D3").unwrap(), &[0, 1, 2, 3]);
    // The S3 element lies on no tet face: a node set and a warning, no surface.
    assert!(mesh.surface("S3").is_err());
    assert_eq!(mesh.node_set("S3").unwrap(), &[4, 5, 6]);
    let warning = summarize_warnings(&imported.warnings).join("\n");
    assert!(
        warning.contains("meshio.inp:18: *ELEMENT, TYPE=S3: 2-D elements on no face"),
        "{warning}"
    );
    // A set of mixed elements: the tet in the element set, the triangles in the surface.
    assert_eq!(mesh.element_set("everything").unwrap(), &[tet]);
    assert_eq!(mesh.surface("everything").unwrap().len(), 2);
}

#[test]
fn a_partly_oriented_block_and_an_unused_orientation_are_warned() {
    let deck = format!(
        "{TWO_HEXES}\
*ELSET, ELSET=FIRST
1
*ORIENTATION, NAME=ALONG_Z
0., 0., 1., 1., 0., 0.
*ORIENTATION, NAME=SPARE
1., 0., 0., 0., 1., 0.
*SOLID SECTION, ELSET=FIRST, ORIENTATION=ALONG_Z
"
    );
    let imported = parse_abaqus(&deck, "part.inp").unwrap();
    let fibers = &imported.mesh.blocks[0].fiber_direction;
    assert_close(fibers[0], [0.0, 0.0, 1.0]);
    assert_close(fibers[1], [1.0, 0.0, 0.0]);
    let source = imported.fiber_sources[0].as_deref().unwrap();
    assert!(
        source.ends_with(
            "(1 of the 2 elements of block 'MUSCLE' are oriented: the others keep the fiber e_x)"
        ),
        "{source}"
    );
    let lines = summarize_warnings(&imported.warnings);
    assert!(
        lines.contains(
            &"part.inp:21: *ORIENTATION SPARE ignored: no *SOLID SECTION names it".into()
        ),
        "{lines:?}"
    );
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("part.inp:23: 1 of the 2 elements")),
        "{lines:?}"
    );
}
