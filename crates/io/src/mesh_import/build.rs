//! The labelled mesh both readers fill ([`RawMesh`]) and its resolution into a [`Mesh`]:
//! labels to 0-based ids, sets and surfaces to ids, then [`Mesh::validate`] with its
//! errors translated back to labels and lines.

use std::collections::HashMap;
use std::collections::hash_map::Entry as MapEntry;
use std::path::PathBuf;

use musclefem_mesh::{ElementBlock, ElementRef, ElementShape, Face, Mesh, MeshError, Nodes};

use super::{ImportError, ImportWarning, ImportedMesh, SkippedKeyword};

mod fibers;
mod surface_elements;

pub(crate) use surface_elements::RawSurfaceElement;

/// A place in the input: file index into [`RawMesh::files`] and 1-based line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Loc {
    pub file: u32,
    pub line: u32,
}

/// One entry of a set: a label, or a `GENERATE` range kept unexpanded until resolution
/// (so a huge range costs nothing until it is checked against the labels).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Member {
    Label(i64),
    Range { first: i64, last: i64, step: i64 },
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct Entry {
    pub member: Member,
    pub loc: Loc,
}

/// Elements of one shape under one name, with file labels.
#[derive(Debug)]
pub(crate) struct RawBlock {
    pub name: String,
    pub type_name: String,
    pub shape: ElementShape,
    pub labels: Vec<i64>,
    /// Node labels, `nodes_per_element` per element.
    pub nodes: Vec<i64>,
    pub locs: Vec<Loc>,
}

/// A mesh in terms of file labels, as read.
#[derive(Debug, Default)]
pub(crate) struct RawMesh {
    pub files: Vec<PathBuf>,
    pub node_labels: Vec<i64>,
    pub nodes: Nodes,
    pub node_locs: Vec<Loc>,
    pub blocks: Vec<RawBlock>,
    pub node_sets: Vec<(String, Vec<Entry>)>,
    pub element_sets: Vec<(String, Vec<Entry>)>,
    /// Surfaces: entries are element labels (or ranges), each with a 0-based face.
    pub surfaces: Vec<(String, Vec<(Entry, u8)>)>,
    pub skipped: Vec<(Loc, String)>,
    /// Warnings: place, keyword or section, message.
    pub warnings: Vec<(Loc, String, String)>,
    /// Fibers given to element sets by the file (Abaqus `*ORIENTATION`).
    pub fiber_assignments: Vec<FiberAssignment>,
    /// 2-D elements (Abaqus R3D3, S4, M3D3, ...) read as surfaces.
    pub surface_elements: Vec<RawSurfaceElement>,
}

/// The fibers of a set of elements.
#[derive(Debug)]
pub(crate) struct FiberAssignment {
    pub elements: Vec<Entry>,
    /// The `*SOLID SECTION` line.
    pub section: Loc,
    /// How `check` names the source, e.g. `*ORIENTATION ORI (deck.inp:12)`.
    pub source: String,
    pub rule: FiberRule,
}

#[derive(Debug)]
pub(crate) enum FiberRule {
    /// One unit direction for all.
    Uniform([f64; 3]),
    /// A unit direction per element (`*DISTRIBUTION`), with the default for the others.
    PerElement {
        distribution: String,
        default: Option<[f64; 3]>,
        per_element: Vec<(Entry, [f64; 3])>,
    },
}

impl RawMesh {
    pub fn file(&self, loc: Loc) -> PathBuf {
        self.files
            .get(loc.file as usize)
            .cloned()
            .unwrap_or_default()
    }

    pub fn error(&self, loc: Loc, message: impl Into<String>) -> ImportError {
        ImportError::Parse {
            file: self.file(loc),
            line: loc.line as usize,
            message: message.into(),
        }
    }

    fn at(&self, loc: Loc) -> String {
        format!("{}:{}", self.file(loc).display(), loc.line)
    }

