//! Malformed, truncated and inconsistent mesh files: each gives an error that names the
//! file, the line and the cause — never a panic.

use std::path::PathBuf;

use musclefem_io::mesh_import::{ImportError, parse_abaqus, parse_gmsh, read_mesh, read_mesh_with};

/// A valid one-tet file; cases below edit it. Lines: 1 *NODE, 2-5 nodes, 6 *ELEMENT, 7.
const TET: &str = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n\
                   *ELEMENT, TYPE=C3D4, ELSET=E\n1, 1, 2, 3, 4\n";

fn tet_with(line: usize, replacement: &str) -> String {
    let mut lines: Vec<&str> = TET.lines().collect();
    lines[line - 1] = replacement;
    lines.join("\n") + "\n"
}

/// Abaqus cases: (what, text, line, words the message must hold).
fn abaqus_cases() -> Vec<(&'static str, String, usize, Vec<&'static str>)> {
    let part = "*PART, NAME=P\n*NODE\n1,0,0,0\n2,1,0,0\n3,0,1,0\n4,0,0,1\n\
                *ELEMENT,TYPE=C3D4\n1,1,2,3,4\n*END PART\n*ASSEMBLY,NAME=A\n\
                *INSTANCE,NAME=I,PART=P\n*END INSTANCE\n";
    vec![
        (
            "truncated node line",
            tet_with(3, "2, 1, 0"),
            3,
            vec!["*NODE", "3 coordinates", "found 3 fields"],
        ),
        (
            "non-numeric coordinate",
            tet_with(3, "2, 1, x0, 0"),
            3,
            vec!["node 2", "'x0' is not a number"],
        ),
        (
            "NaN coordinate",
            tet_with(4, "3, 0, NaN, 0"),
            4,
            vec!["node 3", "'NaN' is not finite"],
        ),
        (
            "non-numeric node label",
            tet_with(2, "one, 0, 0, 0"),
            2,
            vec!["node label 'one'"],
        ),
        (
            "unknown node label",
            tet_with(7, "1, 1, 2, 3, 99"),
            7,
            vec!["element 1 (C3D4)", "node 99 is not defined"],
        ),
        (
            "duplicate node label",
            tet_with(3, "1, 1, 0, 0"),
            3,
            vec!["node 1 is defined twice", "first at t.inp:2"],
        ),
        (
            "duplicate element label",
            format!("{TET}1, 2, 1, 3, 4\n"),
            8,
            vec!["element 1 is defined twice"],
        ),
        (
            "wrong node count",
            tet_with(7, "1, 1, 2, 3"),
            7,
            vec!["C3D4", "element 1", "4 nodes, found 3"],
        ),
        (
            "unknown element type",
            tet_with(6, "*ELEMENT, TYPE=C3D20"),
            6,
            vec!["C3D20 is not supported", "C3D4, C3D4H, C3D8"],
        ),
        (
            "unknown keyword",
            tet_with(1, "*NDOE"),
            1,
            vec!["unknown keyword *NDOE", "did you mean *NODE?"],
        ),
        (
            "refused mesh keyword",
            format!("{TET}*NGEN, NSET=A\n1, 4\n"),
            8,
            vec!["*NGEN is not supported"],
        ),
        (
            "GENERATE with step 0",
            format!("{TET}*NSET, NSET=A, GENERATE\n1, 4, 0\n"),
            9,
            vec!["NSET=A", "GENERATE 1, 4, 0", "step >= 1"],
        ),
        (
            "GENERATE over a missing label",
            format!("{TET}*NSET, NSET=A, GENERATE\n1, 9\n"),
            9,
            vec!["node set 'A'", "node 5 is not defined"],
        ),
        (
            "surface face S7 on a tet",
            format!("{TET}*SURFACE, NAME=S\nE, S7\n"),
            9,
            vec!["surface 'S'", "face S7", "element 1", "S1..S4"],
        ),
        (
            "node-based surface",
            format!("{TET}*SURFACE, NAME=S, TYPE=NODE\n1, 1.\n"),
            8,
            vec!["TYPE=NODE is not supported"],
        ),
        (
            "unknown set name",
            format!("{TET}*NSET, NSET=A\nNOSUCH\n"),
            9,
            vec!["no node set named 'NOSUCH'"],
        ),
        (
            "two instances",
            format!("{part}*INSTANCE,NAME=J,PART=P\n"),
            13,
            vec!["second *INSTANCE 'J'", "only one part and one instance"],
        ),
        (
            "two parts",
            "*PART, NAME=P\n*END PART\n*PART, NAME=Q\n".into(),
            3,
            vec!["second *PART 'Q'"],
        ),
        (
            "part never instanced",
            "*PART, NAME=P\n*NODE\n1,0,0,0\n*END PART\n".into(),
            1,
            vec!["'P' is never instanced"],
        ),
        (
            "inverted element",
            tet_with(7, "1, 2, 1, 3, 4"),
            7,
            vec!["element 1 (C3D4)", "inverted or degenerate"],
        ),
        (
            "data before any keyword",
            "1, 0, 0, 0\n".into(),
            1,
            vec!["data line outside any keyword"],
        ),
        (
            "*INCLUDE from memory",
            format!("*INCLUDE, INPUT=x.inp\n{TET}"),
            1,
            vec!["*INCLUDE, INPUT=x.inp", "read_abaqus"],
        ),
        (
            "unknown parameter",
            tet_with(6, "*ELEMENT, TYPE=C3D4, FOO=1"),
            6,
            vec!["parameter FOO is not supported"],
        ),
    ]
}

