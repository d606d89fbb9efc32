//! The scene file as written (TOML, read with serde). Every table refuses unknown keys;
//! names that refer to other entries (materials, parts, node sets, amplitudes) are kept
//! with their position in the file, so that an error about them can name the line.
//! `docs/scene-format.md` documents the format with examples.

use std::collections::BTreeMap;

use serde::Deserialize;
use toml::Spanned;

pub use super::followers::MotionTable;

/// The version of the scene format this program reads.
pub const SCHEMA_VERSION: u32 = 1;

/// A whole scene file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Must equal [`SCHEMA_VERSION`].
    pub schema_version: Spanned<u32>,
    /// What the scene shows (free text, copied to the run log).
    #[serde(default)]
    pub description: String,
    /// Materials by local name.
    #[serde(default)]
    pub materials: Vec<MaterialEntry>,
    pub parts: Vec<PartEntry>,
    /// Piecewise-linear amplitudes by name.
    #[serde(default)]
    pub amplitudes: Vec<AmplitudeEntry>,
    /// Prescribed displacement components.
    #[serde(default)]
    pub displacements: Vec<DisplacementEntry>,
    /// Nodal forces.
    #[serde(default)]
    pub forces: Vec<ForceEntry>,
    /// Nodes moving with a rigid body.
    #[serde(default)]
    pub rigid_ties: Vec<RigidTieEntry>,
    /// Rigid surfaces (bones) with a prescribed motion, for interactions.
    #[serde(default)]
    pub rigid_bodies: Vec<RigidBodyEntry>,
    /// Contact and cohesion between surfaces.
    #[serde(default)]
    pub interactions: Vec<InteractionEntry>,
    /// Tension-only springs between pairs of nodes (tendons, aponeuroses).
    #[serde(default)]
    pub strands: Vec<StrandsEntry>,
    pub step: StepEntry,
    #[serde(default)]
    pub output: OutputEntry,
}

/// `[[materials]]`: a registry material (or one of a plugin) with its parameters.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialEntry {
    /// Local name the parts use.
    pub name: Spanned<String>,
    /// Registry name (`musclefem materials` lists them), e.g. "neo-hookean", "hill".
    pub model: Spanned<String>,
    /// Shared library to load first, relative to the scene file.
    pub plugin: Option<Spanned<String>>,
    /// Parameters overriding the model's defaults, in the model's units (SI).
    pub parameters: Option<Spanned<BTreeMap<String, f64>>>,
}

impl MaterialEntry {
    /// Set parameter `key` to `value` (as if the file said so; an error about it names the
    /// line of the `parameters` table, or of `model` if the file has none).
    pub fn set_parameter(&mut self, key: &str, value: f64) {
        let span = self.model.span();
        self.parameters
            .get_or_insert_with(|| Spanned::new(span, BTreeMap::new()))
            .get_mut()
            .insert(key.to_string(), value);
    }
}

/// `[[parts]]`: one deformable body.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartEntry {
    pub name: Spanned<String>,
    /// Local material name.
    pub material: Spanned<String>,
    /// Element technology: "hex8-full", "hex8-fbar", "hex8-one-point", "tet4",
    /// "tet4-nodal-average", "tet10" or "tet10-fbar" (`ElementKind::NAMES`).
    pub element: Spanned<String>,
    /// Reference mass density [kg/m³].
    pub density: Spanned<f64>,
    pub mesh: MeshEntry,
    /// Fiber direction of every element; default: the mesh file's Abaqus orientations,
    /// else along x.
    #[serde(default)]
    pub fibers: Option<Spanned<FiberEntry>>,
    /// A recorded activation history driving the part's material (which must have an
    /// activation: the Hill muscle), in place of the material's own n1, n2, t0, t1, S.
    #[serde(default)]
    pub activation: Option<Spanned<ActivationEntry>>,
}

