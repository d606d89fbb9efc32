//! `[[strands]]` of a scene: tendon strands (`musclefem_contact::TendonStrands`) read
//! from a CSV file (`crate::strand_csv`), their end nodes named by the labels of a mesh
//! file that parts share (`shared_nodes = true`). Such a file keeps every node, those in
//! no element too (a strand's end carried with a bone by a rigid tie), so the labels name
//! nodes of the model whichever part holds them.

use std::collections::HashMap;

use musclefem_contact::{Strand, TendonStrands};
use musclefem_core::mesh::Mesh;

use super::error::{Locator, SceneError, suggestion};
use super::format::StrandsEntry;
use super::part_mesh::SharedFile;
use crate::strand_csv::read_strands_csv;

/// The strands of `entry`. `shared_files[p]` is, for part p read with `shared_nodes`,
/// where its file's nodes start in `mesh` and the file's node labels.
pub(super) fn tendon_strands(
    entry: &StrandsEntry,
    part_names: &[String],
    shared_files: &[Option<(u32, SharedFile)>],
    mesh: &Mesh,
    locator: &Locator,
) -> Result<TendonStrands, SceneError> {
    let name = entry.name.get_ref();
    let part = entry.part.get_ref();
    let at = |span: std::ops::Range<usize>, message: String| {
        locator.error(span, format!("strands '{name}': {message}"))
    };
    let Some(index) = part_names.iter().position(|p| p == part) else {
        return Err(at(
            entry.part.span(),
            format!(
                "unknown part '{part}'{}",
                suggestion(part, part_names.iter().map(String::as_str))
            ),
        ));
    };
    let Some((offset, file)) = &shared_files[index] else {
        return Err(at(
            entry.part.span(),
            format!(
                "part '{part}' does not share its mesh file's nodes: a strand's nodes are \
                 named by the labels of a file read with `shared_nodes = true`"
            ),
        ));
    };
    let id_of: HashMap<i64, u32> = (file.node_labels.iter())
        .enumerate()
        .map(|(i, &label)| (label, offset + i as u32))
        .collect();
    let path = locator.resolve(entry.file.span(), entry.file.get_ref())?;
    let rows = read_strands_csv(&path).map_err(|e| at(entry.file.span(), e.to_string()))?;
    let mut strands = Vec::with_capacity(rows.len());
    let lines: Vec<usize> = rows.iter().map(|(line, _)| *line).collect();
    for (line, row) in rows {
        let node = |label: i64| {
            id_of.get(&label).copied().ok_or_else(|| {
                at(
                    entry.file.span(),
                    format!(
                        "'{}' line {line}: node {label} is not a node of part '{part}''s mesh \
                         file",
                        path.display()
                    ),
                )
            })
        };
        strands.push(Strand {
            node_a: node(row.node_a)?,
            node_b: node(row.node_b)?,
            slack_length: row.slack_length,
            strain_stiffness: row.strain_stiffness,
            toe_strain: row.toe_strain,
        });
    }
    TendonStrands::new(name, strands, Some(mesh.node_count())).map_err(|e| {
        let place = match e.strand() {
            Some(strand) => format!("'{}' line {}", path.display(), lines[strand]),
            None => format!("'{}'", path.display()),
        };
        at(entry.file.span(), format!("{place}: {e}"))
    })
}
