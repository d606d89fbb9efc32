//! The finite-element model of the squat: the quadriceps' mesh with fibers from the flow
//! solver, one Hill muscle part per belly and a tendon part per tendon block, the origins
//! tied to the femur (vasti) and the pelvis (rectus femoris), the insertions to the
//! patella, and the interactions ([`super::interactions`]).

use std::sync::Arc;

use anyhow::{Context, Result, bail};

use musclefem_core::element::Technology;
use musclefem_core::mesh::{ElementRef, ElementShape, Face, Mesh};
use musclefem_core::solver::{Loads, Part, RigidMotion, RigidTie};
use musclefem_fibers::{FiberField, FlowBoundary, FlowSettings, compute_fibers};
use musclefem_materials::hill::{HillMuscle, HillParameters};
use musclefem_materials::{Material, MaterialLibrary};

use crate::elongation::ElementChoice;

use super::super::anatomy::bones::{femur_distance, implicit_normals};
use super::super::anatomy::moment_arms::belly_stretch_in_squat;
use super::super::anatomy::visible_human::TendonStrand;
use super::super::anatomy::visible_human::tracking::PatellaTracking;
use super::super::anatomy::{
    Anatomy, BlockRole, BoneMotions, ClosedChain, KneeDimensions, Quadriceps, Squat, TendonSpring,
    Tissue, TriangleSurface,
};
use super::patella::{PatellaTable, TendonPatella};

/// Density of muscle [kg/m³].
pub const MUSCLE_DENSITY: f64 = 1060.0;

/// Density of tendon [kg/m³] (Ker 1981, J Exp Biol 93:283: 1120 kg/m³ for sheep tendon).
pub const TENDON_DENSITY: f64 = 1120.0;

/// Activation level of the active squat (seed §2.4: 50 % of maximum).
pub const ACTIVE_LEVEL: f64 = 0.5;

/// Knee flexion at which the quadriceps' passive fibers become taut [rad]: 60°. See the
/// module documentation of [`super`] ("Passive slack").
pub const PASSIVE_SLACK_FLEXION: f64 = 60.0 * std::f64::consts::PI / 180.0;

/// Knee flexion at which the active squat switches the quadriceps on [rad] (seed §2.4:
/// "at approximately 35° of knee flexion").
pub const ACTIVATION_FLEXION: f64 = 35.0 * std::f64::consts::PI / 180.0;

/// Passive or active quadriceps (active: 50 % from [`ACTIVATION_FLEXION`] on, held
/// through the extension back to 0°).
pub use crate::activation::Activation;

/// The geometry a squat runs on: the muscles' mesh, the bones and their motions. Built
/// from the procedural anatomy ([`KneeGeometry::procedural_knee`]) or read from files.
#[derive(Clone, Debug)]
pub struct KneeGeometry {
    /// The bellies first, one block per muscle in the order of `muscles` (block `b` is
    /// `muscles[b]`'s belly), then any tendon blocks; node sets `<belly>_origin` and
    /// `<belly>_insertion` for every muscle (its ends, on its belly or its tendons), and
    /// `<belly>_belly_start` and `<belly>_belly_end` where it has tendons.
    pub mesh: Mesh,
    /// The muscle of each belly block.
    pub muscles: Vec<Quadriceps>,
    /// The muscle and tissue of every block.
    pub roles: Vec<BlockRole>,
    /// The femur at 0° of flexion: the muscles slide on it and may not enter it.
    pub femur: TriangleSurface,
    /// The femur's outward normals at its vertices where its shape gives them (the
    /// procedural anatomy's implicit femur), else `None` (the facets' are averaged).
    pub femur_normals: Option<Vec<nalgebra::Vector3<f64>>>,
    /// The tibia and patella at 0° (for the frames of the bones).
    pub tibia: TriangleSurface,
    pub patella: TriangleSurface,
    /// The knee's landmarks (the patellar tendon's apex and tuberosity for its extensor
    /// moment).
    pub dimensions: KneeDimensions,
    /// The squat's bone motions (the closed chain).
    pub motions: BoneMotions,
    /// Where each muscle's fiber laws start (in `muscles` order): the procedural knee's
    /// parallel element slack up to the mean fiber stretch its belly reaches at
    /// [`PASSIVE_SLACK_FLEXION`] of knee flexion in the squat, the Visible Human's whole
    /// fiber-direction law from the stretch where its fibers reach optimal length
    /// ([`FiberReference::rest_at`]); the paper's reference for user anatomies. See the
    /// module documentation of [`super`].
    pub fiber_reference: Vec<FiberReference>,
    /// The patella's poses in the femur's frame with the patellar tendon as a spring
    /// (the run's patella).
    pub patella_table: Arc<PatellaTable>,
    /// Tendon strands from the muscles' fiber outlets to their attachment nodes on the
    /// patella (the Visible Human knee's tendinous tissue); none where the tendons are
    /// element blocks (the procedural anatomy).
    pub strands: Vec<TendonStrand>,
    /// The planar patella against the trochlear groove (the Visible Human knee's; the
    /// procedural knee has no cartilage surface to read it from).
    pub patella_tracking: Option<PatellaTracking>,
}

