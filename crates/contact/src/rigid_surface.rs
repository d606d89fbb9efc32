//! Rigid surfaces (bones, tools): triangles fixed in a body frame that moves with a
//! prescribed [`RigidMotion`], x = c + R(t)(X − c) + T(t).
//!
//! Generated shapes (a plane, a sphere, a cylinder) and triangle files (STL, OBJ with or
//! without vertex normals, see `rigid_surface/read.rs`). Each triangle's right-hand
//! normal (X₂ − X₁) × (X₃ − X₁) points to the side where the other body is: out of the
//! bone. The generated sphere and cylinder are faceted: their vertices lie on the exact
//! shape, the flat facets inside it by at most r (1 − cos(θ/2)), θ the angle between
//! neighbouring vertices seen from the centre (the contact sees the facets).

mod read;

use std::f64::consts::PI;
use std::path::Path;

use nalgebra::{Unit, Vector3};

use musclefem_core::solver::RigidMotion;

use crate::error::ContactError;
use crate::surface::boundary_edges;

/// A rigid triangulated surface with a prescribed motion.
#[derive(Debug, Clone)]
pub struct RigidSurface {
    /// Name in messages and outputs.
    pub name: String,
    /// Vertices in the body frame (the positions at t = 0 of a motion that starts at
    /// rest) [m].
    pub vertices: Vec<Vector3<f64>>,
    /// Triangles by vertex index, right-hand normal pointing out of the rigid body.
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle, bit `i` set when its edge `i` (vertex `i` to `i + 1`) belongs to no
    /// other triangle.
    pub boundary_edges: Vec<u8>,
    /// The motion of the body frame.
    pub motion: RigidMotion,
    /// Unit outward normals at the vertices in the body frame, where the surface's own
    /// shape knows them better than its facets do (an implicit or analytic body): the
    /// smooth normal field of [`crate::TangentialMode::SmoothSlide`] and of
    /// [`crate::PenaltyContact::with_smooth_normals`] takes them instead of the
    /// area-weighted facet normals. `None`: the facets'.
    pub vertex_normals: Option<Vec<Vector3<f64>>>,
}

