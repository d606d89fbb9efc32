//! Closed triangle surfaces: the rigid bones of the knee scene.
//!
//! A [`TriangleSurface`] is plain data (vertex positions [m] and vertex-index triangles,
//! counter-clockwise seen from outside so that the right-hand normals point out). The
//! checks a contact algorithm relies on are methods: [`TriangleSurface::check_closed`]
//! (every edge shared by exactly two triangles, traversed in opposite directions, so the
//! surface is a closed, consistently oriented 2-manifold) and
//! [`TriangleSurface::volume`] (positive for outward normals, by the divergence
//! theorem).

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result, bail};
use nalgebra::{Isometry3, Point3, Vector3};

use musclefem_core::mesh::Mesh;

/// A triangulated surface: positions [m] and triangles of vertex indices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleSurface {
    /// Vertex positions [m].
    pub vertices: Vec<Vector3<f64>>,
    /// Triangles, counter-clockwise seen from outside (right-hand normal outward).
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleSurface {
    /// Corner positions of triangle `t`.
    pub fn corners(&self, t: usize) -> [Vector3<f64>; 3] {
        self.triangles[t].map(|i| self.vertices[i as usize])
    }

    /// Enclosed volume [m³]: Σ x₀ · (x₁ × x₂) / 6 over the triangles (the divergence
    /// theorem for div(x)/3 = 1); positive when the normals point outward.
    pub fn volume(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                a.dot(&b.cross(&c))
            })
            .sum::<f64>()
            / 6.0
    }

    /// Centroid of the enclosed volume [m]: Σ V_t (a + b + c)/4 / Σ V_t over the
    /// tetrahedra (0, a, b, c) of the triangles, V_t = a·(b × c)/6.
    pub fn volume_centroid(&self) -> Vector3<f64> {
        let (moment, volume) =
            (0..self.triangles.len()).fold((Vector3::zeros(), 0.0), |(moment, volume), t| {
                let [a, b, c] = self.corners(t);
                let v = a.dot(&b.cross(&c)) / 6.0;
                (moment + v * (a + b + c) / 4.0, volume + v)
            });
        moment / volume
    }

    /// Total area [m²].
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                0.5 * (b - a).cross(&(c - a)).norm()
            })
            .sum()
    }

    /// Axis-aligned bounding box (lower, upper corner) [m].
    pub fn bounds(&self) -> (Vector3<f64>, Vector3<f64>) {
        let mut lower = Vector3::repeat(f64::INFINITY);
        let mut upper = Vector3::repeat(f64::NEG_INFINITY);
        for v in &self.vertices {
            lower = lower.inf(v);
            upper = upper.sup(v);
        }
        (lower, upper)
    }

    /// Errors unless every index is a vertex, no triangle repeats a vertex, and every
    /// undirected edge belongs to exactly two triangles that traverse it in opposite
    /// directions (closed, consistently oriented, no boundary and no fins).
    pub fn check_closed(&self) -> Result<()> {
        let mut edges: HashMap<(u32, u32), (usize, usize)> = HashMap::new();
        for (t, tri) in self.triangles.iter().enumerate() {
            if let Some(&i) = tri.iter().find(|&&i| i as usize >= self.vertices.len()) {
                bail!(
                    "triangle {t} refers to vertex {i} of {}",
                    self.vertices.len()
                );
            }
            if tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0] {
                bail!("triangle {t} repeats a vertex: {tri:?}");
            }
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let entry = edges.entry((a.min(b), a.max(b))).or_insert((0, 0));
                if a < b {
                    entry.0 += 1;
                } else {
                    entry.1 += 1;
                }
            }
        }
        for (&(a, b), &(forward, backward)) in &edges {
            if forward != 1 || backward != 1 {
                bail!(
                    "edge ({a}, {b}) is traversed {forward} time(s) forward and {backward} \
                     backward: the surface is not a closed, consistently oriented manifold"
                );
            }
        }
        Ok(())
    }

    /// Generalised winding number of the surface about `point` (Jacobson et al. 2013):
    /// Σ Ω_t / 4π over the triangles' signed solid angles Ω_t (Van Oosterom & Strackee
    /// 1983: tan(Ω/2) = a·(b × c) / (|a||b||c| + (a·b)|c| + (b·c)|a| + (c·a)|b|) with
    /// a, b, c the corners relative to the point). 1 inside a closed outward surface,
    /// 0 outside.
    pub fn winding_number(&self, point: &Vector3<f64>) -> f64 {
        let total: f64 = (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t).map(|x| x - point);
                let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
                let numerator = a.dot(&b.cross(&c));
                let denominator = la * lb * lc + a.dot(&b) * lc + b.dot(&c) * la + c.dot(&a) * lb;
                2.0 * numerator.atan2(denominator)
            })
            .sum();
        total / (4.0 * std::f64::consts::PI)
    }

    /// Whether `point` is enclosed (winding number above ½).
    pub fn contains(&self, point: &Vector3<f64>) -> bool {
        self.winding_number(point) > 0.5
    }

    /// The surface moved by `motion` (x ↦ motion · x).
    pub fn transformed(&self, motion: &Isometry3<f64>) -> TriangleSurface {
        TriangleSurface {
            vertices: self
                .vertices
                .iter()
                .map(|v| (motion * Point3::from(*v)).coords)
                .collect(),
            triangles: self.triangles.clone(),
        }
    }

    /// The faces of `mesh`'s surface `name` as triangles (each quadrilateral face split
    /// along its diagonal from its first corner), sharing the mesh's node positions.
    pub fn from_mesh_surface(mesh: &Mesh, name: &str) -> Result<TriangleSurface> {
        let mut triangles = Vec::new();
        for &face in mesh.surface(name)? {
            let block = mesh.block(face.element.block)?;
            let ids = mesh.face_nodes(face)?;
            let corners = &ids[..block.shape.face_shape(face.face as usize).corner_count()];
            for k in 1..corners.len() - 1 {
                triangles.push([corners[0], corners[k], corners[k + 1]]);
            }
        }
        Ok(TriangleSurface {
            vertices: (0..mesh.node_count())
                .map(|i| mesh.nodes.position(i))
                .collect(),
            triangles,
        })
    }

    /// Writes the surface as an ASCII STL file named `solid name` (coordinates in metres,
    /// facet normals from the right-hand rule).
    pub fn write_stl(&self, path: &Path, name: &str) -> Result<()> {
        let mut text = format!("solid {name}\n");
        for t in 0..self.triangles.len() {
            let [a, b, c] = self.corners(t);
            let n = (b - a).cross(&(c - a));
            let n = if n.norm() > 0.0 { n.normalize() } else { n };
            let _ = writeln!(text, "  facet normal {:e} {:e} {:e}", n.x, n.y, n.z);
            text.push_str("    outer loop\n");
            for v in [a, b, c] {
                let _ = writeln!(text, "      vertex {:e} {:e} {:e}", v.x, v.y, v.z);
            }
            text.push_str("    endloop\n  endfacet\n");
        }
        let _ = writeln!(text, "endsolid {name}");
        std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube [0, 1]³ as 12 outward triangles.
    fn cube() -> TriangleSurface {
        let vertices = (0..8)
            .map(|i| Vector3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let triangles = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        TriangleSurface {
            vertices,
            triangles,
        }
    }

    #[test]
    fn a_cube_is_closed_with_unit_volume_and_winding_number() {
        let cube = cube();
        cube.check_closed().unwrap();
        assert!((cube.volume() - 1.0).abs() < 1e-15);
        assert!((cube.area() - 6.0).abs() < 1e-15);
        assert!((cube.winding_number(&Vector3::repeat(0.5)) - 1.0).abs() < 1e-12);
        assert!(cube.winding_number(&Vector3::new(1.5, 0.5, 0.5)).abs() < 1e-12);
        assert!(cube.contains(&Vector3::new(0.9, 0.1, 0.2)));
        let moved = cube.transformed(&Isometry3::translation(2.0, 0.0, 0.0));
        assert!(moved.contains(&Vector3::new(2.5, 0.5, 0.5)));
        assert!((moved.volume() - 1.0).abs() < 1e-14);
    }

    #[test]
    fn a_meshed_box_gives_its_closed_outer_surface() {
        let mesh =
            musclefem_core::mesh::generate::box_of_hexes([0.02, 0.03, 0.04], [2, 3, 2]).unwrap();
        let surface = TriangleSurface::from_mesh_surface(&mesh, "outer").unwrap();
        surface.check_closed().unwrap();
        assert!((surface.volume() - 0.02 * 0.03 * 0.04).abs() < 1e-18);
    }

    #[test]
    fn open_or_flipped_surfaces_are_rejected() {
        let mut open = cube();
        open.triangles.pop();
        assert!(open.check_closed().is_err());
        let mut flipped = cube();
        flipped.triangles[0].swap(1, 2);
        assert!(flipped.check_closed().is_err());
        let mut inverted = cube();
        inverted.triangles.iter_mut().for_each(|t| t.swap(1, 2));
        inverted.check_closed().unwrap();
        assert!(inverted.volume() < 0.0);
    }
}
