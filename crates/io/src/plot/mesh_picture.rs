//! A picture of a deformed solid coloured by one value per cell (e.g. the von Mises stress
//! of a frame), seen along a direction, with rigid surfaces (bones) in grey: a PNG with a
//! title, a colour bar, the frame's axes and a scale bar.
//!
//! What is drawn: the boundary faces of the drawn cells ([`surface`]) at their current
//! position x = X + u, projected orthographically ([`view`]) and filled with a depth
//! buffer ([`raster`]), each in the colour of its cell's value on the viridis map, shaded
//! by the Lambert factor
//!
//! s = a + (1 − a)·|n·l|,  a = 0.6,
//!
//! n the face's unit normal and l a light from just above and left of the viewer, so
//! that the shape reads while a face's colour stays near its value's (within 40 %).
//! Values beyond the colour range are drawn in the end colour and counted in a note over
//! the colour bar ("≥ 450 kPa: 37 cells"); a cell without a finite value is magenta.
//! The default range runs from 0 (or the 1st percentile, if a value is negative) to the
//! 99th percentile of the drawn cells' values, so that a few extreme cells do not wash
//! out the rest. The picture is scaled to fit the solid; rigid surfaces beyond it are
//! cut off. Faces hide each other by a depth buffer, not by sorting them (the painter's
//! algorithm), so a bone that cuts through a muscle's faces is drawn as it lies.

pub mod raster;
pub mod surface;
pub mod view;

use std::ops::Range;
use std::path::Path;

use musclefem_core::solver::element_fields::percentile;
use musclefem_mesh::Mesh;
use nalgebra::{Vector2, Vector3};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::colour_bar::{ColourBar, ColourBarLayout, draw_colour_bar, viridis};
use super::{FONT_FAMILY, check_png_path, ensure_font, tick_label};
use crate::OutputError;
use crate::atomic::PendingFile;
use raster::{Raster, SUPERSAMPLING, ScreenTriangle, scaled};
use surface::{Facet, boundary_facets, rigid_facets};
pub use view::{NamedView, View, ViewName};

/// Height of the strip with the title and the note, and width of the colour bar's strip
/// [px].
pub const TITLE_HEIGHT: u32 = 72;
pub const COLOUR_BAR_WIDTH: u32 = 190;
/// Space kept free around the solid, and below it for the axes and the scale bar [px].
const MARGIN: f64 = 28.0;
const BOTTOM_BAND: f64 = 76.0;
/// Ambient share of the shading, and the light's direction in the screen frame (right,
/// up, toward the viewer).
const AMBIENT: f64 = 0.6;
const LIGHT: [f64; 3] = [-0.2, 0.3, 1.0];
/// Colour of rigid surfaces, and of cells whose value is not a number.
pub const RIGID_GREY: RGBColor = RGBColor(208, 208, 208);
pub const NO_VALUE: RGBColor = RGBColor(255, 0, 255);
/// Outlines are drawn (unless asked otherwise) when the median outlined edge is at least
/// this long on the picture [px].
const OUTLINE_MEDIAN_EDGE: f64 = 20.0;

/// The scalar a picture shows: name and unit on the colour bar, and the factor from the
/// values' unit to the shown one (1e-3 for Pa shown in kPa).
#[derive(Debug, Clone, PartialEq)]
pub struct ValueLabel {
    pub name: String,
    /// "" for a quantity without unit.
    pub unit: String,
    pub factor: f64,
}

impl ValueLabel {
    /// "name [unit]", or the name alone without a unit.
    pub fn text(&self) -> String {
        if self.unit.is_empty() {
            self.name.clone()
        } else {
            format!("{} [{}]", self.name, self.unit)
        }
    }
}

/// A rigid surface drawn in grey: triangles by index into the vertices, at their current
/// position [m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidSurface<'a> {
    pub vertices: &'a [Vector3<f64>],
    pub triangles: &'a [[u32; 3]],
}

