//! Material plugins: shared libraries that implement a material through the C ABI of
//! `include/musclefem_material.h` (the "VUMAT-like" boundary), written in C, Rust,
//! Fortran or anything else that can export a C function.
//!
//! - [`abi`]: the `#[repr(C)]` mirror of the header (ABI version [`abi::ABI_VERSION`]);
//! - [`PluginMaterialFactory`]: loads a library, checks its table once (ABI version, sizes,
//!   names, parameter table) and creates materials from user parameter values, which are
//!   resolved exactly like a built-in material's;
//! - the created material calls the plugin's `update` once per block, serially; callers
//!   parallelise over blocks. It keeps the library loaded for as long as it exists.
//!
//! Example plugins: `plugins/neo_hookean_rust` (Rust, with a guide for plugin authors in
//! its README) and `plugins/neo_hookean_c` (C).

pub mod abi;
mod material;
mod table;

use std::collections::BTreeMap;
use std::error::Error;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use libloading::Library;

use crate::parameters::ParameterSet;
use crate::registry::{MaterialInfo, MaterialOrigin};
use crate::{Material, MaterialError};

use material::PluginMaterial;
use table::Description;

/// The C header of the plugin ABI, for tools that hand it to plugin authors.
pub const C_HEADER: &str = include_str!("../../include/musclefem_material.h");

/// A loaded plugin library and the checked description of the material it provides.
#[derive(Debug)]
pub struct PluginMaterialFactory {
    /// The path as given to [`PluginMaterialFactory::load`].
    path: PathBuf,
    description: Description,
    library: Arc<Library>,
}

impl PluginMaterialFactory {
    /// Load the plugin at `path` and check its table.
    ///
    /// Loading a shared library runs its initialisation code and later calls its
    /// functions in this process: only load plugins you trust, as you would only run
    /// programs you trust. The checks below catch mistakes, not malice.
    pub fn load(path: &Path) -> Result<Self, MaterialError> {
        let fail = |message: String| MaterialError::Plugin {
            path: path.to_path_buf(),
            message,
        };
        match std::fs::metadata(path) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Err(fail("file not found (no such file)".into()));
            }
            Err(e) => return Err(fail(format!("cannot be read: {e}"))),
            Ok(m) if !m.is_file() => return Err(fail("is not a file".into())),
            Ok(_) => {}
        }
        // An absolute path, so that the dynamic loader opens this very file instead of
        // searching its library path for a bare file name.
        let resolved = std::fs::canonicalize(path)
            .map_err(|e| fail(format!("cannot resolve the path: {e}")))?;
        let library = open_library(&resolved).map_err(|e| {
            fail(format!(
                "cannot be loaded as a shared library: {}",
                error_chain(&e)
            ))
        })?;

        let symbol = String::from_utf8_lossy(&abi::PLUGIN_SYMBOL[..abi::PLUGIN_SYMBOL.len() - 1]);
        // SAFETY: the symbol is declared by the ABI as
        // `const MusclefemMaterialPlugin* musclefem_material_plugin(void)`, which is
        // `abi::EntryPoint`. The function pointer is copied out and only used below,
        // while `library` is alive.
        let entry: abi::EntryPoint = unsafe { library.get::<abi::EntryPoint>(abi::PLUGIN_SYMBOL) }
            .map(|s| *s)
            .map_err(|e| {
                fail(format!(
                    "it does not export the symbol '{symbol}' (every musclefem material \
                     plugin must export `const MusclefemMaterialPlugin* {symbol}(void)` with C \
                     linkage, see musclefem_material.h): {}",
                    error_chain(&e)
                ))
            })?;
        // SAFETY: calling the ABI's entry point, which takes no arguments and must not
        // unwind (rule 1 of the header).
        let table = unsafe { entry() };
        if table.is_null() {
            return Err(fail(format!(
                "'{symbol}()' returned NULL instead of its table"
            )));
        }
        if !table.is_aligned() {
            return Err(fail(format!(
                "'{symbol}()' returned a misaligned table pointer {table:p}"
            )));
        }
        // SAFETY: every ABI version starts with `abi_version` and `struct_size`, so the
        // 8-byte head is readable whatever version the plugin was built for.
        let head = unsafe { table.cast::<abi::TableHead>().read() };
        if head.abi_version != abi::ABI_VERSION {
            return Err(fail(format!(
                "ABI version mismatch: the plugin was built for material ABI version {}, \
                 this musclefem implements version {} (rebuild the plugin against the \
                 musclefem_material.h of this musclefem)",
                head.abi_version,
                abi::ABI_VERSION
            )));
        }
        let host_size = size_of::<abi::MaterialPlugin>();
        if (head.struct_size as usize) < host_size {
            return Err(fail(format!(
                "its table declares struct_size = {} bytes, smaller than \
                 sizeof(MusclefemMaterialPlugin) = {host_size} of ABI version {} \
                 (set struct_size = sizeof(MusclefemMaterialPlugin))",
                head.struct_size,
                abi::ABI_VERSION
            )));
        }
        // SAFETY: non-null, aligned, and at least as large as `MaterialPlugin`; it lives in
        // the library's memory, which stays mapped while `library` is alive (until the end
        // of this function, then in `Self`). Its pointers are valid as the header requires.
        let description = unsafe { table::describe(&*table) }.map_err(fail)?;
        Ok(PluginMaterialFactory {
            path: path.to_path_buf(),
            description,
            library: Arc::new(library),
        })
    }

    /// Registry name of the plugin's material.
    pub fn name(&self) -> &str {
        &self.description.name
    }

    /// What `musclefem materials` lists (origin: this plugin's path).
    pub fn info(&self) -> MaterialInfo {
        MaterialInfo {
            name: self.description.name.clone(),
            description: self.description.description.clone(),
            parameters: self.description.parameters.clone(),
            origin: MaterialOrigin::Plugin(self.path.clone()),
        }
    }

    /// Create the material from `given` parameter values: resolved against the plugin's
    /// declared parameters by [`ParameterSet::resolve`], exactly like a built-in.
    pub fn create(
        &self,
        given: &BTreeMap<String, f64>,
    ) -> Result<Arc<dyn Material>, MaterialError> {
        let d = &self.description;
        let parameters = ParameterSet::resolve(&d.name, &d.parameters, given)?;
        Ok(Arc::new(PluginMaterial {
            name: d.name.clone(),
            path: self.path.clone(),
            properties: parameters.values().to_vec(),
            states: d.states.clone(),
            provides_tangent: d.provides_tangent,
            update: d.update,
            _library: Arc::clone(&self.library),
        }))
    }
}

