//! `musclefem mesh`: a closed surface (STL or OBJ) to a tet4 or tet10 volume mesh through
//! Gmsh, with `origin` and `insertion` surfaces chosen by planes, boxes or points, written
//! as Gmsh .msh 4.1 (metres). The work is done by `scripts/musclefem_mesh.py` (built into
//! the binary and run with a Python that has the `gmsh` package: Gmsh's meshers are only
//! reachable through its Python, C or C++ API, and the Python wheel installs with pip
//! alone); this command finds that Python, runs the script, reads the file back with
//! musclefem's own reader and prints what the solvers will see: elements, nodes, volume
//! V = Σ Vₑ [m³] and, per surface, its faces and area A = Σ |∫ n dA| [m²].

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};

use musclefem_io::mesh_import::read_mesh;

/// The meshing script, run as `python -c SCRIPT ARGS...`.
const SCRIPT: &str = include_str!("../../../scripts/musclefem_mesh.py");

/// The Python of the project's virtual environment (scripts/setup-gmsh.sh), relative to
/// the repository.
const VENV_PYTHON: &str = "target/python-venv/bin/python";

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum Units {
    M,
    Mm,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum TetElement {
    Tet4,
    Tet10,
}

#[derive(Debug, Args)]
pub struct MeshArgs {
    /// The closed muscle surface: .stl (ASCII or binary) or .obj, one piece, edge-manifold.
    pub surface: PathBuf,
    /// The volume mesh to write, Gmsh .msh 4.1 ASCII in metres [default: the surface's
    /// file name with .msh, in the current directory].
    #[arg(long, value_name = "FILE.msh")]
    pub out: Option<PathBuf>,
    /// Target element edge length, in --units.
    #[arg(long, value_name = "LENGTH")]
    pub size: f64,
    /// Units of the surface and of every length given here (size, points, radii).
    #[arg(long, value_enum, default_value = "m")]
    pub units: Units,
    /// Element type.
    #[arg(long, value_enum, default_value = "tet10")]
    pub element: TetElement,
    /// Mesh the volume on the surface's own triangles instead of remeshing the surface at
    /// --size.
    #[arg(long)]
    pub keep_surface: bool,
    /// When remeshing, edges sharper than this stay edges [degrees].
    #[arg(long, value_name = "DEGREES")]
    pub feature_angle: Option<f64>,
    /// Origin: boundary faces whose centroid c lies beyond the plane through p along its
    /// normal n, (c − p)·n ≥ 0; repeatable (the union is taken).
    #[arg(long, value_name = "PX,PY,PZ,NX,NY,NZ", allow_hyphen_values = true)]
    pub origin_plane: Vec<String>,
    /// Origin: boundary faces whose centroid lies in the box; repeatable.
    #[arg(long, value_name = "X0,Y0,Z0,X1,Y1,Z1", allow_hyphen_values = true)]
    pub origin_box: Vec<String>,
    /// Origin: boundary faces whose centroid lies within --origin-radius of one of the
    /// points ("x,y,z;x,y,z" or a file of x,y,z lines); repeatable.
    #[arg(long, value_name = "X,Y,Z;...|FILE", allow_hyphen_values = true)]
    pub origin_points: Vec<String>,
    /// Radius around the origin points, in --units.
    #[arg(long, value_name = "R")]
    pub origin_radius: Option<f64>,
    /// Insertion: as --origin-plane.
    #[arg(long, value_name = "PX,PY,PZ,NX,NY,NZ", allow_hyphen_values = true)]
    pub insertion_plane: Vec<String>,
    /// Insertion: as --origin-box.
    #[arg(long, value_name = "X0,Y0,Z0,X1,Y1,Z1", allow_hyphen_values = true)]
    pub insertion_box: Vec<String>,
    /// Insertion: as --origin-points.
    #[arg(long, value_name = "X,Y,Z;...|FILE", allow_hyphen_values = true)]
    pub insertion_points: Vec<String>,
    /// Radius around the insertion points, in --units.
    #[arg(long, value_name = "R")]
    pub insertion_radius: Option<f64>,
    /// The Python with the gmsh package [default: $MUSCLEFEM_PYTHON, else
    /// target/python-venv/bin/python in this directory or one above it or the program's,
    /// else python3 on the PATH].
    #[arg(long, value_name = "PATH")]
    pub python: Option<PathBuf>,
    /// Show Gmsh's messages.
    #[arg(long)]
    pub verbose: bool,
    /// Replace an earlier mesh file.
    #[arg(long)]
    pub force: bool,
}

pub fn mesh(args: &MeshArgs) -> Result<()> {
    let out = args.out.clone().unwrap_or_else(|| {
        PathBuf::from(args.surface.file_name().unwrap_or_default()).with_extension("msh")
    });
    crate::commands::refuse_existing(std::slice::from_ref(&out), args.force)?;
    let python = find_python(args.python.as_deref())?;
    let output = Command::new(&python)
        .arg("-c")
        .arg(SCRIPT)
        .args(script_arguments(args, &out))
        .output()
        .with_context(|| format!("running {}", python.display()))?;
    print!("{}", String::from_utf8_lossy(&output.stdout));
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let message = stderr.trim().trim_start_matches("error: ");
        bail!("meshing {}: {message}", args.surface.display());
    }
    let imported = read_mesh(&out).with_context(|| format!("reading back {}", out.display()))?;
    print!(
        "{}",
        summary(&out, &imported.mesh, &imported.element_types)?
    );
    Ok(())
}

