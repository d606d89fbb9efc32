//! Gmsh 4.1 binary files (`$MeshFormat` `4.1 1 8`, then the integer 1 in the writer's
//! byte order): `$Entities`, `$Nodes` and `$Elements` in binary (`int` of 4 bytes,
//! `size_t` of 8, `double` of 8, little-endian), `$PhysicalNames` in ASCII as always.
//!
//! Errors name the section and the byte offset; their line is the section's header line.

use std::path::Path;

use super::super::build::Loc;
use super::elements::node_count;
use super::{Reader, is_skipped, physical_name, short};
use crate::mesh_import::{ImportError, ImportedMesh};

/// Bytes read front to back.
struct Cursor<'b> {
    bytes: &'b [u8],
    at: usize,
    /// 1-based line of the current section's header.
    line: usize,
    section: String,
}

impl Cursor<'_> {
    fn error(&self, message: impl std::fmt::Display) -> String {
        format!("${} (binary, byte {}): {message}", self.section, self.at)
    }

    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return Err(self.error(format!("the file ends within {n} bytes of data")));
        };
        let out = &self.bytes[self.at..end];
        self.at = end;
        Ok(out)
    }

    /// The next text line (without the newline), trimmed.
    fn line(&mut self) -> Result<Option<String>, String> {
        if self.at >= self.bytes.len() {
            return Ok(None);
        }
        let rest = &self.bytes[self.at..];
        let n = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        let text = String::from_utf8_lossy(&rest[..n]).trim().to_string();
        self.at += (n + 1).min(rest.len());
        self.line += 1;
        Ok(Some(text))
    }

    fn int(&mut self) -> Result<i64, String> {
        let b = self.take(4)?;
        Ok(i64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])))
    }

    fn size(&mut self) -> Result<u64, String> {
        let b = self.take(8)?;
        Ok(u64::from_le_bytes(std::array::from_fn(|i| b[i])))
    }

    fn double(&mut self) -> Result<f64, String> {
        let b = self.take(8)?;
        Ok(f64::from_le_bytes(std::array::from_fn(|i| b[i])))
    }

    /// A count of items of `bytes_each` bytes that must fit in the rest of the file.
    fn count(&mut self, bytes_each: usize, what: &str) -> Result<usize, String> {
        let n = self.size()?;
        let left = self.bytes.len() - self.at;
        match usize::try_from(n) {
            Ok(n) if n.saturating_mul(bytes_each) <= left => Ok(n),
            _ => Err(self.error(format!(
                "{what}: {n} items cannot fit in the {left} bytes left"
            ))),
        }
    }

    /// A tag held in a `size_t`, as the readers' `i64`.
    fn tag(&mut self, what: &str) -> Result<i64, String> {
        let t = self.size()?;
        i64::try_from(t).map_err(|_| self.error(format!("{what} {t} is too large")))
    }
}

/// Reads the bytes of a 4.1 binary file.
pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<ImportedMesh, ImportError> {
    let mut reader = Reader::new(path, "");
    let mut cursor = Cursor {
        bytes,
        at: 0,
        line: 0,
        section: "MeshFormat".into(),
    };
    read(&mut reader, &mut cursor).map_err(|message| ImportError::Parse {
        file: path.to_path_buf(),
        line: cursor.line.max(1),
        message,
    })?;
    reader.format = Some(super::Format::Binary41);
    reader.finish()?.build()
}

fn read(reader: &mut Reader, c: &mut Cursor) -> Result<(), String> {
    // "$MeshFormat", "4.1 1 8" (checked by the caller), then the int 1 and a newline.
    c.line()?;
    c.line()?;
    let one = c.take(4)?;
    if one == [0, 0, 0, 1] {
        return Err(c.error(
            "big-endian files are not supported: write it on a little-endian machine or as ASCII",
        ));
    }
    if one != [1, 0, 0, 0] {
        return Err(c.error("expected the integer 1 after the format line"));
    }
    loop {
        let header_line = c.line + 1;
        let Some(header) = c.line()? else {
            return Ok(());
        };
        if header.is_empty() {
            continue;
        }
        let Some(section) = header.strip_prefix('$') else {
            return Err(format!(
                "expected a section header ($Name), found '{}'",
                short(&header)
            ));
        };
        c.section = section.to_string();
        c.line = header_line;
        let loc = Loc {
            file: 0,
            line: u32::try_from(header_line).unwrap_or(u32::MAX),
        };
        match section {
            "EndMeshFormat" => continue,
            "PhysicalNames" => physical_names(reader, c)?,
            "Entities" => entities(reader, c)?,
            "Nodes" => nodes(reader, c, loc)?,
            "Elements" => elements(reader, c, loc)?,
            _ => {}
        }
        // Up to $End<Name>: a skipped section is searched for it.
        let end = format!("$End{section}");
        if is_skipped(section) {
            let rest = &c.bytes[c.at..];
            let found = rest
                .windows(end.len())
                .position(|w| w == end.as_bytes())
                .ok_or_else(|| c.error(format!("no {end}")))?;
            c.at += found;
        }
        loop {
            match c.line()? {
                Some(line) if line.is_empty() => continue,
                Some(line) if line == end => break,
                other => {
                    return Err(c.error(format!(
                        "expected {end}, found '{}'",
                        short(&other.unwrap_or_default())
                    )));
                }
            }
        }
    }
}