/// `[parts.activation]`: where a part's activation a(t) comes from — an amplitude of the
/// scene, or a column of a CSV file or of an OpenSim storage file (`.sto`, `.mot`) — and
/// whether those values are activations or excitations (then turned into activation by
/// first-order dynamics).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActivationEntry {
    /// An amplitude of the scene whose values are the activation (or excitation) levels.
    pub amplitude: Option<Spanned<String>>,
    /// A CSV or OpenSim storage file, relative to the scene file.
    pub file: Option<Spanned<String>>,
    /// The file's column for this part.
    pub column: Option<Spanned<String>>,
    /// The file's time column (default "time").
    pub time_column: Option<Spanned<String>>,
    /// The record's time [s] at the scene's t = 0 (default 0): a record from a longer
    /// trial starts where the scene does.
    pub time_offset: Option<Spanned<f64>>,
    /// The values are excitations u ∈ [0, 1], not activations (default false).
    #[serde(default)]
    pub excitation: bool,
    /// τ_act [s] of the activation dynamics (default 0.010; only with `excitation`).
    pub activation_time_constant: Option<Spanned<f64>>,
    /// τ_deact [s] of the activation dynamics (default 0.040; only with `excitation`).
    pub deactivation_time_constant: Option<Spanned<f64>>,
}

/// `[parts.mesh]`: a generated box, or a block of a mesh file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshEntry {
    /// "box" (then `size` and `divisions`), or absent with `file`.
    pub generator: Option<Spanned<String>>,
    /// Edge lengths along x, y, z [m].
    pub size: Option<Spanned<[f64; 3]>>,
    /// Elements along x, y, z (boxes of tets have 6 tets per cell).
    pub divisions: Option<Spanned<[usize; 3]>>,
    /// Corner of the box with the smallest coordinates [m]; default the origin.
    pub origin: Option<[f64; 3]>,
    /// Abaqus `.inp` or Gmsh `.msh` file, relative to the scene file; coordinates in m
    /// unless `units` says otherwise.
    pub file: Option<Spanned<String>>,
    /// The length unit of the file's coordinates: "m" (the default) or "mm" (what
    /// segmentation tools and CAD write); read into metres.
    pub units: Option<Spanned<String>>,
    /// The element block of the file to use (by name); needed when it has several.
    pub block: Option<Spanned<String>>,
    /// Share the file's nodes with the other parts that take a block of the same file
    /// (with the same `units`) and say so: the file's nodes enter the model once, in the
    /// file's order, and blocks that meet there stay joined; default false (the part
    /// takes its own copy of its block's nodes).
    #[serde(default)]
    pub shared_nodes: bool,
}

/// `[parts.fibers]`: a constant fiber direction (normalised when read), one per element
/// from a fibers CSV file (`element,cx,cy,cz,fx,fy,fz`, as `musclefem fibers` writes), or
/// computed from a potential flow from `inlet` (origin) to `outlet` (insertion).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FiberEntry {
    pub direction: Option<Spanned<[f64; 3]>>,
    /// Relative to the scene file; element ids are the mesh file's labels, or 0-based
    /// indices for a generated mesh.
    pub file: Option<Spanned<String>>,
    /// Surfaces or node sets of the part where the flow enters (origin).
    pub inlet: Option<Spanned<OneOrMany>>,
    /// Surfaces or node sets of the part where the flow leaves (insertion).
    pub outlet: Option<Spanned<OneOrMany>>,
}

/// One name, or a list of names.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum OneOrMany {
    One(String),
    Many(Vec<String>),
}

impl OneOrMany {
    /// The names.
    pub fn names(&self) -> Vec<String> {
        match self {
            OneOrMany::One(name) => vec![name.clone()],
            OneOrMany::Many(names) => names.clone(),
        }
    }
}

/// `[[amplitudes]]`: a piecewise-linear function of time, constant outside its knots.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AmplitudeEntry {
    pub name: Spanned<String>,
    /// (time [s], value) knots with increasing times.
    /// (Read as lists so that a knot of another length is refused with its line.)
    pub points: Spanned<Vec<Vec<f64>>>,
}

