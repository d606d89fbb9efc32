//! The squat's interactions (seed §2.4): cohesive interfaces between adjacent muscles and
//! between the muscles and the femur, and penalty contact that keeps every muscle out of
//! its neighbours and out of the femur.
//!
//! - **Which surfaces bond.** Every pair of muscles whose surfaces come within
//!   [`BOND_TOLERANCE`] of each other at 0° bonds there (in the procedural knee: VI with VL,
//!   VM and RF), and so does every muscle that comes within it of the femur's shaft
//!   between [`FEMUR_BOND_HEIGHTS`] (VI, VL, VM). The bonds form stress-free: the initial
//!   gaps (1–4 mm between the faceted muscles of the coarse mesh) are their rest state.
//! - **The law** ([`InterfaceLaw`]). The paper's interfaces "resist separation and
//!   interpenetration but permit relative sliding". By default
//!   ([`InterfaceLaw::Sliding`]) each bond follows the closest point of the main surface's
//!   smooth normal field ([`TangentialMode::SmoothSlide`]): K_nn = 0.05 N/mm³ across,
//!   nothing along. The smooth field (vertex normals interpolated over each triangle; the
//!   femur's from the gradient of its implicit shape) keeps the force continuous where a
//!   node passes an edge of the faceted surface: with the facets' own normals Newton
//!   stalled at 8° of flexion. `--interfaces elastic-shear` keeps the paper's elastic
//!   law with K_ss = K_tt = 0.05 N/mm³ ([`TangentialMode::Elastic`]): the bonds stay at
//!   their material points and a 1 mm slide costs 50 kPa, which pins the vasti to the
//!   femur (README, "The knee", compares the two).
//! - **Penalty contact** (t_n = ε⟨−g⟩, ε = 10 E/h, along the same smooth normals) of every
//!   muscle against every other, both ways, and against the femur: the bonds hold only
//!   the nodes that bonded at 0°, the rectus slides ~60 mm down the intermedius as the hip
//!   flexes, and the distal muscles and tendons wrap over the trochlea in flexion. Muscle
//!   nodes press with the muscle's penalty, tendon nodes with the tendon's (E of its
//!   matrix, ~90 times the muscle's), against the femur and against the other muscles:
//!   with the muscle's a tendon wrapping the femur sank ~30 mm into it, and in the active
//!   squat the laminae of VI and VL, pressed together side by side, sank into each other
//!   far enough that their feet swung around each other's edge (force direction turning
//!   by ~40° from one Newton iteration to the next): the residual stayed at 2e-4 at 75°
//!   (coarse, 2026-11-25) and the run stopped there; with the tendon's it finished.
//!
//! Left out: contact with the patella (the insertions are tied to it). Every run measures
//! how close the other muscle nodes come to it instead ([`super::patella_clearance`]).

use std::collections::BTreeSet;

use anyhow::{Context, Result};

use musclefem_contact::{
    CohesiveError, CohesiveInterface, CohesiveSettings, DeformableSurface, PenaltyContact,
    RigidSurface, Strand, TangentialMode, TendonStrands, default_penalty,
};
use musclefem_core::mesh::Mesh;
use musclefem_core::solver::Interaction;
use musclefem_io::scene::{InteractionModel, small_strain_shear_modulus};
use musclefem_materials::Material;

use super::super::anatomy::Tissue;
use super::model::{KneeGeometry, muscle_surface_name, tendon_material};

/// Secondary nodes within this distance of another surface at 0° bond to it [m].
pub const BOND_TOLERANCE: f64 = 0.004;

/// Bonds fewer than this between two muscles are not an interface (a few corner nodes
/// that happen to come close).
pub const MINIMUM_BONDS: usize = 3;

/// The name of the knee's tendon strands (the Visible Human's), an interaction's name.
pub const STRANDS_NAME: &str = "tendon-strands";

/// What one interaction is, for the log.
#[derive(Clone, Debug, PartialEq)]
pub struct InteractionSummary {
    pub name: String,
    /// `cohesive`, `contact` or `strands`.
    pub kind: &'static str,
    /// Cohesive: bonded secondary nodes and their reference area [m²]; contact: the
    /// secondary surface's nodes and its area; strands: the number of strands (area 0).
    pub nodes: usize,
    pub area: f64,
}

