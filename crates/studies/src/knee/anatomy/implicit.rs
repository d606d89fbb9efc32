//! Implicit solids and their surfaces: the bones are built as signed-distance-like
//! functions f(x) [m] (negative inside) from simple primitives joined smoothly, and
//! triangulated by marching tetrahedra.
//!
//! The primitives are exact signed distances (sphere, capsule, rounded disc) or
//! first-order ones (an ellipse's f/|∇f|); the smooth union of two fields is the
//! polynomial smooth minimum of Quílez (2013),
//!
//! smin(a, b; k) = min(a, b) − h² k / 4,   h = max(k − |a − b|, 0) / k,
//!
//! which rounds the crease between two solids with a fillet of size ~k; the smooth
//! difference is −smin(−a, b; k). The composed functions are distance-like (their
//! zero set is the surface, their magnitude close to the distance nearby), which is all
//! the meshing and the clearance checks need.
//!
//! [`marching_tetrahedra`] samples f on a rectilinear [`Grid`], splits every cell into the six
//! tetrahedra of the Kuhn triangulation (the same split in every cube, so neighbouring
//! cubes cut their shared faces alike), and in every tetrahedron whose corners change
//! sign places one triangle (one corner apart) or two (two and two) on the edges' zero
//! crossings, linearly interpolated. Vertices are shared through their grid edge, so the
//! result is closed and manifold whenever the solid stays inside the grid; triangles are
//! oriented with the normal pointing from the negative corners to the positive ones.
//!
//! Marching tetrahedra leave slivers where the surface passes close to a grid node (on
//! the coarse femur 8 % of the triangles had an angle below 5°). [`relax_on_surface`]
//! evens them out: each vertex moves halfway to the mean of its neighbours and back onto
//! f = 0 along ∇f (Newton steps), a few times, a move undone where it would turn a
//! triangle over.

use std::collections::HashMap;

use anyhow::{Result, bail};
use nalgebra::Vector3;
use rayon::prelude::*;

use super::surface::TriangleSurface;

/// Polynomial smooth minimum with blend width `k` [m] (see the module documentation).
pub fn smooth_min(a: f64, b: f64, k: f64) -> f64 {
    let h = (k - (a - b).abs()).max(0.0) / k;
    a.min(b) - h * h * k / 4.0
}

/// Smooth maximum (the intersection of two solids), blend width `k` [m]: −smin(−a, −b).
pub fn smooth_max(a: f64, b: f64, k: f64) -> f64 {
    -smooth_min(-a, -b, k)
}

/// Smooth difference: the solid `a` without the solid `b`, blend width `k` [m].
pub fn smooth_subtract(a: f64, b: f64, k: f64) -> f64 {
    -smooth_min(-a, b, k)
}

/// Signed distance to the sphere of `centre` and `radius` [m].
pub fn sphere(p: &Vector3<f64>, centre: &Vector3<f64>, radius: f64) -> f64 {
    (p - centre).norm() - radius
}

/// Signed distance to the capsule of radius `radius` around the segment `a`–`b` [m].
pub fn capsule(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>, radius: f64) -> f64 {
    let (pa, ba) = (p - a, b - a);
    let h = (pa.dot(&ba) / ba.norm_squared()).clamp(0.0, 1.0);
    (pa - h * ba).norm() - radius
}

/// Signed distance to a disc (a cylinder about the z axis through (x, y) = `centre`) of
/// `radius`, spanning z ∈ [`z0`, `z1`], its rims rounded with radius `rounding` [m].
pub fn rounded_disc(
    p: &Vector3<f64>,
    centre: [f64; 2],
    radius: f64,
    z: [f64; 2],
    rounding: f64,
) -> f64 {
    let radial = (p.x - centre[0]).hypot(p.y - centre[1]) - radius + rounding;
    let axial = (p.z - 0.5 * (z[0] + z[1])).abs() - 0.5 * (z[1] - z[0]) + rounding;
    radial.max(axial).min(0.0) + radial.max(0.0).hypot(axial.max(0.0)) - rounding
}

