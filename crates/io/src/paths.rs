//! Where a file named by an input lies: [`lies_in_folder`].

use std::path::Path;

/// Whether `file` lies in `folder` or below it, after `..` and symbolic links are
/// resolved (an empty folder is the current one). A path that cannot be resolved (a
/// missing file) counts as inside: the reader then reports it missing, quoting nothing.
pub fn lies_in_folder(file: &Path, folder: &Path) -> bool {
    let folder = if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    };
    match (folder.canonicalize(), file.canonicalize()) {
        (Ok(folder), Ok(file)) => file.starts_with(folder),
        _ => true,
    }
}
