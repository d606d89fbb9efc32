//! Gmsh mesh files (`.msh`), format 4.1 in ASCII.
//!
//! Read sections: `$MeshFormat` (must say `4.1 0 8`), `$PhysicalNames`, `$Entities`,
//! `$Nodes` (parametric coordinates are read over), `$Elements`. Other sections
//! (`$Periodic`, `$NodeData`, `$Comments`, ...) are skipped up to their `$End...` line.
//!
//! - Volume elements: Gmsh types 4 (tet4), 5 (hex8) and 11 (tet10), one line each. Node
//!   order: tet4 and hex8 are Abaqus's; Gmsh's tet10 puts its mid-edge nodes on the edges
//!   (0,1), (1,2), (2,0), (3,0), (3,2), (3,1) — its last two are swapped into Abaqus's
//!   (1,3), (2,3). One block per (physical volume name, shape): a volume entity's block is
//!   named after its first physical group (`physical_3_TAG` if the group has no name), or
//!   `volume_TAG` if it has none; `element_types` holds "tet4", "hex8" or "tet10".
//!   Other volume types (prisms, pyramids, hex20, ...) are refused with an error.
//! - Physical groups: each volume group becomes an element set, each surface group a
//!   surface (every triangle or quadrangle — types 2, 3, 9, 10, 16 — matched by its
//!   corner nodes to the face of the volume element that holds it; on an interface shared
//!   by two elements, the one whose outward normal agrees with the 2-D element's node
//!   order), and every group, of any dimension, a node set of the nodes of its elements.
//!   Unnamed groups are named `physical_DIM_TAG`.
//! - Points and lines (dimensions 0 and 1) only contribute to node sets.
//!
//! Refused: binary files (save with `Mesh.Binary = 0`), format versions other than 4.1
//! (save with `Mesh.MshFileVersion = 4.1`).

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use musclefem_mesh::ElementShape;

use super::build::{Entry, Loc, Member, RawBlock, RawMesh};
use super::{ImportError, ImportedMesh, read_bytes, utf8};

mod faces;

/// Reads a Gmsh 4.1 ASCII file.
pub fn read_gmsh(path: impl AsRef<Path>) -> Result<ImportedMesh, ImportError> {
    let path = path.as_ref();
    let bytes = read_bytes(path)?;
    let text = match String::from_utf8(bytes) {
        Ok(text) => text,
        Err(e) => {
            // A binary file has a text header: say what it is rather than "not UTF-8".
            let bytes = e.into_bytes();
            let head = String::from_utf8_lossy(bytes.get(..64).unwrap_or(&bytes)).into_owned();
            let mut lines = head.lines();
            if lines.next().map(str::trim) == Some("$MeshFormat")
                && let Some(format) = lines.next()
            {
                check_format(format).map_err(|m| ImportError::Parse {
                    file: path.to_path_buf(),
                    line: 2,
                    message: m,
                })?;
            }
            utf8(bytes, path)?
        }
    };
    parse_gmsh(&text, path)
}

/// Reads Gmsh 4.1 ASCII text already in memory; `name` is used in error messages.
pub fn parse_gmsh(text: &str, name: impl AsRef<Path>) -> Result<ImportedMesh, ImportError> {
    let mut reader = Reader {
        raw: RawMesh {
            files: vec![name.as_ref().to_path_buf()],
            ..RawMesh::default()
        },
        lines: text.lines().enumerate(),
        last_line: 0,
        physical_names: HashMap::new(),
        entity_groups: HashMap::new(),
        blocks: HashMap::new(),
        entity_blocks: HashMap::new(),
        group_nodes: BTreeMap::new(),
        group_elements: BTreeMap::new(),
        surface_elements: Vec::new(),
        group_entries: 0,
        format_seen: false,
    };
    reader.run()?;
    reader.finish()?.build()
}

/// Errors unless the `$MeshFormat` line is `4.1 0 <size>`.
fn check_format(line: &str) -> Result<(), String> {
    let fields: Vec<&str> = line.split_whitespace().collect();
    let (Some(&version), Some(&file_type)) = (fields.first(), fields.get(1)) else {
        return Err(format!(
            "$MeshFormat: expected 'version file-type data-size', found '{}'",
            line.trim()
        ));
    };
    if version != "4.1" {
        return Err(format!(
            "$MeshFormat: version {version} is not supported: only 4.1 is (save with Mesh.MshFileVersion = 4.1)"
        ));
    }
    if file_type != "0" {
        return Err(
            "$MeshFormat: binary .msh files are not supported: save as ASCII (Mesh.Binary = 0)"
                .into(),
        );
    }
    Ok(())
}

