//! The Visible Human Female's quadriceps (issue #35): the tet10 volume meshes of VI, VL,
//! VM and RF that `scripts/visible_human_knee.py` made from the segmented surfaces
//! (Andreassen et al. 2022, Sci Data, CC BY 4.0) and that are committed in
//! `crates/studies/data/visible_human/` with the surfaces' notice and citations, so that
//! nothing outside the repository is read.
//!
//! Each mesh is in metres in the data's frame (x to the subject's right, y anterior,
//! z superior) and carries the surfaces `origin`, `insertion`, `aponeurosis` (disjoint),
//! `interface_<N>` for its neighbours N and `outer`; the folder's README gives the rules
//! that chose them. The fiber flow runs from [`FIBER_INLETS`] to [`FIBER_OUTLETS`].

use std::collections::HashMap;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use nalgebra::{Matrix3, SymmetricEigen, Vector3};

use musclefem_core::mesh::{ElementRef, Mesh};
use musclefem_fibers::{FiberField, FlowBoundary, FlowSettings, compute_fibers};
use musclefem_io::mesh_import::read_mesh;

use super::{Quadriceps, TriangleSurface};

pub mod knee;
pub mod landmarks;
pub mod mechanism;
pub mod tracking;

pub use knee::{TendonStrand, VisibleHumanKnee};
pub use landmarks::{Landmark, Landmarks};

/// The folder of the committed meshes, surfaces and their README.
pub fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/visible_human")
}

/// The two committed mesh resolutions (target edge 9 and 6 mm).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MeshResolution {
    /// Target element edge 9 mm: 1.6–4.7 thousand tet10 per muscle.
    Coarse,
    /// Target element edge 6 mm.
    Medium,
}

impl MeshResolution {
    /// Both, coarse first.
    pub const ALL: [MeshResolution; 2] = [MeshResolution::Coarse, MeshResolution::Medium];

    /// The name in the files: `coarse`, `medium`.
    pub fn name(self) -> &'static str {
        match self {
            MeshResolution::Coarse => "coarse",
            MeshResolution::Medium => "medium",
        }
    }
}

/// The surfaces the fiber flow enters through (potential 1): the origin.
pub const FIBER_INLETS: [&str; 1] = ["origin"];
/// The surfaces the fiber flow leaves through (potential 0): the aponeurosis and the
/// insertion, which hand the fibers' force to the tendinous tissue.
pub const FIBER_OUTLETS: [&str; 2] = ["aponeurosis", "insertion"];

/// The path of a muscle's mesh, `<data_dir>/<VI|VL|VM|RF>_<resolution>.msh`.
pub fn mesh_path(muscle: Quadriceps, resolution: MeshResolution) -> PathBuf {
    data_dir().join(format!(
        "{}_{}.msh",
        muscle.abbreviation(),
        resolution.name()
    ))
}

/// A muscle's volume mesh (one tet10 block, `muscle`) with its named surfaces.
pub fn load_muscle(muscle: Quadriceps, resolution: MeshResolution) -> Result<Mesh> {
    let path = mesh_path(muscle, resolution);
    Ok(read_mesh(&path)
        .with_context(|| format!("the Visible Human mesh {}", path.display()))?
        .mesh)
}

/// The names of the surfaces that mark the faces within 1 mm of another muscle's
/// segmented surface, `interface_<N>`, in the mesh.
pub fn interface_names(mesh: &Mesh) -> Vec<&str> {
    mesh.surfaces
        .keys()
        .map(String::as_str)
        .filter(|name| name.starts_with("interface_"))
        .collect()
}

/// The committed bone and cartilage surfaces (`<name>.stl`, binary STL in mm): the
/// femoral shaft built by the script (the femur is missing from the data) and the
/// segmented surfaces remeshed.
pub const SURFACES: [&str; 5] = [
    "femur_shaft",
    "femur_cartilage_distal",
    "patella",
    "patella_cartilage",
    "tibia",
];

/// One of the [`SURFACES`], in metres, with the vertices of bitwise equal coordinates
/// merged.
pub fn load_surface(name: &str) -> Result<TriangleSurface> {
    let path = data_dir().join(format!("{name}.stl"));
    let data = std::fs::read(&path).with_context(|| format!("reading {}", path.display()))?;
    let count = match data.get(80..84) {
        Some(bytes) => u32::from_le_bytes(bytes.try_into()?) as usize,
        None => bail!("{}: shorter than an STL header", path.display()),
    };
    if data.len() != 84 + 50 * count {
        bail!("{}: not a binary STL of {count} triangles", path.display());
    }
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    let mut surface = TriangleSurface::default();
    for t in 0..count {
        let mut triangle = [0; 3];
        for (k, corner) in triangle.iter_mut().enumerate() {
            let at = 84 + 50 * t + 12 * (k + 1);
            let bits: [u32; 3] = std::array::from_fn(|i| {
                u32::from_le_bytes(data[at + 4 * i..at + 4 * i + 4].try_into().unwrap())
            });
            *corner = *index.entry(bits).or_insert_with(|| {
                let [x, y, z] = bits.map(|b| f64::from(f32::from_bits(b)) * 1e-3);
                surface.vertices.push(Vector3::new(x, y, z));
                (surface.vertices.len() - 1) as u32
            });
        }
        surface.triangles.push(triangle);
    }
    Ok(surface)
}