fn check(error: &ImportError, file: &str, line: usize, words: &[&str], what: &str) {
    let text = error.to_string();
    assert!(
        text.starts_with(&format!("{file}:{line}: ")),
        "{what}: {text}"
    );
    assert_eq!(error.line(), Some(line), "{what}: {text}");
    for word in words {
        assert!(text.contains(word), "{what}: '{word}' missing in: {text}");
    }
}

#[test]
fn malformed_abaqus_inputs_name_file_line_and_cause() {
    let cases = abaqus_cases();
    assert!(cases.len() >= 15);
    for (what, text, line, words) in &cases {
        let error = parse_abaqus(text, "t.inp").expect_err(what);
        check(&error, "t.inp", *line, words, what);
    }
}

#[test]
fn empty_file_says_it_has_no_elements() {
    let error = parse_abaqus("", "empty.inp").unwrap_err();
    assert_eq!(
        error.to_string(),
        "empty.inp: the file defines no volume element (supported: hex8, tet4, tet10)"
    );
    let error = parse_abaqus("** only a comment\n*NODE\n1, 0, 0, 0\n", "nodes.inp").unwrap_err();
    assert!(error.to_string().contains("no volume element"), "{error}");
}

/// A scratch directory of this test process.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "musclefem-mesh-import-{}-{name}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn file_errors_name_the_file() {
    let dir = scratch("files");
    // Missing *INCLUDE target: the including file and line, and the missing path.
    let main = dir.join("main.inp");
    std::fs::write(&main, format!("{TET}*INCLUDE, INPUT=missing.inp\n")).unwrap();
    let error = read_mesh(&main).unwrap_err();
    check(
        &error,
        &main.display().to_string(),
        8,
        &["*INCLUDE: cannot read", "missing.inp"],
        "include",
    );
    // An error inside an included file names that file and its own line.
    std::fs::write(
        dir.join("bad.inp"),
        "** header\n*ELEMENT, TYPE=C3D4\n1, 1, 2\n",
    )
    .unwrap();
    std::fs::write(&main, format!("{TET}*INCLUDE, INPUT=bad.inp\n")).unwrap();
    let error = read_mesh(&main).unwrap_err();
    check(
        &error,
        &dir.join("bad.inp").display().to_string(),
        3,
        &["4 nodes, found 2"],
        "included",
    );
    // Binary garbage.
    let garbage = dir.join("garbage.inp");
    std::fs::write(&garbage, b"*NODE\n\xff\xfe\x00\x13binary").unwrap();
    let error = read_mesh(&garbage).unwrap_err();
    check(
        &error,
        &garbage.display().to_string(),
        2,
        &["not a text file", "UTF-8"],
        "garbage",
    );
    // A file that does not exist.
    let error = read_mesh(dir.join("nowhere.msh")).unwrap_err();
    assert!(matches!(error, ImportError::Io { .. }), "{error}");
    assert!(error.to_string().contains("nowhere.msh"), "{error}");
    // Binary Gmsh 2.2 (4.1 binary is read: tests/mesh_import_gmsh_versions.rs).
    let binary = dir.join("binary.msh");
    std::fs::write(
        &binary,
        b"$MeshFormat\n2.2 1 8\n\x01\x00\x00\x00\xff\xff\n$EndMeshFormat\n",
    )
    .unwrap();
    let error = read_mesh(&binary).unwrap_err();
    check(
        &error,
        &binary.display().to_string(),
        2,
        &["binary 2.2 files are not supported"],
        "binary msh",
    );
    let error = read_mesh(dir.join("mesh.vtu")).unwrap_err();
    assert!(error.to_string().contains("unknown mesh format"), "{error}");
    std::fs::remove_dir_all(&dir).unwrap();
}

