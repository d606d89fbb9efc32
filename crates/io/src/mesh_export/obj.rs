//! Triangle surfaces written as Wavefront OBJ text, so that a study can hand a rigid
//! body (a bone) to a scene file (`surface = { file = "femur.obj" }`) and the scene
//! reads back the same surface: every coordinate and normal component written as the
//! shortest decimal that parses back to the same `f64` (to the last bit), the vertices
//! in order (`v`), then the vertex normals if the surface has them (`vn`, one per vertex,
//! in the same order), then the triangles (`f`, 1-based, `f a//a b//b c//c` with
//! normals), so the vertex and triangle indices read back as they were.

use std::fmt::Write as _;

use nalgebra::Vector3;

/// The surface of `vertices` [m] and `triangles` (0-based vertex indices, right-hand
/// normal outward) with one unit outward normal per vertex if `normals` is given, as
/// the text of an OBJ file whose first line is the comment `# {comment}`.
pub fn obj_text(
    comment: &str,
    vertices: &[Vector3<f64>],
    triangles: &[[u32; 3]],
    normals: Option<&[Vector3<f64>]>,
) -> String {
    let mut text = format!("# {}\n", comment.replace('\n', " "));
    // `{:?}` is the shortest representation that reads back to the same f64.
    for v in vertices {
        let _ = writeln!(text, "v {:?} {:?} {:?}", v.x, v.y, v.z);
    }
    for n in normals.unwrap_or_default() {
        let _ = writeln!(text, "vn {:?} {:?} {:?}", n.x, n.y, n.z);
    }
    for triangle in triangles {
        let [a, b, c] = triangle.map(|v| v + 1);
        let _ = match normals {
            Some(_) => writeln!(text, "f {a}//{a} {b}//{b} {c}//{c}"),
            None => writeln!(text, "f {a} {b} {c}"),
        };
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_text_lists_vertices_normals_and_faces_by_one_based_index() {
        let vertices = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(0.1, 0.0, 0.0),
            Vector3::new(0.0, 1.0 / 3.0, 2e-7),
        ];
        let normals = [Vector3::z(), Vector3::z(), Vector3::new(0.6, 0.0, 0.8)];
        let text = obj_text("a bone\nfacet", &vertices, &[[0, 1, 2]], Some(&normals));
        assert_eq!(
            text,
            "# a bone facet\nv 0.0 0.0 0.0\nv 0.1 0.0 0.0\nv 0.0 0.3333333333333333 2e-7\n\
             vn 0.0 0.0 1.0\nvn 0.0 0.0 1.0\nvn 0.6 0.0 0.8\nf 1//1 2//2 3//3\n"
        );
        let bare = obj_text("a bone", &vertices, &[[0, 1, 2]], None);
        assert!(
            bare.ends_with("v 0.0 0.3333333333333333 2e-7\nf 1 2 3\n"),
            "{bare}"
        );
    }
}