impl KneeGeometry {
    /// The procedural knee at the anatomy's resolution, squatting `squat`.
    pub fn procedural_knee(anatomy: &Anatomy, squat: &Squat) -> Result<Self> {
        let dimensions = *anatomy.dimensions();
        let motions = squat
            .motions(&ClosedChain::from_dimensions(&dimensions))
            .context("the squat's bone motions")?;
        let patella_table = PatellaTable::new(
            &anatomy.kinematics,
            TendonSpring::from_dimensions(&dimensions),
            squat.peak_flexion,
        )
        .context("the patella's poses with the tendon stretched")?;
        let (mesh, roles) = anatomy.muscle_mesh();
        let fiber_reference =
            belly_stretch_in_squat(&anatomy.kinematics, &anatomy.muscles, PASSIVE_SLACK_FLEXION)
                .context("the muscles' fiber stretch in the squat")?
                .into_iter()
                .map(|s| FiberReference::parallel_slack(s.max(1.0)))
                .collect();
        Ok(KneeGeometry {
            mesh,
            muscles: anatomy.muscles.iter().map(|m| m.muscle).collect(),
            roles,
            femur: anatomy.bones.femur.clone(),
            femur_normals: Some(implicit_normals(&anatomy.bones.femur, femur_distance)),
            tibia: anatomy.bones.tibia.clone(),
            patella: anatomy.bones.patella.clone(),
            dimensions,
            motions,
            fiber_reference,
            patella_table: Arc::new(patella_table),
            strands: Vec::new(),
            patella_tracking: None,
        })
    }

    /// Name the outer surface of every block without a `<block>_lateral` surface (muscles
    /// read from files, the Visible Human's) `<block>_outer`: the faces of its elements
    /// that no other element of the block shares, in (element, face) order. The
    /// interactions take a muscle's `_lateral` surface, else this one
    /// ([`muscle_surface_name`]), in the knee and in its scene alike.
    pub fn name_outer_surfaces(&mut self) -> Result<()> {
        for b in 0..self.mesh.blocks.len() {
            let name = self.block_name(b).to_string();
            if self.mesh.surfaces.contains_key(&format!("{name}_lateral")) {
                continue;
            }
            let alone = Mesh::new(self.mesh.nodes.clone(), vec![self.mesh.blocks[b].clone()]);
            let faces: Vec<Face> = (alone.boundary_faces())
                .with_context(|| format!("the outer surface of block '{name}'"))?
                .into_iter()
                .map(|f| Face::new(ElementRef::new(b as u32, f.element.element), f.face))
                .collect();
            self.mesh.surfaces.insert(format!("{name}_outer"), faces);
        }
        Ok(())
    }

    /// The block name of muscle block `b`.
    pub fn block_name(&self, b: usize) -> &str {
        &self.mesh.blocks[b].name
    }

    /// The node set `<block>_<end>` of muscle block `b` (`end` = origin or insertion).
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