/// What to draw.
#[derive(Debug, Clone)]
pub struct MeshPicture<'a> {
    /// First line of the title.
    pub title: String,
    /// Second, smaller line (the view, the time, ...); "" for none.
    pub note: String,
    /// The mesh in its reference configuration.
    pub mesh: &'a Mesh,
    /// Displacement of each node [m]: the picture shows x = X + u.
    pub displacement: &'a [Vector3<f64>],
    /// One value per cell, in block order (the order of a frame's cells).
    pub values: &'a [f64],
    /// The blocks drawn (indices into `mesh.blocks`); `None` for all.
    pub blocks: Option<&'a [usize]>,
    pub view: View,
    pub label: ValueLabel,
    /// The values at the ends of the colour bar, in the values' unit; `None` for the
    /// default (see the module documentation).
    pub range: Option<Range<f64>>,
    pub rigid: Vec<RigidSurface<'a>>,
    /// Size of the whole picture [px].
    pub size: (u32, u32),
    /// Draw the faces' edges darker: `None` decides by their size on the picture.
    pub outlines: Option<bool>,
}

/// Where a point of the model lands on the picture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    pub view: View,
    /// Pixels per metre.
    pub scale: f64,
    /// Screen coordinates (right, up) [m] of the solid's centre, and its pixel.
    centre: Vector2<f64>,
    centre_pixel: Vector2<f64>,
    /// The image area: left, top, width, height [px] in the picture.
    pub image: (u32, u32, u32, u32),
}

impl Projection {
    /// The picture coordinates (x right, y down) [px] of the point `x` [m].
    pub fn pixel(&self, x: &Vector3<f64>) -> Vector2<f64> {
        let s = self.view.screen(x);
        self.centre_pixel + Vector2::new(s.x - self.centre.x, self.centre.y - s.y) * self.scale
    }
}

/// What was drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct PictureSummary {
    /// The colour range, in the values' unit.
    pub range: Range<f64>,
    /// Drawn cells above and below the range, and without a finite value (magenta).
    pub above: usize,
    pub below: usize,
    pub not_finite: usize,
    /// Drawn cells, their boundary triangles and the rigid triangles.
    pub cells: usize,
    pub facets: usize,
    pub rigid_facets: usize,
    pub outlines: bool,
    pub projection: Projection,
    /// The colour bar in picture pixels: its top row has the colour of the range's end,
    /// its bottom row that of its start.
    pub colour_bar: PixelBox,
}

/// A box of pixels: columns and rows, first included, last excluded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PixelBox {
    pub columns: (i32, i32),
    pub rows: (i32, i32),
}

/// The colour of a cell with `value` in `range`: viridis of the value's place in the
/// range, clamped to the ends; [`NO_VALUE`] if it is not finite.
pub fn value_colour(value: f64, range: &Range<f64>) -> RGBColor {
    if !value.is_finite() {
        return NO_VALUE;
    }
    viridis((value - range.start) / (range.end - range.start))
}

/// `colour` lit by the Lambert factor of a face with unit normal `normal` in `view` (see
/// the module documentation; either side of a face is lit alike).
pub fn shaded(colour: RGBColor, normal: &Vector3<f64>, view: &View) -> RGBColor {
    let light = (view.right.into_inner() * LIGHT[0]
        + view.up.into_inner() * LIGHT[1]
        + view.toward_viewer.into_inner() * LIGHT[2])
        .normalize();
    scaled(colour, AMBIENT + (1.0 - AMBIENT) * normal.dot(&light).abs())
}

/// The default colour range of `values`: from 0 (or the 1st percentile if a value is
/// negative) to the 99th percentile, over the finite values; widened to the largest value,
/// then to a unit, if that range is empty.
pub fn default_range(values: &[f64]) -> Range<f64> {
    let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    let Some(top) = percentile(&finite, 0.99) else {
        return 0.0..1.0;
    };
    let smallest = finite.iter().copied().fold(f64::INFINITY, f64::min);
    let largest = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let start = if smallest >= 0.0 {
        0.0
    } else {
        percentile(&finite, 0.01).unwrap_or(smallest)
    };
    let end = if top > start { top } else { largest };
    if end > start {
        start..end
    } else {
        let half = if start == 0.0 { 0.5 } else { 0.5 * start.abs() };
        (start - half)..(start + half)
    }
}

