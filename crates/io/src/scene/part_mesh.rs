//! The mesh of one part: a generated box, or one block of an Abaqus/Gmsh file with its
//! nodes renumbered and the sets and surfaces that touch it, with its fibers (constant or
//! per element from a CSV file), and how parts are appended into the one mesh of a model
//! (node sets, element sets and surfaces renamed `PART.SET`).

use std::collections::{HashMap, HashSet};

use nalgebra::Vector3;
use toml::Spanned;

use musclefem_core::element::ElementKind;
use musclefem_core::mesh::generate::{TetOrder, box_of_hexes, box_of_tets};
use musclefem_core::mesh::{ElementRef, ElementShape, Face, Mesh};

use super::error::{Locator, SceneError, suggestion};
use super::format::{FiberEntry, OneOrMany, PartEntry};
use super::memory;
use crate::fiber_csv::read_fibers_csv;
use crate::mesh_import::{read_mesh_with, summarize_warnings};
use musclefem_fibers::{FlowBoundary, FlowSettings, compute_fibers};

/// What a mesh file says of a part beyond its mesh: where its fibers come from and the
/// reader's warnings, as lines for `check` and `run`.
#[derive(Debug, Default)]
pub(super) struct FileNotes {
    /// `Some` when the file gives the block's fibers (Abaqus `*ORIENTATION`).
    fiber_source: Option<String>,
    warnings: Vec<String>,
}