    /// Resolves labels to ids, builds and validates the mesh.
    pub fn build(self) -> Result<ImportedMesh, ImportError> {
        let main_file = self.files.first().cloned().unwrap_or_default();
        if self.blocks.iter().all(|b| b.labels.is_empty()) {
            return Err(ImportError::Mesh {
                file: main_file,
                message: "the file defines no volume element (supported: hex8, tet4, tet10)".into(),
            });
        }
        let mut node_ids: HashMap<i64, u32> = HashMap::with_capacity(self.node_labels.len());
        for (i, &label) in self.node_labels.iter().enumerate() {
            let id = u32::try_from(i)
                .map_err(|_| self.error(self.node_locs[i], "more than 2^32 nodes"))?;
            match node_ids.entry(label) {
                MapEntry::Occupied(first) => {
                    let first = self.node_locs[*first.get() as usize];
                    return Err(self.error(
                        self.node_locs[i],
                        format!(
                            "node {label} is defined twice (first at {})",
                            self.at(first)
                        ),
                    ));
                }
                MapEntry::Vacant(v) => {
                    v.insert(id);
                }
            }
        }
        let mut element_ids: HashMap<i64, ElementRef> = HashMap::new();
        let mut blocks = Vec::with_capacity(self.blocks.len());
        for (b, raw) in self.blocks.iter().enumerate() {
            let n = raw.shape.nodes_per_element();
            let mut connectivity = Vec::with_capacity(raw.nodes.len());
            for (e, (&label, &loc)) in raw.labels.iter().zip(&raw.locs).enumerate() {
                let element = u32::try_from(e)
                    .map_err(|_| self.error(loc, "more than 2^32 elements in one block"))?;
                let r = ElementRef::new(b as u32, element);
                if let Some(first) = element_ids.insert(label, r) {
                    let first = self.element_loc(first);
                    return Err(self.error(
                        loc,
                        format!(
                            "element {label} is defined twice (first at {})",
                            self.at(first)
                        ),
                    ));
                }
                for &node in raw.nodes.get(e * n..(e + 1) * n).unwrap_or_default() {
                    let id = node_ids.get(&node).ok_or_else(|| {
                        self.error(
                            loc,
                            format!(
                                "element {label} ({}): node {node} is not defined",
                                raw.type_name
                            ),
                        )
                    })?;
                    connectivity.push(*id);
                }
            }
            let block =
                ElementBlock::new(raw.name.clone(), raw.shape, connectivity).map_err(|e| {
                    ImportError::Mesh {
                        file: main_file.clone(),
                        message: e.to_string(),
                    }
                })?;
            blocks.push(block);
        }
        let mut warnings = Vec::new();
        let targets = self.surface_targets(&element_ids, &mut warnings)?;
        let mut mesh = Mesh::new(self.nodes.clone(), blocks);
        for (name, entries) in &self.node_sets {
            let mut ids = self.resolve(entries, &node_ids, "node set", name, "node")?;
            ids.sort_unstable();
            ids.dedup();
            mesh.node_sets.insert(name.clone(), ids);
        }
        let mut element_surfaces = Vec::new();
        for (name, entries) in &self.element_sets {
            let all = self.resolve(entries, &targets, "element set", name, "element")?;
            let mut refs: Vec<ElementRef> = all.iter().filter_map(|t| t.volume()).collect();
            if refs.len() < all.len() {
                element_surfaces.push((name.clone(), all));
                if refs.is_empty() {
                    continue;
                }
            }
            refs.sort_unstable();
            refs.dedup();
            mesh.element_sets.insert(name.clone(), refs);
        }
        for (name, entries) in &self.surfaces {
            let mut faces = Vec::new();
            for (entry, face) in entries {
                let refs = self.resolve(
                    std::slice::from_ref(entry),
                    &element_ids,
                    "surface",
                    name,
                    "element",
                )?;
                for r in refs {
                    let block = &self.blocks[r.block as usize];
                    if usize::from(*face) >= block.shape.face_count() {
                        let label = block.labels[r.element as usize];
                        return Err(self.error(
                            entry.loc,
                            format!(
                                "surface '{name}': face S{} does not exist on element {label} \
                                 ({}, a {} has faces S1..S{})",
                                face + 1,
                                block.type_name,
                                block.shape,
                                block.shape.face_count()
                            ),
                        ));
                    }
                    faces.push(Face::new(r, *face));
                }
            }
            faces.sort_unstable();
            faces.dedup();
            mesh.surfaces.insert(name.clone(), faces);
        }
        self.add_element_surfaces(&mut mesh, &node_ids, &targets, element_surfaces)?;
        let fiber_sources = self.apply_fibers(&mut mesh, &element_ids, &mut warnings)?;
        mesh.validate().map_err(|e| self.translate(e, &main_file))?;
        warnings.extend(
            self.warnings
                .iter()
                .map(|(loc, keyword, message)| (*loc, keyword.clone(), message.clone())),
        );
        warnings.sort_by_key(|(loc, _, _)| (loc.file, loc.line));
        Ok(ImportedMesh {
            fiber_sources,
            warnings: warnings
                .into_iter()
                .map(|(loc, keyword, message)| ImportWarning {
                    file: self.file(loc),
                    line: loc.line as usize,
                    keyword,
                    message,
                })
                .collect(),
            node_labels: self.node_labels.clone(),
            element_labels: self.blocks.iter().map(|b| b.labels.clone()).collect(),
            element_types: self.blocks.iter().map(|b| b.type_name.clone()).collect(),
            skipped_keywords: self
                .skipped
                .iter()
                .map(|(loc, keyword)| SkippedKeyword {
                    file: self.file(*loc),
                    line: loc.line as usize,
                    keyword: keyword.clone(),
                })
                .collect(),
            mesh,
        })
    }

