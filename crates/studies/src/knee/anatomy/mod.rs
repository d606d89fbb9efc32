//! The procedural anatomy of the knee scene (issue 8), built into the program: rigid femur,
//! tibia and patella as closed triangle surfaces, the four quadriceps as hex8 meshes, the
//! patellar tendon's attachments, and the knee's kinematics.
//!
//! - [`dimensions`]: the frame (x anterior, y proximal, z lateral; origin on the flexion
//!   axis), the landmark dimensions with their sources, and [`KneeDimensions`], the
//!   landmarks the mechanism reads;
//! - [`surface`]: [`TriangleSurface`], its closedness check, volume and winding number;
//! - [`implicit`]: implicit primitives and marching tetrahedra;
//! - [`bones`]: femur, tibia, patella;
//! - [`kinematics`]: tibia rotation about the flexion axis, patellar tracking by
//!   trochlear contact, tendon and quadriceps equilibrium;
//! - [`rollback`]: the femur's rollback on the tibial plateau (a fixed axis unless a
//!   knee's dimensions ask for rolling);
//! - [`path`]: the quadriceps' free path, wrapped over the trochlea;
//! - [`muscles`]: VI, VL, VM and RF as swept solids and meshes, volume-matched to the
//!   Visible Human;
//! - [`moment_arms`]: musculotendon lengths and moment arms r = dL/dθ;
//! - [`closed_chain`]: the paper's closed-chain squat: ankle pinned, pelvis moved
//!   vertically, hip flexing with the knee;
//! - [`squat`]: θ(t) for 0° → 90° → 0° and the bones' [`RigidMotion`]s;
//! - [`tendon`]: the patellar tendon's toe-then-linear spring and its stiffness source;
//! - [`export`]: the anatomy at a flexion angle as STL and VTU files;
//! - [`visible_human`]: the Visible Human Female's segmented quadriceps as tet10 meshes
//!   (committed data, issue #35; not yet part of the knee scene).
//!
//! Except for [`visible_human`]'s committed meshes, no data file is read: every number
//! of the procedural knee is a documented constant (the Visible Human
//! volumes and the OpenSim moment arms it was dimensioned from live in
//! `../shared/data/knee_reference/` and are read only by the tests).
//!
//! [`RigidMotion`]: musclefem_core::solver::RigidMotion

pub mod bones;
pub mod closed_chain;
pub mod dimensions;
pub mod export;
pub mod implicit;
pub mod kinematics;
pub mod moment_arms;
pub mod muscles;
pub mod path;
pub mod rollback;
pub mod squat;
pub mod surface;
pub mod tendon;
pub mod visible_human;

use anyhow::{Context, Result};
use nalgebra::Vector3;

use musclefem_core::mesh::Mesh;

pub use bones::Bones;
pub use closed_chain::{ClosedChain, LegPose};
pub use dimensions::KneeDimensions;
pub use kinematics::{KneeKinematics, PatellaPose};
pub use muscles::{BlockRole, Muscle, Quadriceps, Tissue};
pub use rollback::Rollback;
pub use squat::{BoneMotions, Squat};
pub use surface::TriangleSurface;
pub use tendon::TendonSpring;

use dimensions::MM;

/// How finely the muscles and bones are meshed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Resolution {
    /// 4 × 4 O-grid cells inside 1 ring (32 per section), 12 layers: 384 hex8 per
    /// muscle belly, 1536 in all, and 1376 in the tendons; bones on a 3 mm grid at the knee
    /// (9 mm along the shafts).
    Coarse,
    /// 6 × 6 inside 2 rings (84 per section), 28 layers: 2352 per muscle belly, 9408 in
    /// all, plus the tendons; bones on a 2 mm grid at the knee (6 mm along the shafts).
    Medium,
    /// 8 × 8 inside 3 rings (160 per section), 56 layers: 8960 per muscle belly, 35 840
    /// in all, plus the tendons; bones on a 1.5 mm grid at the knee (4.5 mm along the
    /// shafts).
    Fine,
}

impl Resolution {
    /// O-grid cells per side, rings and layers of every muscle's mesh.
    pub fn muscle_divisions(self) -> (usize, usize, usize) {
        match self {
            Resolution::Coarse => (4, 1, 12),
            Resolution::Medium => (6, 2, 28),
            Resolution::Fine => (8, 3, 56),
        }
    }

    /// Elements per muscle belly: (n² + 4 n r) per section × layers, for n × n O-grid
    /// cells inside r rings (the tendons are meshed at the same density beyond).
    pub fn elements_per_muscle(self) -> usize {
        let (cells, rings, layers) = self.muscle_divisions();
        (cells * cells + 4 * cells * rings) * layers
    }