/// The volume [m³] enclosed by a muscle's segmented surface, as the script recorded it
/// in `summary.csv` (column `surface_volume_mm3`).
pub fn recorded_surface_volume(muscle: Quadriceps) -> Result<f64> {
    let path = data_dir().join("summary.csv");
    let text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let column = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .with_context(|| format!("{}: no column {name}", path.display()))
    };
    let (name, volume) = (column("muscle")?, column("surface_volume_mm3")?);
    for line in lines {
        let fields: Vec<&str> = line.split(',').collect();
        if fields.get(name) == Some(&muscle.abbreviation()) {
            let mm3: f64 = fields
                .get(volume)
                .and_then(|v| v.parse().ok())
                .with_context(|| format!("{}: bad volume in '{line}'", path.display()))?;
            return Ok(mm3 * 1e-9);
        }
    }
    bail!("{}: no row for {}", path.display(), muscle.abbreviation())
}

/// The fiber directions of a muscle's mesh from the potential flow (seed §2.3) between
/// [`FIBER_INLETS`] and [`FIBER_OUTLETS`].
pub fn muscle_fibers(mesh: &Mesh) -> Result<FiberField> {
    let boundary = FlowBoundary::from_names(mesh, &FIBER_INLETS, &FIBER_OUTLETS)?;
    Ok(compute_fibers(mesh, &boundary, &FlowSettings::default())?)
}

/// Centroid of each element's corner nodes [m], in block order.
pub fn element_centroids(mesh: &Mesh) -> Vec<Vector3<f64>> {
    let mut centroids = Vec::with_capacity(mesh.element_count());
    for block in &mesh.blocks {
        let corners = block.shape.corner_count();
        for nodes in block.elements() {
            let sum: Vector3<f64> = nodes[..corners]
                .iter()
                .map(|&n| mesh.nodes.position(n as usize))
                .sum();
            centroids.push(sum / corners as f64);
        }
    }
    centroids
}

/// The muscle's long axis (unit, pointing proximally, +z): the principal direction of
/// largest variance of its element centroids.
pub fn long_axis(mesh: &Mesh) -> Vector3<f64> {
    let centroids = element_centroids(mesh);
    let mean = centroids.iter().sum::<Vector3<f64>>() / centroids.len() as f64;
    let covariance = centroids
        .iter()
        .map(|c| (c - mean) * (c - mean).transpose())
        .sum::<Matrix3<f64>>();
    let eigen = SymmetricEigen::new(covariance);
    let largest = eigen.eigenvalues.imax();
    let axis = eigen.eigenvectors.column(largest).into_owned();
    if axis.z < 0.0 { -axis } else { axis }
}

/// The distribution of the fibers' angle to the muscle's [`long_axis`] over its volume
/// [rad]: the volume-weighted mean and the 10th and 90th percentiles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PennationStatistics {
    /// Volume-weighted mean angle [rad].
    pub mean: f64,
    /// 10th percentile by volume [rad]: a tenth of the volume has fibers closer to the axis.
    pub p10: f64,
    /// 90th percentile by volume [rad].
    pub p90: f64,
}

/// The [`PennationStatistics`] of the fibers (one unit vector per element, in block
/// order) relative to the muscle's [`long_axis`]; each angle is in [0, π/2].
pub fn pennation_statistics(
    mesh: &Mesh,
    directions: &[Vector3<f64>],
) -> Result<PennationStatistics> {
    let axis = long_axis(mesh);
    let mut samples = Vec::with_capacity(mesh.element_count());
    let mut e = 0;
    for (b, block) in mesh.blocks.iter().enumerate() {
        for element in 0..block.len() {
            let volume = mesh.element_volume(ElementRef::new(b as u32, element as u32))?;
            let cosine = directions[e].dot(&axis).abs().min(1.0);
            samples.push((cosine.acos(), volume));
            e += 1;
        }
    }
    let total: f64 = samples.iter().map(|s| s.1).sum();
    let mean = samples.iter().map(|(a, v)| a * v).sum::<f64>() / total;
    samples.sort_by(|a, b| a.0.total_cmp(&b.0));
    let percentile = |q: f64| {
        let mut below = 0.0;
        for &(angle, volume) in &samples {
            below += volume;
            if below >= q * total {
                return angle;
            }
        }
        samples.last().map_or(0.0, |s| s.0)
    };
    Ok(PennationStatistics {
        mean,
        p10: percentile(0.1),
        p90: percentile(0.9),
    })
}

/// Volume-weighted mean angle [rad] between the fibers (one unit vector per element, in
/// block order) and the muscle's [`long_axis`]: the mean pennation relative to the line
/// of the muscle, in [0, π/2].
pub fn mean_pennation(mesh: &Mesh, directions: &[Vector3<f64>]) -> Result<f64> {
    Ok(pennation_statistics(mesh, directions)?.mean)
}
