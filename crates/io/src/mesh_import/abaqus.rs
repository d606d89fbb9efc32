//! Abaqus input files (`.inp`): the mesh part of the model.
//!
//! Read:
//!
//! - `*NODE` (label and x, y, z; up to three more fields, the normal, are ignored;
//!   `NSET=` adds the nodes to a node set);
//! - `*ELEMENT, TYPE=..., ELSET=...` for C3D4(H), C3D8(H, I, R, RH), C3D10(H, M, MH); a data
//!   line ending in a comma continues on the next line (C3D10 often wraps); one block per
//!   (type, `ELSET`), named after the element set (or the type), and `ELSET=` also makes
//!   the element set;
//! - 2-D elements (R3D3/R3D4, S3/S3R/S4/S4R, M3D3/M3D4(R)/M3D6/M3D8, SFM3D3/4(R)/6,
//!   STRI65) as surfaces: each is matched by its corners to a volume element's face, and
//!   the `*ELEMENT`'s `ELSET=` (or its type, e.g. `R3D3`) and every `*ELSET` listing it
//!   name a surface of those faces and a node set of its nodes (one on no volume face is
//!   only in the node set, with a warning);
//! - `*ORIENTATION` (rectangular; points a, b[, c] or a `*DISTRIBUTION` name; optional
//!   rotation line), `*DISTRIBUTION, LOCATION=ELEMENT` with its `*DISTRIBUTION TABLE`
//!   `COORD3D, COORD3D`, and `*SOLID SECTION, ELSET=..., ORIENTATION=...`: the elements of
//!   the set get the local 1-axis as their fiber (the convention of transversely
//!   isotropic UMATs: e1 = (a − c)/|a − c|, turned by the rotation line); the section's
//!   material is ignored with a warning;
//! - `*NSET` / `*ELSET` with labels, names of sets defined earlier (also
//!   `instance.set`), or `GENERATE` (`first, last[, step]`, step ≥ 1);
//! - `*SURFACE, NAME=..., TYPE=ELEMENT` (the default) with `element set or label, Sn`
//!   lines: S1..S6 on hexes, S1..S4 on tets;
//! - `*PART` / `*END PART`, `*ASSEMBLY` / `*END ASSEMBLY`, `*INSTANCE` / `*END INSTANCE`
//!   with exactly one part and one instance; the instance's optional translation line and
//!   rotation line (point a, point b, angle [deg] about the axis a→b) move the part's
//!   nodes, translation first; assembly-level sets and surfaces name the instance
//!   (`INSTANCE=` or `instance.set`);
//! - `*INCLUDE, INPUT=path`, relative to the including file (errors then name the
//!   included file and its line), in the top file's folder or below it unless read with
//!   [`read_abaqus_with`]`(path, true)` (a deck is not a key to the whole disk: an
//!   error in an included file quotes its content); nodes may come after the elements
//!   that use them.
//!
//! Keywords and parameters are case-insensitive, `**` starts a comment line, labels are
//! any positive integers (not necessarily contiguous). Model and history keywords that do
//! not shape the mesh (`*MATERIAL`, `*STEP`, `*BOUNDARY`, ...) are skipped with their
//! data, listed in [`super::ImportedMesh::skipped_keywords`] and warned about, with the
//! reason, in [`super::ImportedMesh::warnings`].
//!
//! Refused with an error naming them (never silently skipped): mesh generation keywords
//! (`*NGEN`, `*NFILL`, `*ELGEN`, `*NCOPY`, ...), `*SYSTEM`, `*TRANSFORM`, `*PARAMETER`,
//! other element types (C3D20, C3D6, beams, ...), cylindrical, spherical or node-based
//! orientations, node-based surfaces, several parts or instances,
//! assembly-level nodes and elements (reference points), unknown parameters of the read
//! keywords, and any keyword that is not an Abaqus keyword at all (with the nearest known
//! one suggested).

use std::collections::HashMap;
use std::path::Path;

use super::abaqus_keywords::{Class, classify, nearest, skip_reason};
use super::build::{Entry, FiberRule, Loc, RawMesh};
use super::{ImportError, ImportedMesh, read_bytes, utf8};