impl RigidSurface {
    /// A fixed surface of these `vertices` [m] and `triangles`.
    ///
    /// Errors if there is no triangle, a triangle names a missing vertex, or a triangle
    /// has no area.
    pub fn new(
        name: &str,
        vertices: Vec<Vector3<f64>>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Self, ContactError> {
        if triangles.is_empty() {
            return Err(ContactError::EmptySurface(name.to_string()));
        }
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&vertex) = tri.iter().find(|&&v| v as usize >= vertices.len()) {
                return Err(ContactError::VertexOutOfRange {
                    surface: name.to_string(),
                    triangle: t,
                    vertex,
                    count: vertices.len(),
                });
            }
            let [a, b, c] = tri.map(|v| vertices[v as usize]);
            let area = 0.5 * (b - a).cross(&(c - a)).norm();
            let scale = (b - a).norm_squared().max((c - a).norm_squared());
            if area.is_nan() || area <= 1e-12 * scale {
                return Err(ContactError::DegenerateTriangle {
                    surface: name.to_string(),
                    triangle: t,
                    nodes: *tri,
                });
            }
        }
        let boundary_edges = boundary_edges(&triangles);
        Ok(RigidSurface {
            name: name.to_string(),
            vertices,
            triangles,
            boundary_edges,
            motion: RigidMotion::fixed(),
            vertex_normals: None,
        })
    }

    /// The same surface with these unit outward `normals` at its vertices (body frame; see
    /// [`RigidSurface::vertex_normals`]). Errors unless there is one finite unit vector per
    /// vertex.
    pub fn with_vertex_normals(mut self, normals: Vec<Vector3<f64>>) -> Result<Self, ContactError> {
        if normals.len() != self.vertices.len()
            || normals
                .iter()
                .any(|n| !n.iter().all(|x| x.is_finite()) || (n.norm() - 1.0).abs() > 1e-6)
        {
            return Err(ContactError::InvalidNormals {
                surface: self.name.clone(),
                reason: format!(
                    "{} vertex normals for {} vertices, each a finite unit vector",
                    normals.len(),
                    self.vertices.len()
                ),
            });
        }
        self.vertex_normals = Some(normals);
        Ok(self)
    }

    /// The same surface moving with `motion`.
    pub fn with_motion(mut self, motion: RigidMotion) -> Self {
        self.motion = motion;
        self
    }

    /// A square of side 2 `half_size` [m] centred on `point` [m], facing `normal`, cut into
    /// `divisions × divisions` squares of two triangles each.
    pub fn plane(
        name: &str,
        point: Vector3<f64>,
        normal: Vector3<f64>,
        half_size: f64,
        divisions: usize,
    ) -> Result<Self, ContactError> {
        positive("plane half size", half_size)?;
        let n = unit("plane normal", normal)?;
        let (t1, t2) = tangents(&n);
        let d = divisions.max(1);
        let step = 2.0 * half_size / d as f64;
        let mut vertices = Vec::with_capacity((d + 1) * (d + 1));
        for j in 0..=d {
            for i in 0..=d {
                let (u, v) = (-half_size + i as f64 * step, -half_size + j as f64 * step);
                vertices.push(point + t1 * u + t2 * v);
            }
        }
        let id = |i: usize, j: usize| (i + (d + 1) * j) as u32;
        let mut triangles = Vec::with_capacity(2 * d * d);
        for j in 0..d {
            for i in 0..d {
                // t1 × t2 = n: counter-clockwise in (u, v) faces n.
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        Self::new(name, vertices, triangles)
    }

    /// A sphere of `radius` [m] about `center` [m], facing out: an icosahedron whose
    /// triangles are cut in four `refinement` times (20 · 4^refinement triangles), every
    /// vertex pushed onto the sphere.
    pub fn sphere(
        name: &str,
        center: Vector3<f64>,
        radius: f64,
        refinement: u32,
    ) -> Result<Self, ContactError> {
        positive("sphere radius", radius)?;
        if refinement > 8 {
            return Err(ContactError::invalid(
                "sphere refinement",
                refinement as f64,
                "is above 8 (1.3 million triangles)",
            ));
        }
        let g = 0.5 * (1.0 + 5f64.sqrt());
        let mut points: Vec<Vector3<f64>> = [
            [-1.0, g, 0.0],
            [1.0, g, 0.0],
            [-1.0, -g, 0.0],
            [1.0, -g, 0.0],
            [0.0, -1.0, g],
            [0.0, 1.0, g],
            [0.0, -1.0, -g],
            [0.0, 1.0, -g],
            [g, 0.0, -1.0],
            [g, 0.0, 1.0],
            [-g, 0.0, -1.0],
            [-g, 0.0, 1.0],
        ]
        .iter()
        .map(|p| Vector3::from(*p).normalize())
        .collect();
        let mut triangles: Vec<[u32; 3]> = vec![
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ];
        for _ in 0..refinement {
            let mut midpoints = std::collections::HashMap::new();
            let mut midpoint = |a: u32, b: u32, points: &mut Vec<Vector3<f64>>| {
                *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    points.push((points[a as usize] + points[b as usize]).normalize());
                    (points.len() - 1) as u32
                })
            };
            let mut finer = Vec::with_capacity(4 * triangles.len());
            for [a, b, c] in triangles {
                let ab = midpoint(a, b, &mut points);
                let bc = midpoint(b, c, &mut points);
                let ca = midpoint(c, a, &mut points);
                finer.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
            }
            triangles = finer;
        }
        let vertices = points.iter().map(|p| center + p * radius).collect();
        Self::new(name, vertices, triangles)
    }

    /// The lateral surface of a cylinder (open at both ends) of `radius` and `length` [m],
    /// centred on `center` [m] along `axis`, facing out: `divisions[0]` segments around,
    /// `divisions[1]` along, two triangles each.
    pub fn cylinder(
        name: &str,
        center: Vector3<f64>,
        axis: Vector3<f64>,
        radius: f64,
        length: f64,
        divisions: [usize; 2],
    ) -> Result<Self, ContactError> {
        positive("cylinder radius", radius)?;
        positive("cylinder length", length)?;
        let a = unit("cylinder axis", axis)?;
        let (e1, e2) = tangents(&a);
        let (around, along) = (divisions[0].max(3), divisions[1].max(1));
        let mut vertices = Vec::with_capacity(around * (along + 1));
        for j in 0..=along {
            let s = -0.5 * length + length * j as f64 / along as f64;
            for i in 0..around {
                let phi = 2.0 * PI * i as f64 / around as f64;
                vertices
                    .push(center + a.into_inner() * s + (e1 * phi.cos() + e2 * phi.sin()) * radius);
            }
        }
        let id = |i: usize, j: usize| ((i % around) + around * j) as u32;
        let mut triangles = Vec::with_capacity(2 * around * along);
        for j in 0..along {
            for i in 0..around {
                // (e_φ, a) is right-handed about the outward radius: e_φ × a = e_r.
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        Self::new(name, vertices, triangles)
    }

    /// The triangles of an STL file (ASCII or binary), named after the file stem.
    /// Vertices with bitwise equal coordinates are merged. Errors name the file and the
    /// line (ASCII) or triangle record (binary).
    pub fn from_stl(path: impl AsRef<Path>) -> Result<Self, ContactError> {
        let path = path.as_ref();
        let (vertices, triangles) = read::stl(path)?;
        Self::new(&stem(path), vertices, triangles)
    }

    /// The faces of a Wavefront OBJ file (`v` and `f` lines; polygons fanned into
    /// triangles from their first vertex), named after the file stem, with the file's
    /// `vn` normals as [`RigidSurface::vertex_normals`] when they give every vertex one
    /// normal (the rules are `rigid_surface/read.rs`'s `obj`). Errors name the file and
    /// the line.
    pub fn from_obj(path: impl AsRef<Path>) -> Result<Self, ContactError> {
        let path = path.as_ref();
        let read = read::obj(path)?;
        let surface = Self::new(&stem(path), read.vertices, read.triangles)?;
        match read.normals {
            Some(normals) => surface.with_vertex_normals(normals),
            None => Ok(surface),
        }
    }

    /// Total area [m²].
    pub fn area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| self.vertices[v as usize]);
                0.5 * (b - a).cross(&(c - a)).norm()
            })
            .sum()
    }
}