fn physical_names(reader: &mut Reader, c: &mut Cursor) -> Result<(), String> {
    let count = c.line()?.unwrap_or_default();
    let n: usize = count
        .parse()
        .map_err(|_| c.error(format!("'{}' is not a count", short(&count))))?;
    for _ in 0..n {
        let line = c.line()?.unwrap_or_default();
        let (dim, tag, name) = physical_name(&line).map_err(|m| c.error(m))?;
        reader.physical_names.insert((dim, tag), name);
    }
    Ok(())
}

fn entities(reader: &mut Reader, c: &mut Cursor) -> Result<(), String> {
    let mut counts = [0usize; 4];
    for n in &mut counts {
        *n = c.count(4, "the number of entities")?;
    }
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let tag = c.int()?;
            // A point's x y z, or the bounding box of a curve, surface or volume.
            for _ in 0..if dim == 0 { 3 } else { 6 } {
                c.double()?;
            }
            let physical = c.count(4, "numPhysicalTags")?;
            let mut groups = Vec::with_capacity(physical);
            for _ in 0..physical {
                groups.push(c.int()?.abs());
            }
            if dim > 0 {
                let bounding = c.count(4, "the number of bounding entities")?;
                c.take(4 * bounding)?;
            }
            reader.entity_groups.insert((dim as i64, tag), groups);
        }
    }
    Ok(())
}

fn nodes(reader: &mut Reader, c: &mut Cursor, loc: Loc) -> Result<(), String> {
    let blocks = c.count(20, "numEntityBlocks")?;
    let total = c.size()?;
    c.size()?;
    c.size()?;
    let first = reader.raw.node_labels.len();
    for _ in 0..blocks {
        let dim = c.int()?;
        c.int()?;
        let parametric = c.int()?;
        if !(0..=3).contains(&dim) {
            return Err(c.error(format!("entity dimension {dim} is not 0..3")));
        }
        let values = 3 + if parametric != 0 { dim as usize } else { 0 };
        let n = c.count(8 + 8 * values, "numNodesInBlock")?;
        let mut tags = Vec::with_capacity(n);
        for _ in 0..n {
            let tag = c.tag("node tag")?;
            if tag <= 0 {
                return Err(c.error(format!("node tag {tag} is not positive")));
            }
            tags.push(tag);
        }
        for tag in tags {
            let mut x = [0.0; 3];
            for (i, v) in (0..values).map(|i| (i, c.double())) {
                let v = v?;
                if i < 3 {
                    x[i] = v;
                }
            }
            if x.iter().any(|v| !v.is_finite()) {
                return Err(c.error(format!("node {tag}: coordinates are not finite")));
            }
            reader.raw.node_labels.push(tag);
            reader.raw.nodes.x.push(x[0]);
            reader.raw.nodes.y.push(x[1]);
            reader.raw.nodes.z.push(x[2]);
            reader.raw.node_locs.push(loc);
        }
    }
    let read = reader.raw.node_labels.len() - first;
    if read as u64 != total {
        return Err(c.error(format!(
            "the header announces {total} nodes, the blocks hold {read}"
        )));
    }
    Ok(())
}

fn elements(reader: &mut Reader, c: &mut Cursor, loc: Loc) -> Result<(), String> {
    let blocks = c.count(20, "numEntityBlocks")?;
    let total = c.size()?;
    c.size()?;
    c.size()?;
    let mut read = 0u64;
    for _ in 0..blocks {
        let dim = c.int()?;
        let entity = c.int()?;
        let element_type = c.int()?;
        let nodes = node_count(element_type)
            .ok_or_else(|| c.error(format!("element type {element_type} is not supported")))?;
        let n = c.count(8 * (nodes + 1), "numElementsInBlock")?;
        let groups = reader
            .entity_groups
            .get(&(dim, entity))
            .cloned()
            .unwrap_or_default();
        if let Some(m) =
            super::elements::unsupported_type(dim, entity, element_type, !groups.is_empty())
        {
            return Err(c.error(m));
        }
        let mut tags = vec![0i64; nodes];
        for _ in 0..n {
            let tag = c.tag("element tag")?;
            for t in tags.iter_mut() {
                *t = c.tag("node tag")?;
            }
            reader
                .add_element(dim, entity, element_type, &groups, tag, &tags, loc)
                .map_err(|e| match e {
                    ImportError::Parse { message, .. } => c.error(message),
                    other => other.to_string(),
                })?;
        }
        read += n as u64;
    }
    if read != total {
        return Err(c.error(format!(
            "the header announces {total} elements, the blocks hold {read}"
        )));
    }
    Ok(())
}
