//! Shared test geometry of the smooth normal field's users: a triangle in general position
//! with tilted vertex normals, rigid bumpy, folded and conical patches, and the measures
//! of continuity along a path.

use musclefem_core::mesh::{Mesh, Nodes};
use nalgebra::Vector3;

use crate::rigid_surface::RigidSurface;

/// The test triangle of the frame's derivative checks (size ~1 m, in general position).
pub const CORNERS: [Vector3<f64>; 3] = [
    Vector3::new(0.1, -0.2, 0.3),
    Vector3::new(1.2, 0.1, 0.2),
    Vector3::new(0.3, 0.9, 0.7),
];

pub fn face_normal(corners: &[Vector3<f64>; 3]) -> Vector3<f64> {
    (corners[1] - corners[0])
        .cross(&(corners[2] - corners[0]))
        .normalize()
}

/// Vertex normals tilted from the face normal by 0.2–0.35 rad, in different directions.
pub fn tilted(corners: &[Vector3<f64>; 3]) -> [Vector3<f64>; 3] {
    let n = face_normal(corners);
    let tilts = [
        Vector3::new(0.3, -0.1, 0.05),
        Vector3::new(-0.2, 0.25, 0.1),
        Vector3::new(0.05, 0.2, -0.3),
    ];
    tilts.map(|t| (n + t - n * n.dot(&t)).normalize())
}

/// The point whose foot has barycentric coordinates `phi` and lies `along` × N(φ) below
/// it.
pub fn point_over(
    corners: &[Vector3<f64>; 3],
    normals: &[Vector3<f64>; 3],
    phi: [f64; 3],
    along: f64,
) -> Vector3<f64> {
    (0..3)
        .map(|k| phi[k] * (corners[k] + along * normals[k]))
        .sum()
}

/// A mesh of `points` without elements.
pub fn mesh(points: &[Vector3<f64>]) -> Mesh {
    let mut nodes = Nodes::new();
    for p in points {
        nodes.push(*p);
    }
    Mesh::new(nodes, vec![])
}

/// A rigid bumpy patch: a 4 × 4 grid of unit squares on z = 0.15 (x² − 0.6 y²) + 0.05 x y,
/// every vertex normal different.
pub fn bumpy() -> RigidSurface {
    let mut vertices = Vec::new();
    for j in 0..5 {
        for i in 0..5 {
            let (x, y) = (f64::from(i) - 2.0, f64::from(j) - 2.0);
            vertices.push(Vector3::new(
                x,
                y,
                0.15 * (x * x - 0.6 * y * y) + 0.05 * x * y,
            ));
        }
    }
    RigidSurface::new("bumps", vertices, grid_triangles(4, 4)).unwrap()
}

/// The triangles of an `nx` × `ny` grid of squares (vertices row after row), each split
/// along its diagonal from the lower-left corner, counter-clockwise seen from +z.
pub fn grid_triangles(nx: u32, ny: u32) -> Vec<[u32; 3]> {
    let id = |i: u32, j: u32| i + (nx + 1) * j;
    (0..ny)
        .flat_map(|j| {
            (0..nx).flat_map(move |i| {
                [
                    [id(i, j), id(i + 1, j), id(i + 1, j + 1)],
                    [id(i, j), id(i + 1, j + 1), id(i, j + 1)],
                ]
            })
        })
        .collect()
}

/// A sheet folded along the y axis, z = `slope` |x| over x, y in [−2, 2] (unit squares):
/// a convex ridge for a negative slope, a concave valley for a positive one.
pub fn folded(slope: f64) -> RigidSurface {
    let mut vertices = Vec::new();
    for j in 0..5 {
        for i in 0..5 {
            let (x, y) = (f64::from(i) - 2.0, f64::from(j) - 2.0);
            vertices.push(Vector3::new(x, y, slope * x.abs()));
        }
    }
    RigidSurface::new("fold", vertices, grid_triangles(4, 4)).unwrap()
}

/// An inverted cone around a concave vertex: the apex (0, 0, 0) and two rings of 6
/// vertices at radius 1 and 2 rising with `slope`, 18 triangles facing up.
pub fn bowl(slope: f64) -> RigidSurface {
    let mut vertices = vec![Vector3::zeros()];
    for ring in [1.0, 2.0] {
        for i in 0..6 {
            let angle = std::f64::consts::PI / 3.0 * f64::from(i) + 0.1;
            vertices.push(Vector3::new(
                ring * angle.cos(),
                ring * angle.sin(),
                slope * ring,
            ));
        }
    }
    let mut triangles = Vec::new();
    for i in 0..6u32 {
        let (a, b) = (1 + i, 1 + (i + 1) % 6);
        triangles.push([0, a, b]);
        triangles.push([a, a + 6, b + 6]);
        triangles.push([a, b + 6, b]);
    }
    RigidSurface::new("bowl", vertices, triangles).unwrap()
}

/// The point of the rigid `surface` (at rest) straight below (x, y) [m], on the first
/// triangle whose shadow holds it.
pub fn below(surface: &RigidSurface, x: f64, y: f64) -> Vector3<f64> {
    surface
        .triangles
        .iter()
        .find_map(|t| {
            let [a, b, c] = t.map(|v| surface.vertices[v as usize]);
            let (e1, e2) = ((b - a).xy(), (c - a).xy());
            let d = nalgebra::Vector2::new(x, y) - a.xy();
            let m = nalgebra::Matrix2::from_columns(&[e1, e2]).try_inverse()?;
            let xi = m * d;
            (xi.x >= 0.0 && xi.y >= 0.0 && xi.x + xi.y <= 1.0)
                .then(|| a + xi.x * (b - a) + xi.y * (c - a))
        })
        .unwrap()
}

/// `samples` + 1 points from `from` to `to`.
pub fn line(from: Vector3<f64>, to: Vector3<f64>, samples: usize) -> Vec<Vector3<f64>> {
    (0..=samples)
        .map(|i| from + (to - from) * (i as f64 / samples as f64))
        .collect()
}

/// The largest and the median of `changes`.
pub fn largest_and_median(mut changes: Vec<f64>) -> (f64, f64) {
    changes.sort_by(f64::total_cmp);
    (changes[changes.len() - 1], changes[changes.len() / 2])
}

/// The largest and the median change of consecutive forces [N].
pub fn jumps(forces: &[Vector3<f64>]) -> (f64, f64) {
    largest_and_median(forces.windows(2).map(|w| (w[1] - w[0]).norm()).collect())
}

/// The largest and the median angle between consecutive forces [rad].
pub fn turns(forces: &[Vector3<f64>]) -> (f64, f64) {
    largest_and_median(forces.windows(2).map(|w| w[0].angle(&w[1])).collect())
}