mod data;
mod include;
mod orientation;

use include::{Includes, flatten};

/// Set and surface entries over the whole file (guards against sets that double in size
/// line after line by naming themselves).
const MAX_COPIED_ENTRIES: usize = 1 << 24;

/// Reads an Abaqus input file and the files it includes (from its folder or below).
pub fn read_abaqus(path: impl AsRef<Path>) -> Result<ImportedMesh, ImportError> {
    read_abaqus_with(path, false)
}

/// [`read_abaqus`], with includes from outside the file's folder when
/// `outside_includes` (the user trusts the deck).
pub fn read_abaqus_with(
    path: impl AsRef<Path>,
    outside_includes: bool,
) -> Result<ImportedMesh, ImportError> {
    let path = path.as_ref();
    let text = utf8(read_bytes(path)?, path)?;
    let includes = if outside_includes {
        Includes::Anywhere
    } else {
        Includes::InFolder
    };
    parse(&text, path, includes)
}

/// Reads Abaqus input already in memory; `name` is used in error messages. `*INCLUDE`
/// is refused (there is no file to be relative to): use [`read_abaqus`] for that.
pub fn parse_abaqus(text: &str, name: impl AsRef<Path>) -> Result<ImportedMesh, ImportError> {
    parse(text, name.as_ref(), Includes::Refused)
}

fn parse(text: &str, path: &Path, includes: Includes) -> Result<ImportedMesh, ImportError> {
    let mut raw = RawMesh {
        files: vec![path.to_path_buf()],
        ..RawMesh::default()
    };
    let mut lines = Vec::new();
    flatten(&mut raw.files, &mut lines, text, 0, includes, 0)?;
    let mut reader = Reader::new(raw);
    reader.run(&lines)?;
    reader.finish()?.build()
}

/// One line of input after `*INCLUDE` expansion, trimmed.
struct Line {
    loc: Loc,
    text: String,
}

fn is_keyword(text: &str) -> bool {
    text.starts_with('*') && !text.starts_with("**")
}

/// A keyword line: the name in upper case with single spaces, and the parameters (keys
/// in upper case, values as written without quotes).
struct Keyword {
    name: String,
    params: Vec<(String, Option<String>)>,
    loc: Loc,
}

/// Upper case, inner runs of blanks as one space.
fn normalize(s: &str) -> String {
    s.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_ascii_uppercase()
}

/// Splits at commas outside double quotes.
fn split_fields(s: &str) -> Vec<&str> {
    let mut fields = Vec::new();
    let mut start = 0;
    let mut quoted = false;
    for (i, c) in s.char_indices() {
        match c {
            '"' => quoted = !quoted,
            ',' if !quoted => {
                fields.push(s.get(start..i).unwrap_or("").trim());
                start = i + 1;
            }
            _ => {}
        }
    }
    fields.push(s.get(start..).unwrap_or("").trim());
    fields
}

impl Keyword {
    fn parse(text: &str, loc: Loc) -> Result<Self, String> {
        let body = text.strip_prefix('*').unwrap_or(text);
        let mut fields = split_fields(body).into_iter();
        let name = normalize(fields.next().unwrap_or(""));
        if name.is_empty() {
            return Err("a keyword line with no keyword ('*' alone)".into());
        }
        let params = fields
            .filter(|f| !f.is_empty())
            .map(|f| match f.split_once('=') {
                Some((key, value)) => (
                    normalize(key),
                    Some(value.trim().trim_matches('"').to_string()),
                ),
                None => (normalize(f), None),
            })
            .collect();
        Ok(Self { name, params, loc })
    }

    fn get(&self, key: &str) -> Option<&str> {
        self.params
            .iter()
            .find(|(k, _)| k == key)
            .and_then(|(_, v)| v.as_deref())
    }

    fn has(&self, key: &str) -> bool {
        self.params.iter().any(|(k, _)| k == key)
    }
}

/// The data lines of one keyword, split into fields.
struct Data<'a> {
    loc: Loc,
    fields: Vec<&'a str>,
    /// The line ended with a comma (an `*ELEMENT` line continues).
    continued: bool,
}