/// `[[displacements]]`: components of a node set follow value × amplitude(t) [m].
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DisplacementEntry {
    pub part: Spanned<String>,
    /// Node set of the part (boxes have x0, x1, y0, y1, z0, z1 and all).
    pub nodes: Spanned<String>,
    /// Components: any of "x", "y", "z".
    pub components: Spanned<Vec<String>>,
    /// Displacement [m] (times the amplitude); default 0 (held).
    #[serde(default)]
    pub value: f64,
    /// Amplitude name; without one the value applies from t = 0.
    pub amplitude: Option<Spanned<String>>,
}

/// `[[forces]]`: a force on each node of a node set, value × amplitude(t) [N].
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceEntry {
    pub part: Spanned<String>,
    pub nodes: Spanned<String>,
    /// One of "x", "y", "z".
    pub component: Spanned<String>,
    /// Force per node [N] (times the amplitude).
    pub value: f64,
    pub amplitude: Option<Spanned<String>>,
}

/// `[[rigid_ties]]`: a node set moving with a rigid body.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidTieEntry {
    pub name: Spanned<String>,
    pub part: Spanned<String>,
    pub nodes: Spanned<String>,
    /// Translation [m] (times `translation_amplitude`); default none.
    #[serde(default)]
    pub translation: [f64; 3],
    pub translation_amplitude: Option<Spanned<String>>,
    /// Rotation about an axis; default none.
    pub rotation: Option<RotationEntry>,
    /// A pose the run sets, `{ follower = "KIND", ... }` (a registered follower kind and
    /// its parameters), in place of `translation` and `rotation`.
    pub motion: Option<Spanned<MotionTable>>,
}

/// `[rigid_ties.rotation]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotationEntry {
    /// A point of the axis [m].
    pub center: [f64; 3],
    /// Axis direction (normalised when read).
    pub axis: Spanned<[f64; 3]>,
    /// Angle [degrees] (times the amplitude), right-hand rule about the axis.
    pub angle_degrees: f64,
    pub amplitude: Option<Spanned<String>>,
}

/// `[[rigid_bodies]]`: a rigid triangle surface moving with a prescribed motion
/// x = c + R(t)(X − c) + T(t), like a rigid tie.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidBodyEntry {
    pub name: Spanned<String>,
    /// The surface: a generated shape or a file.
    pub surface: Spanned<RigidSurfaceEntry>,
    /// Translation [m] (times `translation_amplitude`); default none.
    #[serde(default)]
    pub translation: [f64; 3],
    pub translation_amplitude: Option<Spanned<String>>,
    /// Rotation about an axis; default none.
    pub rotation: Option<RotationEntry>,
    /// A pose the run sets, `{ follower = "KIND", ... }`, as for a rigid tie (a body
    /// with the same table as ties moves with them).
    pub motion: Option<Spanned<MotionTable>>,
}

/// `[rigid_bodies.surface]`: `shape = "plane"` (`point`, `normal`, `half_size`),
/// `"sphere"` (`center`, `radius`), `"cylinder"` (`center`, `axis`, `radius`,
/// `half_length`), or `file = "bone.stl"` (STL or OBJ, relative to the scene, in m or,
/// with `units = "mm"`, in millimetres).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidSurfaceEntry {
    pub shape: Option<Spanned<String>>,
    pub file: Option<Spanned<String>>,
    /// The length unit of the file's coordinates: "m" (default) or "mm" (read as 1e-3 m).
    pub units: Option<Spanned<String>>,
    /// A point of the plane [m].
    pub point: Option<[f64; 3]>,
    /// Outward normal of the plane (the side the bodies are on).
    pub normal: Option<[f64; 3]>,
    /// Half the side of the square plane patch [m].
    pub half_size: Option<f64>,
    /// Centre of the sphere or of the cylinder's axis [m].
    pub center: Option<[f64; 3]>,
    /// Axis direction of the cylinder.
    pub axis: Option<[f64; 3]>,
    /// Radius of the sphere or cylinder [m].
    pub radius: Option<f64>,
    /// Half the length of the cylinder [m].
    pub half_length: Option<f64>,
    /// Triangle subdivisions (refinement of the generated shape); default 16.
    pub divisions: Option<usize>,
}