/// The mesh of a part (generated, or one block of a file), with its fibers, and the
/// lines `check` prints about it: the mesh file's warnings, where the fibers come from.
///
/// Fibers: the scene's `fibers` table when it has one; otherwise the mesh file's
/// orientations when it has them; otherwise e_x.
///
/// A part with `shared_nodes` keeps every node of its file, by the file's ids, and
/// comes with its [`SharedFile`] for [`append_part`].
pub(super) fn part_mesh(
    entry: &PartEntry,
    shape: ElementShape,
    locator: &Locator,
) -> Result<(Mesh, Vec<String>, Option<SharedFile>), SceneError> {
    let spec = &entry.mesh;
    let mut notes = FileNotes::default();
    let mut shared_file = None;
    let (mut mesh, labels) = match (&spec.generator, &spec.file) {
        (Some(generator), None) => {
            if let Some(units) = &spec.units {
                return Err(locator.error(
                    units.span(),
                    "`units` is the unit of a mesh file's coordinates; a generated box's \
                     size and origin are in m"
                        .to_string(),
                ));
            }
            if spec.shared_nodes {
                return Err(locator.error(
                    generator.span(),
                    "`shared_nodes` shares a mesh file's nodes between parts; a generated \
                     box has its own"
                        .to_string(),
                ));
            }
            (generate_box(entry, generator, locator)?, None)
        }
        (None, Some(file)) => {
            let (mesh, mut labels) = read_block(entry, file, locator, &mut notes)?;
            if spec.shared_nodes {
                let path = locator.resolve(file.span(), file.get_ref())?;
                let units = spec.units.as_ref().map_or("m", |u| u.get_ref().as_str());
                shared_file = Some(SharedFile {
                    key: format!("{} ({units})", path.display()),
                    node_labels: std::mem::take(&mut labels.nodes),
                });
            }
            (mesh, Some(labels))
        }
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
    let mut lines: Vec<String> = notes
        .warnings
        .iter()
        .map(|w| format!("warning: mesh file {w}"))
        .collect();
    match (&entry.fibers, notes.fiber_source) {
        (Some(fibers), source) => {
            let directions = fiber_directions(fibers, &mesh, labels.as_ref(), locator)?;
            mesh.blocks[0].fiber_direction = directions;
            if let Some(source) = source {
                lines.push(format!(
                    "fibers from the scene's fibers table (the mesh file's {source} is not used)"
                ));
            }
        }
        (None, Some(source)) => lines.push(format!("fibers from the mesh file: {source}")),
        (None, None) => {}
    }
    Ok((mesh, lines, shared_file))
}

/// The fiber direction of every element of the part's (one) block: a constant, or read
/// per element from a fibers file. Every element must be given exactly once.
fn fiber_directions(
    fibers: &Spanned<FiberEntry>,
    mesh: &Mesh,
    labels: Option<&BlockLabels>,
    locator: &Locator,
) -> Result<Vec<Vector3<f64>>, SceneError> {
    let elements = mesh.blocks[0].len();
    let entry = fibers.get_ref();
    if let (Some(inlet), Some(outlet)) = (&entry.inlet, &entry.outlet) {
        if entry.direction.is_some() || entry.file.is_some() {
            return Err(locator.error(
                fibers.span(),
                "give the fibers one way: direction, file, or inlet and outlet".to_string(),
            ));
        }
        return flow_directions(mesh, inlet, outlet, locator);
    }
    if entry.inlet.is_some() != entry.outlet.is_some() {
        return Err(locator.error(
            fibers.span(),
            "fibers from a flow need both an inlet and an outlet".to_string(),
        ));
    }
    match (&entry.direction, &entry.file) {
        (Some(direction), None) => {
            let value = Vector3::from(*direction.get_ref());
            if !(value.norm() > 0.0 && value.iter().all(|x| x.is_finite())) {
                return Err(locator.error(
                    direction.span(),
                    "the fiber direction must be a finite non-zero vector".to_string(),
                ));
            }
            Ok(vec![value.normalize(); elements])
        }
        (None, Some(file)) => {
            let path = locator.resolve(file.span(), file.get_ref())?;
            let at = |message: String| locator.error(file.span(), message);
            let rows = read_fibers_csv(&path).map_err(|e| at(e.to_string()))?;
            // Element id → index in the block.
            let index: HashMap<i64, usize> = match labels {
                Some(labels) => labels
                    .own
                    .iter()
                    .enumerate()
                    .map(|(i, &l)| (l, i))
                    .collect(),
                None => (0..elements).map(|i| (i as i64, i)).collect(),
            };
            let mut directions: Vec<Option<Vector3<f64>>> = vec![None; elements];
            for (line, row) in rows {
                let Some(&element) = index.get(&row.element) else {
                    if labels.is_some_and(|l| l.others.contains(&row.element)) {
                        // Another block of the same mesh file: one fibers file serves
                        // every part of it.
                        continue;
                    }
                    return Err(at(format!(
                        "'{}' line {line}: the part has no element {}",
                        path.display(),
                        row.element
                    )));
                };
                if directions[element].replace(row.direction).is_some() {
                    return Err(at(format!(
                        "'{}' line {line}: element {} is given twice",
                        path.display(),
                        row.element
                    )));
                }
            }
            let missing: Vec<usize> = (0..elements).filter(|&e| directions[e].is_none()).collect();
            if let Some(&first) = missing.first() {
                let id = labels.map_or(first as i64, |l| l.own[first]);
                return Err(at(format!(
                    "'{}' gives no fiber for {} of the part's {elements} elements (the first: \
                     element {id})",
                    path.display(),
                    missing.len()
                )));
            }
            Ok(directions.into_iter().flatten().collect())
        }
        _ => Err(locator.error(
            fibers.span(),
            "give the fibers either as direction = [x, y, z], as file = \"fibers.csv\" or as \
             inlet = \"SURFACE\" and outlet = \"SURFACE\""
                .to_string(),
        )),
    }
}

/// Fibers along the potential flow from `inlet` to `outlet` (surfaces or node sets of the
/// part, by their names in the part's mesh file or generator).
fn flow_directions(
    mesh: &Mesh,
    inlet: &Spanned<OneOrMany>,
    outlet: &Spanned<OneOrMany>,
    locator: &Locator,
) -> Result<Vec<Vector3<f64>>, SceneError> {
    let boundary =
        FlowBoundary::from_names(mesh, &inlet.get_ref().names(), &outlet.get_ref().names())
            .map_err(|e| locator.error(inlet.span(), format!("fibers: {e}")))?;
    let field = compute_fibers(mesh, &boundary, &FlowSettings::default())
        .map_err(|e| locator.error(inlet.span(), format!("fibers from the flow: {e}")))?;
    Ok(field.direction)
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
    // An unknown element name is reported where the part is built; the box is of hexes.
    let shape = ElementKind::from_name(entry.element.get_ref())
        .map_or(ElementShape::Hex8, ElementKind::shape);
    let tets = shape != ElementShape::Hex8;
    let elements = divisions_value
        .iter()
        .fold(if tets { 6u64 } else { 1 }, |n, &d| {
            n.saturating_mul(d as u64)
        });
    if let Some(reason) = memory::too_large(elements, memory::available_bytes()) {
        return Err(locator.error(
            divisions.span(),
            format!("divisions {divisions_value:?}: {reason}"),
        ));
    }
    let generated = match shape {
        ElementShape::Tet4 => box_of_tets(size_value, divisions_value, TetOrder::Linear),
        ElementShape::Tet10 => box_of_tets(size_value, divisions_value, TetOrder::Quadratic),
        ElementShape::Hex8 => box_of_hexes(size_value, divisions_value),
    };
    let mut mesh = generated.map_err(|e| locator.error(size.span(), e.to_string()))?;
    if let Some(origin) = spec.origin {
        let shift = nalgebra::Vector3::from(origin);
        for n in 0..mesh.node_count() {
            let moved = mesh.nodes.position(n) + shift;
            mesh.nodes.set_position(n, moved);
        }
    }
    Ok(mesh)
}

/// The element labels of a block read from a mesh file: its own (by element index) and
/// those of the file's other blocks (rows of a fibers file for them are skipped); and,
/// for a part with `shared_nodes`, the file's node labels (by node index).
pub(super) struct BlockLabels {
    own: Vec<i64>,
    others: HashSet<i64>,
    nodes: Vec<i64>,
}

/// The mesh file that parts with `shared_nodes` share: its key (path and length unit;
/// parts with the same key share one copy of its nodes) and the label of each of its
/// nodes, in the file's order (the order the parts keep).
#[derive(Debug, Clone)]
pub(super) struct SharedFile {
    pub key: String,
    pub node_labels: Vec<i64>,
}

/// One block of a mesh file, with only its nodes (renumbered in the file's order), the node sets, element sets
/// and surfaces restricted to it, and the file's label of each element.
fn read_block(
    entry: &PartEntry,
    file: &Spanned<String>,
    locator: &Locator,
    notes: &mut FileNotes,
) -> Result<(Mesh, BlockLabels), SceneError> {
    let path = locator.resolve(file.span(), file.get_ref())?;
    let imported = read_mesh_with(&path, locator.trust().outside_paths)
        .map_err(|e| locator.error(file.span(), e.to_string()))?;
    notes.warnings = summarize_warnings(&imported.warnings);
    let mesh = imported.mesh;
    let mut element_labels = imported.element_labels;
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
    let scale = match entry.mesh.units.as_ref().map(|u| u.get_ref().as_str()) {
        None | Some("m") => 1.0,
        Some("mm") => 1e-3,
        Some(other) => {
            let units = entry.mesh.units.as_ref().map_or(0..0, |u| u.span());
            return Err(locator.error(
                units,
                format!("units = \"{other}\": the mesh's length unit is \"m\" or \"mm\""),
            ));
        }
    };
    notes.fiber_source = imported.fiber_sources.get(index).cloned().flatten();
    let mut block = mesh.blocks[index].clone();
    // The block's nodes keep the file's order (a mesh written by a study reads back with
    // its own numbering, and with it the implicit solver's ordering and round-off); with
    // `shared_nodes`, every node of the file is kept, by its id in the file.
    let mut used = vec![false; mesh.nodes.len()];
    for &id in &block.connectivity {
        used[id as usize] = true;
    }
    let shared = entry.mesh.shared_nodes;
    let mut new_id = vec![u32::MAX; mesh.nodes.len()];
    let mut nodes = musclefem_core::mesh::Nodes::new();
    for old in (0..mesh.nodes.len()).filter(|&old| shared || used[old]) {
        new_id[old] = nodes.push(scale * mesh.nodes.position(old));
    }
    for id in block.connectivity.iter_mut() {
        *id = new_id[*id as usize];
    }
    // With `shared_nodes`, the nodes in no element of the file (e.g. the ends of tendon
    // strands) belong to no block: every part sharing the file may name them.
    let mut in_an_element = vec![false; mesh.nodes.len()];
    for other in &mesh.blocks {
        for &id in &other.connectivity {
            in_an_element[id as usize] = true;
        }
    }
    let kept_in_set = |n: usize| used[n] || (shared && !in_an_element[n]);
    let mut part = Mesh::new(nodes, vec![block]);
    for (name, set) in &mesh.node_sets {
        // The set's nodes on this block (and the file's free nodes, shared).
        let kept: Vec<u32> = set
            .iter()
            .filter(|&&n| kept_in_set(n as usize))
            .map(|&n| new_id[n as usize])
            .collect();
        if !kept.is_empty() {
            part.node_sets.insert(name.clone(), kept);
        }
    }
    let in_block = |block: u32| block as usize == index;
    for (name, set) in &mesh.element_sets {
        let kept: Vec<ElementRef> = set
            .iter()
            .filter(|e| in_block(e.block))
            .map(|e| ElementRef { block: 0, ..*e })
            .collect();
        if !kept.is_empty() {
            part.element_sets.insert(name.clone(), kept);
        }
    }
    for (name, faces) in &mesh.surfaces {
        let kept: Vec<Face> = faces
            .iter()
            .filter(|f| in_block(f.element.block))
            .map(|f| Face {
                element: ElementRef {
                    block: 0,
                    ..f.element
                },
                ..*f
            })
            .collect();
        if !kept.is_empty() {
            part.surfaces.insert(name.clone(), kept);
        }
    }
    let own = std::mem::take(&mut element_labels[index]);
    let others = element_labels.into_iter().flatten().collect();
    let nodes = if shared {
        imported.node_labels
    } else {
        Vec::new()
    };
    Ok((part, BlockLabels { own, others, nodes }))
}

/// Append `part` (one block) to `mesh`: nodes renumbered after the existing ones, the
/// block named after the part, node sets, element sets and surfaces renamed `PART.SET`.
/// A part of a shared file (`shared`, see [`part_mesh`]) whose file an earlier part
/// brought in (`offsets`: where each shared file's nodes start) adds no nodes: its block
/// refers to that file's. Returns where the part's nodes start in `mesh`.
pub(super) fn append_part(
    mesh: &mut Mesh,
    part: Mesh,
    name: &str,
    shared: Option<&SharedFile>,
    offsets: &mut HashMap<String, u32>,
) -> u32 {
    let present = shared.and_then(|file| offsets.get(&file.key)).copied();
    let offset = present.unwrap_or(mesh.nodes.len() as u32);
    if let (Some(file), None) = (shared, present) {
        offsets.insert(file.key.clone(), offset);
    }
    let first_block = mesh.blocks.len() as u32;
    let moved = |e: ElementRef| ElementRef {
        block: e.block + first_block,
        ..e
    };
    for (set, elements) in part.element_sets {
        mesh.element_sets.insert(
            format!("{name}.{set}"),
            elements.into_iter().map(moved).collect(),
        );
    }
    for (surface, faces) in part.surfaces {
        mesh.surfaces.insert(
            format!("{name}.{surface}"),
            faces
                .into_iter()
                .map(|f| Face {
                    element: moved(f.element),
                    ..f
                })
                .collect(),
        );
    }
    if present.is_none() {
        for i in 0..part.nodes.len() {
            mesh.nodes.push(part.nodes.position(i));
        }
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
    offset
}
