//! The squat's interactions as a scene's `[[interactions]]` (issue 30, step 4): the
//! cohesive interfaces and penalty contacts of [`super::interactions::knee_interactions`],
//! in its order (the order the solver sums their forces), on `muscles.inp`'s surfaces
//! and the femur's rigid body.
//!
//! - **A muscle's surface** is its `<belly>_lateral` surface, which spans its belly and
//!   its tendon: in the scene, the list of that surface on each part that has faces of it
//!   (`["vastus_lateralis.vastus_lateralis_lateral",
//!   "vastus_lateralis_tendon.vastus_lateralis_lateral"]`), one surface across parts that
//!   share the file's nodes. The knee sorts each surface's faces as the mesh file reads them
//!   back, so the listed parts' faces, belly then tendon, are the knee's own triangles in
//!   the knee's order.
//! - **Bonds**: `bond_band` keeps the knee's height bands ([`MUSCLE_BOND_HEIGHTS`],
//!   [`FEMUR_BOND_HEIGHTS`], heights along y), `bond_tolerance` its [`BOND_TOLERANCE`],
//!   `tangential` the [`InterfaceLaw`]'s mode, `minimum_bonds` its [`MINIMUM_BONDS`].
//!   Only the interfaces that bonded in the knee are written: the scene refuses one with
//!   fewer bonds.
//! - **Contact**: `smooth_normals = true` and the default penalty, which the scene takes
//!   per node from the stiffest part that holds it, so a tendon node presses with the
//!   tendon's penalty as in the knee.

use std::fmt::Write as _;

use anyhow::{Result, bail};

use musclefem_contact::TangentialMode;
use musclefem_io::csv::format_number;

use super::interactions::{
    BOND_TOLERANCE, FEMUR_BOND_HEIGHTS, InterfaceLaw, KneeInteractions, MINIMUM_BONDS,
    MUSCLE_BOND_HEIGHTS,
};
use super::model::{KneeGeometry, muscle_surface_name};
use super::scene_bones::FEMUR_BODY;

/// The axis the bond heights are measured along: the femur's y at 0° [1].
const HEIGHT_AXIS: &str = "[0.0, 1.0, 0.0]";

/// The surface of muscle `m` (its belly is block `m`) as a scene writes it: its
/// `<belly>_lateral` (or `<belly>_outer`, [`muscle_surface_name`]) surface on every part
/// (block) that has faces of it, in block order.
fn muscle_surface(geometry: &KneeGeometry, m: usize) -> Result<String> {
    let lateral = muscle_surface_name(&geometry.mesh, geometry.block_name(m))?;
    let Some(faces) = geometry.mesh.surfaces.get(&lateral) else {
        bail!("the knee's mesh has no surface '{lateral}'");
    };
    let parts: Vec<String> = (0..geometry.mesh.blocks.len())
        .filter(|&b| faces.iter().any(|f| f.element.block as usize == b))
        .map(|b| format!("{:?}", format!("{}.{lateral}", geometry.block_name(b))))
        .collect();
    Ok(format!("[{}]", parts.join(", ")))
}

/// The scene's name of a tangential mode.
fn tangential_name(law: InterfaceLaw) -> &'static str {
    match law.tangential() {
        TangentialMode::Elastic => "elastic",
        TangentialMode::FreeSlide => "free-slide",
        TangentialMode::SmoothSlide => "smooth-slide",
    }
}

/// One cohesive `[[interactions]]` entry of the knee bonding `secondary` to `main` (both
/// as the scene writes them) where the secondary's faces lie between `heights` [m].
fn cohesive_entry(
    name: &str,
    secondary: &str,
    main: &str,
    heights: [f64; 2],
    law: InterfaceLaw,
) -> String {
    format!(
        "[[interactions]]\nname = {name:?}\nkind = \"cohesive\"\nsecondary = {secondary}\n\
         main = {main}\ntangential = {:?}\nbond_tolerance = {}\nbond_band = {{ axis = \
         {HEIGHT_AXIS}, heights = [{}, {}] }}\nminimum_bonds = {MINIMUM_BONDS}\n",
        tangential_name(law),
        format_number(BOND_TOLERANCE),
        format_number(heights[0]),
        format_number(heights[1]),
    )
}

/// One penalty contact `[[interactions]]` entry of the knee: `secondary`'s nodes on
/// `main`, along the main surface's smooth normals, with the default penalties.
fn contact_entry(name: &str, secondary: &str, main: &str) -> String {
    format!(
        "[[interactions]]\nname = {name:?}\nkind = \"contact\"\nsecondary = {secondary}\n\
         main = {main}\nsmooth_normals = true\n"
    )
}

/// The `[[interactions]]` entries of `geometry`'s squat with its interfaces bonded by
/// `law`, as `built` (its [`super::interactions::knee_interactions`] with that law) has
/// them: the muscle–muscle bonds, the muscle–femur bonds, the muscle–muscle contacts
/// (every ordered pair) and the muscle–femur contacts, with the knee's names.
pub fn knee_interaction_entries(
    geometry: &KneeGeometry,
    built: &KneeInteractions,
    law: InterfaceLaw,
) -> Result<String> {
    let surfaces = (0..geometry.muscles.len())
        .map(|m| muscle_surface(geometry, m))
        .collect::<Result<Vec<_>>>()?;
    let abbreviation = |m: usize| geometry.muscles[m].abbreviation();
    let femur = format!("{FEMUR_BODY:?}");
    let mut text = String::new();
    for &(secondary, main, _) in &built.muscle_interfaces {
        let name = format!("{}-{}", abbreviation(secondary), abbreviation(main));
        let _ = writeln!(
            text,
            "{}",
            cohesive_entry(
                &name,
                &surfaces[secondary],
                &surfaces[main],
                MUSCLE_BOND_HEIGHTS,
                law
            )
        );
    }
    for &(m, _) in &built.femur_interfaces {
        let name = format!("{}-femur", abbreviation(m));
        let _ = writeln!(
            text,
            "{}",
            cohesive_entry(&name, &surfaces[m], &femur, FEMUR_BOND_HEIGHTS, law)
        );
    }
    for secondary in 0..surfaces.len() {
        for main in (0..surfaces.len()).filter(|&main| main != secondary) {
            let name = format!("{}-{}-contact", abbreviation(secondary), abbreviation(main));
            let _ = writeln!(
                text,
                "{}",
                contact_entry(&name, &surfaces[secondary], &surfaces[main])
            );
        }
    }
    for (m, surface) in surfaces.iter().enumerate() {
        let name = format!("{}-femur-contact", abbreviation(m));
        let _ = writeln!(text, "{}", contact_entry(&name, surface, &femur));
    }
    Ok(text)
}
