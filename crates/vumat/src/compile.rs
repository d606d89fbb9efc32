//! Building a plugin: the user's Fortran file (a VUMAT or a UMAT) with gfortran, its
//! adapter with the C compiler, both linked by gfortran into one shared library in a scratch directory, which
//! is loaded once as a material plugin to check it before it is moved to its place.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use musclefem_materials::plugin::PluginMaterialFactory;
use musclefem_materials::{MaterialInfo, MaterialOrigin};

use crate::config_header;
use crate::error::VumatError;
use crate::options::VumatBuild;
use crate::sources::ADAPTER_FILES;
use crate::toolchain::{Tool, undefined_symbols};

/// gfortran's options for the user's file, those of Abaqus's own Linux build where
/// gfortran has them: position-independent code, every local variable on the stack
/// (`-frecursive`, Intel's `-auto`: the host calls the VUMAT from several threads),
/// 132-column fixed form (`-extend_source`), the C preprocessor (`-fpp`).
pub const FORTRAN_FLAGS: [&str; 6] = [
    "-O2",
    "-fPIC",
    "-frecursive",
    "-ffixed-line-length-132",
    "-cpp",
    "-c",
];

/// The C compiler's options for the adapter (only `musclefem_material_plugin` is exported;
/// -O3 unrolls the 3x3 loops).
pub const C_FLAGS: [&str; 6] = [
    "-O3",
    "-fPIC",
    "-std=c11",
    "-fvisibility=hidden",
    "-ffp-contract=off",
    "-c",
];

/// What a build produced.
#[derive(Debug, Clone)]
pub struct BuiltPlugin {
    /// The plugin library written.
    pub library: PathBuf,
    /// The material it provides (name, parameters), as `musclefem materials` lists it.
    pub info: MaterialInfo,
    /// gfortran's warnings on the user's file (empty when it had none).
    pub warnings: String,
}

/// A scratch directory, removed when dropped.
struct ScratchDir(PathBuf);

impl ScratchDir {
    fn new() -> Result<ScratchDir, VumatError> {
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let path = std::env::temp_dir().join(format!(
            "musclefem-vumat-{}-{}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).map_err(|source| VumatError::Io {
            what: "create the scratch directory".into(),
            path: path.clone(),
            source,
        })?;
        Ok(ScratchDir(path))
    }
}

impl Drop for ScratchDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn write(path: &Path, text: &str) -> Result<(), VumatError> {
    std::fs::write(path, text).map_err(|source| VumatError::Io {
        what: "write".into(),
        path: path.to_path_buf(),
        source,
    })
}

/// Build the plugin `build` asks for; see the module documentation.
pub fn build_plugin(build: &VumatBuild) -> Result<BuiltPlugin, VumatError> {
    build.check()?;
    match std::fs::metadata(&build.source) {
        Ok(m) if m.is_file() => {}
        Ok(_) => {
            return Err(VumatError::Option(format!(
                "{} is not a file",
                build.source.display()
            )));
        }
        Err(source) => {
            return Err(VumatError::Io {
                what: "read the Fortran file".into(),
                path: build.source.clone(),
                source,
            });
        }
    }
    if build.out.exists() && !build.replace {
        return Err(VumatError::OutputExists(build.out.clone()));
    }
    let scratch = ScratchDir::new()?;
    let dir = scratch.0.as_path();
    for (name, text) in ADAPTER_FILES {
        write(&dir.join(name), text)?;
    }
    write(&dir.join("vumat_config.h"), &config_header::render(build))?;

    let fortran = Tool::fortran();
    let c = Tool::c();
    let subroutine = build.subroutine;
    let vumat_object = dir.join(format!("{}.o", subroutine.symbol().trim_end_matches('_')));
    let mut args: Vec<&OsStr> = FORTRAN_FLAGS.iter().map(OsStr::new).collect();
    args.extend([
        OsStr::new("-I"),
        dir.as_os_str(),
        OsStr::new("-J"),
        dir.as_os_str(),
        OsStr::new("-o"),
        vumat_object.as_os_str(),
        build.source.as_os_str(),
    ]);
    let warnings = fortran.run(&args)?.map_err(|output| VumatError::Compile {
        source: build.source.clone(),
        output,
    })?;

    let mut objects = vec![vumat_object.clone()];
    for file in subroutine.c_files() {
        let object = dir.join(file).with_extension("o");
        let source = dir.join(file);
        let mut args: Vec<&OsStr> = C_FLAGS.iter().map(OsStr::new).collect();
        args.extend([
            OsStr::new("-I"),
            dir.as_os_str(),
            OsStr::new("-o"),
            object.as_os_str(),
            source.as_os_str(),
        ]);
        c.run(&args)?.map_err(|output| VumatError::Adapter {
            step: format!("compiling the adapter's {file} with {}", c.program),
            output,
        })?;
        objects.push(object);
    }

    let library = dir.join(format!(
        "{}{}{}",
        std::env::consts::DLL_PREFIX,
        subroutine.symbol().trim_end_matches('_'),
        std::env::consts::DLL_SUFFIX
    ));
    let mut args: Vec<&OsStr> = vec![OsStr::new("-shared"), OsStr::new("-o"), library.as_os_str()];
    args.extend(objects.iter().map(|o| o.as_os_str()));
    if cfg!(target_os = "linux") {
        // An undefined routine is a link error here, not a load error later.
        args.push(OsStr::new("-Wl,--no-undefined"));
    }
    args.push(OsStr::new("-lm"));
    fortran.run(&args)?.map_err(|output| {
        let routines = undefined_symbols(&output);
        if routines.is_empty() {
            VumatError::Adapter {
                step: format!("linking the plugin with {}", fortran.program),
                output,
            }
        } else {
            VumatError::Undefined {
                subroutine,
                source: build.source.clone(),
                routines,
                output,
            }
        }
    })?;

    let mut info = PluginMaterialFactory::load(&library)
        .map_err(VumatError::Load)?
        .info();
    install(&library, &build.out)?;
    info.origin = MaterialOrigin::Plugin(build.out.clone());
    Ok(BuiltPlugin {
        library: build.out.clone(),
        info,
        warnings,
    })
}

/// Copy `built` next to `out` and rename it there, so that `out` is complete or absent.
fn install(built: &Path, out: &Path) -> Result<(), VumatError> {
    let io = |what: &str, path: &Path| {
        let path = path.to_path_buf();
        let what = what.to_string();
        move |source| VumatError::Io { what, path, source }
    };
    if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(io("create the directory", parent))?;
    }
    let file_name = out
        .file_name()
        .ok_or_else(|| VumatError::Option(format!("--out {}: not a file name", out.display())))?;
    let partial = out.with_file_name(format!(
        ".{}.partial-{}",
        file_name.to_string_lossy(),
        std::process::id()
    ));
    std::fs::copy(built, &partial).map_err(io("write", &partial))?;
    std::fs::rename(&partial, out).map_err(|e| {
        let _ = std::fs::remove_file(&partial);
        io("write", out)(e)
    })
}
