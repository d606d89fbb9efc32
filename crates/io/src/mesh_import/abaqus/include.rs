//! `*INCLUDE`: the lines of included files in place of the keyword line.

use std::path::{Path, PathBuf};

use super::super::build::Loc;
use super::super::utf8;
use super::{Keyword, Line, is_keyword};
use crate::mesh_import::ImportError;

/// Deepest `*INCLUDE` nesting accepted (deeper is taken for a cycle).
const MAX_INCLUDE_DEPTH: usize = 16;

/// Where `*INCLUDE` may reach.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Includes {
    /// Text in memory: no file to be relative to.
    Refused,
    /// Files in the top file's folder or below it.
    InFolder,
    /// Any file.
    Anywhere,
}

/// Appends the lines of `text` (file `file`) to `out`, replacing each `*INCLUDE` line by
/// the lines of the included file.
pub(super) fn flatten(
    files: &mut Vec<PathBuf>,
    out: &mut Vec<Line>,
    text: &str,
    file: u32,
    includes: Includes,
    depth: usize,
) -> Result<(), ImportError> {
    let path = files.get(file as usize).cloned().unwrap_or_default();
    for (i, line) in text.lines().enumerate() {
        let loc = Loc {
            file,
            line: u32::try_from(i + 1).unwrap_or(u32::MAX),
        };
        let text = line.trim();
        let error = |message: String| ImportError::Parse {
            file: path.clone(),
            line: i + 1,
            message,
        };
        if is_keyword(text)
            && let Ok(keyword) = Keyword::parse(text, loc)
            && keyword.name == "INCLUDE"
        {
            let input = keyword
                .get("INPUT")
                .ok_or_else(|| error("*INCLUDE: parameter INPUT= is missing".into()))?;
            if includes == Includes::Refused {
                return Err(error(format!(
                    "*INCLUDE, INPUT={input}: includes need a file to be relative to; \
                     read the file with read_abaqus"
                )));
            }
            if depth >= MAX_INCLUDE_DEPTH {
                return Err(error(format!(
                    "*INCLUDE, INPUT={input}: includes nested more than {MAX_INCLUDE_DEPTH} \
                     deep (does a file include itself?)"
                )));
            }
            let included = path.parent().unwrap_or(Path::new("")).join(input);
            if includes == Includes::InFolder {
                let top = &files[0];
                if !crate::paths::lies_in_folder(&included, top.parent().unwrap_or(Path::new(""))) {
                    return Err(error(format!(
                        "*INCLUDE, INPUT={input}: '{}' lies outside the folder of '{}': \
                         included files must be in the deck's folder or below it (a scene \
                         allows others with --allow-outside-paths)",
                        included.display(),
                        top.display()
                    )));
                }
            }
            let bytes = std::fs::read(&included).map_err(|e| {
                error(format!(
                    "*INCLUDE: cannot read '{}': {e}",
                    included.display()
                ))
            })?;
            let text = utf8(bytes, &included)?;
            let id = u32::try_from(files.len()).map_err(|_| error("too many files".into()))?;
            files.push(included);
            flatten(files, out, &text, id, includes, depth + 1)?;
            continue;
        }
        out.push(Line {
            loc,
            text: text.to_string(),
        });
    }
    Ok(())
}
