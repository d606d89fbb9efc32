//! The mesh of one part: a generated box, or one block of an Abaqus/Gmsh file with its
//! nodes renumbered, and how parts are appended into the one mesh of a model (node sets
//! renamed `PART.SET`).

use std::path::Path;

use nalgebra::Vector3;
use toml::Spanned;

use musclefem_core::mesh::generate::{TetOrder, box_of_hexes, box_of_tets};
use musclefem_core::mesh::{ElementShape, Mesh};

use super::error::{Locator, SceneError, suggestion};
use super::format::PartEntry;
use crate::mesh_import::read_mesh;

/// The mesh of a part (generated, or one block of a file), with its fibers.
pub(super) fn part_mesh(
    entry: &PartEntry,
    shape: ElementShape,
    directory: &Path,
    locator: &Locator,
) -> Result<Mesh, SceneError> {
    let spec = &entry.mesh;
    let mut mesh = match (&spec.generator, &spec.file) {
        (Some(generator), None) => generate_box(entry, generator, locator)?,
        (None, Some(file)) => read_block(entry, file, directory, locator)?,
        _ => {
            return Err(locator.error(
                entry.name.span(),
                format!(
                    "part '{}': give the mesh either as generator = \"box\" or as file = \"...\"",
                    entry.name.get_ref()
                ),
            ));
        }
    };
    let element = entry.element.get_ref();
    if mesh.blocks[0].shape != shape {
        return Err(locator.error(
            entry.element.span(),
            format!(
                "element '{element}' needs {} elements, the mesh has {}",
                shape.name(),
                mesh.blocks[0].shape.name()
            ),
        ));
    }
    if let Some(fibers) = &entry.fibers {
        let direction = Vector3::from(*fibers.direction.get_ref());
        if !(direction.norm() > 0.0 && direction.iter().all(|x| x.is_finite())) {
            return Err(locator.error(
                fibers.direction.span(),
                "the fiber direction must be a finite non-zero vector".to_string(),
            ));
        }
        for block in &mut mesh.blocks {
            block.fiber_direction.fill(direction.normalize());
        }
    }
    Ok(mesh)
}

/// A generated box of hexes, or of tets (linear or quadratic) for tet elements.
fn generate_box(
    entry: &PartEntry,
    generator: &Spanned<String>,
    locator: &Locator,
) -> Result<Mesh, SceneError> {
    let spec = &entry.mesh;
    if generator.get_ref() != "box" {
        return Err(locator.error(
            generator.span(),
            format!(
                "unknown generator '{}'{}; the only generator is box",
                generator.get_ref(),
                suggestion(generator.get_ref(), ["box"])
            ),
        ));
    }
    let (Some(size), Some(divisions)) = (&spec.size, &spec.divisions) else {
        return Err(locator.error(
            generator.span(),
            "a box needs size = [x, y, z] (m) and divisions = [nx, ny, nz]".to_string(),
        ));
    };
    let (size_value, divisions_value) = (*size.get_ref(), *divisions.get_ref());
    let generated = match entry.element.get_ref().as_str() {
        "tet4" | "tet4-nodal-average" => box_of_tets(size_value, divisions_value, TetOrder::Linear),
        "tet10" => box_of_tets(size_value, divisions_value, TetOrder::Quadratic),
        _ => box_of_hexes(size_value, divisions_value),
    };
    generated.map_err(|e| locator.error(size.span(), e.to_string()))
}

/// One block of a mesh file, with only its nodes (renumbered) and the node sets restricted
/// to them.
fn read_block(
    entry: &PartEntry,
    file: &Spanned<String>,
    directory: &Path,
    locator: &Locator,
) -> Result<Mesh, SceneError> {
    let path = directory.join(file.get_ref());
    let imported = read_mesh(&path).map_err(|e| locator.error(file.span(), e.to_string()))?;
    let mesh = imported.mesh;
    let names: Vec<&str> = mesh.blocks.iter().map(|b| b.name.as_str()).collect();
    let index = match &entry.mesh.block {
        Some(name) => names
            .iter()
            .position(|n| n == name.get_ref())
            .ok_or_else(|| {
                locator.error(
                    name.span(),
                    format!(
                        "'{}' has no element block '{}'{}; it has: {}",
                        path.display(),
                        name.get_ref(),
                        suggestion(name.get_ref(), names.iter().copied()),
                        names.join(", ")
                    ),
                )
            })?,
        None if names.len() == 1 => 0,
        None => {
            return Err(locator.error(
                file.span(),
                format!(
                    "'{}' has {} element blocks ({}): name one with block = \"...\"",
                    path.display(),
                    names.len(),
                    names.join(", ")
                ),
            ));
        }
    };
    let mut block = mesh.blocks[index].clone();
    let mut new_id = vec![u32::MAX; mesh.nodes.len()];
    let mut nodes = musclefem_core::mesh::Nodes::new();
    for id in block.connectivity.iter_mut() {
        let old = *id as usize;
        if new_id[old] == u32::MAX {
            new_id[old] = nodes.push(mesh.nodes.position(old));
        }
        *id = new_id[old];
    }
    let mut part = Mesh::new(nodes, vec![block]);
    for (name, set) in &mesh.node_sets {
        let kept: Vec<u32> = set
            .iter()
            .map(|&n| new_id[n as usize])
            .filter(|&n| n != u32::MAX)
            .collect();
        if !kept.is_empty() {
            part.node_sets.insert(name.clone(), kept);
        }
    }
    Ok(part)
}

/// Append `part` (one block) to `mesh`: nodes renumbered after the existing ones, the
/// block named after the part, node sets renamed `PART.SET`.
pub(super) fn append_part(mesh: &mut Mesh, part: Mesh, name: &str) {
    let offset = mesh.nodes.len() as u32;
    for i in 0..part.nodes.len() {
        mesh.nodes.push(part.nodes.position(i));
    }
    for mut block in part.blocks {
        block.connectivity.iter_mut().for_each(|id| *id += offset);
        block.name = name.to_string();
        mesh.blocks.push(block);
    }
    for (set, nodes) in part.node_sets {
        mesh.node_sets.insert(
            format!("{name}.{set}"),
            nodes.into_iter().map(|n| n + offset).collect(),
        );
    }
}