/// The interactions of one squat, fresh (no damage, no history).
pub struct KneeInteractions {
    /// Contacts and cohesive interfaces as a scene builds them (its `[[interactions]]`:
    /// [`super::scene_interactions`]), in the order the solver sums their forces.
    pub interactions: Vec<InteractionModel>,
    pub summaries: Vec<InteractionSummary>,
    /// Nodes on a muscle–muscle interface (both sides), for locating peak stresses.
    pub interface_nodes: BTreeSet<u32>,
    /// (muscle, index in `interactions`) of every muscle–femur cohesive interface.
    pub femur_interfaces: Vec<(usize, usize)>,
    /// (muscle, index in `interactions`) of every muscle–femur penalty contact.
    pub femur_contacts: Vec<(usize, usize)>,
    /// (secondary muscle, main muscle, index in `interactions`) of every muscle–muscle
    /// cohesive interface.
    pub muscle_interfaces: Vec<(usize, usize, usize)>,
    /// The tendon strands from the muscles' outlets to the patella, where the geometry
    /// has them (the Visible Human knee); the solver sums them after `interactions`.
    pub strands: Option<TendonStrands>,
}

impl KneeInteractions {
    /// The interactions' names in the order the solver sums them (the strands last).
    pub fn names(&self) -> Vec<String> {
        let mut names: Vec<String> = self
            .interactions
            .iter()
            .map(|i| i.name().to_string())
            .collect();
        if let Some(strands) = &self.strands {
            names.push(strands.name().to_string());
        }
        names
    }

    /// Fresh copies of the interactions for a solver.
    pub fn solver_interactions(&self) -> Vec<Box<dyn Interaction>> {
        let mut interactions: Vec<Box<dyn Interaction>> = self
            .interactions
            .iter()
            .map(InteractionModel::boxed)
            .collect();
        if let Some(strands) = &self.strands {
            interactions.push(Box::new(strands.clone()));
        }
        interactions
    }
}

/// The muscle surface of block `block`: its `<block>_lateral` or `<block>_outer` surface
/// ([`muscle_surface_name`]).
fn muscle_surface(mesh: &Mesh, block: &str) -> Result<DeformableSurface> {
    let name = muscle_surface_name(mesh, block)?;
    DeformableSurface::from_mesh_surface(mesh, &name)
        .with_context(|| format!("the surface of muscle '{block}'"))
}

/// Where the muscles bond to the femur: its round shaft between these heights [m] (in its
/// frame at 0°). Below, the suprapatellar bursa and fat separate the quadriceps from the
/// distal femur, and above, the trochanters' region is the vasti's origin: contact only
/// there. (The femur's creases there, where its implicit shape joins condyles, trochlea
/// and trochanters, also turn its normals abruptly: a muscle sliding on them along its
/// normal field felt tangential forces that stalled Newton's method.)
pub const FEMUR_BOND_HEIGHTS: [f64; 2] = [0.100, 0.360];

/// Where the muscles bond to each other: the secondary muscle's faces between these
/// heights [m] (at 0°). The bonds slide along the main muscle, the rectus's some 60 mm
/// down the intermedius as the hip flexes: bonds from nearer the ends slid off the
/// strongly curved ends of the main surface (its tapering tendon, its rim), where the
/// closest point is ill-defined, and Newton stalled there (coarse passive squat at 50° in
/// extension, 2026-11-25). Beyond these heights the muscles touch through penalty contact.
pub const MUSCLE_BOND_HEIGHTS: [f64; 2] = [0.150, 0.360];

/// The faces of `surface` whose centroids lie between the heights `heights` [m] at the
/// reference positions of `mesh`, as a surface named `name`; `None` if there is none.
fn faces_between(
    mesh: &Mesh,
    surface: &DeformableSurface,
    heights: [f64; 2],
    name: &str,
) -> Result<Option<DeformableSurface>> {
    let triangles = surface.triangles_between_heights(mesh, &nalgebra::Vector3::y(), heights);
    if triangles.is_empty() {
        return Ok(None);
    }
    Ok(Some(
        DeformableSurface::from_triangles(mesh, name, triangles)
            .with_context(|| format!("the surface {name}"))?,
    ))
}

/// Bond `secondary` to `main` if they come within the tolerance, else `None`.
fn bond(
    name: &str,
    secondary: &DeformableSurface,
    main: impl Into<musclefem_contact::ContactTarget>,
    mesh: &Mesh,
    settings: &CohesiveSettings,
) -> Result<Option<CohesiveInterface>> {
    match CohesiveInterface::new(name, secondary, main, mesh, settings) {
        Ok(interface) if interface.bond_count() >= MINIMUM_BONDS => Ok(Some(interface)),
        Ok(_) | Err(CohesiveError::NoBond { .. }) => Ok(None),
        Err(e) => Err(e).with_context(|| format!("cohesive interface {name}")),
    }
}

