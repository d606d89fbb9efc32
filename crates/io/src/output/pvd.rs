//! PVD files: ParaView's time-series index, a VTK XML `Collection` listing one dataset
//! file per time step.
//!
//! ```xml
//! <?xml version="1.0"?>
//! <VTKFile type="Collection" version="0.1" byte_order="LittleEndian">
//!   <Collection>
//!     <DataSet timestep="0.001" group="" part="0" file="frames/frame_00000.vtu"/>
//!   </Collection>
//! </VTKFile>
//! ```
//!
//! `timestep` is the time [s] as the shortest decimal that parses back to the same `f64`
//! ([`format_number`]); `file` is relative to the directory of the `.pvd` file, with `/`
//! separators. The file is rewritten whole and atomically ([`write_pvd`]), so a reader
//! sees the old list or the new one.

use std::path::Path;

use crate::OutputError;
use crate::atomic::write_atomically;
use crate::csv::format_number;

/// One dataset of a collection.
#[derive(Clone, Debug, PartialEq)]
pub struct PvdEntry {
    /// Time [s].
    pub time: f64,
    /// Path of the dataset file relative to the `.pvd` file's directory, `/`-separated.
    pub file: String,
}

/// The `.pvd` text of `entries`, in their order.
pub fn format_pvd(entries: &[PvdEntry]) -> String {
    let mut text = String::from(
        "<?xml version=\"1.0\"?>\n\
         <VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  \
         <Collection>\n",
    );
    for entry in entries {
        text.push_str(&format!(
            "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
            format_number(entry.time),
            escape(&entry.file)
        ));
    }
    text.push_str("  </Collection>\n</VTKFile>\n");
    text
}

/// Write `entries` to `path` atomically.
pub fn write_pvd(path: &Path, entries: &[PvdEntry]) -> Result<(), OutputError> {
    write_atomically(path, format_pvd(entries).as_bytes())
}

/// Read the entries of a `.pvd` file (as written by [`write_pvd`]; attributes in any
/// order, single or double quotes). Errors name the file and the line.
pub fn read_pvd(path: &Path) -> Result<Vec<PvdEntry>, OutputError> {
    let text = std::fs::read_to_string(path).map_err(|e| OutputError::io("read", path, e))?;
    let error = |offset: usize, message: String| OutputError::Parse {
        path: path.to_path_buf(),
        line: text[..offset].matches('\n').count() + 1,
        message,
    };
    if !text.contains("type=\"Collection\"") {
        return Err(error(0, "not a VTK Collection file".into()));
    }
    let mut entries = Vec::new();
    let mut rest = 0;
    while let Some(found) = text[rest..].find("<DataSet") {
        let start = rest + found;
        let end = text[start..]
            .find('>')
            .map(|e| start + e)
            .ok_or_else(|| error(start, "unterminated <DataSet".into()))?;
        let tag = &text[start..end];
        let time = attribute(tag, "timestep")
            .ok_or_else(|| error(start, "DataSet without timestep".into()))?;
        let time = time
            .parse::<f64>()
            .map_err(|_| error(start, format!("timestep '{time}' is not a number")))?;
        let file =
            attribute(tag, "file").ok_or_else(|| error(start, "DataSet without file".into()))?;
        entries.push(PvdEntry {
            time,
            file: unescape(file),
        });
        rest = end;
    }
    if !text.trim_end().ends_with("</VTKFile>") {
        return Err(error(
            text.len(),
            "no closing </VTKFile>: the file is truncated".into(),
        ));
    }
    Ok(entries)
}

/// The value of attribute `name` in the tag text `tag`.
fn attribute<'t>(tag: &'t str, name: &str) -> Option<&'t str> {
    let mut from = 0;
    while let Some(i) = tag[from..].find(name) {
        let at = from + i;
        from = at + name.len();
        let before_ok = tag[..at].ends_with(char::is_whitespace);
        let after = tag[from..].trim_start();
        if !before_ok || !after.starts_with('=') {
            continue;
        }
        let value = after[1..].trim_start();
        let quote = value.chars().next()?;
        if quote != '"' && quote != '\'' {
            return None;
        }
        let close = value[1..].find(quote)?;
        return Some(&value[1..1 + close]);
    }
    None
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

fn unescape(text: &str) -> String {
    text.replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&apos;", "'")
        .replace("&amp;", "&")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atomic::tests::test_dir;

    #[test]
    fn pvd_round_trips_and_truncation_is_detected() {
        let dir = test_dir("pvd-round-trip");
        let path = dir.join("result.pvd");
        let entries = vec![
            PvdEntry {
                time: 0.0,
                file: "frames/frame_00000.vtu".into(),
            },
            PvdEntry {
                time: 0.1 + 0.2,
                file: "odd \"name\" & <x>.vtu".into(),
            },
            PvdEntry {
                time: 1.5e-7,
                file: "c.vtu".into(),
            },
        ];
        write_pvd(&path, &entries).unwrap();
        assert_eq!(read_pvd(&path).unwrap(), entries);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("timestep=\"1.5e-7\""), "{text}");
        for (cut, expected) in [(2, "truncated"), (30, "unterminated <DataSet")] {
            std::fs::write(&path, &text[..text.len() - cut]).unwrap();
            let err = read_pvd(&path).unwrap_err().to_string();
            assert!(
                err.contains(expected) && err.contains("result.pvd"),
                "{err}"
            );
        }
    }

    #[test]
    fn attributes_in_any_order_and_quotes() {
        let tag = "<DataSet file='a.vtu' part=\"0\" timestep = \"2\"";
        assert_eq!(attribute(tag, "file"), Some("a.vtu"));
        assert_eq!(attribute(tag, "timestep"), Some("2"));
        assert_eq!(attribute(tag, "group"), None);
        // "step" inside "timestep" is not the attribute "step".
        assert_eq!(attribute(tag, "step"), None);
    }
}