/// Render `picture` into a staged PNG for `path` (commit it with [`PendingFile::commit`]).
/// Errors, naming the file: a name not ending in .png, a size outside 320 × 240 to
/// 16384 × 16384 px, slices of the wrong length, a block that does not exist, nothing
/// to draw, a range that is not increasing, and a failure to draw or write.
pub fn stage_mesh_png(
    path: &Path,
    picture: &MeshPicture,
) -> Result<(PendingFile, PictureSummary), OutputError> {
    let plot_error = |message: String| OutputError::Plot {
        path: path.to_path_buf(),
        message,
    };
    check_png_path(path)?;
    let (width, height) = picture.size;
    if !(320..=16_384).contains(&width) || !(240..=16_384).contains(&height) {
        return Err(plot_error(format!(
            "picture size {width}x{height} px is outside 320x240..16384x16384"
        )));
    }
    let mesh = picture.mesh;
    if picture.displacement.len() != mesh.node_count()
        || picture.values.len() != mesh.element_count()
    {
        return Err(plot_error(format!(
            "{} displacements for {} nodes and {} values for {} cells",
            picture.displacement.len(),
            mesh.node_count(),
            picture.values.len(),
            mesh.element_count()
        )));
    }
    let current: Vec<Vector3<f64>> = (0..mesh.node_count())
        .map(|i| mesh.nodes.position(i) + picture.displacement[i])
        .collect();
    if let Some(i) = current
        .iter()
        .position(|x| !x.iter().all(|c| c.is_finite()))
    {
        return Err(plot_error(format!("node {i} is not at a finite position")));
    }
    let solid =
        boundary_facets(mesh, &current, picture.values, picture.blocks).map_err(plot_error)?;
    if solid.is_empty() {
        return Err(plot_error("no cell to draw".to_string()));
    }
    let mut rigid = Vec::new();
    for surface in &picture.rigid {
        rigid.extend(rigid_facets(surface.vertices, surface.triangles).map_err(plot_error)?);
    }
    let drawn = drawn_values(picture);
    let range = picture
        .range
        .clone()
        .unwrap_or_else(|| default_range(&drawn));
    if !(range.start < range.end && range.start.is_finite() && range.end.is_finite()) {
        return Err(plot_error(format!(
            "the colour range {} to {} is not increasing",
            range.start, range.end
        )));
    }
    let projection = fit(&solid, picture.view, picture.size);
    let outlines = picture
        .outlines
        .unwrap_or_else(|| median_outline(&solid, &projection) >= OUTLINE_MEDIAN_EDGE);
    let summary = PictureSummary {
        above: drawn.iter().filter(|&&v| v > range.end).count(),
        below: drawn.iter().filter(|&&v| v < range.start).count(),
        not_finite: drawn.iter().filter(|v| !v.is_finite()).count(),
        cells: drawn.len(),
        facets: solid.len(),
        rigid_facets: rigid.len(),
        outlines,
        projection,
        colour_bar: PixelBox::default(),
        range,
    };
    let raster = rasterize(&solid, &rigid, &summary);
    ensure_font().map_err(plot_error)?;
    let mut bar_box = PixelBox::default();
    let staged = PendingFile::stage(path, |temp| {
        bar_box = render(temp, picture, &summary, &raster).map_err(plot_error)?;
        Ok(())
    })?;
    Ok((
        staged,
        PictureSummary {
            colour_bar: bar_box,
            ..summary
        },
    ))
}

/// The values of the drawn blocks' cells.
fn drawn_values(picture: &MeshPicture) -> Vec<f64> {
    let mut first = 0;
    let mut values = Vec::new();
    for (b, block) in picture.mesh.blocks.iter().enumerate() {
        if picture.blocks.is_none_or(|list| list.contains(&b)) {
            values.extend_from_slice(&picture.values[first..first + block.len()]);
        }
        first += block.len();
    }
    values
}