    /// The tendon blocks, with the index of their muscle in `muscles`.
    pub fn tendon_blocks(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.roles
            .iter()
            .enumerate()
            .filter(|(_, role)| role.tissue == Tissue::Tendon)
            .filter_map(|(b, role)| {
                self.muscles
                    .iter()
                    .position(|&m| m == role.muscle)
                    .map(|m| (b, m))
            })
    }

    /// How muscle block `b`'s origin moves: with the femur for the vasti; for the rectus
    /// femoris, pinned at the anterior inferior iliac spine (the centre of its origin's
    /// nodes), carried by the pelvis without turning with it, as its direct tendon swings
    /// about the spine when the hip flexes.
    pub fn origin_motion(&self, b: usize) -> Result<RigidMotion> {
        Ok(match self.muscles[b] {
            Quadriceps::RectusFemoris => {
                let nodes = self.end_nodes(b, "origin")?;
                let centre = nodes
                    .iter()
                    .map(|&n| self.mesh.nodes.position(n as usize))
                    .sum::<nalgebra::Vector3<f64>>()
                    / nodes.len() as f64;
                self.motions.pinned_to_pelvis(centre)
            }
            _ => self.motions.femur.clone(),
        })
    }

    /// The name of the node set through which the flow enters (`start`) or leaves muscle
    /// block `b`'s belly: `<block>_belly_start`/`_belly_end` where the mesh has them,
    /// else the origin and insertion.
    fn belly_end(&self, b: usize, start: bool) -> String {
        let name = self.block_name(b);
        let (belly, end) = if start {
            ("belly_start", "origin")
        } else {
            ("belly_end", "insertion")
        };
        let belly = format!("{name}_{belly}");
        if self.mesh.node_sets.contains_key(&belly) {
            belly
        } else {
            format!("{name}_{end}")
        }
    }

    /// The mesh with `fibers` (computed by [`KneeGeometry::fibers`]) as its bellies'
    /// fiber directions: the mesh the squat runs on and its frames show.
    pub fn fibered_mesh(&self, fibers: &FiberField) -> Result<Mesh> {
        let mut mesh = self.mesh.clone();
        for (b, block) in mesh.blocks.iter_mut().enumerate().take(self.muscles.len()) {
            let directions = fibers.block_directions(b);
            if directions.len() != block.len() {
                bail!(
                    "the fibers of block '{}' do not match its {} elements",
                    block.name,
                    block.len()
                );
            }
            block.fiber_direction = directions.to_vec();
        }
        Ok(mesh)
    }

    /// The fiber directions of every muscle's belly from a potential flow, its start
    /// (origin) the inlet, its end (the muscle–tendon junction) the outlet: one solve on
    /// the bellies alone (the muscles are disconnected parts of one mesh). The field's
    /// blocks are the belly blocks `0..muscles.len()`.
    pub fn fibers(&self) -> Result<FiberField> {
        let bellies = self.muscles.len();
        let mut mesh = Mesh::new(
            self.mesh.nodes.clone(),
            self.mesh.blocks[..bellies].to_vec(),
        );
        let ends = |start: bool| -> Vec<String> {
            (0..bellies).map(|b| self.belly_end(b, start)).collect()
        };
        let (inlets, outlets) = (ends(true), ends(false));
        for name in inlets.iter().chain(&outlets) {
            let nodes = self.mesh.node_set(name)?.to_vec();
            mesh.node_sets.insert(name.clone(), nodes);
        }
        let boundary = FlowBoundary::from_names(&mesh, &inlets, &outlets)
            .context("the muscles' origins and junctions as the flow's inlets and outlets")?;
        compute_fibers(&mesh, &boundary, &FlowSettings::default()).context("the quadriceps' fibers")
    }
}

/// The time at which the squat passes `flexion` [rad] on its way down [s].
pub fn flexion_time(squat: &Squat, flexion: f64) -> f64 {
    let phase = (1.0 - 2.0 * flexion / squat.peak_flexion).clamp(-1.0, 1.0);
    squat.duration * phase.acos() / (2.0 * std::f64::consts::PI)
}