/// Distance-like function of the ellipse of semi-axes (`a`, `b`) [m] at in-plane
/// offsets (`u`, `v`) from its centre: f/|∇f| with f = (u/a)² + (v/b)² − 1 near the
/// boundary (|f| < ½; exact there to first order), (√(f + 1) − 1)·min(a, b) elsewhere.
pub fn ellipse(u: f64, v: f64, a: f64, b: f64) -> f64 {
    let f = (u / a).powi(2) + (v / b).powi(2) - 1.0;
    if f.abs() < 0.5 {
        f / (2.0 * (u * u / a.powi(4) + v * v / b.powi(4)).sqrt()).max(f64::MIN_POSITIVE)
    } else {
        ((f + 1.0).sqrt() - 1.0) * a.min(b)
    }
}

/// The six tetrahedra of the Kuhn split of the unit cube, as corner offsets: the walks
/// from (0,0,0) to (1,1,1) along the axes in every order.
const KUHN: [[[usize; 3]; 4]; 6] = {
    const ORDERS: [[usize; 3]; 6] = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let mut tets = [[[0; 3]; 4]; 6];
    let mut t = 0;
    while t < 6 {
        let mut corner = [0usize; 3];
        let mut step = 0;
        while step < 3 {
            corner[ORDERS[t][step]] = 1;
            tets[t][step + 1] = corner;
            step += 1;
        }
        t += 1;
    }
    tets
};

/// A rectilinear grid: increasing node coordinates along x, y and z [m].
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub axes: [Vec<f64>; 3],
}

impl Grid {
    /// Nodes every `spacing` [m] (or a little less, to end exactly on `upper`) over the
    /// box [`lower`, `upper`].
    pub fn uniform(lower: Vector3<f64>, upper: Vector3<f64>, spacing: f64) -> Self {
        Self {
            axes: [0, 1, 2].map(|k| axis(lower[k], upper[k], spacing)),
        }
    }

    /// As [`Grid::uniform`], but along y only every `coarsening` × `spacing` outside the
    /// band `fine` = [y₀, y₁] [m] (kept at `spacing`): long, smooth shafts need fewer
    /// layers than the knee.
    pub fn graded_along_y(
        lower: Vector3<f64>,
        upper: Vector3<f64>,
        spacing: f64,
        fine: [f64; 2],
        coarsening: f64,
    ) -> Self {
        let coarse = coarsening * spacing;
        let (y0, y1) = (
            fine[0].clamp(lower.y, upper.y),
            fine[1].clamp(lower.y, upper.y),
        );
        let mut y = vec![lower.y];
        for (end, step) in [(y0, coarse), (y1, spacing), (upper.y, coarse)] {
            let start = y[y.len() - 1];
            if end > start {
                y.extend(axis(start, end, step).into_iter().skip(1));
            }
        }
        Self {
            axes: [
                axis(lower.x, upper.x, spacing),
                y,
                axis(lower.z, upper.z, spacing),
            ],
        }
    }

    /// Nodes along each axis.
    fn counts(&self) -> [usize; 3] {
        self.axes.each_ref().map(Vec::len)
    }
}

/// Equally spaced coordinates from `start` to `end`, at most `spacing` apart (at least
/// two).
fn axis(start: f64, end: f64, spacing: f64) -> Vec<f64> {
    let cells = ((end - start) / spacing).ceil().max(1.0) as usize;
    (0..=cells)
        .map(|i| {
            if i == cells {
                end
            } else {
                start + (end - start) * i as f64 / cells as f64
            }
        })
        .collect()
}