/// The projection that fits the solid's facets into the image area, with a margin and a
/// band at the bottom for the axes and the scale bar.
fn fit(facets: &[Facet], view: View, size: (u32, u32)) -> Projection {
    let (mut lo, mut hi) = (
        Vector2::repeat(f64::INFINITY),
        Vector2::repeat(f64::NEG_INFINITY),
    );
    for corner in facets.iter().flat_map(|f| &f.corners) {
        let s = view.screen(corner).xy();
        lo = lo.inf(&s);
        hi = hi.sup(&s);
    }
    let image = (
        0,
        TITLE_HEIGHT,
        size.0 - COLOUR_BAR_WIDTH,
        size.1 - TITLE_HEIGHT,
    );
    let room = Vector2::new(
        f64::from(image.2) - 2.0 * MARGIN,
        f64::from(image.3) - MARGIN - BOTTOM_BAND,
    );
    let extent = hi - lo;
    let scale = [room.x / extent.x, room.y / extent.y]
        .into_iter()
        .filter(|s| s.is_finite() && *s > 0.0)
        .fold(f64::INFINITY, f64::min);
    Projection {
        view,
        scale: if scale.is_finite() { scale } else { 1.0 },
        centre: 0.5 * (lo + hi),
        centre_pixel: Vector2::new(
            f64::from(image.0) + 0.5 * f64::from(image.2),
            f64::from(image.1) + MARGIN + 0.5 * room.y,
        ),
        image,
    }
}

/// Median length of the outlined edges on the picture [px].
fn median_outline(facets: &[Facet], projection: &Projection) -> f64 {
    let mut lengths: Vec<f64> = facets
        .iter()
        .flat_map(|f| {
            (0..3).filter(|&k| f.outline[k]).map(move |k| {
                let (a, b) = (f.corners[(k + 1) % 3], f.corners[(k + 2) % 3]);
                (projection.pixel(&a) - projection.pixel(&b)).norm()
            })
        })
        .collect();
    lengths.sort_by(f64::total_cmp);
    lengths.get(lengths.len() / 2).copied().unwrap_or(0.0)
}

/// The image area drawn at [`SUPERSAMPLING`] and averaged down to its size.
fn rasterize(solid: &[Facet], rigid: &[Facet], summary: &PictureSummary) -> Raster {
    let projection = &summary.projection;
    let (left, top, width, height) = projection.image;
    let ss = SUPERSAMPLING as f64;
    let mut raster = Raster::new(
        width as usize * SUPERSAMPLING,
        height as usize * SUPERSAMPLING,
    );
    for facet in solid.iter().chain(rigid) {
        let base = match facet.value {
            Some(v) => value_colour(v, &summary.range),
            None => RIGID_GREY,
        };
        let corners = facet.corners.map(|c| {
            let p = projection.pixel(&c);
            let depth = projection.view.screen(&c).z;
            Vector3::new(
                (p.x - f64::from(left)) * ss,
                (p.y - f64::from(top)) * ss,
                depth,
            )
        });
        let triangle = ScreenTriangle {
            corners,
            colour: shaded(base, &facet.normal, &projection.view),
            outline: facet.outline,
        };
        raster.fill(&triangle, summary.outlines);
    }
    raster.downsampled(SUPERSAMPLING, WHITE)
}

/// Draw the picture into the PNG file `file`; returns the colour bar's pixel box.
fn render(
    file: &Path,
    picture: &MeshPicture,
    summary: &PictureSummary,
    raster: &Raster,
) -> Result<PixelBox, String> {
    let error = |e: DrawingAreaErrorKind<_>| e.to_string();
    let root = BitMapBackend::new(file, picture.size).into_drawing_area();
    root.fill(&WHITE).map_err(error)?;
    let (strip, body) = root.split_vertically(TITLE_HEIGHT);
    let strip = strip
        .titled(&picture.title, (FONT_FAMILY, 24))
        .map_err(error)?;
    if !picture.note.is_empty() {
        strip
            .titled(&picture.note, (FONT_FAMILY, 15))
            .map_err(error)?;
    }
    let (image, bar_area) = body.split_horizontally(summary.projection.image.2);
    for y in 0..raster.height {
        for x in 0..raster.width {
            if let Some(colour) = raster.pixel(x, y) {
                image
                    .draw_pixel((x as i32, y as i32), &colour)
                    .map_err(error)?;
            }
        }
    }
    draw_axes(&image, &summary.projection).map_err(|e| format!("axes: {e}"))?;
    draw_scale_bar(&image, &summary.projection).map_err(|e| format!("scale bar: {e}"))?;

    let factor = picture.label.factor;
    let shown = (summary.range.start * factor)..(summary.range.end * factor);
    let span = shown.end - shown.start;
    let unit = if picture.label.unit.is_empty() {
        String::new()
    } else {
        format!(" {}", picture.label.unit)
    };
    let note = |sign: &str, value: f64, count: usize| {
        let cells = if count == 1 { "cell" } else { "cells" };
        format!("{sign} {}{unit}: {count} {cells}", tick_label(value, span))
    };
    let bar = ColourBar {
        label: picture.label.text(),
        above: (summary.above > 0).then(|| note("≥", shown.end, summary.above)),
        below: (summary.below > 0).then(|| note("≤", shown.start, summary.below)),
        range: shown,
    };
    draw_colour_bar(&bar_area, &bar).map_err(|e| format!("colour bar: {e}"))?;
    root.present().map_err(error)?;
    let notes = usize::from(bar.above.is_some()) + usize::from(bar.below.is_some());
    let layout = ColourBarLayout::new(picture.size.1 - TITLE_HEIGHT, notes);
    let (dx, dy) = (summary.projection.image.2 as i32, TITLE_HEIGHT as i32);
    Ok(PixelBox {
        columns: (layout.bar_x.0 + dx, layout.bar_x.1 + dx),
        rows: (layout.bar_y.0 + dy, layout.bar_y.1 + dy),
    })
}

