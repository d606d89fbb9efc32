//! `musclefem picture`: a PNG of one frame of a run, its parts deformed and coloured by a
//! cell array (von Mises stress by default), the bones of the same instant in grey
//! (`musclefem_io::output::frame_picture`).

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use nalgebra::Vector3;

use musclefem_io::output::{FramePicture, frame_time, run_frame_at, stage_frame_picture};
use musclefem_io::plot::mesh_picture::View;

#[derive(Debug, Args)]
pub struct PictureArgs {
    /// The part frame to draw (RUN/frames/frame_NNNNN.vtu).
    #[arg(
        long,
        value_name = "FILE.vtu",
        required_unless_present = "run",
        conflicts_with = "run"
    )]
    pub frame: Option<PathBuf>,
    /// The rigid-body frame of the same instant (RUN/frames/rigid_NNNNN.vtu), drawn in
    /// grey; with --frame only.
    #[arg(long, value_name = "FILE.vtu", conflicts_with = "run")]
    pub rigid: Option<PathBuf>,
    /// A run's output directory: draw its frame nearest --time (from result.pvd), with its
    /// rigid bodies of that instant (from rigid.pvd) unless --no-rigid.
    #[arg(long, value_name = "DIR", requires = "time")]
    pub run: Option<PathBuf>,
    /// The time of the frame to draw with --run [s].
    #[arg(long, value_name = "SECONDS", requires = "run")]
    pub time: Option<f64>,
    /// Leave out the rigid bodies of a --run.
    #[arg(long, requires = "run")]
    pub no_rigid: bool,
    /// The cell array that colours the cells (one component), e.g. von_mises,
    /// fiber_stretch, activation.
    #[arg(long, value_name = "NAME", default_value = "von_mises")]
    pub field: String,
    /// The view: anterior, posterior, lateral, medial, superior, inferior (frame: x
    /// anterior, y superior, z lateral), or a direction toward the viewer X,Y,Z.
    #[arg(
        long,
        value_name = "VIEW",
        default_value = "lateral",
        value_parser = parse_view,
        allow_hyphen_values = true
    )]
    pub view: View,
    /// Turn the view about its line of sight so that this direction X,Y,Z points up
    /// [default: y, or x when looking along y].
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_direction, allow_hyphen_values = true)]
    pub up: Option<[f64; 3]>,
    /// Colour range LO,HI in the file's unit (Pa for stresses) [default: 0 to the 99th
    /// percentile of the drawn cells].
    #[arg(long, value_name = "LO,HI", value_parser = parse_range, allow_hyphen_values = true)]
    pub range: Option<(f64, f64)>,
    /// Draw only this block (its block_id); repeatable [default: all].
    #[arg(long = "block", value_name = "ID")]
    pub blocks: Vec<usize>,
    /// Picture size WIDTHxHEIGHT [px].
    #[arg(long, value_name = "WxH", default_value = "1200x900", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Darker edges around the faces: auto draws them when faces are at least 20 px wide.
    #[arg(long, value_enum, default_value_t = Outlines::Auto)]
    pub outlines: Outlines,
    /// The PNG file to write.
    #[arg(long, value_name = "FILE.png", default_value = "picture.png")]
    pub out: PathBuf,
    /// Replace an existing picture.
    #[arg(long)]
    pub force: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Outlines {
    Auto,
    On,
    Off,
}

/// `value` with three or four significant digits (no exponent between 1e-3 and 1e6).
fn readable(value: f64) -> String {
    let magnitude = value.abs();
    if magnitude == 0.0 {
        "0".to_string()
    } else if !value.is_finite() || (1e-3..1e6).contains(&magnitude) {
        let decimals = if magnitude >= 100.0 {
            0
        } else if magnitude >= 10.0 {
            1
        } else {
            3
        };
        format!("{value:.decimals$}")
    } else {
        format!("{value:.3e}")
    }
}

fn parse_view(text: &str) -> Result<View, String> {
    text.parse()
}

