//! Readers of triangle files: STL (ASCII and binary) and Wavefront OBJ. Coordinates are
//! taken as they are (the caller's length unit must be metres).

use std::collections::HashMap;
use std::path::Path;

use nalgebra::Vector3;

use crate::error::ContactError;

type Triangles = (Vec<Vector3<f64>>, Vec<[u32; 3]>);

fn parse_error(path: &Path, line: usize, reason: impl Into<String>) -> ContactError {
    ContactError::Parse {
        path: path.to_path_buf(),
        line,
        reason: reason.into(),
    }
}

fn read_bytes(path: &Path) -> Result<Vec<u8>, ContactError> {
    std::fs::read(path).map_err(|source| ContactError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Vertices merged by their exact bit patterns.
#[derive(Default)]
struct Welder {
    index: HashMap<[u64; 3], u32>,
    vertices: Vec<Vector3<f64>>,
}

impl Welder {
    fn add(&mut self, p: Vector3<f64>) -> u32 {
        let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        let vertices = &mut self.vertices;
        *self.index.entry(key).or_insert_with(|| {
            vertices.push(p);
            (vertices.len() - 1) as u32
        })
    }
}

/// An STL file: binary when its length is 84 + 50 n with n the count at byte 80, ASCII
/// otherwise.
pub(super) fn stl(path: &Path) -> Result<Triangles, ContactError> {
    let bytes = read_bytes(path)?;
    if bytes.len() >= 84 {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if bytes.len() == 84 + 50 * count {
            return Ok(binary_stl(&bytes[84..], count));
        }
    }
    let text = std::str::from_utf8(&bytes).map_err(|_| {
        parse_error(
            path,
            1,
            "neither a binary STL (its length does not match the triangle count) nor ASCII text",
        )
    })?;
    ascii_stl(path, text)
}

fn binary_stl(records: &[u8], count: usize) -> Triangles {
    let mut welder = Welder::default();
    let mut triangles = Vec::with_capacity(count);
    for record in records.chunks_exact(50).take(count) {
        let float = |i: usize| {
            let at = 12 + 4 * i;
            f32::from_le_bytes([record[at], record[at + 1], record[at + 2], record[at + 3]]) as f64
        };
        let mut tri = [0u32; 3];
        for (k, slot) in tri.iter_mut().enumerate() {
            *slot = welder.add(Vector3::new(
                float(3 * k),
                float(3 * k + 1),
                float(3 * k + 2),
            ));
        }
        triangles.push(tri);
    }
    (welder.vertices, triangles)
}

fn ascii_stl(path: &Path, text: &str) -> Result<Triangles, ContactError> {
    let mut welder = Welder::default();
    let mut triangles = Vec::new();
    let mut corners: Vec<u32> = Vec::with_capacity(3);
    let mut in_facet = false;
    let mut last = 0;
    for (number, line) in text.lines().enumerate() {
        let number = number + 1;
        last = number;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("facet") => {
                if in_facet {
                    return Err(parse_error(path, number, "'facet' inside a facet"));
                }
                in_facet = true;
                corners.clear();
            }
            Some("vertex") => {
                if !in_facet {
                    return Err(parse_error(path, number, "'vertex' outside a facet"));
                }
                let mut p = [0.0; 3];
                for x in &mut p {
                    let word = words
                        .next()
                        .ok_or_else(|| parse_error(path, number, "a vertex needs 3 coordinates"))?;
                    *x = word.parse().map_err(|_| {
                        parse_error(path, number, format!("'{word}' is not a number"))
                    })?;
                }
                if corners.len() == 3 {
                    return Err(parse_error(
                        path,
                        number,
                        "a facet has more than 3 vertices",
                    ));
                }
                corners.push(welder.add(Vector3::from(p)));
            }
            Some("endfacet") => {
                if corners.len() != 3 {
                    return Err(parse_error(
                        path,
                        number,
                        format!("a facet has {} vertices instead of 3", corners.len()),
                    ));
                }
                triangles.push([corners[0], corners[1], corners[2]]);
                in_facet = false;
            }
            Some("solid" | "endsolid" | "outer" | "endloop") | None => {}
            Some(word) => {
                return Err(parse_error(path, number, format!("unexpected '{word}'")));
            }
        }
    }
    if in_facet {
        return Err(parse_error(path, last, "the file ends inside a facet"));
    }
    Ok((welder.vertices, triangles))
}

/// The surface of an OBJ file: its vertices and triangles and, where the file gives
/// every vertex one normal, those normals (see [`obj`]).
pub(super) struct ObjSurface {
    pub vertices: Vec<Vector3<f64>>,
    pub triangles: Vec<[u32; 3]>,
    /// One unit normal per vertex, or `None`.
    pub normals: Option<Vec<Vector3<f64>>>,
}

/// How far from 1 the length of a normal may be to be kept as written; a longer or
/// shorter one is scaled to unit length.
const UNIT_TOLERANCE: f64 = 1e-6;

/// A Wavefront OBJ file: `v x y z` vertices, `vn x y z` normals and `f` faces (indices
/// 1-based, negative from the end; corners `v`, `v/vt`, `v//vn` or `v/vt/vn`); other
/// lines are ignored. Polygons are fanned into triangles from their first corner.
///
/// The normals are the surface's vertex normals when every corner of every face names
/// one, every vertex is a corner of some face, and all the corners at one vertex name
/// the same normal (the same three numbers); otherwise (no `vn`, a corner without one,
/// a vertex with two normals as at a crease of a flat-shaded export) there are none and
/// the contact averages the facets' normals. A normal within 10⁻⁶ of unit length is kept
/// as written, any other scaled to unit length. A corner naming a normal that does not
/// exist, or a normal of zero or non-finite length, is an error at its line.
pub(super) fn obj(path: &Path) -> Result<ObjSurface, ContactError> {
    let bytes = read_bytes(path)?;
    let text = std::str::from_utf8(&bytes).map_err(|_| parse_error(path, 1, "not UTF-8 text"))?;
    let mut vertices = Vec::new();
    let mut normals: Vec<Vector3<f64>> = Vec::new();
    let mut triangles = Vec::new();
    // The normal (index into `normals`) each vertex's corners name so far.
    let mut vertex_normal: Vec<Option<u32>> = Vec::new();
    // Whether every corner named a normal, and each vertex always the same one.
    let mut normals_fit = true;
    let mut polygon: Vec<u32> = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let number = number + 1;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                vertices.push(three_numbers(path, number, &mut words, "vertex")?);
                vertex_normal.push(None);
            }
            Some("vn") => {
                let n = three_numbers(path, number, &mut words, "normal")?;
                let length = n.norm();
                if !(length.is_finite() && length > 0.0) {
                    return Err(parse_error(
                        path,
                        number,
                        format!("the normal's length is {length}: it gives no direction"),
                    ));
                }
                normals.push(if (length - 1.0).abs() <= UNIT_TOLERANCE {
                    n
                } else {
                    n / length
                });
            }
            Some("f") => {
                polygon.clear();
                for word in words {
                    let mut indices = word.split('/');
                    let vertex = indices.next().unwrap_or("");
                    let v = resolve(path, number, vertex, word, vertices.len(), "vertex")?;
                    match indices.nth(1).filter(|n| !n.is_empty()) {
                        Some(normal) => {
                            let n = resolve(path, number, normal, word, normals.len(), "normal")?;
                            match vertex_normal[v as usize] {
                                None => vertex_normal[v as usize] = Some(n),
                                Some(m) if normals[m as usize] == normals[n as usize] => {}
                                Some(_) => normals_fit = false,
                            }
                        }
                        None => normals_fit = false,
                    }
                    polygon.push(v);
                }
                if polygon.len() < 3 {
                    return Err(parse_error(
                        path,
                        number,
                        "a face needs at least 3 vertices",
                    ));
                }
                for k in 1..polygon.len() - 1 {
                    triangles.push([polygon[0], polygon[k], polygon[k + 1]]);
                }
            }
            _ => {}
        }
    }
    let normals = if normals_fit {
        vertex_normal
            .iter()
            .map(|n| n.map(|n| normals[n as usize]))
            .collect::<Option<Vec<_>>>()
    } else {
        None
    };
    Ok(ObjSurface {
        vertices,
        triangles,
        normals,
    })
}

