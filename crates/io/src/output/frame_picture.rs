//! A picture of one frame of a run: its parts, deformed, coloured by one of its cell
//! arrays (the von Mises stress by default), with the rigid bodies of the same instant in
//! grey ([`crate::plot::mesh_picture`] draws it). What `musclefem picture` writes.

use std::ops::Range;
use std::path::{Path, PathBuf};

use musclefem_core::mesh::ElementShape;

use super::read_frame::{read_frame, read_rigid_frame};
use crate::OutputError;
use crate::atomic::PendingFile;
use crate::plot::mesh_picture::{
    MeshPicture, PictureSummary, RigidSurface, ValueLabel, View, ViewName, stage_mesh_png,
};

/// Which frame to draw, and how.
#[derive(Debug, Clone)]
pub struct FramePicture {
    /// The part frame (`frames/frame_NNNNN.vtu`).
    pub frame: PathBuf,
    /// Its time [s], for the title, if known.
    pub time: Option<f64>,
    /// The rigid-body frame of the same instant, if the bones are to be drawn.
    pub rigid: Option<PathBuf>,
    /// The cell array that colours the cells (one component), e.g. `von_mises`.
    pub field: String,
    /// Name, unit and factor of the field on the colour bar; `None` for
    /// [`default_label`].
    pub label: Option<ValueLabel>,
    pub view: View,
    /// The colour range in the field's unit (as in the file); `None` for the default.
    pub range: Option<Range<f64>>,
    /// The blocks drawn (`block_id`s); `None` for all.
    pub blocks: Option<Vec<usize>>,
    /// Size of the picture [px].
    pub size: (u32, u32),
    /// Outlines of the faces: `None` decides by their size.
    pub outlines: Option<bool>,
}

/// One block of the frame: its cells and their shape.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockSummary {
    pub block: usize,
    pub shape: ElementShape,
    pub cells: usize,
    /// Largest value of the field over its cells, in the field's unit (NaN if none is
    /// finite).
    pub largest: f64,
}

/// What was drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct FramePictureSummary {
    pub picture: PictureSummary,
    pub label: ValueLabel,
    pub blocks: Vec<BlockSummary>,
    pub nodes: usize,
    pub rigid_vertices: usize,
}

/// The colour bar's name and unit of a frame's cell array: `von_mises` as "von Mises
/// stress [kPa]" (the file holds Pa), anything else by its name, without a unit.
pub fn default_label(field: &str) -> ValueLabel {
    let (name, unit, factor) = if field == "von_mises" {
        ("von Mises stress", "kPa", 1e-3)
    } else {
        (field, "", 1.0)
    };
    ValueLabel {
        name: name.to_string(),
        unit: unit.to_string(),
        factor,
    }
}

/// Read the frame (and the rigid frame) of `request` and stage its picture for `out`
/// (commit it with [`PendingFile::commit`]). Errors name the file read or written and
/// what is missing.
pub fn stage_frame_picture(
    out: &Path,
    request: &FramePicture,
) -> Result<(PendingFile, FramePictureSummary), OutputError> {
    let frame = read_frame(&request.frame)?;
    let values = frame.cell_scalar(&request.field)?;
    let rigid = request.rigid.as_deref().map(read_rigid_frame).transpose()?;
    let label = request
        .label
        .clone()
        .unwrap_or_else(|| default_label(&request.field));

    let mut blocks = Vec::with_capacity(frame.mesh.blocks.len());
    let mut first = 0;
    for (b, block) in frame.mesh.blocks.iter().enumerate() {
        let own = &values[first..first + block.len()];
        first += block.len();
        blocks.push(BlockSummary {
            block: b,
            shape: block.shape,
            cells: block.len(),
            largest: own
                .iter()
                .copied()
                .filter(|v| v.is_finite())
                .fold(f64::NAN, f64::max),
        });
    }

    let file_name = request
        .frame
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let title = match request.time {
        Some(t) => format!("{} at t = {t:.3} s", label.name),
        None => label.name.clone(),
    };
    let view = match request.view.name {
        ViewName::Named(named) => format!(
            "{} view (frame: x anterior, y superior, z lateral)",
            capitalised(named.name())
        ),
        name @ ViewName::Direction(_) => format!("View {name}"),
    };
    let mut note = format!("{file_name} · {view} · deformed (scale 1)");
    if let Some(list) = &request.blocks {
        let list: Vec<String> = list.iter().map(usize::to_string).collect();
        note.push_str(&format!(" · blocks {}", list.join(", ")));
    }
    if rigid.is_some() {
        note.push_str(" · rigid bodies in grey");
    }
    let surfaces: Vec<RigidSurface> = rigid
        .iter()
        .map(|r| RigidSurface {
            vertices: &r.vertices,
            triangles: &r.triangles,
        })
        .collect();
    let picture = MeshPicture {
        title,
        note,
        mesh: &frame.mesh,
        displacement: &frame.displacement,
        values,
        blocks: request.blocks.as_deref(),
        view: request.view,
        label: label.clone(),
        range: request.range.clone(),
        rigid: surfaces,
        size: request.size,
        outlines: request.outlines,
    };
    let (staged, summary) = stage_mesh_png(out, &picture)?;
    Ok((
        staged,
        FramePictureSummary {
            picture: summary,
            label,
            blocks,
            nodes: frame.mesh.node_count(),
            rigid_vertices: rigid.as_ref().map_or(0, |r| r.vertices.len()),
        },
    ))
}

/// `text` with its first letter in upper case.
fn capitalised(text: &str) -> String {
    let mut chars = text.chars();
    match chars.next() {
        Some(first) => first.to_uppercase().chain(chars).collect(),
        None => String::new(),
    }
}