/// A 2-D element on a physical surface, kept to be matched to a volume face.
struct SurfaceElement {
    tag: i64,
    entity: i64,
    /// Physical surface groups it belongs to.
    groups: Vec<i64>,
    /// Corner node tags in the element's order.
    corners: Vec<i64>,
    loc: Loc,
}

struct Reader<'t> {
    raw: RawMesh,
    lines: std::iter::Enumerate<std::str::Lines<'t>>,
    last_line: usize,
    physical_names: HashMap<(i64, i64), String>,
    /// Physical tags of each entity (dim, tag).
    entity_groups: HashMap<(i64, i64), Vec<i64>>,
    /// Block index by (name, shape).
    blocks: HashMap<(String, ElementShape), usize>,
    /// Block index by (entity, its first physical group, shape).
    entity_blocks: HashMap<(i64, Option<i64>, ElementShape), usize>,
    /// Node tags of the elements of each physical group (dim, tag).
    group_nodes: BTreeMap<(i64, i64), Vec<Entry>>,
    group_elements: BTreeMap<(i64, i64), Vec<Entry>>,
    surface_elements: Vec<SurfaceElement>,
    /// Entries in `group_nodes`, bounded by [`MAX_GROUP_ENTRIES`].
    group_entries: usize,
    format_seen: bool,
}

/// Node entries over all physical groups (an entity in many groups multiplies them).
const MAX_GROUP_ENTRIES: usize = 1 << 26;

/// Gmsh types of 2-D elements and their number of nodes (corners first).
fn surface_type(element_type: i64) -> Option<(usize, usize)> {
    match element_type {
        2 => Some((3, 3)),
        9 => Some((6, 3)),
        20 => Some((9, 3)),
        21 => Some((10, 3)),
        3 => Some((4, 4)),
        16 => Some((8, 4)),
        10 => Some((9, 4)),
        _ => None,
    }
}

/// Why an element type cannot be read in an entity of dimension `dim` (`grouped`: the
/// entity is in a physical group), if it cannot.
fn unsupported_type(dim: i64, entity: i64, element_type: i64, grouped: bool) -> Option<String> {
    if dim == 3 && volume_type(element_type).is_none() {
        return Some(format!(
            "$Elements: element type {element_type} in volume {entity} is not supported \
             (supported: 4 tet4, 5 hex8, 11 tet10)"
        ));
    }
    if dim == 2 && grouped && surface_type(element_type).is_none() {
        return Some(format!(
            "$Elements: element type {element_type} on physical surface {entity} is not \
             supported (supported: 2, 3, 9, 10, 16, 20, 21)"
        ));
    }
    None
}

fn volume_type(element_type: i64) -> Option<ElementShape> {
    match element_type {
        4 => Some(ElementShape::Tet4),
        5 => Some(ElementShape::Hex8),
        11 => Some(ElementShape::Tet10),
        _ => None,
    }
}