fn parse_direction(text: &str) -> Result<[f64; 3], String> {
    let numbers: Vec<f64> = text
        .split(',')
        .map(|n| n.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{text}' is not X,Y,Z (three numbers)"))?;
    <[f64; 3]>::try_from(numbers).map_err(|_| format!("'{text}' is not X,Y,Z (three numbers)"))
}

fn parse_range(text: &str) -> Result<(f64, f64), String> {
    let numbers: Vec<f64> = text
        .split(',')
        .map(|n| n.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{text}' is not LO,HI (two numbers)"))?;
    match numbers[..] {
        [lo, hi] if lo < hi && lo.is_finite() && hi.is_finite() => Ok((lo, hi)),
        [_, _] => Err(format!("'{text}': LO must be below HI, both finite")),
        _ => Err(format!("'{text}' is not LO,HI (two numbers)")),
    }
}

fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{text}' is not WIDTHxHEIGHT"))?;
    let number = |n: &str| {
        n.trim()
            .parse::<u32>()
            .map_err(|_| format!("'{text}': '{n}' is not a whole number of pixels"))
    };
    Ok((number(w)?, number(h)?))
}

pub fn picture(args: &PictureArgs) -> Result<()> {
    crate::commands::refuse_existing(std::slice::from_ref(&args.out), args.force)?;
    let (frame, time, rigid) = match (&args.frame, &args.run, args.time) {
        (Some(frame), _, _) => (frame.clone(), frame_time(frame), args.rigid.clone()),
        (None, Some(run), Some(time)) => {
            let found = run_frame_at(run, time)
                .with_context(|| format!("the frame of {} at t = {time} s", run.display()))?;
            let rigid = if args.no_rigid { None } else { found.rigid };
            (found.frame, Some(found.time), rigid)
        }
        _ => bail!("give --frame FILE or --run DIR --time SECONDS"),
    };
    let view = match args.up {
        None => args.view,
        Some(up) => args.view.with_up(Vector3::from(up)).with_context(|| {
            format!("--up {up:?} is zero or along the line of sight of the view")
        })?,
    };
    let request = FramePicture {
        frame,
        time,
        rigid,
        field: args.field.clone(),
        label: None,
        view,
        range: args.range.map(|(lo, hi)| lo..hi),
        blocks: (!args.blocks.is_empty()).then(|| args.blocks.clone()),
        size: args.size,
        outlines: match args.outlines {
            Outlines::Auto => None,
            Outlines::On => Some(true),
            Outlines::Off => Some(false),
        },
    };
    let (staged, summary) = stage_frame_picture(&args.out, &request)?;
    staged.commit()?;

    let label = &summary.label;
    let shown = |v: f64| {
        let unit = if label.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", label.unit)
        };
        format!("{}{unit}", readable(v * label.factor))
    };
    let when = time.map_or(String::new(), |t| format!(" (t = {t} s)"));
    println!(
        "{}{when}: {} nodes, {} blocks",
        request.frame.display(),
        summary.nodes,
        summary.blocks.len()
    );
    for block in &summary.blocks {
        println!(
            "  block {}: {} {} cells, largest {} {}",
            block.block,
            block.cells,
            block.shape,
            args.field,
            shown(block.largest)
        );
    }
    if let Some(rigid) = &request.rigid {
        println!(
            "rigid bodies: {} ({} vertices, {} triangles)",
            rigid.display(),
            summary.rigid_vertices,
            summary.picture.rigid_facets
        );
    }
    let p = &summary.picture;
    let how = if args.range.is_some() {
        "as given"
    } else {
        "default: 0 or the 1st percentile to the 99th percentile"
    };
    println!(
        "{} cells drawn by {} boundary triangles; colour range {} to {} ({how}); {} cells \
         above it, {} below, {} not finite",
        p.cells,
        p.facets,
        shown(p.range.start),
        shown(p.range.end),
        p.above,
        p.below,
        p.not_finite
    );
    println!(
        "wrote {} ({}x{} px, {} view)",
        args.out.display(),
        args.size.0,
        args.size.1,
        args.view.name
    );
    Ok(())
}
