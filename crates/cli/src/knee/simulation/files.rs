//! `musclefem knee --anatomy DIR`: the quadriceps from a mesh file instead of the default
//! anatomy, with the default knee's bones and motions.
//!
//! DIR holds `muscles.msh` (Gmsh 4.1) or `muscles.inp` (Abaqus) with one element block
//! per muscle, named `VI`, `VL`, `VM`, `RF` or `vastus_intermedius`, `vastus_lateralis`,
//! `vastus_medialis`, `rectus_femoris` (any letter case), and for each block the node sets
//! `<block>_origin` (tied to the femur or pelvis) and `<block>_insertion` (tied to the
//! patella). `DIR/femur.stl`, if present, replaces the default femur (the surface the
//! muscles bond to and may not enter). Coordinates are in metres, in the default knee's
//! frame: x anterior, y proximal, z lateral, the flexion axis through the origin along z.

use std::path::Path;

use anyhow::{Context, Result, bail};

use musclefem_contact::RigidSurface;
use musclefem_io::mesh_import::read_mesh;

use super::super::anatomy::{Anatomy, Quadriceps, Squat, TriangleSurface};
use super::model::KneeGeometry;

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
    for block in &imported.mesh.blocks {
        let Some(muscle) = muscle_of_block(&block.name) else {
            bail!(
                "{}: block '{}' is not one of the quadriceps (VI, VL, VM, RF or their full \
                 names)",
                path.display(),
                block.name
            );
        };
        if muscles.contains(&muscle) {
            bail!("{}: two blocks are the {}", path.display(), muscle.name());
        }
        muscles.push(muscle);
    }
    if muscles.is_empty() {
        bail!("{}: no element block", path.display());
    }
    let mut geometry = KneeGeometry::default_knee(anatomy, squat)?;
    geometry.mesh = imported.mesh;
    geometry.muscles = muscles;
    for b in 0..geometry.mesh.blocks.len() {
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
    }
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