/// Where in the part/assembly structure the reader is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scope {
    Model,
    Part,
    Assembly,
    Instance,
}

/// The one instance of the one part, with its placement.
struct Instance {
    name: String,
    translation: [f64; 3],
    /// Point a, point b and the angle [deg] of a rotation about the axis a→b.
    rotation: Option<([f64; 3], [f64; 3], f64)>,
    loc: Loc,
}

/// A named set during reading: index into the raw mesh's list, by lower-case name.
type Names = HashMap<String, usize>;

struct Reader {
    raw: RawMesh,
    scope: Scope,
    scope_loc: Loc,
    part: Option<(String, Loc)>,
    assembly_seen: bool,
    instance: Option<Instance>,
    node_sets: Names,
    element_sets: Names,
    surfaces: Names,
    /// Block index by (element type, lower-case element set name).
    blocks: HashMap<(String, String), usize>,
    copied: usize,
    orientations: orientation::Orientations,
}

impl Reader {
    fn new(raw: RawMesh) -> Self {
        Self {
            raw,
            scope: Scope::Model,
            scope_loc: Loc::default(),
            part: None,
            assembly_seen: false,
            instance: None,
            node_sets: Names::new(),
            element_sets: Names::new(),
            surfaces: Names::new(),
            blocks: HashMap::new(),
            copied: 0,
            orientations: orientation::Orientations::default(),
        }
    }

    fn error(&self, loc: Loc, message: impl Into<String>) -> ImportError {
        self.raw.error(loc, message)
    }

    /// Records a warning at `loc` about `keyword`.
    fn warn(&mut self, loc: Loc, keyword: &str, message: String) {
        self.raw.warnings.push((loc, keyword.to_string(), message));
    }

    fn run(&mut self, lines: &[Line]) -> Result<(), ImportError> {
        let mut i = 0;
        while let Some(line) = lines.get(i) {
            i += 1;
            if line.text.is_empty() || line.text.starts_with("**") {
                continue;
            }
            if !is_keyword(&line.text) {
                return Err(self.error(
                    line.loc,
                    format!("data line outside any keyword: '{}'", short(&line.text)),
                ));
            }
            let mut text = line.text.clone();
            while text.ends_with(',')
                && let Some(next) = lines.get(i)
                && !next.text.starts_with('*')
            {
                text.push_str(&next.text);
                i += 1;
            }
            let keyword = Keyword::parse(&text, line.loc).map_err(|m| self.error(line.loc, m))?;
            let mut data = Vec::new();
            while let Some(next) = lines.get(i).filter(|l| !is_keyword(&l.text)) {
                i += 1;
                if next.text.is_empty() || next.text.starts_with("**") {
                    continue;
                }
                let mut fields = split_fields(&next.text);
                let continued = next.text.ends_with(',');
                if continued {
                    fields.pop();
                }
                data.push(Data {
                    loc: next.loc,
                    fields,
                    continued,
                });
            }
            self.keyword(&keyword, &data)?;
        }
        Ok(())
    }

    fn keyword(&mut self, keyword: &Keyword, data: &[Data]) -> Result<(), ImportError> {
        let name = keyword.name.as_str();
        match classify(name) {
            Class::Read => match name {
                "NODE" => self.nodes(keyword, data),
                "ELEMENT" => self.elements(keyword, data),
                "NSET" => self.set(keyword, data, false),
                "ELSET" => self.set(keyword, data, true),
                "SURFACE" => self.surface(keyword, data),
                "INSTANCE" => self.instance(keyword, data),
                "SOLID SECTION" => {
                    self.raw.skipped.push((keyword.loc, keyword.name.clone()));
                    self.solid_section(keyword)
                }
                "ORIENTATION" => self.orientation(keyword, data),
                "DISTRIBUTION" => self.distribution(keyword, data),
                "DISTRIBUTION TABLE" => self.distribution_table(keyword, data),
                "HEADING" | "INCLUDE" => Ok(()),
                _ => self.structure(keyword, data),
            },
            Class::Skipped => {
                self.raw.skipped.push((keyword.loc, keyword.name.clone()));
                let message = format!("*{name} ignored: {}", skip_reason(name));
                self.warn(keyword.loc, name, message);
                Ok(())
            }
            Class::Refused => Err(self.error(
                keyword.loc,
                format!(
                    "*{name} is not supported: the mesh must be given explicitly with *NODE, \
                     *ELEMENT, *NSET, *ELSET, *SURFACE (in at most one *PART/*INSTANCE), \
                     *INCLUDE"
                ),
            )),
            Class::Unknown => Err(self.error(
                keyword.loc,
                format!(
                    "unknown keyword *{}: did you mean *{}?",
                    short(name),
                    nearest(name)
                ),
            )),
        }
    }