/// The closed triangle surface f = 0 of the implicit solid f < 0, sampled on `grid`
/// (see the module documentation).
///
/// Errors if an axis has fewer than two nodes, the spacing is not positive, the grid
/// would exceed 2³¹ nodes, or the solid reaches the grid's boundary (the surface would
/// be open there).
pub fn marching_tetrahedra(
    f: impl Fn(&Vector3<f64>) -> f64 + Sync,
    grid: &Grid,
) -> Result<TriangleSurface> {
    let [nx, ny, nz] = grid.counts();
    if nx < 2 || ny < 2 || nz < 2 {
        bail!("marching tetrahedra: every axis needs two nodes, got {nx} × {ny} × {nz}");
    }
    if grid.axes.iter().any(|a| {
        a.windows(2)
            .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
    }) {
        bail!("marching tetrahedra: grid coordinates must increase");
    }
    let count = nx * ny * nz;
    if count > (1 << 31) {
        bail!("marching tetrahedra: {count} grid nodes are too many");
    }
    let id = |i: usize, j: usize, k: usize| i + nx * (j + ny * k);
    let position = |i: usize, j: usize, k: usize| {
        Vector3::new(grid.axes[0][i], grid.axes[1][j], grid.axes[2][k])
    };
    // Nudge exact zeros off the surface so no crossing sits on a grid node.
    let smallest = grid
        .axes
        .iter()
        .flat_map(|a| a.windows(2).map(|w| w[1] - w[0]))
        .fold(f64::INFINITY, f64::min);
    let floor = 1e-9 * smallest;
    let values: Vec<f64> = (0..count)
        .into_par_iter()
        .map(|g| {
            let (i, j, k) = (g % nx, (g / nx) % ny, g / (nx * ny));
            let v = f(&position(i, j, k));
            if v.abs() < floor { floor } else { v }
        })
        .collect();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let boundary =
                    i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1;
                if boundary && values[id(i, j, k)] < 0.0 {
                    bail!(
                        "marching tetrahedra: the solid reaches the grid's boundary at {:?}",
                        position(i, j, k)
                    );
                }
            }
        }
    }
    let cells = Vector3::new(nx - 1, ny - 1, nz - 1);
    let mut surface = TriangleSurface::default();
    let mut edge_vertex: HashMap<(usize, usize), u32> = HashMap::new();
    let mut crossing =
        |a: (usize, Vector3<f64>), b: (usize, Vector3<f64>), surface: &mut TriangleSurface| {
            let key = (a.0.min(b.0), a.0.max(b.0));
            *edge_vertex.entry(key).or_insert_with(|| {
                let (fa, fb) = (values[a.0], values[b.0]);
                let t = fa / (fa - fb);
                surface.vertices.push(a.1 + t * (b.1 - a.1));
                (surface.vertices.len() - 1) as u32
            })
        };
    for k in 0..cells.z {
        for j in 0..cells.y {
            for i in 0..cells.x {
                for tet in &KUHN {
                    let corners = tet.map(|[di, dj, dk]| {
                        (id(i + di, j + dj, k + dk), position(i + di, j + dj, k + dk))
                    });
                    let (inside, outside): (Vec<_>, Vec<_>) =
                        corners.iter().partition(|c| values[c.0] < 0.0);
                    if inside.is_empty() || outside.is_empty() {
                        continue;
                    }
                    let centroid = |cs: &[&(usize, Vector3<f64>)]| {
                        cs.iter().map(|c| c.1).sum::<Vector3<f64>>() / cs.len() as f64
                    };
                    let outward = centroid(&outside) - centroid(&inside);
                    let loops: Vec<[u32; 3]> = match inside.len() {
                        1 => {
                            let a = *inside[0];
                            let e: Vec<u32> = outside
                                .iter()
                                .map(|&&o| crossing(a, o, &mut surface))
                                .collect();
                            vec![[e[0], e[1], e[2]]]
                        }
                        3 => {
                            let d = *outside[0];
                            let e: Vec<u32> = inside
                                .iter()
                                .map(|&&o| crossing(o, d, &mut surface))
                                .collect();
                            vec![[e[0], e[1], e[2]]]
                        }
                        _ => {
                            let (a, b, c, d) = (*inside[0], *inside[1], *outside[0], *outside[1]);
                            let ac = crossing(a, c, &mut surface);
                            let ad = crossing(a, d, &mut surface);
                            let bd = crossing(b, d, &mut surface);
                            let bc = crossing(b, c, &mut surface);
                            vec![[ac, ad, bd], [ac, bd, bc]]
                        }
                    };
                    for mut tri in loops {
                        let [p0, p1, p2] = tri.map(|v| surface.vertices[v as usize]);
                        if (p1 - p0).cross(&(p2 - p0)).dot(&outward) < 0.0 {
                            tri.swap(1, 2);
                        }
                        surface.triangles.push(tri);
                    }
                }
            }
        }
    }
    Ok(surface)
}