/// The frame's axes x, y, z as seen in the view, in the lower left corner.
fn draw_axes<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    projection: &Projection,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    const LENGTH: f64 = 30.0;
    let (_, height) = area.dim_in_pixel();
    let origin = (64, height as i32 - 40);
    let style =
        TextStyle::from((FONT_FAMILY, 15).into_font()).pos(Pos::new(HPos::Center, VPos::Center));
    for (axis, name) in [
        (Vector3::x(), "x"),
        (Vector3::y(), "y"),
        (Vector3::z(), "z"),
    ] {
        let s = projection.view.screen(&axis);
        let tip = (
            origin.0 + (LENGTH * s.x).round() as i32,
            origin.1 - (LENGTH * s.y).round() as i32,
        );
        let label = if s.xy().norm() < 0.2 {
            // Along the line of sight: a dot, marked towards or away from the viewer.
            area.draw(&Circle::new(origin, 3, BLACK.filled()))?;
            let side = if s.z > 0.0 { "toward you" } else { "away" };
            (format!("{name} ({side})"), (origin.0 + 56, origin.1 + 12))
        } else {
            area.draw(&PathElement::new(vec![origin, tip], BLACK.stroke_width(2)))?;
            let beyond = (
                (origin.0 + ((LENGTH + 10.0) * s.x).round() as i32).max(8),
                (origin.1 - ((LENGTH + 10.0) * s.y).round() as i32).min(height as i32 - 9),
            );
            (name.to_string(), beyond)
        };
        area.draw(&Text::new(label.0, label.1, style.clone()))?;
    }
    Ok(())
}

/// A bar of a round length (1, 2 or 5 × 10ᵏ m, at most 160 px) in the lower right corner.
fn draw_scale_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    projection: &Projection,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let most = 160.0 / projection.scale;
    let decade = 10f64.powf(most.log10().floor());
    let length = [5.0, 2.0, 1.0]
        .iter()
        .map(|m| m * decade)
        .find(|&l| l <= most)
        .unwrap_or(decade);
    let pixels = (length * projection.scale).round() as i32;
    let (width, height) = area.dim_in_pixel();
    let (right, y) = (width as i32 - 24, height as i32 - 24);
    let left = right - pixels;
    area.draw(&PathElement::new(
        vec![(left, y), (right, y)],
        BLACK.stroke_width(3),
    ))?;
    for x in [left, right] {
        area.draw(&PathElement::new(
            vec![(x, y - 6), (x, y + 6)],
            BLACK.stroke_width(2),
        ))?;
    }
    let text = if length < 1.0 {
        format!("{} mm", tick_label(length * 1e3, length * 1e3))
    } else {
        format!("{} m", tick_label(length, length))
    };
    let style =
        TextStyle::from((FONT_FAMILY, 15).into_font()).pos(Pos::new(HPos::Center, VPos::Bottom));
    area.draw(&Text::new(text, ((left + right) / 2, y - 8), style))
}
