//! The finite-element model of the squat: the quadriceps' mesh with fibers from the flow
//! solver, one Hill muscle part per muscle, the origins and insertions tied to the bones'
//! motions, and the interactions ([`super::interactions`]).

use std::sync::Arc;

use anyhow::{Context, Result, bail};

use musclefem_core::mesh::Mesh;
use musclefem_core::solver::{Loads, Part, RigidMotion, RigidTie};
use musclefem_fibers::{FiberField, FlowBoundary, FlowSettings, compute_fibers};
use musclefem_materials::{Material, MaterialLibrary};

use crate::elongation::ElementChoice;

use super::super::anatomy::{
    Anatomy, BoneMotions, Quadriceps, Squat, TendonSpring, TriangleSurface,
};
use super::patella::{PatellaTable, TendonPatella};

/// Density of muscle [kg/m³].
pub const MUSCLE_DENSITY: f64 = 1060.0;

/// Activation level of the active squat (seed §2.4: 50 % of maximum).
pub const ACTIVE_LEVEL: f64 = 0.5;

/// Knee flexion at which the active squat switches the quadriceps on [rad] (seed §2.4:
/// "at approximately 35° of knee flexion").
pub const ACTIVATION_FLEXION: f64 = 35.0 * std::f64::consts::PI / 180.0;

/// Passive or active quadriceps.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Activation {
    /// No activation: the Hill model's matrix and parallel element only.
    Passive,
    /// 50 % activation from 35° of flexion on, held through the extension back to 0°.
    Active,
}

impl Activation {
    /// `passive` or `active` (the CSV's `activation` column).
    pub fn name(self) -> &'static str {
        match self {
            Activation::Passive => "passive",
            Activation::Active => "active",
        }
    }
}

/// The geometry a squat runs on: the muscles' mesh, the bones and their motions. Built
/// from the default anatomy ([`KneeGeometry::default_knee`]) or read from files.
#[derive(Clone, Debug)]
pub struct KneeGeometry {
    /// One block per muscle, named as [`Quadriceps::name`], each with node sets
    /// `<block>_origin` and `<block>_insertion`.
    pub mesh: Mesh,
    /// The muscle of each block.
    pub muscles: Vec<Quadriceps>,
    /// The femur (with the pelvis) at 0° of flexion: the muscles bond to it and may not
    /// enter it.
    pub femur: TriangleSurface,
    /// The tibia and patella at 0° (for the frames of the bones).
    pub tibia: TriangleSurface,
    pub patella: TriangleSurface,
    /// The squat's bone motions with an inextensible tendon (the femur's and tibia's are
    /// the run's; the patella's is the run's at zero tension).
    pub motions: BoneMotions,
    /// The patella's poses with the patellar tendon as a spring (the run's patella).
    pub patella_table: Arc<PatellaTable>,
}

impl KneeGeometry {
    /// The default knee at the anatomy's resolution, squatting `squat`.
    pub fn default_knee(anatomy: &Anatomy, squat: &Squat) -> Result<Self> {
        let motions = squat
            .motions(&anatomy.kinematics, &anatomy.patella_reference)
            .context("the squat's bone motions")?;
        let patella_table = PatellaTable::new(
            &anatomy.kinematics,
            TendonSpring::default_knee(),
            squat.peak_flexion,
        )
        .context("the patella's poses with the tendon stretched")?;
        Ok(KneeGeometry {
            mesh: anatomy.muscle_mesh(),
            muscles: anatomy.muscles.iter().map(|m| m.muscle).collect(),
            femur: anatomy.bones.femur.clone(),
            tibia: anatomy.bones.tibia.clone(),
            patella: anatomy.bones.patella.clone(),
            motions,
            patella_table: Arc::new(patella_table),
        })
    }

    /// The block name of muscle block `b`.
    pub fn block_name(&self, b: usize) -> &str {
        &self.mesh.blocks[b].name
    }

    /// The node set `<block>_<end>` of block `b` (`end` = origin or insertion).
    pub fn end_nodes(&self, b: usize, end: &str) -> Result<Vec<u32>> {
        let name = format!("{}_{end}", self.block_name(b));
        let nodes = self
            .mesh
            .node_set(&name)
            .with_context(|| format!("the knee's muscle mesh has no node set '{name}'"))?;
        if nodes.is_empty() {
            bail!("node set '{name}' of the knee's muscle mesh is empty");
        }
        Ok(nodes.to_vec())
    }