/// The script's arguments, each option as `--name=value` (so that values starting with
/// a minus sign are not taken for options).
fn script_arguments(args: &MeshArgs, out: &Path) -> Vec<String> {
    let mut list = vec![
        args.surface.to_string_lossy().into_owned(),
        format!("--out={}", out.to_string_lossy()),
        format!("--size={}", args.size),
        format!(
            "--units={}",
            if matches!(args.units, Units::Mm) {
                "mm"
            } else {
                "m"
            }
        ),
        format!(
            "--element={}",
            if matches!(args.element, TetElement::Tet4) {
                "tet4"
            } else {
                "tet10"
            }
        ),
    ];
    if args.keep_surface {
        list.push("--keep-surface".into());
    }
    if args.verbose {
        list.push("--verbose".into());
    }
    if let Some(angle) = args.feature_angle {
        list.push(format!("--feature-angle={angle}"));
    }
    let repeated = [
        ("origin-plane", &args.origin_plane),
        ("origin-box", &args.origin_box),
        ("origin-points", &args.origin_points),
        ("insertion-plane", &args.insertion_plane),
        ("insertion-box", &args.insertion_box),
        ("insertion-points", &args.insertion_points),
    ];
    for (name, values) in repeated {
        list.extend(values.iter().map(|v| format!("--{name}={v}")));
    }
    for (name, radius) in [
        ("origin-radius", args.origin_radius),
        ("insertion-radius", args.insertion_radius),
    ] {
        if let Some(r) = radius {
            list.push(format!("--{name}={r}"));
        }
    }
    list
}

/// The first Python that imports gmsh: `explicit` alone when given, else
/// $MUSCLEFEM_PYTHON, the project's virtual environment above the current directory or
/// the program, and python3.
fn find_python(explicit: Option<&Path>) -> Result<PathBuf> {
    let candidates: Vec<PathBuf> = match explicit {
        Some(path) => vec![path.to_path_buf()],
        None => {
            let mut list: Vec<PathBuf> = std::env::var_os("MUSCLEFEM_PYTHON")
                .map(PathBuf::from)
                .into_iter()
                .collect();
            let places = [std::env::current_dir().ok(), std::env::current_exe().ok()];
            for start in places.into_iter().flatten() {
                list.extend(
                    start
                        .ancestors()
                        .map(|a| a.join(VENV_PYTHON))
                        .filter(|p| p.exists()),
                );
            }
            list.push(PathBuf::from("python3"));
            list
        }
    };
    for python in &candidates {
        let imports = Command::new(python)
            .args(["-c", "import gmsh"])
            .output()
            .is_ok_and(|o| o.status.success());
        if imports {
            return Ok(python.clone());
        }
    }
    let tried: Vec<String> = candidates.iter().map(|p| p.display().to_string()).collect();
    bail!(
        "no Python with the gmsh package found (tried {}): run scripts/setup-gmsh.sh, which \
         installs it into target/python-venv, or give --python PATH",
        tried.join(", ")
    )
}

/// What the solvers will see of a mesh: its blocks, nodes and volume, and each surface's
/// faces and area.
fn summary(path: &Path, mesh: &musclefem_core::mesh::Mesh, types: &[String]) -> Result<String> {
    use std::fmt::Write as _;
    let mut text = String::new();
    let volume = mesh.total_volume()?;
    let blocks: Vec<String> = mesh
        .blocks
        .iter()
        .zip(types)
        .map(|(b, t)| format!("{} {t} in '{}'", b.len(), b.name))
        .collect();
    writeln!(
        text,
        "{}: {}, {} nodes, volume {volume:.6e} m³ ({:.1} mm³)",
        path.display(),
        blocks.join(", "),
        mesh.node_count(),
        volume * 1e9
    )?;
    for (name, faces) in &mesh.surfaces {
        let mut area = 0.0;
        for &face in faces {
            area += mesh.face_area_vector(face)?.norm();
        }
        writeln!(
            text,
            "  surface '{name}': {} faces, area {area:.6e} m² ({:.1} mm²)",
            faces.len(),
            area * 1e6
        )?;
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;

    #[derive(Debug, Parser)]
    struct Wrapper {
        #[command(flatten)]
        args: MeshArgs,
    }

    #[test]
    fn options_reach_the_script_as_name_equals_value_even_when_negative() {
        let parsed = Wrapper::try_parse_from([
            "mesh",
            "muscle.stl",
            "--size",
            "4",
            "--units",
            "mm",
            "--element",
            "tet4",
            "--origin-box",
            "-10,-10,-1,10,10,1",
            "--origin-plane",
            "0,0,1,0,0,-1",
            "--insertion-points",
            "-1,2,3;4,5,6",
            "--insertion-radius",
            "2.5",
        ])
        .unwrap()
        .args;
        let list = script_arguments(&parsed, Path::new("out/m.msh"));
        assert_eq!(
            list,
            [
                "muscle.stl",
                "--out=out/m.msh",
                "--size=4",
                "--units=mm",
                "--element=tet4",
                "--origin-plane=0,0,1,0,0,-1",
                "--origin-box=-10,-10,-1,10,10,1",
                "--insertion-points=-1,2,3;4,5,6",
                "--insertion-radius=2.5",
            ]
        );
    }

    #[test]
    fn a_python_without_gmsh_is_refused_with_the_set_up_step() {
        let error = find_python(Some(Path::new("/nonexistent/python3")))
            .unwrap_err()
            .to_string();
        assert!(error.contains("tried /nonexistent/python3"), "{error}");
        assert!(error.contains("scripts/setup-gmsh.sh"), "{error}");
    }
}
