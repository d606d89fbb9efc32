//! `musclefem knee --anatomy DIR`: the quadriceps from a mesh file instead of the default
//! anatomy, with the procedural knee's bones and motions.
//!
//! DIR holds `muscles.msh` (Gmsh 4.1) or `muscles.inp` (Abaqus) with one element block
//! per muscle, named `VI`, `VL`, `VM`, `RF` or `vastus_intermedius`, `vastus_lateralis`,
//! `vastus_medialis`, `rectus_femoris` (any letter case), and for each block the node sets
//! `<block>_origin` (tied to the femur or pelvis) and `<block>_insertion` (tied to the
//! patella). Tendon blocks `<block>_tendon` (tendon material, no fibers from the flow)
//! may follow the muscles' blocks; a muscle with one names where its belly ends in the
//! node set `<block>_belly_end` (the flow's outlet; its insertion otherwise). `DIR/femur.stl`, if present, replaces the default femur (the surface the
//! muscles bond to and may not enter). Coordinates are in metres, in the procedural knee's
//! frame: x anterior, y proximal, z lateral, the flexion axis through the origin along z.

use std::path::Path;

use anyhow::{Context, Result, bail};

use musclefem_contact::RigidSurface;
use musclefem_io::mesh_import::read_mesh;

use super::super::anatomy::{Anatomy, BlockRole, Quadriceps, Squat, Tissue, TriangleSurface};
use super::model::{FiberReference, KneeGeometry};

/// The muscle a block name stands for.
pub fn muscle_of_block(name: &str) -> Option<Quadriceps> {
    Quadriceps::ALL.into_iter().find(|m| {
        name.eq_ignore_ascii_case(m.abbreviation()) || name.eq_ignore_ascii_case(m.name())
    })
}

/// The geometry of the squat with the muscles of `directory` and the bones and motions
/// of `anatomy` (see the module documentation).
pub fn geometry_from_directory(
    directory: &Path,
    anatomy: &Anatomy,
    squat: &Squat,
) -> Result<KneeGeometry> {
    let candidates = ["muscles.msh", "muscles.inp"].map(|f| directory.join(f));
    let Some(path) = candidates.iter().find(|p| p.is_file()) else {
        bail!(
            "--anatomy {}: neither muscles.msh nor muscles.inp is there",
            directory.display()
        );
    };
    let imported = read_mesh(path).with_context(|| format!("reading {}", path.display()))?;
    let mut muscles = Vec::new();
    let mut roles = Vec::new();
    for block in &imported.mesh.blocks {
        let (name, tissue) = match block.name.to_ascii_lowercase().strip_suffix("_tendon") {
            Some(muscle) => (muscle.to_string(), Tissue::Tendon),
            None => (block.name.clone(), Tissue::Muscle),
        };
        let Some(muscle) = muscle_of_block(&name) else {
            bail!(
                "{}: block '{}' is not one of the quadriceps (VI, VL, VM, RF or their full \
                 names) or a tendon of one (<muscle>_tendon)",
                path.display(),
                block.name
            );
        };
        match tissue {
            Tissue::Muscle => {
                if muscles.contains(&muscle) {
                    bail!("{}: two blocks are the {}", path.display(), muscle.name());
                }
                if roles.iter().any(|r: &BlockRole| r.tissue == Tissue::Tendon) {
                    bail!(
                        "{}: block '{}' comes after a tendon block: list the muscles' blocks \
                         first, then their tendons",
                        path.display(),
                        block.name
                    );
                }
                muscles.push(muscle);
            }
            Tissue::Tendon if !muscles.contains(&muscle) => bail!(
                "{}: tendon block '{}' has no muscle block '{}' before it",
                path.display(),
                block.name,
                name
            ),
            Tissue::Tendon => {}
        }
        roles.push(BlockRole { muscle, tissue });
    }
    if muscles.is_empty() {
        bail!("{}: no element block", path.display());
    }
    let mut geometry = KneeGeometry::procedural_knee(anatomy, squat)?;
    geometry.mesh = imported.mesh;
    geometry.fiber_reference = vec![FiberReference::paper(); muscles.len()];
    geometry.muscles = muscles;
    geometry.roles = roles;
    for b in 0..geometry.muscles.len() {
        for end in ["origin", "insertion"] {
            geometry
                .end_nodes(b, end)
                .with_context(|| format!("{}", path.display()))?;
        }
    }
    let femur = directory.join("femur.stl");
    if femur.is_file() {
        let surface = RigidSurface::from_stl(&femur)
            .with_context(|| format!("reading {}", femur.display()))?;
        geometry.femur = TriangleSurface {
            vertices: surface.vertices,
            triangles: surface.triangles,
        };
        geometry.femur_normals = None;
    }
    geometry.name_outer_surfaces()?;
    Ok(geometry)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_are_named_by_abbreviation_or_full_name() {
        assert_eq!(muscle_of_block("vi"), Some(Quadriceps::VastusIntermedius));
        assert_eq!(
            muscle_of_block("Rectus_Femoris"),
            Some(Quadriceps::RectusFemoris)
        );
        assert_eq!(muscle_of_block("biceps"), None);
    }
}