    /// The fiber directions of every muscle from a potential flow, origin = inlet,
    /// insertion = outlet (one solve: the muscles are disconnected parts of one mesh).
    pub fn fibers(&self) -> Result<FiberField> {
        let names = |end: &str| -> Vec<String> {
            self.mesh
                .blocks
                .iter()
                .map(|b| format!("{}_{end}", b.name))
                .collect()
        };
        let boundary = FlowBoundary::from_names(&self.mesh, &names("origin"), &names("insertion"))
            .context("the muscles' origins and insertions as the flow's inlets and outlets")?;
        compute_fibers(&self.mesh, &boundary, &FlowSettings::default())
            .context("the quadriceps' fibers")
    }
}

/// The time at which the squat passes `flexion` [rad] on its way down [s].
pub fn flexion_time(squat: &Squat, flexion: f64) -> f64 {
    let phase = (1.0 - 2.0 * flexion / squat.peak_flexion).clamp(-1.0, 1.0);
    squat.duration * phase.acos() / (2.0 * std::f64::consts::PI)
}

/// The Hill muscle of `activation`: Table 1's parameters, `n2` = 0.5 from the time the
/// squat passes 35° (activation rate S = 50/s), never switched off (t1 = ∞).
pub fn muscle_material(activation: Activation, squat: &Squat) -> Result<Arc<dyn Material>> {
    let level = match activation {
        Activation::Passive => 0.0,
        Activation::Active => ACTIVE_LEVEL,
    };
    let parameters = [
        ("n2".to_string(), level),
        ("t0".to_string(), flexion_time(squat, ACTIVATION_FLEXION)),
    ]
    .into_iter()
    .collect();
    MaterialLibrary::with_builtins()
        .create("hill", &parameters)
        .context("the quadriceps' Hill muscle")
}

/// The mesh (with fibers), parts and loads of one squat.
pub struct KneeModel {
    pub mesh: Mesh,
    pub parts: Vec<Part>,
    /// Every origin tied to the femur, every insertion to the patella.
    pub loads: Loads,
    pub material: Arc<dyn Material>,
    /// The patella, held by the tendon against the pull the run reports.
    pub patella: Arc<TendonPatella>,
    /// Indices in `loads.rigid_ties` of the insertions (their reactions are the pull).
    pub insertion_ties: Vec<usize>,
}

impl KneeModel {
    /// The model of `geometry` with `fibers` and `activation` over `squat`, its muscles
    /// meshed with `element` (a hexahedron: the knee's meshes are hex8).
    pub fn new(
        geometry: &KneeGeometry,
        fibers: &FiberField,
        activation: Activation,
        squat: &Squat,
        element: ElementChoice,
    ) -> Result<Self> {
        if !element.is_hex() {
            bail!(
                "the knee's muscles are meshed with hex8: element {} needs a tetrahedral \
                 mesh (use hex8-fbar or hex8-one-point)",
                element.name()
            );
        }
        let mut mesh = geometry.mesh.clone();
        fibers
            .assign_to(&mut mesh)
            .context("assigning the fibers to the muscles")?;
        let material = muscle_material(activation, squat)?;
        let technology = element.technology(material.as_ref())?;
        let parts = (0..mesh.blocks.len())
            .map(|block| Part {
                block,
                technology,
                material: material.clone(),
                density: MUSCLE_DENSITY,
            })
            .collect();
        let patella = Arc::new(TendonPatella::new(geometry.patella_table.clone(), *squat));
        let mut rigid_ties = Vec::new();
        let mut insertion_ties = Vec::new();
        for (b, muscle) in geometry.muscles.iter().enumerate() {
            rigid_ties.push(RigidTie {
                name: format!("{}_origin", muscle.abbreviation()),
                nodes: geometry.end_nodes(b, "origin")?,
                motion: geometry.motions.femur.clone(),
            });
            insertion_ties.push(rigid_ties.len());
            rigid_ties.push(RigidTie {
                name: format!("{}_insertion", muscle.abbreviation()),
                nodes: geometry.end_nodes(b, "insertion")?,
                motion: RigidMotion::followed(patella.clone()),
            });
        }
        Ok(KneeModel {
            mesh,
            parts,
            loads: Loads {
                rigid_ties,
                ..Loads::default()
            },
            material,
            patella,
            insertion_ties,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_activation_starts_where_the_squat_passes_35_degrees() {
        let squat = Squat::to_ninety_degrees(2.0);
        let t = flexion_time(&squat, ACTIVATION_FLEXION);
        assert!((squat.flexion_at(t) - ACTIVATION_FLEXION).abs() < 1e-12);
        assert!(t > 0.0 && t < 0.5);
        assert_eq!(flexion_time(&squat, squat.peak_flexion), 1.0);
    }
}