    /// Errors if the keyword has a parameter not in `allowed`.
    fn check_params(&self, keyword: &Keyword, allowed: &[&str]) -> Result<(), ImportError> {
        match keyword
            .params
            .iter()
            .find(|(k, _)| !allowed.contains(&k.as_str()))
        {
            Some((key, _)) => Err(self.error(
                keyword.loc,
                format!(
                    "*{}: parameter {} is not supported (supported: {})",
                    keyword.name,
                    short(key),
                    allowed.join(", ")
                ),
            )),
            None => Ok(()),
        }
    }

    fn require<'k>(&self, keyword: &'k Keyword, key: &str) -> Result<&'k str, ImportError> {
        keyword.get(key).filter(|v| !v.is_empty()).ok_or_else(|| {
            self.error(
                keyword.loc,
                format!("*{}: parameter {key}= is missing", keyword.name),
            )
        })
    }

    /// `*PART`, `*END PART`, `*ASSEMBLY`, `*END ASSEMBLY`, `*END INSTANCE`.
    fn structure(&mut self, keyword: &Keyword, data: &[Data]) -> Result<(), ImportError> {
        let loc = keyword.loc;
        let name = keyword.name.as_str();
        if let Some(d) = data.first() {
            return Err(self.error(d.loc, format!("*{name} takes no data lines")));
        }
        let (from, to) = match name {
            "PART" => (Scope::Model, Scope::Part),
            "END PART" => (Scope::Part, Scope::Model),
            "ASSEMBLY" => (Scope::Model, Scope::Assembly),
            "END ASSEMBLY" => (Scope::Assembly, Scope::Model),
            _ => (Scope::Instance, Scope::Assembly),
        };
        if self.scope != from {
            return Err(self.error(loc, format!("*{name} inside {:?} scope", self.scope)));
        }
        match name {
            "PART" => {
                self.check_params(keyword, &["NAME"])?;
                let part = self.require(keyword, "NAME")?.to_string();
                if let Some((first, first_loc)) = &self.part {
                    return Err(self.error(
                        loc,
                        format!(
                            "second *PART '{part}' (part '{first}' at line {}): only one part \
                             and one instance are supported",
                            first_loc.line
                        ),
                    ));
                }
                if !self.raw.node_labels.is_empty() || !self.blocks.is_empty() {
                    return Err(self.error(
                        loc,
                        "*PART after nodes or elements defined outside any part",
                    ));
                }
                self.part = Some((part, loc));
            }
            "ASSEMBLY" => {
                self.check_params(keyword, &["NAME"])?;
                if self.assembly_seen {
                    return Err(self.error(loc, "second *ASSEMBLY"));
                }
                self.assembly_seen = true;
            }
            _ => {}
        }
        self.scope = to;
        self.scope_loc = loc;
        Ok(())
    }

    /// Checks the structure at the end and places the part's nodes.
    fn finish(mut self) -> Result<RawMesh, ImportError> {
        if self.scope != Scope::Model {
            let closing = match self.scope {
                Scope::Part => "*END PART",
                Scope::Assembly => "*END ASSEMBLY",
                _ => "*END INSTANCE",
            };
            return Err(self.error(self.scope_loc, format!("not closed by {closing}")));
        }
        if let Some((part, loc)) = &self.part
            && self.instance.is_none()
        {
            return Err(self.error(
                *loc,
                format!("*PART '{part}' is never instanced (no *INSTANCE, PART={part})"),
            ));
        }
        self.raw.fiber_assignments = self.fiber_assignments()?;
        if let Some(instance) = self.instance.take() {
            self.place(instance.translation, instance.rotation)
                .map_err(|m| self.raw.error(instance.loc, m))?;
        }
        Ok(self.raw)
    }

    /// Moves every node: translation first, then the rotation about the axis a→b.
    fn place(
        &mut self,
        t: [f64; 3],
        rotation: Option<([f64; 3], [f64; 3], f64)>,
    ) -> Result<(), String> {
        let nodes = &mut self.raw.nodes;
        for i in 0..nodes.len() {
            nodes.x[i] += t[0];
            nodes.y[i] += t[1];
            nodes.z[i] += t[2];
        }
        let Some((a, b, degrees)) = rotation else {
            return Ok(());
        };
        let axis = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let length = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
        if !(length > 0.0 && length.is_finite()) {
            return Err("*INSTANCE: the rotation axis a→b has zero length".into());
        }
        let k = axis.map(|c| c / length);
        let (s, c) = degrees.to_radians().sin_cos();
        for i in 0..nodes.len() {
            let v = [nodes.x[i] - a[0], nodes.y[i] - a[1], nodes.z[i] - a[2]];
            let r = rodrigues(v, k, s, c);
            nodes.x[i] = a[0] + r[0];
            nodes.y[i] = a[1] + r[1];
            nodes.z[i] = a[2] + r[2];
        }
        // The fibers turn with the part.
        let rotate = |v: &mut [f64; 3]| *v = rodrigues(*v, k, s, c);
        for assignment in &mut self.raw.fiber_assignments {
            match &mut assignment.rule {
                FiberRule::Uniform(d) => rotate(d),
                FiberRule::PerElement {
                    default,
                    per_element,
                    ..
                } => {
                    default.iter_mut().for_each(rotate);
                    per_element.iter_mut().for_each(|(_, d)| rotate(d));
                }
            }
        }
        Ok(())
    }

    /// Counts set or surface entries against [`MAX_COPIED_ENTRIES`].
    fn count_copies(&mut self, count: usize, loc: Loc) -> Result<(), ImportError> {
        self.copied = self.copied.saturating_add(count);
        if self.copied > MAX_COPIED_ENTRIES {
            return Err(self.error(
                loc,
                format!("more than {MAX_COPIED_ENTRIES} set entries: sets grow without bound"),
            ));
        }
        Ok(())
    }

    /// Appends entries to the named set (created on first use), counting copies.
    fn add_to(
        &mut self,
        kind: SetKind,
        name: &str,
        entries: Vec<Entry>,
        loc: Loc,
    ) -> Result<(), ImportError> {
        self.count_copies(entries.len(), loc)?;
        let (names, list) = match kind {
            SetKind::Node => (&mut self.node_sets, &mut self.raw.node_sets),
            SetKind::Element => (&mut self.element_sets, &mut self.raw.element_sets),
        };
        let index = *names.entry(name.to_ascii_lowercase()).or_insert_with(|| {
            list.push((name.to_string(), Vec::new()));
            list.len() - 1
        });
        if let Some((_, set)) = list.get_mut(index) {
            set.extend(entries);
        }
        Ok(())
    }
}

/// Rodrigues: v' = v cos + (k × v) sin + k (k·v)(1 − cos), for the unit axis k and
/// the sine s and cosine c of the angle.
fn rodrigues(v: [f64; 3], k: [f64; 3], s: f64, c: f64) -> [f64; 3] {
    let kxv = [
        k[1] * v[2] - k[2] * v[1],
        k[2] * v[0] - k[0] * v[2],
        k[0] * v[1] - k[1] * v[0],
    ];
    let kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    std::array::from_fn(|d| v[d] * c + kxv[d] * s + k[d] * kv * (1.0 - c))
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SetKind {
    Node,
    Element,
}

/// At most 40 characters of `s`, for quoting input in messages.
fn short(s: &str) -> String {
    let mut out: String = s.chars().take(40).collect();
    if s.chars().nth(40).is_some() {
        out.push('…');
    }
    out
}