/// Moves the vertices of `surface`, a triangulation of f = 0, to even out its triangles
/// (see the module documentation): `iterations` rounds of x ← x + ½ (mean of the
/// neighbours − x), then three Newton steps x ← x − f ∇f / |∇f|² (∇f by central
/// differences of 1 µm); a vertex whose move would turn one of its triangles by more than
/// 60° keeps its place that round. The connectivity does not change.
pub fn relax_on_surface(
    surface: &mut TriangleSurface,
    f: impl Fn(&Vector3<f64>) -> f64 + Sync,
    iterations: usize,
) {
    let count = surface.vertices.len();
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); count];
    let mut triangles_of: Vec<Vec<u32>> = vec![Vec::new(); count];
    for (t, triangle) in surface.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (triangle[k], triangle[(k + 1) % 3]);
            neighbours[a as usize].push(b);
            neighbours[b as usize].push(a);
            triangles_of[a as usize].push(t as u32);
        }
    }
    for list in &mut neighbours {
        list.sort_unstable();
        list.dedup();
    }
    let h = 1e-6;
    let onto_surface = |mut x: Vector3<f64>| {
        for _ in 0..3 {
            let gradient = Vector3::from_fn(|k, _| {
                let mut e = Vector3::zeros();
                e[k] = h;
                (f(&(x + e)) - f(&(x - e))) / (2.0 * h)
            });
            let norm2 = gradient.norm_squared();
            if norm2 > 0.0 {
                x -= f(&x) * gradient / norm2;
            }
        }
        x
    };
    let normal = |vertices: &[Vector3<f64>], t: u32| {
        let [a, b, c] = surface.triangles[t as usize].map(|i| vertices[i as usize]);
        (b - a).cross(&(c - a))
    };
    for _ in 0..iterations {
        let old = surface.vertices.clone();
        let moved: Vec<Vector3<f64>> = (0..count)
            .into_par_iter()
            .map(|v| {
                let list = &neighbours[v];
                if list.is_empty() {
                    return old[v];
                }
                let mean =
                    list.iter().map(|&n| old[n as usize]).sum::<Vector3<f64>>() / list.len() as f64;
                onto_surface(old[v] + 0.5 * (mean - old[v]))
            })
            .collect();
        surface.vertices = moved;
        // Undo the moves that turn a triangle over (compared with the old positions).
        let turned: Vec<usize> = (0..count)
            .into_par_iter()
            .filter(|&v| {
                triangles_of[v].iter().any(|&t| {
                    let before = normal(&old, t);
                    let after = normal(&surface.vertices, t);
                    after.dot(&before) <= 0.5 * after.norm() * before.norm()
                })
            })
            .collect();
        for v in turned {
            surface.vertices[v] = old[v];
        }
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;

    #[test]
    fn a_sphere_is_closed_with_the_right_volume_and_outward_normals() {
        let centre = Vector3::new(0.01, -0.02, 0.005);
        let radius = 0.02;
        let surface = marching_tetrahedra(
            |p| sphere(p, &centre, radius),
            &Grid::uniform(
                centre - Vector3::repeat(0.03),
                centre + Vector3::repeat(0.03),
                0.001,
            ),
        )
        .unwrap();
        surface.check_closed().unwrap();
        let exact = 4.0 / 3.0 * PI * radius.powi(3);
        assert!(
            (surface.volume() - exact).abs() < 0.01 * exact,
            "{} {exact}",
            surface.volume()
        );
        for v in &surface.vertices {
            assert!(((v - centre).norm() - radius).abs() < 2e-5);
        }
        assert!(surface.contains(&centre));
        assert!(!surface.contains(&(centre + Vector3::new(0.025, 0.0, 0.0))));
    }

    #[test]
    fn smooth_joins_and_primitives_are_distances() {
        // Far from the blend the smooth minimum is the minimum.
        assert_eq!(smooth_min(0.5, -0.3, 0.1), -0.3);
        assert!(smooth_min(0.0, 0.0, 0.1) < 0.0);
        assert!((smooth_subtract(-0.2, 0.3, 0.05) - -0.2).abs() < 1e-15);
        let p = Vector3::new(0.0, 0.03, 0.0);
        assert!(
            (capsule(&p, &Vector3::zeros(), &Vector3::new(1.0, 0.0, 0.0), 0.01) - 0.02).abs()
                < 1e-15
        );
        // A disc of radius 0.02 and thickness 0.01: 5 mm beyond its rim on the mid-plane.
        let rim = Vector3::new(0.025, 0.0, 0.005);
        assert!((rounded_disc(&rim, [0.0, 0.0], 0.02, [0.0, 0.01], 0.002) - 0.005).abs() < 1e-15);
        assert!(
            rounded_disc(
                &Vector3::new(0.0, 0.0, 0.005),
                [0.0, 0.0],
                0.02,
                [0.0, 0.01],
                0.002
            ) < 0.0
        );
        assert!((ellipse(0.021, 0.0, 0.02, 0.01) - 0.001).abs() < 1e-4);
        assert!(ellipse(0.05, 0.0, 0.02, 0.01) > 0.0 && ellipse(0.0, 0.005, 0.02, 0.01) < 0.0);
        assert!((ellipse(0.0, 0.011, 0.02, 0.01) - 0.001).abs() < 1e-4);
    }

    #[test]
    fn a_solid_at_the_grid_boundary_is_refused() {
        let grid = Grid::uniform(Vector3::repeat(-0.5), Vector3::repeat(0.5), 0.1);
        let result = marching_tetrahedra(|p| sphere(p, &Vector3::zeros(), 1.0), &grid);
        assert!(result.is_err());
    }

    #[test]
    fn a_graded_grid_still_gives_a_closed_surface() {
        // A capsule along y, meshed finely only around its middle.
        let (a, b) = (Vector3::new(0.0, -0.1, 0.0), Vector3::new(0.0, 0.1, 0.0));
        let grid = Grid::graded_along_y(
            Vector3::new(-0.03, -0.14, -0.03),
            Vector3::new(0.03, 0.14, 0.03),
            0.002,
            [-0.02, 0.03],
            3.0,
        );
        let y = &grid.axes[1];
        assert!(y.windows(2).all(|w| w[1] > w[0]));
        assert!(y.contains(&-0.02) && y.contains(&0.03) && *y.last().unwrap() == 0.14);
        let surface = marching_tetrahedra(|p| capsule(p, &a, &b, 0.015), &grid).unwrap();
        surface.check_closed().unwrap();
        let exact = PI * 0.015f64.powi(2) * 0.2 + 4.0 / 3.0 * PI * 0.015f64.powi(3);
        assert!(
            (surface.volume() - exact).abs() < 0.02 * exact,
            "{}",
            surface.volume()
        );
    }
}
