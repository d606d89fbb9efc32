//! Gmsh mesh files (`.msh`): format 4.1 in ASCII or binary, format 2.2 in ASCII.
//!
//! Read sections: `$MeshFormat` (`4.1 0 8`, `4.1 1 8` or `2.2 0 8`), `$PhysicalNames`,
//! `$Entities` (4.1), `$Nodes` (parametric coordinates are read over), `$Elements`.
//! Other sections (`$Periodic`, `$NodeData`, `$Comments`, ...) are skipped up to their
//! `$End...` line. A 4.1 binary file (little-endian, `size_t` of 8 bytes) is read by
//! [`read_gmsh`] and [`parse_gmsh_bytes`] (not [`parse_gmsh`], which takes text); in a 2.2 file the first tag of
//! an element is its physical group (0: none) and the second its elementary entity, and
//! everything below applies with the element's physical group as the entity's.
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
//! Refused: 2.2 binary files, big-endian binary files, other versions (save with
//! `Mesh.MshFileVersion = 4.1`, or as ASCII with `Mesh.Binary = 0`).

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use musclefem_mesh::ElementShape;

use super::build::{Entry, Loc, RawMesh};
use super::{ImportError, ImportedMesh, read_bytes, utf8};

mod binary;
mod elements;
mod faces;
mod v2;
mod v4;

/// Reads a Gmsh file: 4.1 (ASCII or binary) or 2.2 (ASCII).
pub fn read_gmsh(path: impl AsRef<Path>) -> Result<ImportedMesh, ImportError> {
    let path = path.as_ref();
    parse_gmsh_bytes(read_bytes(path)?, path)
}

/// Reads the bytes of a Gmsh file (4.1 ASCII or binary, 2.2 ASCII) already in memory;
/// `name` is used in error messages.
pub fn parse_gmsh_bytes(
    bytes: Vec<u8>,
    name: impl AsRef<Path>,
) -> Result<ImportedMesh, ImportError> {
    let path = name.as_ref();
    // The header is text in every encoding: it says whether the rest is binary.
    let head = String::from_utf8_lossy(bytes.get(..64).unwrap_or(&bytes)).into_owned();
    let mut lines = head.lines();
    if lines.next().map(str::trim) == Some("$MeshFormat")
        && let Some(format) = lines.next()
    {
        let format = check_format(format).map_err(|m| ImportError::Parse {
            file: path.to_path_buf(),
            line: 2,
            message: m,
        })?;
        if format == Format::Binary41 {
            return binary::parse(&bytes, path);
        }
    }
    parse_gmsh(&utf8(bytes, path)?, path)
}

/// Reads Gmsh ASCII text (4.1 or 2.2) already in memory; `name` is used in error
/// messages.
pub fn parse_gmsh(text: &str, name: impl AsRef<Path>) -> Result<ImportedMesh, ImportError> {
    let mut reader = Reader::new(name.as_ref(), text);
    reader.run()?;
    reader.finish()?.build()
}

/// The versions and encodings read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Ascii41,
    Binary41,
    Ascii22,
}

/// The format of the `$MeshFormat` line `version file-type data-size`, or why it is not
/// read.
fn check_format(line: &str) -> Result<Format, String> {
    let fields: Vec<&str> = line.split_whitespace().collect();
    let (Some(&version), Some(&file_type)) = (fields.first(), fields.get(1)) else {
        return Err(format!(
            "$MeshFormat: expected 'version file-type data-size', found '{}'",
            short(line.trim())
        ));
    };
    match (version, file_type) {
        ("4.1", "0") => Ok(Format::Ascii41),
        ("4.1", "1") if fields.get(2) == Some(&"8") => Ok(Format::Binary41),
        ("4.1", "1") => Err(format!(
            "$MeshFormat: binary data size {} is not supported: only 8 (size_t of 64 bits) is",
            fields.get(2).map_or("(missing)", |s| s)
        )),
        ("2.2", "0") => Ok(Format::Ascii22),
        ("2.2", _) => Err(
            "$MeshFormat: binary 2.2 files are not supported: save as 4.1 \
             (Mesh.MshFileVersion = 4.1) or as ASCII (Mesh.Binary = 0)"
                .into(),
        ),
        _ => Err(format!(
            "$MeshFormat: version {} is not supported: 4.1 (ASCII or binary) and 2.2 (ASCII) \
             are (save with Mesh.MshFileVersion = 4.1)",
            short(version)
        )),
    }
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
    /// Entries in `group_nodes`, bounded by [`elements::MAX_GROUP_ENTRIES`].
    group_entries: usize,
    format: Option<Format>,
}

impl<'t> Reader<'t> {
    fn new(name: &Path, text: &'t str) -> Self {
        Reader {
            raw: RawMesh {
                files: vec![name.to_path_buf()],
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
            format: None,
        }
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
            let format_seen = self.format.is_some();
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
            if self.format.is_none() && section != "MeshFormat" {
                return Err(self.error(format!(
                    "expected $MeshFormat first, found '{}'",
                    short(&header)
                )));
            }
            match section {
                "MeshFormat" => {
                    let line = self.line("the format line")?.to_string();
                    let format = check_format(&line).map_err(|m| self.error(m))?;
                    if format == Format::Binary41 {
                        return Err(self.error(
                            "$MeshFormat: a binary file given as text: read it with read_gmsh or parse_gmsh_bytes",
                        ));
                    }
                    self.format = Some(format);
                }
                "PhysicalNames" => self.physical_names()?,
                "Entities" => self.entities()?,
                "Nodes" if self.format == Some(Format::Ascii22) => self.nodes_v2()?,
                "Elements" if self.format == Some(Format::Ascii22) => self.elements_v2()?,
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
            let (dim, tag, name) = physical_name(&line).map_err(|m| self.error(m))?;
            self.physical_names.insert((dim, tag), name);
        }
        Ok(())
    }

    /// Turns physical groups into sets and surfaces.
    fn finish(mut self) -> Result<RawMesh, ImportError> {
        if self.format.is_none() {
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

/// A `$PhysicalNames` line `dim tag "name"`.
fn physical_name(line: &str) -> Result<(i64, i64, String), String> {
    let mut fields = line.splitn(3, char::is_whitespace);
    let dim = fields.next().and_then(|f| f.parse::<i64>().ok());
    let tag = fields.next().and_then(|f| f.parse::<i64>().ok());
    let name = fields
        .next()
        .map(|f| f.trim().trim_matches('"').to_string());
    match (dim, tag, name) {
        (Some(dim), Some(tag), Some(name)) if !name.is_empty() => Ok((dim, tag, name)),
        _ => Err(format!(
            "$PhysicalNames: expected 'dim tag \"name\"', found '{}'",
            short(line)
        )),
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