/// Open a shared library. On Unix with `RTLD_NOW`, so that a plugin with unresolved
/// symbols fails here with a message rather than aborting the process at its first call
/// (the default lazy binding), and `RTLD_LOCAL`, so its symbols do not leak into other
/// plugins.
fn open_library(path: &Path) -> Result<Library, libloading::Error> {
    #[cfg(unix)]
    {
        use libloading::os::unix;
        // SAFETY: loading runs the library's initialisers; that is inherent to loading a
        // plugin the user asked for (see `PluginMaterialFactory::load`).
        unsafe { unix::Library::open(Some(path), unix::RTLD_NOW | unix::RTLD_LOCAL) }
            .map(Library::from)
    }
    #[cfg(not(unix))]
    {
        // SAFETY: as above.
        unsafe { Library::new(path) }
    }
}

/// An error with its chain of sources: libloading's own text is only "dlopen failed" or
/// "dlsym failed"; the reason (e.g. "invalid ELF header", "undefined symbol: x") is in the
/// source.
fn error_chain(error: &dyn Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(s) = source {
        let next = s.to_string();
        if !text.contains(&next) {
            text.push_str(": ");
            text.push_str(&next);
        }
        source = s.source();
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_file_is_reported_as_such_with_its_path() {
        let path = Path::new("/nonexistent/dir/libnothing.so");
        let err = PluginMaterialFactory::load(path).unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("/nonexistent/dir/libnothing.so") && text.contains("file not found"),
            "{text}"
        );
    }

    #[test]
    fn a_text_file_is_not_a_shared_library_and_the_reason_is_given() {
        let path =
            std::env::temp_dir().join(format!("musclefem-not-a-lib-{}.so", std::process::id()));
        std::fs::write(&path, "this is not a shared library\n").unwrap();
        let err = PluginMaterialFactory::load(&path).unwrap_err();
        std::fs::remove_file(&path).ok();
        let text = err.to_string();
        assert!(
            text.contains("cannot be loaded as a shared library"),
            "{text}"
        );
        // The reason from the source chain (e.g. "invalid ELF header" on Linux) follows
        // libloading's bare "dlopen failed".
        #[cfg(unix)]
        assert!(text.contains("dlopen failed: "), "{text}");
    }

    #[test]
    fn header_states_the_same_abi_version_and_symbol() {
        assert!(C_HEADER.contains(&format!(
            "#define MUSCLEFEM_MATERIAL_ABI_VERSION {}u",
            abi::ABI_VERSION
        )));
        assert!(C_HEADER.contains("musclefem_material_plugin(void);"));
    }
}
