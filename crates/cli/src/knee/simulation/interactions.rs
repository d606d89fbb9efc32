//! The squat's interactions (seed §2.4): cohesive contact between adjacent muscles and
//! between the muscles and the femur, and penalty contact that keeps every muscle out of
//! the femur.
//!
//! - **Which surfaces bond.** Every pair of muscles whose surfaces come within
//!   [`BOND_TOLERANCE`] of each other at 0° bonds there (in the default knee: VI with VL,
//!   VM and RF), and so does every muscle that comes within it of the femur (VI, VL, VM).
//!   The bonds form stress-free: the initial gaps (1–4 mm between the faceted muscles of
//!   the coarse mesh) are their rest state.
//! - **The law.** The paper's K_nn = K_ss = K_tt = 0.05 N/mm³ and damage initiation at
//!   30 mm ([`TangentialMode::Elastic`]): the surfaces slide against the shear stiffness
//!   K_ss (a 1 mm slide costs 50 kPa). Compression is resisted with the same K_nn.
//!   Free sliding ([`TangentialMode::FreeSlide`], bonds that follow the closest point)
//!   reads the paper's "permits relative sliding" more literally, but its force turns
//!   abruptly where a node passes a concave edge of the faceted surfaces, and the
//!   implicit solver's Newton iterations stalled at 8° of flexion on the coarse knee
//!   (increments cut to 2e-5 s); with elastic bonds the whole squat converges.
//! - **Penalty contact** of every muscle's surface against the femur (t_n = ε⟨−g⟩,
//!   ε = 10 E/h): the distal muscles wrap over the trochlea in flexion, where they did not
//!   bond; and between every pair of muscles that did not bond (the default knee's VL–VM,
//!   VL–RF and VM–RF, 4–17 mm apart at 0°). On the coarse default squat those three never
//!   touch (zero active area in both runs, 2026-11-23): they guard user anatomies and finer
//!   meshes, for about 2 % of the run time.
//!
//! Left out: contact with the patella (the insertions are tied to it). Every run measures
//! how close the other muscle nodes come to it instead ([`super::patella_clearance`]): on
//! the coarse default squat no closer than 7.5 mm, at 0° (2026-11-24).

use std::collections::BTreeSet;

use anyhow::{Context, Result};

use musclefem_contact::{
    CohesiveError, CohesiveInterface, CohesiveSettings, DeformableSurface, PenaltyContact,
    RigidSurface, TangentialMode,
};
use musclefem_core::mesh::Mesh;
use musclefem_core::solver::Interaction;
use musclefem_io::scene::small_strain_shear_modulus;
use musclefem_materials::Material;

use super::model::KneeGeometry;

/// Secondary nodes within this distance of another surface at 0° bond to it [m].
pub const BOND_TOLERANCE: f64 = 0.004;

/// Bonds fewer than this between two muscles are not an interface (a few corner nodes
/// that happen to come close).
const MINIMUM_BONDS: usize = 3;

/// What one interaction is, for the log.
#[derive(Clone, Debug, PartialEq)]
pub struct InteractionSummary {
    pub name: String,
    /// `cohesive` or `contact`.
    pub kind: &'static str,
    /// Cohesive: bonded secondary nodes and their reference area [m²]; contact: the
    /// secondary surface's nodes and its area.
    pub nodes: usize,
    pub area: f64,
}

/// The interactions of one squat, fresh (no damage, no history).
pub struct KneeInteractions {
    pub interactions: Vec<Box<dyn Interaction>>,
    pub summaries: Vec<InteractionSummary>,
    /// Nodes on a muscle–muscle interface (both sides), for locating peak stresses.
    pub interface_nodes: BTreeSet<u32>,
}

/// The muscle surface of block `b`: its named `<block>_lateral` surface if the mesh has
/// one (the default anatomy's: the sides without the end faces), else its outer surface.
fn muscle_surface(mesh: &Mesh, block: &str) -> Result<DeformableSurface> {
    let lateral = format!("{block}_lateral");
    let surface = if mesh.surfaces.contains_key(&lateral) {
        DeformableSurface::from_mesh_surface(mesh, &lateral)
    } else {
        DeformableSurface::outer_surface(mesh, &[block])
    };
    surface.with_context(|| format!("the surface of muscle '{block}'"))
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

/// The interactions of `geometry` on `mesh` (its muscles' mesh) for muscles of
/// `material` (whose small-strain modulus sets the contact penalty).
pub fn knee_interactions(
    geometry: &KneeGeometry,
    mesh: &Mesh,
    material: &dyn Material,
) -> Result<KneeInteractions> {
    let settings = CohesiveSettings {
        tangential: TangentialMode::Elastic,
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
    let surfaces = (0..mesh.blocks.len())
        .map(|b| muscle_surface(mesh, &mesh.blocks[b].name))
        .collect::<Result<Vec<_>>>()?;
    let abbreviation = |b: usize| geometry.muscles[b].abbreviation();
    let modulus = 3.0
        * small_strain_shear_modulus(material)
            .context("the muscle material has no small-strain shear modulus")?;

    let mut result = KneeInteractions {
        interactions: Vec::new(),
        summaries: Vec::new(),
        interface_nodes: BTreeSet::new(),
    };
    let push_cohesive = |interface: CohesiveInterface, result: &mut KneeInteractions| {
        result.summaries.push(InteractionSummary {
            name: interface.name().to_string(),
            kind: "cohesive",
            nodes: interface.bond_count(),
            area: interface.bonded_reference_area(),
        });
        result.interactions.push(Box::new(interface));
    };
    let mut unbonded_pairs = Vec::new();
    for main in 0..surfaces.len() {
        for secondary in main + 1..surfaces.len() {
            let name = format!("{}-{}", abbreviation(secondary), abbreviation(main));
            let forward = bond(
                &name,
                &surfaces[secondary],
                surfaces[main].clone(),
                mesh,
                &settings,
            )?;
            let Some(interface) = forward else {
                unbonded_pairs.push((secondary, main));
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
            push_cohesive(interface, &mut result);
        }
    }
    for (b, surface) in surfaces.iter().enumerate() {
        let name = format!("{}-femur", abbreviation(b));
        if let Some(interface) = bond(&name, surface, femur.clone(), mesh, &settings)? {
            push_cohesive(interface, &mut result);
        }
    }
    for (secondary, main) in unbonded_pairs {
        let name = format!("{}-{}-contact", abbreviation(secondary), abbreviation(main));
        let contact = PenaltyContact::with_default_penalty(
            &name,
            surfaces[secondary].clone(),
            surfaces[main].clone(),
            modulus,
        )
        .with_context(|| format!("contact {name}"))?;
        result.summaries.push(InteractionSummary {
            name,
            kind: "contact",
            nodes: surfaces[secondary].nodes.len(),
            area: surfaces[secondary].area(),
        });
        result.interactions.push(Box::new(contact));
    }
    for (b, surface) in surfaces.iter().enumerate() {
        let name = format!("{}-femur-contact", abbreviation(b));
        let contact =
            PenaltyContact::with_default_penalty(&name, surface.clone(), femur.clone(), modulus)
                .with_context(|| format!("contact {name}"))?;
        result.summaries.push(InteractionSummary {
            name,
            kind: "contact",
            nodes: surface.nodes.len(),
            area: surface.area(),
        });
        result.interactions.push(Box::new(contact));
    }
    Ok(result)
}