/// `[[interactions]]`: contact (`kind = "contact"`, penalty, optional friction) or
/// cohesion (`kind = "cohesive"`, traction–separation with damage) of the `secondary`
/// surface's nodes against the `main` surface.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InteractionEntry {
    pub name: Spanned<String>,
    /// "contact" or "cohesive".
    pub kind: Spanned<String>,
    /// A surface of a part, "PART.SURFACE" (boxes have x0 … z1 and outer), or a list of
    /// them, one surface across parts that share nodes (their faces in the order listed).
    pub secondary: Spanned<OneOrMany>,
    /// A rigid body's name, or a surface of a part "PART.SURFACE", or a list of them.
    pub main: Spanned<OneOrMany>,
    /// Contact: penalty stiffness [N/m³] (pressure per penetration); default from the
    /// parts' stiffness and element size.
    pub penalty_stiffness: Option<Spanned<f64>>,
    /// Contact: Coulomb friction coefficient [1]; default 0 (frictionless).
    pub friction: Option<Spanned<f64>>,
    /// Contact: measure the gap and the force direction along the smooth field of vertex
    /// normals of the main surface instead of at the closest point; default false.
    pub smooth_normals: Option<Spanned<bool>>,
    /// Cohesive: K_nn [N/m³]; default 5e7 (0.05 N/mm³, the paper).
    pub normal_stiffness: Option<Spanned<f64>>,
    /// Cohesive: K_ss = K_tt [N/m³]; default 5e7.
    pub shear_stiffness: Option<Spanned<f64>>,
    /// Cohesive: separation at damage initiation [m]; default 0.03 (the paper's 30 mm).
    pub initiation_separation: Option<Spanned<f64>>,
    /// Cohesive: separation at failure [m] (linear damage evolution).
    pub failure_separation: Option<Spanned<f64>>,
    /// Cohesive: "elastic" (shear resisted by K_ss, the paper), "free-slide" (normal
    /// cohesion only) or "smooth-slide" (normal cohesion only, along the smooth normal
    /// field of the main surface); default "elastic".
    pub tangential: Option<Spanned<String>>,
    /// Cohesive: bonds form where the surfaces are within this distance at the start [m].
    pub bond_tolerance: Option<Spanned<f64>>,
    /// Cohesive: only the secondary faces whose centroids lie in this band of heights
    /// bond; default every face.
    pub bond_band: Option<Spanned<BondBandEntry>>,
    /// Cohesive: the fewest bonds the interface may have; fewer is an error. Default 1.
    pub minimum_bonds: Option<Spanned<usize>>,
}

/// `[[strands]]`: tendon strands, tension-only toe-then-linear springs between pairs of
/// nodes of a mesh file that parts share (`shared_nodes = true`), read from a CSV file
/// (`musclefem_io::strand_csv`). Their forces are summed after the `[[interactions]]`'.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrandsEntry {
    pub name: Spanned<String>,
    /// A part whose mesh file (read with `shared_nodes = true`) holds the strands' nodes;
    /// the file's node labels name them, nodes in no element included.
    pub part: Spanned<String>,
    /// The strands, relative to the scene file.
    pub file: Spanned<String>,
}

/// `bond_band = { axis, heights }` of a cohesive interaction: a band of heights along
/// an axis.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BondBandEntry {
    /// The direction heights are measured along (made unit length) [1].
    pub axis: [f64; 3],
    /// The lowest and the highest height of a face centroid, x · axis [m].
    pub heights: [f64; 2],
}