/// The three numbers after a `v` or `vn` keyword.
fn three_numbers<'a>(
    path: &Path,
    number: usize,
    words: &mut impl Iterator<Item = &'a str>,
    what: &str,
) -> Result<Vector3<f64>, ContactError> {
    let mut p = [0.0; 3];
    for x in &mut p {
        let word = words
            .next()
            .ok_or_else(|| parse_error(path, number, format!("a {what} needs 3 coordinates")))?;
        *x = word
            .parse()
            .map_err(|_| parse_error(path, number, format!("'{word}' is not a number")))?;
    }
    Ok(Vector3::from(p))
}

/// The 0-based index of the 1-based (or, negative, counted back from the last)
/// `index` of a face corner `word` among the `count` vertices or normals so far.
fn resolve(
    path: &Path,
    number: usize,
    index: &str,
    word: &str,
    count: usize,
    what: &str,
) -> Result<u32, ContactError> {
    let i: i64 = index
        .parse()
        .map_err(|_| parse_error(path, number, format!("'{word}' is not a {what} index")))?;
    let count = count as i64;
    let resolved = if i > 0 { i - 1 } else { count + i };
    if i == 0 || !(0..count).contains(&resolved) {
        let plural = if what == "vertex" {
            "vertices"
        } else {
            "normals"
        };
        return Err(parse_error(
            path,
            number,
            format!("{what} {i} does not exist ({count} {plural} so far)"),
        ));
    }
    Ok(resolved as u32)
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::super::RigidSurface;

    fn temporary(name: &str, contents: &[u8]) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("musclefem-contact-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, contents).unwrap();
        path
    }

    const ASCII: &str = "solid square\n\
        facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 1 1 0\n endloop\nendfacet\n\
        facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 1 0\n  vertex 0 1 0\n endloop\nendfacet\n\
        endsolid square\n";

    #[test]
    fn ascii_and_binary_stl_and_obj_give_the_same_square() {
        let ascii = RigidSurface::from_stl(temporary("square.stl", ASCII.as_bytes())).unwrap();
        assert_eq!(ascii.name, "square");
        assert_eq!(ascii.vertices.len(), 4);
        assert_eq!(ascii.triangles.len(), 2);
        assert!((ascii.area() - 1.0).abs() < 1e-15);

        let mut binary = vec![0u8; 80];
        binary.extend(2u32.to_le_bytes());
        for tri in &ascii.triangles {
            binary.extend([0u8; 12]);
            for &v in tri {
                for x in ascii.vertices[v as usize].iter() {
                    binary.extend((*x as f32).to_le_bytes());
                }
            }
            binary.extend([0u8; 2]);
        }
        let from_binary = RigidSurface::from_stl(temporary("binary.stl", &binary)).unwrap();
        assert_eq!(from_binary.vertices, ascii.vertices);
        assert_eq!(from_binary.triangles, ascii.triangles);

        let obj = "# a square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1/1 2/2 3/3 -1\n";
        let from_obj = RigidSurface::from_obj(temporary("square.obj", obj.as_bytes())).unwrap();
        assert_eq!(from_obj.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert!((from_obj.area() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn an_objs_normals_are_the_vertex_normals_when_each_vertex_has_one() {
        // A tent of two faces, the normals leaning out of each facet as a smooth
        // surface's would; one written off unit length.
        let tent = "v 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0.5\n\
                    vn 0 0 1\nvn 0.1 0.2 0.9746794344808963\nvn 0 -0.6 1.6\n\
                    f 1//1 2//2 3//3\nf 1/1/1 3/3/3 4/4/3\n";
        let surface = RigidSurface::from_obj(temporary("tent.obj", tent.as_bytes())).unwrap();
        let normals = surface.vertex_normals.unwrap();
        assert_eq!(normals.len(), 4);
        assert_eq!(normals[0], Vector3::new(0.0, 0.0, 1.0));
        // Unit to round-off: kept as written.
        assert_eq!(normals[1], Vector3::new(0.1, 0.2, 0.9746794344808963));
        // Off unit length: scaled to it.
        let leaning = Vector3::new(0.0, -0.6, 1.6);
        assert_eq!(normals[2], leaning / leaning.norm());
        assert_eq!(normals[3], normals[2]);

        // A flat-shaded export (vertex 1 with each facet's normal) and a corner without
        // a normal give none: the contact averages the facets'.
        for faces in [
            "f 1//1 2//1 3//1\nf 1//3 3//3 4//3\n",
            "f 1//1 2//2 3//3\nf 1//1 3//3 4\n",
        ] {
            let text = tent.replace("f 1//1 2//2 3//3\nf 1/1/1 3/3/3 4/4/3\n", faces);
            let surface = RigidSurface::from_obj(temporary("flat.obj", text.as_bytes())).unwrap();
            assert_eq!(surface.triangles.len(), 2);
            assert!(surface.vertex_normals.is_none(), "{faces}");
        }
    }

    #[test]
    fn errors_name_the_file_and_the_line() {
        let bad = ASCII.replace(
            "vertex 1 1 0\n endloop\nendfacet\nfacet",
            "vertex 1 x 0\n endloop\nendfacet\nfacet",
        );
        let path = temporary("bad.stl", bad.as_bytes());
        let e = RigidSurface::from_stl(&path).unwrap_err().to_string();
        assert!(e.contains("bad.stl:6:") && e.contains("'x'"), "{e}");
        let path = temporary("bad.obj", b"v 0 0 0\nv 1 0 0\nf 1 2 7\n");
        let e = RigidSurface::from_obj(&path).unwrap_err().to_string();
        assert!(e.contains("bad.obj:3:") && e.contains("vertex 7"), "{e}");
        let path = temporary(
            "bad_normal.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\n\nf 1//1 2//1 3//2\n",
        );
        let e = RigidSurface::from_obj(&path).unwrap_err().to_string();
        assert!(
            e.contains("bad_normal.obj:6:") && e.contains("normal 2 does not exist (1 normals"),
            "{e}"
        );
        let path = temporary("zero_normal.obj", b"v 0 0 0\nvn 0 0 0\n");
        let e = RigidSurface::from_obj(&path).unwrap_err().to_string();
        assert!(
            e.contains("zero_normal.obj:2:") && e.contains("gives no direction"),
            "{e}"
        );
        let e = RigidSurface::from_obj("/nonexistent/bone.obj")
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nonexistent/bone.obj"), "{e}");
    }
}