    fn element_loc(&self, r: ElementRef) -> Loc {
        self.blocks
            .get(r.block as usize)
            .and_then(|b| b.locs.get(r.element as usize))
            .copied()
            .unwrap_or_default()
    }

    /// The ids of the entries of a set; an unknown label is an error at its line.
    pub(crate) fn resolve<T: Copy>(
        &self,
        entries: &[Entry],
        ids: &HashMap<i64, T>,
        kind: &str,
        name: &str,
        what: &str,
    ) -> Result<Vec<T>, ImportError> {
        let mut out = Vec::new();
        let unknown = |entry: &Entry, label: i64| {
            self.error(
                entry.loc,
                format!("{kind} '{name}': {what} {label} is not defined"),
            )
        };
        for entry in entries {
            match entry.member {
                Member::Label(label) => {
                    out.push(*ids.get(&label).ok_or_else(|| unknown(entry, label))?)
                }
                Member::Range { first, last, step } => {
                    // At most ids.len() labels exist: a longer range fails at the first
                    // missing label, found within ids.len() + 1 steps.
                    let mut label = first;
                    while label <= last {
                        out.push(*ids.get(&label).ok_or_else(|| unknown(entry, label))?);
                        label = match label.checked_add(step) {
                            Some(next) => next,
                            None => break,
                        };
                    }
                }
            }
        }
        Ok(out)
    }

    /// A validation error in terms of labels and lines where it names an element.
    fn translate(&self, error: MeshError, main_file: &std::path::Path) -> ImportError {
        let element = match &error {
            MeshError::InvertedElement { block, element, .. }
            | MeshError::RepeatedNode { block, element, .. }
            | MeshError::NodeOutOfRange { block, element, .. }
            | MeshError::InvalidFiber { block, element, .. } => Some((block.clone(), *element)),
            _ => None,
        };
        if let Some((name, e)) = element
            && let Some(block) = self.blocks.iter().find(|b| b.name == name)
            && let (Some(label), Some(loc)) = (block.labels.get(e), block.locs.get(e))
        {
            return self.error(
                *loc,
                format!("element {label} ({}): {error}", block.type_name),
            );
        }
        if let MeshError::NonFiniteNode { node, .. } = error
            && let (Some(label), Some(loc)) = (self.node_labels.get(node), self.node_locs.get(node))
        {
            return self.error(*loc, format!("node {label}: {error}"));
        }
        ImportError::Mesh {
            file: main_file.to_path_buf(),
            message: error.to_string(),
        }
    }
}