/// How the bonded muscle–muscle and muscle–femur interfaces resist a slide.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum InterfaceLaw {
    /// The bonds follow the closest point of the smooth surface: they resist opening and
    /// interpenetration (K_nn = 0.05 N/mm³) but not a slide — the paper's "permits
    /// relative sliding" ([`TangentialMode::SmoothSlide`]).
    #[default]
    Sliding,
    /// The paper's elastic traction–separation law, K_ss = K_tt = 0.05 N/mm³ in shear:
    /// a 1 mm slide costs 50 kPa ([`TangentialMode::Elastic`]).
    ElasticShear,
}

impl InterfaceLaw {
    pub fn name(self) -> &'static str {
        match self {
            InterfaceLaw::Sliding => "sliding",
            InterfaceLaw::ElasticShear => "elastic-shear",
        }
    }

    pub fn tangential(self) -> TangentialMode {
        match self {
            InterfaceLaw::Sliding => TangentialMode::SmoothSlide,
            InterfaceLaw::ElasticShear => TangentialMode::Elastic,
        }
    }
}

/// The interactions of `geometry` on `mesh` (its muscles' mesh) for muscles of
/// `material` (whose small-strain modulus sets the contact penalty), the interfaces
/// bonded with `law`.
pub fn knee_interactions(
    geometry: &KneeGeometry,
    mesh: &Mesh,
    material: &dyn Material,
    law: InterfaceLaw,
) -> Result<KneeInteractions> {
    let settings = CohesiveSettings {
        tangential: law.tangential(),
        bond_tolerance: BOND_TOLERANCE,
        ..CohesiveSettings::default()
    };
    let femur = RigidSurface::new(
        "femur",
        geometry.femur.vertices.clone(),
        geometry.femur.triangles.clone(),
    )
    .context("the femur's surface")?
    .with_motion(geometry.motions.femur.clone());
    let femur = match &geometry.femur_normals {
        Some(normals) => femur
            .with_vertex_normals(normals.clone())
            .context("the femur's vertex normals")?,
        None => femur,
    };
    let surfaces = (0..geometry.muscles.len())
        .map(|b| muscle_surface(mesh, &mesh.blocks[b].name))
        .collect::<Result<Vec<_>>>()?;
    let abbreviation = |b: usize| geometry.muscles[b].abbreviation();
    let modulus = 3.0
        * small_strain_shear_modulus(material)
            .context("the muscle material has no small-strain shear modulus")?;
    // Tendon nodes press with the tendon's wrap (MPa against the bone, kN between the
    // laminae in the active squat): their penalty is the tendon matrix's (E = 3μ, across
    // the fibers), ~90 times the muscle's (see the module docs).
    let tendon_modulus = 3.0
        * small_strain_shear_modulus(tendon_material()?.as_ref())
            .context("the tendon material has no small-strain shear modulus")?;
    let mut in_tendon = vec![false; mesh.node_count()];
    for (b, role) in geometry.roles.iter().enumerate() {
        if role.tissue == Tissue::Tendon {
            for &n in &mesh.blocks[b].connectivity {
                in_tendon[n as usize] = true;
            }
        }
    }
    let penalties = |surface: &DeformableSurface| -> Result<Vec<f64>> {
        let h = surface.element_size();
        let muscle = default_penalty(modulus, h)?;
        let tendon = default_penalty(tendon_modulus, h)?;
        Ok(surface
            .nodes
            .iter()
            .map(|&n| {
                if in_tendon[n as usize] {
                    tendon
                } else {
                    muscle
                }
            })
            .collect())
    };

    let mut result = KneeInteractions {
        interactions: Vec::new(),
        summaries: Vec::new(),
        interface_nodes: BTreeSet::new(),
        femur_interfaces: Vec::new(),
        femur_contacts: Vec::new(),
        muscle_interfaces: Vec::new(),
        strands: None,
    };
    let push_cohesive = |interface: CohesiveInterface, result: &mut KneeInteractions| {
        result.summaries.push(InteractionSummary {
            name: interface.name().to_string(),
            kind: "cohesive",
            nodes: interface.bond_count(),
            area: interface.bonded_reference_area(),
        });
        result
            .interactions
            .push(InteractionModel::Cohesive(Box::new(interface)));
    };
    for main in 0..surfaces.len() {
        for secondary in main + 1..surfaces.len() {
            let name = format!("{}-{}", abbreviation(secondary), abbreviation(main));
            let Some(bonding) =
                faces_between(mesh, &surfaces[secondary], MUSCLE_BOND_HEIGHTS, &name)?
            else {
                continue;
            };
            let forward = bond(&name, &bonding, surfaces[main].clone(), mesh, &settings)?;
            let Some(interface) = forward else {
                continue;
            };
            result.interface_nodes.extend(interface.bonded_nodes());
            // The main side's nodes near the interface: the bonds the other way round.
            if let Some(reverse) = bond(
                &name,
                &surfaces[main],
                surfaces[secondary].clone(),
                mesh,
                &settings,
            )? {
                result.interface_nodes.extend(reverse.bonded_nodes());
            }
            result
                .muscle_interfaces
                .push((secondary, main, result.interactions.len()));
            push_cohesive(interface, &mut result);
        }
    }
    for (b, surface) in surfaces.iter().enumerate() {
        let name = format!("{}-femur", abbreviation(b));
        let Some(surface) = faces_between(mesh, surface, FEMUR_BOND_HEIGHTS, &name)? else {
            continue;
        };
        let surface = &surface;
        if let Some(interface) = bond(&name, surface, femur.clone(), mesh, &settings)? {
            result.femur_interfaces.push((b, result.interactions.len()));
            push_cohesive(interface, &mut result);
        }
    }
    // Penalty contact between every pair of muscles, both ways: the bonds hold only the
    // nodes that bonded at 0°, and the muscles slide far (the rectus 60 mm down the
    // intermedius as the hip flexes), so others reach the neighbour's surface. (Once
    // only, the later muscle's nodes on the earlier one's surface, the coarse passive
    // squat stalled at 0.91 s instead of passing 1.29 s, 2026-11-25.)
    let pairs: Vec<(usize, usize)> = (0..surfaces.len())
        .flat_map(|a| {
            (0..surfaces.len())
                .filter(move |&b| b != a)
                .map(move |b| (a, b))
        })
        .collect();
    for (secondary, main) in pairs {
        let name = format!("{}-{}-contact", abbreviation(secondary), abbreviation(main));
        let contact = PenaltyContact::with_default_penalty(
            &name,
            surfaces[secondary].clone(),
            surfaces[main].clone(),
            modulus,
        )
        .with_context(|| format!("contact {name}"))?
        .with_node_penalties(penalties(&surfaces[secondary])?)?
        .with_smooth_normals();
        result.summaries.push(InteractionSummary {
            name,
            kind: "contact",
            nodes: surfaces[secondary].nodes.len(),
            area: surfaces[secondary].area(),
        });
        result
            .interactions
            .push(InteractionModel::Contact(Box::new(contact)));
    }
    for (b, surface) in surfaces.iter().enumerate() {
        let name = format!("{}-femur-contact", abbreviation(b));
        result.femur_contacts.push((b, result.interactions.len()));
        let contact =
            PenaltyContact::with_default_penalty(&name, surface.clone(), femur.clone(), modulus)
                .with_context(|| format!("contact {name}"))?
                .with_node_penalties(penalties(surface)?)?
                .with_smooth_normals();
        result.summaries.push(InteractionSummary {
            name,
            kind: "contact",
            nodes: surface.nodes.len(),
            area: surface.area(),
        });
        result
            .interactions
            .push(InteractionModel::Contact(Box::new(contact)));
    }
    if !geometry.strands.is_empty() {
        let strands: Vec<Strand> = geometry
            .strands
            .iter()
            .map(|s| Strand {
                node_a: s.node,
                node_b: s.attachment,
                slack_length: s.slack_length,
                strain_stiffness: s.strain_stiffness,
                toe_strain: s.toe_strain,
            })
            .collect();
        let count = strands.len();
        let strands = TendonStrands::new(STRANDS_NAME, strands, Some(mesh.node_count()))
            .context("the tendon strands")?;
        result.summaries.push(InteractionSummary {
            name: STRANDS_NAME.to_string(),
            kind: "strands",
            nodes: count,
            area: 0.0,
        });
        result.strands = Some(strands);
    }
    Ok(result)
}