const MSH: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n\
                   0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n";

fn msh_with(line: usize, replacement: &str) -> String {
    let mut lines: Vec<&str> = MSH.lines().collect();
    lines[line - 1] = replacement;
    lines.join("\n") + "\n"
}

#[test]
fn malformed_gmsh_inputs_name_file_line_and_cause() {
    assert!(parse_gmsh(MSH, "ok.msh").is_ok());
    let cases: Vec<(&str, String, usize, Vec<&str>)> = vec![
        (
            "old version",
            msh_with(2, "2.0 0 8"),
            2,
            vec!["version 2.0 is not supported"],
        ),
        ("binary", msh_with(2, "4.1 1 8"), 2, vec!["binary"]),
        (
            "truncated",
            MSH.lines().take(12).collect::<Vec<_>>().join("\n"),
            13,
            vec!["unexpected end of file", "node coordinates"],
        ),
        (
            "unknown node",
            msh_with(19, "1 1 2 3 99"),
            19,
            vec!["element 1 (tet4)", "node 99 is not defined"],
        ),
        (
            "prism",
            msh_with(18, "3 1 6 1"),
            18,
            vec!["element type 6", "supported: 4 tet4, 5 hex8, 11 tet10"],
        ),
        (
            "wrong node count",
            msh_with(19, "1 1 2 3"),
            19,
            vec!["element 1 (tet4)", "expected 4 node tags, found 3"],
        ),
        (
            "NaN coordinate",
            msh_with(12, "1 nan 0"),
            12,
            vec!["node 2", "not finite"],
        ),
        (
            "non-numeric",
            msh_with(12, "1 zero 0"),
            12,
            vec!["node 2", "expected 3 numbers"],
        ),
        (
            "count mismatch",
            msh_with(5, "1 5 1 4"),
            5,
            vec!["announces 5 nodes", "hold 4"],
        ),
        (
            "no format",
            "$Nodes\n".into(),
            1,
            vec!["expected $MeshFormat first"],
        ),
        ("empty", String::new(), 1, vec!["empty file"]),
        (
            "missing end",
            msh_with(15, "$Foo"),
            15,
            vec!["expected $EndNodes", "$Foo"],
        ),
    ];
    for (what, text, line, words) in &cases {
        let error = parse_gmsh(text, "m.msh").expect_err(what);
        check(&error, "m.msh", *line, words, what);
    }
}

/// `*INCLUDE, INPUT=/etc/passwd` used to quote the file's first line in the error: an
/// include outside the deck's folder is refused before it is read, naming both files;
/// one in the folder or below is read; `read_mesh_with(.., true)` lifts the limit.
#[test]
fn includes_stay_in_the_decks_folder_unless_allowed() {
    let dir = scratch("include-outside");
    let deck_dir = dir.join("deck");
    std::fs::create_dir_all(deck_dir.join("parts")).unwrap();
    std::fs::write(dir.join("secret.inp"), "root:x:0:0:root:/root:/bin/bash\n").unwrap();
    std::fs::write(deck_dir.join("parts/tet.inp"), TET).unwrap();
    std::fs::write(
        deck_dir.join("inside.inp"),
        "*INCLUDE, INPUT=parts/tet.inp\n",
    )
    .unwrap();
    std::fs::write(
        deck_dir.join("outside.inp"),
        "*INCLUDE, INPUT=../secret.inp\n",
    )
    .unwrap();
    let inside = read_mesh(deck_dir.join("inside.inp")).unwrap();
    assert_eq!(inside.mesh.element_count(), 1);
    let refused = read_mesh(deck_dir.join("outside.inp"))
        .unwrap_err()
        .to_string();
    assert!(
        refused.contains("outside.inp:1:") && refused.contains("lies outside the folder"),
        "{refused}"
    );
    assert!(
        !refused.contains("root:x"),
        "the error quotes the file: {refused}"
    );
    // Allowed, it is read (and is no mesh).
    let read = read_mesh_with(deck_dir.join("outside.inp"), true)
        .unwrap_err()
        .to_string();
    assert!(read.contains("secret.inp:1:"), "{read}");
    std::fs::remove_dir_all(&dir).unwrap();
}