/// `[step]`: the analysis.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepEntry {
    /// "auto" (the default: see `solver_choice.rs`), "explicit" or "implicit".
    pub solver: Option<Spanned<String>>,
    /// Duration [s] (the step starts at t = 0).
    pub duration: Spanned<f64>,
    /// Time between output rows/frames [s]; default duration / 100.
    pub output_interval: Option<Spanned<f64>>,
    #[serde(default)]
    pub explicit: ExplicitEntry,
    #[serde(default)]
    pub implicit: ImplicitEntry,
}

/// `[step.explicit]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExplicitEntry {
    /// Fraction of the stable step (0, 1]; default 0.9.
    pub safety_factor: Option<Spanned<f64>>,
    /// Mass scaling to this stable step [s]; default none.
    pub mass_scaling_time_step: Option<Spanned<f64>>,
    /// Linear and quadratic bulk viscosity on (Abaqus defaults 0.06, 1.2); default off.
    #[serde(default)]
    pub bulk_viscosity: bool,
    /// Shear (deviatoric) viscosity η [Pa s] of every element; default none.
    pub shear_viscosity: Option<Spanned<f64>>,
    /// Largest energy-balance error as a fraction of the largest energy; default 0.01.
    pub energy_tolerance: Option<Spanned<f64>>,
    /// The rigid body whose motion carries the mass that mass scaling adds (it gets the
    /// body's acceleration as a body force); default none.
    pub mass_scaling_frame: Option<Spanned<String>>,
}

/// `[step.implicit]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImplicitEntry {
    /// Increments over the duration; default 10.
    pub increments: Option<Spanned<usize>>,
    /// Newmark dynamics instead of quasi-static; default false.
    #[serde(default)]
    pub dynamic: bool,
    /// Automatic step cutting on a failed increment; default true.
    pub step_cutting: Option<bool>,
    /// Relative residual tolerance; default that of the solver.
    pub residual_tolerance: Option<Spanned<f64>>,
    /// Relative correction tolerance; default that of the solver (1e-6).
    pub correction_tolerance: Option<Spanned<f64>>,
    /// Newton iterations allowed per increment; default 25.
    pub max_iterations: Option<Spanned<usize>>,
    /// Halvings the line search may try per Newton iteration; default 8.
    pub line_search_cuts: Option<Spanned<usize>>,
    /// Reuse the last factor as a conjugate-gradient preconditioner; default true.
    pub factor_reuse: Option<bool>,
    /// Stop the iterative linear solves at Newton's forcing term (Eisenstat–Walker);
    /// default true.
    pub inexact_newton: Option<bool>,
    /// Start each increment from the last one extrapolated when that guess is good;
    /// default true.
    pub extrapolate: Option<bool>,
    /// With `dynamic`: Newmark's numerical dissipation α ∈ [0, 0.5] (γ = ½ + α,
    /// β = (1 + α)²/4); default 0, the trapezoidal rule.
    pub numerical_dissipation: Option<Spanned<f64>>,
    /// A rigid body whose motion carries the model to each increment's first guess.
    pub predictor_frame: Option<Spanned<String>>,
    /// The solver of symmetric tangents: "direct" (default), "amg_cg" (conjugate
    /// gradients preconditioned with smoothed-aggregation multigrid) or "auto".
    pub linear_solver: Option<Spanned<String>>,
}

/// `[output]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputEntry {
    /// Write VTU frames (ParaView); default true.
    pub frames: Option<bool>,
    /// Time between frames [s]; default the step's `output_interval`.
    pub frame_interval: Option<Spanned<f64>>,
    /// Each part's P-th percentile of its elements' von Mises stress in `history.csv`
    /// (P ∈ (0, 100); the paper's peak stress is P = 95).
    pub von_mises_percentile: Option<Spanned<f64>>,
}