fn stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(|| "rigid".to_string(), |s| s.to_string_lossy().into_owned())
}

fn positive(what: &str, value: f64) -> Result<(), ContactError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ContactError::invalid(
            what,
            value,
            "must be finite and positive",
        ))
    }
}

fn unit(what: &str, v: Vector3<f64>) -> Result<Unit<Vector3<f64>>, ContactError> {
    let norm = v.norm();
    if norm.is_finite() && norm > 0.0 {
        Ok(Unit::new_normalize(v))
    } else {
        Err(ContactError::invalid(
            what,
            norm,
            "(its length) must be finite and positive",
        ))
    }
}

/// Two unit vectors t₁, t₂ with t₁ × t₂ = n.
fn tangents(n: &Unit<Vector3<f64>>) -> (Vector3<f64>, Vector3<f64>) {
    let helper = if n.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let t1 = helper.cross(n).normalize();
    let t2 = n.cross(&t1);
    (t1, t2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outward(surface: &RigidSurface, centre: impl Fn(&Vector3<f64>) -> Vector3<f64>) {
        for (t, tri) in surface.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|v| surface.vertices[v as usize]);
            let middle = (a + b + c) / 3.0;
            let normal = (b - a).cross(&(c - a));
            assert!(
                normal.dot(&(middle - centre(&middle))) > 0.0,
                "{} {t}",
                surface.name
            );
        }
    }

    #[test]
    fn generated_shapes_face_out_and_have_their_area() {
        let n = Vector3::new(0.0, 1.0, 1.0);
        let plane = RigidSurface::plane("floor", Vector3::zeros(), n, 0.5, 4).unwrap();
        assert!((plane.area() - 1.0).abs() < 1e-14);
        outward(&plane, |m| m - n);
        let rim: u32 = plane.boundary_edges.iter().map(|b| b.count_ones()).sum();
        assert_eq!(rim, 16);

        let c = Vector3::new(1.0, 2.0, 3.0);
        let sphere = RigidSurface::sphere("ball", c, 0.2, 4).unwrap();
        assert_eq!(sphere.triangles.len(), 20 * 256);
        assert!(sphere.boundary_edges.iter().all(|&b| b == 0));
        let exact = 4.0 * PI * 0.04;
        assert!(
            (sphere.area() - exact).abs() < 2e-3 * exact,
            "{}",
            sphere.area()
        );
        assert!(sphere.area() < exact);
        outward(&sphere, |_| c);

        let axis = Vector3::new(0.0, 0.0, 2.0);
        let cylinder = RigidSurface::cylinder("rod", c, axis, 0.1, 0.5, [64, 4]).unwrap();
        let lateral = 2.0 * PI * 0.1 * 0.5;
        assert!((cylinder.area() - lateral).abs() < 2e-3 * lateral);
        outward(&cylinder, |m| Vector3::new(c.x, c.y, m.z));
    }

    #[test]
    fn bad_parameters_are_refused_by_name() {
        let e = RigidSurface::sphere("ball", Vector3::zeros(), -1.0, 2).unwrap_err();
        assert!(e.to_string().contains("sphere radius"), "{e}");
        let e = RigidSurface::plane("p", Vector3::zeros(), Vector3::zeros(), 1.0, 1).unwrap_err();
        assert!(e.to_string().contains("plane normal"), "{e}");
        let e = RigidSurface::new("none", vec![], vec![]).unwrap_err();
        assert!(e.to_string().contains("'none' is empty"), "{e}");
        let e = RigidSurface::new("bad", vec![Vector3::zeros()], vec![[0, 1, 2]]).unwrap_err();
        assert!(e.to_string().contains("vertex 1"), "{e}");
    }
}
