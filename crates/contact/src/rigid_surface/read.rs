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

/// A Wavefront OBJ file: `v x y z` vertices and `f` faces (indices 1-based, negative from
/// the end, `i/t/n` forms accepted); other lines are ignored.
pub(super) fn obj(path: &Path) -> Result<Triangles, ContactError> {
    let bytes = read_bytes(path)?;
    let text = std::str::from_utf8(&bytes).map_err(|_| parse_error(path, 1, "not UTF-8 text"))?;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    let mut polygon: Vec<u32> = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let number = number + 1;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let mut p = [0.0; 3];
                for x in &mut p {
                    let word = words
                        .next()
                        .ok_or_else(|| parse_error(path, number, "a vertex needs 3 coordinates"))?;
                    *x = word.parse().map_err(|_| {
                        parse_error(path, number, format!("'{word}' is not a number"))
                    })?;
                }
                vertices.push(Vector3::from(p));
            }
            Some("f") => {
                polygon.clear();
                for word in words {
                    let index = word.split('/').next().unwrap_or("");
                    let i: i64 = index.parse().map_err(|_| {
                        parse_error(path, number, format!("'{word}' is not a vertex index"))
                    })?;
                    let count = vertices.len() as i64;
                    let resolved = if i > 0 { i - 1 } else { count + i };
                    if i == 0 || !(0..count).contains(&resolved) {
                        return Err(parse_error(
                            path,
                            number,
                            format!("vertex {i} does not exist ({count} vertices so far)"),
                        ));
                    }
                    polygon.push(resolved as u32);
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
    Ok((vertices, triangles))
}

#[cfg(test)]
mod tests {
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
        let e = RigidSurface::from_obj("/nonexistent/bone.obj")
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nonexistent/bone.obj"), "{e}");
    }
}