    /// Mean muscle element size [m]: (V / N)^(1/3) for the four bellies' Visible Human
    /// volume V and their N elements (coarse 12.8 mm, medium 7.0 mm, fine 4.5 mm).
    pub fn mean_element_size(self) -> f64 {
        let volume: f64 = Quadriceps::ALL
            .iter()
            .map(|m| m.visible_human_volume())
            .sum();
        let elements = Quadriceps::ALL.len() * self.elements_per_muscle();
        (volume / elements as f64).cbrt()
    }

    /// The resolution whose [`Resolution::mean_element_size`] is within 1 % of `size` [m].
    pub fn with_mean_element_size(size: f64) -> Option<Resolution> {
        [Resolution::Coarse, Resolution::Medium, Resolution::Fine]
            .into_iter()
            .find(|r| (r.mean_element_size() - size).abs() <= 0.01 * size)
    }

    /// Grid spacing of the bones' marching tetrahedra [m].
    pub fn bone_spacing(self) -> f64 {
        match self {
            Resolution::Coarse => 3.0 * MM,
            Resolution::Medium => 2.0 * MM,
            Resolution::Fine => 1.5 * MM,
        }
    }
}

/// The patellar tendon: its attachments and rest length. Its force–length law is
/// [`TendonSpring`], slack at this rest length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatellarTendon {
    /// The apex of the patella [m], at the patella's 0° pose (global frame).
    pub apex: Vector3<f64>,
    /// The tibial tuberosity [m], at the tibia's 0° pose (global frame).
    pub tuberosity: Vector3<f64>,
    /// Rest length [m] (the apex–tuberosity distance the kinematics keeps without a
    /// pull).
    pub length: f64,
}

impl PatellarTendon {
    /// The slack tendon of the knee of `dimensions`, its patella at `patella_reference`
    /// (the pose at 0°).
    pub fn from_dimensions(dimensions: &KneeDimensions, patella_reference: &PatellaPose) -> Self {
        Self {
            apex: patella_reference.to_world(&dimensions.apex),
            tuberosity: dimensions.tuberosity,
            length: dimensions.patellar_tendon_length,
        }
    }
}

/// The procedural knee: bones, muscles, patellar tendon and kinematics, every part in its
/// pose at 0° of flexion in the global frame of [`dimensions`].
#[derive(Clone, Debug)]
pub struct Anatomy {
    /// Femur, tibia and patella at 0°.
    pub bones: Bones,
    /// VI, VL, VM, RF (in [`Quadriceps::ALL`] order).
    pub muscles: Vec<Muscle>,
    pub patellar_tendon: PatellarTendon,
    /// The knee's kinematics, which hold its landmarks ([`Anatomy::dimensions`]).
    pub kinematics: KneeKinematics,
    /// The patella's pose at 0° (the reference pose of the patella's surface and of its
    /// rigid motion).
    pub patella_reference: PatellaPose,
    pub resolution: Resolution,
}

impl Anatomy {
    /// The default right knee at `resolution`: the quadriceps' femur-fixed stations set
    /// the patella's equilibrium at 0°, which places the muscles' insertions; then the
    /// muscles are volume-matched and meshed, and the bones triangulated.
    pub fn procedural_knee(resolution: Resolution) -> Result<Anatomy> {
        let kinematics = KneeKinematics::from_dimensions(
            KneeDimensions::procedural_knee(),
            Quadriceps::ALL.iter().map(|m| m.pull()).collect(),
        );
        let reference = kinematics
            .patella_pose(0.0)
            .context("the patella's pose in extension")?;
        let muscles = Quadriceps::ALL
            .iter()
            .map(|&m| Muscle::new(m, &reference, resolution))
            .collect::<Result<Vec<_>>>()?;
        let mut bones = Bones::new(resolution.bone_spacing())?;
        bones.patella = bones.patella.transformed(&reference.isometry());
        Ok(Anatomy {
            bones,
            patellar_tendon: PatellarTendon::from_dimensions(&kinematics.dimensions, &reference),
            muscles,
            kinematics,
            patella_reference: reference,
            resolution,
        })
    }

    /// The knee's landmarks, those its kinematics reads.
    pub fn dimensions(&self) -> &KneeDimensions {
        &self.kinematics.dimensions
    }

    /// The muscle `muscle`.
    pub fn muscle(&self, muscle: Quadriceps) -> &Muscle {
        self.muscles
            .iter()
            .find(|m| m.muscle == muscle)
            .expect("the procedural knee has all four quadriceps")
    }

    /// The four muscles' meshes as one mesh, the bellies first, and every block's role
    /// (see [`muscles::combined_mesh`]).
    pub fn muscle_mesh(&self) -> (Mesh, Vec<BlockRole>) {
        muscles::combined_mesh(&self.muscles)
    }
}