/// Where a muscle's fiber-direction laws start, as isochoric fiber stretches from the
/// mesh's pose (0° of flexion): the Hill parameters λ_PE, λ_M and λ_opt.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FiberReference {
    /// The parallel element's slack stretch λ_PE.
    pub parallel_slack: f64,
    /// The matrix's slack stretch along the fiber λ_M.
    pub matrix_slack: f64,
    /// The force–length relation's optimal stretch λ_opt.
    pub optimal_stretch: f64,
}

impl FiberReference {
    /// The paper's: the mesh's pose is the specimen's rest (λ_PE = λ_M = 1, λ_opt = 1.05).
    pub fn paper() -> Self {
        let paper = HillParameters::default();
        FiberReference {
            parallel_slack: paper.parallel_slack,
            matrix_slack: paper.matrix_slack,
            optimal_stretch: paper.optimal_stretch,
        }
    }

    /// The paper's with the parallel element slack up to `slack` (the procedural knee).
    pub fn parallel_slack(slack: f64) -> Self {
        FiberReference {
            parallel_slack: slack,
            ..Self::paper()
        }
    }

    /// The paper's laws moved to start at the fiber stretch `rest` (≥ 1), where the
    /// relaxed fibers are at the paper's rest length: λ_PE = λ_M = rest and λ_opt = 1.05
    /// rest. For muscles whose mesh pose is shorter than their fibers' rest length.
    pub fn rest_at(rest: f64) -> Self {
        let paper = Self::paper();
        FiberReference {
            parallel_slack: paper.parallel_slack * rest,
            matrix_slack: paper.matrix_slack * rest,
            optimal_stretch: paper.optimal_stretch * rest,
        }
    }
}

/// The Hill muscle of `activation`: Table 1's parameters, `n2` = 0.5 from the time the
/// squat passes 35° (activation rate S = 50/s), never switched off (t1 = ∞), the fiber
/// laws starting at `reference` (see [`KneeGeometry::fiber_reference`]).
pub fn muscle_material(
    activation: Activation,
    squat: &Squat,
    reference: &FiberReference,
) -> Result<Arc<dyn Material>> {
    HillMuscle::with_parameters(&muscle_parameters(activation, squat, reference))
        .context("the quadriceps' Hill muscle")
}

/// The parameters of [`muscle_material`].
pub fn muscle_parameters(
    activation: Activation,
    squat: &Squat,
    reference: &FiberReference,
) -> HillParameters {
    let level = match activation {
        Activation::Passive => 0.0,
        Activation::Active => ACTIVE_LEVEL,
    };
    let mut parameters = HillParameters::default();
    parameters.activation.n2 = level;
    parameters.activation.t0 = flexion_time(squat, ACTIVATION_FLEXION);
    parameters.parallel_slack = reference.parallel_slack;
    parameters.matrix_slack = reference.matrix_slack;
    parameters.optimal_stretch = reference.optimal_stretch;
    parameters
}

/// The name of the surface of block `block` that the knee's interactions act on: its
/// `<block>_lateral` surface (the procedural anatomy's: the sides without the end faces)
/// when `mesh` has one, else `<block>_outer` ([`KneeGeometry::name_outer_surfaces`]).
pub fn muscle_surface_name(mesh: &Mesh, block: &str) -> Result<String> {
    for name in [format!("{block}_lateral"), format!("{block}_outer")] {
        if mesh.surfaces.contains_key(&name) {
            return Ok(name);
        }
    }
    bail!("the knee's mesh has neither '{block}_lateral' nor '{block}_outer'")
}

/// The element of a block of `shape`: `element` (a hexahedron) for the hex8 blocks of
/// the procedural anatomy, the quadratic tetrahedron with the element's mean dilatation
/// (F-bar: muscle is nearly incompressible, K/μ ≈ 10⁴, where the plain tet10's pressure
/// oscillates) for the Visible Human's tet10 meshes.
pub fn block_element(element: ElementChoice, shape: ElementShape) -> Result<ElementChoice> {
    match shape {
        ElementShape::Hex8 if element.is_hex() => Ok(element),
        ElementShape::Hex8 => bail!(
            "the knee's hex8 blocks need a hexahedron: element {} is not one (use hex8-fbar \
             or hex8-one-point)",
            element.name()
        ),
        ElementShape::Tet10 => Ok(ElementChoice::Tet10Fbar),
        ElementShape::Tet4 => bail!("the knee takes hex8 or tet10 meshes, not tet4"),
    }
}