impl Reader<'_> {
    fn loc(&self) -> Loc {
        Loc {
            file: 0,
            line: u32::try_from(self.last_line).unwrap_or(u32::MAX),
        }
    }

    fn error(&self, message: impl Into<String>) -> ImportError {
        self.raw.error(self.loc(), message)
    }

    /// The next non-blank line, trimmed; an error naming `what` at the end of the file.
    fn line(&mut self, what: &str) -> Result<&str, ImportError> {
        for (i, line) in self.lines.by_ref() {
            self.last_line = i + 1;
            let line = line.trim();
            if !line.is_empty() {
                return Ok(line);
            }
        }
        self.last_line += 1;
        Err(self.error(format!("unexpected end of file: expected {what}")))
    }

    /// The next line as whitespace-separated integers, at least `min` of them.
    fn integers(&mut self, min: usize, what: &str) -> Result<Vec<i64>, ImportError> {
        let line = self.line(what)?.to_string();
        let values: Option<Vec<i64>> = line.split_whitespace().map(|f| f.parse().ok()).collect();
        match values {
            Some(v) if v.len() >= min => Ok(v),
            Some(v) => Err(self.error(format!(
                "{what}: expected at least {min} integers, found {}",
                v.len()
            ))),
            None => Err(self.error(format!(
                "{what}: '{}' holds a field that is not an integer",
                short(&line)
            ))),
        }
    }

    /// A count from the file, non-negative.
    fn count(&self, value: i64, what: &str) -> Result<usize, ImportError> {
        usize::try_from(value).map_err(|_| self.error(format!("{what}: negative count {value}")))
    }

    fn run(&mut self) -> Result<(), ImportError> {
        loop {
            let format_seen = self.format_seen;
            let header = match self.line("a section") {
                Ok(line) => line.to_string(),
                Err(_) if format_seen => return Ok(()),
                Err(_) => return Err(self.error("empty file: expected $MeshFormat")),
            };
            let Some(section) = header.strip_prefix('$') else {
                return Err(self.error(format!(
                    "expected a section header ($Name), found '{}'",
                    short(&header)
                )));
            };
            if !self.format_seen && section != "MeshFormat" {
                return Err(self.error(format!(
                    "expected $MeshFormat first, found '{}'",
                    short(&header)
                )));
            }
            match section {
                "MeshFormat" => {
                    let line = self.line("the format line")?.to_string();
                    check_format(&line).map_err(|m| self.error(m))?;
                    self.format_seen = true;
                }
                "PhysicalNames" => self.physical_names()?,
                "Entities" => self.entities()?,
                "Nodes" => self.nodes()?,
                "Elements" => self.elements()?,
                _ => {}
            }
            // Every section ends with $End<Name>; skipped sections are read up to it.
            let end = format!("$End{section}");
            loop {
                let line = self.line(&end)?;
                if line == end {
                    break;
                }
                if !is_skipped(section) {
                    let line = line.to_string();
                    return Err(self.error(format!(
                        "${section}: expected {end}, found '{}'",
                        short(&line)
                    )));
                }
            }
        }
    }

    fn physical_names(&mut self) -> Result<(), ImportError> {
        let n = self.integers(1, "$PhysicalNames: the number of names")?[0];
        for _ in 0..self.count(n, "$PhysicalNames")? {
            let line = self.line("$PhysicalNames: 'dim tag \"name\"'")?.to_string();
            let mut fields = line.splitn(3, char::is_whitespace);
            let dim = fields.next().and_then(|f| f.parse::<i64>().ok());
            let tag = fields.next().and_then(|f| f.parse::<i64>().ok());
            let name = fields
                .next()
                .map(|f| f.trim().trim_matches('"').to_string());
            match (dim, tag, name) {
                (Some(dim), Some(tag), Some(name)) if !name.is_empty() => {
                    self.physical_names.insert((dim, tag), name);
                }
                _ => {
                    return Err(self.error(format!(
                        "$PhysicalNames: expected 'dim tag \"name\"', found '{}'",
                        short(&line)
                    )));
                }
            }
        }
        Ok(())
    }

    fn entities(&mut self) -> Result<(), ImportError> {
        let counts = self.integers(4, "$Entities: numPoints numCurves numSurfaces numVolumes")?;
        for dim in 0..4 {
            let n = self.count(counts[dim], "$Entities")?;
            // Points: tag x y z numPhysical ...; others: tag and a bounding box first.
            let physical_at = if dim == 0 { 4 } else { 7 };
            for _ in 0..n {
                let line = self.line("an entity line")?.to_string();
                let fields: Vec<&str> = line.split_whitespace().collect();
                let bad = || {
                    self.error(format!(
                        "$Entities: malformed entity of dimension {dim}: '{}'",
                        short(&line)
                    ))
                };
                let tag = fields
                    .first()
                    .and_then(|f| f.parse::<i64>().ok())
                    .ok_or_else(bad)?;
                let n_physical = fields
                    .get(physical_at)
                    .and_then(|f| f.parse::<usize>().ok())
                    .ok_or_else(bad)?;
                let groups: Option<Vec<i64>> = fields
                    .get(physical_at + 1..(physical_at + 1).saturating_add(n_physical))
                    .and_then(|g| {
                        g.iter()
                            .map(|f| f.parse::<i64>().ok().map(i64::abs))
                            .collect()
                    });
                self.entity_groups
                    .insert((dim as i64, tag), groups.ok_or_else(bad)?);
            }
        }
        Ok(())
    }

    fn nodes(&mut self) -> Result<(), ImportError> {
        let header = self.integers(4, "$Nodes: numEntityBlocks numNodes minNodeTag maxNodeTag")?;
        let header_loc = self.loc();
        let (blocks, total) = (
            self.count(header[0], "$Nodes")?,
            self.count(header[1], "$Nodes")?,
        );
        let first_node = self.raw.node_labels.len();
        for _ in 0..blocks {
            let block =
                self.integers(4, "$Nodes: entityDim entityTag parametric numNodesInBlock")?;
            if !(0..=3).contains(&block[0]) {
                return Err(
                    self.error(format!("$Nodes: entity dimension {} is not 0..3", block[0]))
                );
            }
            let extra = if block[2] != 0 { block[0] as usize } else { 0 };
            let n = self.count(block[3], "$Nodes: numNodesInBlock")?;
            let mut tags = Vec::new();
            for _ in 0..n {
                let tag = self.integers(1, "$Nodes: a node tag")?[0];
                if tag <= 0 {
                    return Err(self.error(format!("$Nodes: node tag {tag} is not positive")));
                }
                tags.push((tag, self.loc()));
            }
            for &(tag, loc) in &tags {
                let line = self.line("$Nodes: node coordinates")?.to_string();
                let values: Option<Vec<f64>> =
                    line.split_whitespace().map(|f| f.parse().ok()).collect();
                let x = match values {
                    Some(v) if v.len() == 3 + extra => v,
                    _ => {
                        return Err(self.error(format!(
                            "$Nodes: node {tag}: expected {} numbers, found '{}'",
                            3 + extra,
                            short(&line)
                        )));
                    }
                };
                if x.iter().any(|c| !c.is_finite()) {
                    return Err(self.error(format!(
                        "$Nodes: node {tag}: coordinates '{}' are not finite",
                        short(&line)
                    )));
                }
                self.raw.node_labels.push(tag);
                self.raw.nodes.x.push(x[0]);
                self.raw.nodes.y.push(x[1]);
                self.raw.nodes.z.push(x[2]);
                self.raw.node_locs.push(loc);
            }
        }
        let read = self.raw.node_labels.len() - first_node;
        if read != total {
            return Err(self.raw.error(
                header_loc,
                format!("$Nodes: the header announces {total} nodes, the blocks hold {read}"),
            ));
        }
        Ok(())
    }

    fn elements(&mut self) -> Result<(), ImportError> {
        let header = self.integers(4, "$Elements: numEntityBlocks numElements minTag maxTag")?;
        let header_loc = self.loc();
        let (blocks, total) = (
            self.count(header[0], "$Elements")?,
            self.count(header[1], "$Elements")?,
        );
        let mut read = 0usize;
        for _ in 0..blocks {
            let block = self.integers(
                4,
                "$Elements: entityDim entityTag elementType numElementsInBlock",
            )?;
            let (dim, entity, element_type) = (block[0], block[1], block[2]);
            let n = self.count(block[3], "$Elements: numElementsInBlock")?;
            let groups = self
                .entity_groups
                .get(&(dim, entity))
                .cloned()
                .unwrap_or_default();
            if let Some(m) = unsupported_type(dim, entity, element_type, !groups.is_empty()) {
                return Err(self.error(m));
            }
            for _ in 0..n {
                let tags = self.integers(2, "$Elements: elementTag nodeTag ...")?;
                let loc = self.loc();
                self.add_element(dim, entity, element_type, &groups, tags[0], &tags[1..], loc)?;
            }
            read += n;
        }
        if read != total {
            return Err(self.raw.error(
                header_loc,
                format!("$Elements: the header announces {total} elements, the blocks hold {read}"),
            ));
        }
        Ok(())
    }

    /// One element of entity (`dim`, `entity`) in the physical `groups`: a volume element
    /// goes to its block and element sets, a 2-D element of a physical surface is kept to
    /// be matched to a volume face, and every element's nodes go to its groups' node sets.
    #[allow(clippy::too_many_arguments)]
    fn add_element(
        &mut self,
        dim: i64,
        entity: i64,
        element_type: i64,
        groups: &[i64],
        tag: i64,
        nodes: &[i64],
        loc: Loc,
    ) -> Result<(), ImportError> {
        let error = |m: String| self.raw.error(loc, m);
        if tag <= 0 || nodes.iter().any(|&t| t <= 0) {
            return Err(error(format!(
                "$Elements: element {tag}: tags must be positive"
            )));
        }
        self.group_entries = self
            .group_entries
            .saturating_add(groups.len() * nodes.len());
        if self.group_entries > MAX_GROUP_ENTRIES {
            return Err(error(format!(
                "$Elements: physical groups hold more than {MAX_GROUP_ENTRIES} node entries"
            )));
        }
        for &g in groups {
            let set = self.group_nodes.entry((dim, g)).or_default();
            set.extend(nodes.iter().map(|&l| Entry {
                member: Member::Label(l),
                loc,
            }));
        }
        if let Some(m) = unsupported_type(dim, entity, element_type, !groups.is_empty()) {
            return Err(error(m));
        }
        match dim {
            3 => {
                let Some(shape) = volume_type(element_type) else {
                    return Ok(());
                };
                let expected = shape.nodes_per_element();
                if nodes.len() != expected {
                    return Err(error(format!(
                        "$Elements: element {tag} ({shape}): expected {expected} node tags, found {}",
                        nodes.len()
                    )));
                }
                let b = self.block(entity, groups, shape);
                let block = &mut self.raw.blocks[b];
                block.labels.push(tag);
                let start = block.nodes.len();
                block.nodes.extend_from_slice(nodes);
                if shape == ElementShape::Tet10 {
                    block.nodes.swap(start + 8, start + 9);
                }
                block.locs.push(loc);
                for &g in groups {
                    let set = self.group_elements.entry((3, g)).or_default();
                    set.push(Entry {
                        member: Member::Label(tag),
                        loc,
                    });
                }
            }
            2 if !groups.is_empty() => {
                let Some((count, corners)) = surface_type(element_type) else {
                    return Ok(());
                };
                if nodes.len() != count {
                    return Err(error(format!(
                        "$Elements: surface element {tag} (type {element_type}): expected {count} node tags, found {}",
                        nodes.len()
                    )));
                }
                self.surface_elements.push(SurfaceElement {
                    tag,
                    entity,
                    groups: groups.to_vec(),
                    corners: nodes[..corners].to_vec(),
                    loc,
                });
            }
            _ => {}
        }
        Ok(())
    }

    /// The name of physical group (dim, tag).
    fn group_name(&self, dim: i64, tag: i64) -> String {
        self.physical_names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| format!("physical_{dim}_{tag}"))
    }

    /// The block of a volume entity's elements of one shape.
    fn block(&mut self, entity: i64, groups: &[i64], shape: ElementShape) -> usize {
        let cached = (entity, groups.first().copied(), shape);
        if let Some(&b) = self.entity_blocks.get(&cached) {
            return b;
        }
        let b = self.named_block(entity, groups, shape);
        self.entity_blocks.insert(cached, b);
        b
    }

    fn named_block(&mut self, entity: i64, groups: &[i64], shape: ElementShape) -> usize {
        let name = match groups.first() {
            Some(&g) => self.group_name(3, g),
            None => format!("volume_{entity}"),
        };
        let key = (name.clone(), shape);
        if let Some(&b) = self.blocks.get(&key) {
            return b;
        }
        let mut unique = name.clone();
        if self.raw.blocks.iter().any(|b| b.name == unique) {
            unique = format!("{name}_{shape}");
        }
        self.raw.blocks.push(RawBlock {
            name: unique,
            type_name: shape.name().to_string(),
            shape,
            labels: Vec::new(),
            nodes: Vec::new(),
            locs: Vec::new(),
        });
        self.blocks.insert(key, self.raw.blocks.len() - 1);
        self.raw.blocks.len() - 1
    }

    /// Turns physical groups into sets and surfaces.
    fn finish(mut self) -> Result<RawMesh, ImportError> {
        if !self.format_seen {
            return Err(self.error("no $MeshFormat section"));
        }
        let mut node_sets: BTreeMap<String, Vec<Entry>> = BTreeMap::new();
        for (&(dim, tag), entries) in &self.group_nodes {
            node_sets
                .entry(self.group_name(dim, tag))
                .or_default()
                .extend(entries);
        }
        self.raw.node_sets = node_sets.into_iter().collect();
        self.raw.element_sets = self
            .group_elements
            .iter()
            .map(|(&(dim, tag), entries)| (self.group_name(dim, tag), entries.clone()))
            .collect();
        self.raw.surfaces = faces::surfaces(&self)?;
        Ok(self.raw)
    }
}

fn is_skipped(section: &str) -> bool {
    !matches!(
        section,
        "MeshFormat" | "PhysicalNames" | "Entities" | "Nodes" | "Elements"
    )
}

fn short(s: &str) -> String {
    let mut out: String = s.chars().take(60).collect();
    if s.chars().nth(60).is_some() {
        out.push('…');
    }
    out
}