/// The element technology of a block of `shape` ([`block_element`]) for `material`.
pub fn block_technology(
    element: ElementChoice,
    shape: ElementShape,
    material: &dyn Material,
) -> Result<Technology> {
    block_element(element, shape)?.technology(material)
}

/// The tendon material: [`musclefem_materials::tendon`] with its defaults (fibers of
/// 1 GPa in a 1 MPa matrix).
pub fn tendon_material() -> Result<Arc<dyn Material>> {
    MaterialLibrary::with_builtins()
        .create("tendon", &Default::default())
        .context("the quadriceps' tendon material")
}

/// The mesh (with fibers), parts and loads of one squat.
pub struct KneeModel {
    pub mesh: Mesh,
    pub parts: Vec<Part>,
    /// Every origin tied to the femur or pelvis, every insertion to the patella.
    pub loads: Loads,
    /// The muscles' material with the paper's parallel element (each muscle's part has
    /// its own slack, [`KneeGeometry::passive_slack`]; the tendons' is [`tendon_material`]).
    pub material: Arc<dyn Material>,
    /// The patella, held by the tendon against the pull the run reports.
    pub patella: Arc<TendonPatella>,
    /// Indices in `loads.rigid_ties` of the insertions (their reactions are the pull).
    pub insertion_ties: Vec<usize>,
}

impl KneeModel {
    /// The model of `geometry` with `fibers` and `activation` over `squat`, its hex8
    /// blocks with `element` (a hexahedron), its tet10 blocks with the F-bar quadratic
    /// tetrahedron ([`block_technology`]).
    pub fn new(
        geometry: &KneeGeometry,
        fibers: &FiberField,
        activation: Activation,
        squat: &Squat,
        element: ElementChoice,
    ) -> Result<Self> {
        let mesh = geometry.fibered_mesh(fibers)?;
        let materials = geometry
            .fiber_reference
            .iter()
            .map(|reference| muscle_material(activation, squat, reference))
            .collect::<Result<Vec<_>>>()?;
        let material = muscle_material(activation, squat, &FiberReference::paper())?;
        let tendon = tendon_material()?;
        let parts = geometry
            .roles
            .iter()
            .enumerate()
            .map(|(block, role)| {
                let muscle = geometry.muscles.iter().position(|&m| m == role.muscle);
                let (material, density) = match (role.tissue, muscle) {
                    (Tissue::Muscle, Some(m)) => (materials[m].clone(), MUSCLE_DENSITY),
                    (Tissue::Muscle, None) => (material.clone(), MUSCLE_DENSITY),
                    (Tissue::Tendon, _) => (tendon.clone(), TENDON_DENSITY),
                };
                Ok(Part {
                    block,
                    technology: block_technology(
                        element,
                        geometry.mesh.blocks[block].shape,
                        material.as_ref(),
                    )
                    .with_context(|| format!("block '{}'", geometry.block_name(block)))?,
                    material,
                    density,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let patella = Arc::new(TendonPatella::new(
            geometry.patella_table.clone(),
            *squat,
            geometry.motions.chain,
        ));
        let mut rigid_ties = Vec::new();
        let mut insertion_ties = Vec::new();
        for (b, muscle) in geometry.muscles.iter().enumerate() {
            rigid_ties.push(RigidTie {
                name: format!("{}_origin", muscle.abbreviation()),
                nodes: geometry.end_nodes(b, "origin")?,
                motion: geometry.origin_motion(b)?,
            });
            insertion_ties.push(rigid_ties.len());
            rigid_ties.push(RigidTie {
                name: format!("{}_insertion", muscle.abbreviation()),
                nodes: geometry.end_nodes(b, "insertion")?,
                motion: RigidMotion::followed(patella.clone()),
            });
        }
        patella.pulled_by(insertion_ties.clone());
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
