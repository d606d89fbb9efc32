//! A picture of a direction field in 3-D (e.g. the fiber directions of a muscle): one
//! arrow per point, projected onto the plane of the two principal axes of the point cloud,
//! coloured by a scalar with a colour bar.
//!
//! The view: the principal axes are the eigenvectors of the covariance of the points
//! (PCA), ordered by variance; the picture shows the first two (the directions of largest
//! extent), both at the same scale, seen from the side of the third (a right-handed frame).
//! Every arrow has the same length in 3-D, so an arrow that leaves the plane is drawn
//! shorter; nearer arrows are drawn over farther ones.

use std::path::Path;

use nalgebra::{Matrix3, SymmetricEigen, Vector2, Vector3};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::colour_bar::{ColourBar, draw_colour_bar, viridis};
use super::{FONT_FAMILY, check_png_path, ensure_font, tick_label};
use crate::OutputError;
use crate::atomic::PendingFile;

/// Width of the plotting area (inside the axes) in pixels.
const PLOT_WIDTH: u32 = 900;
/// Smallest and largest height of the plotting area in pixels (the axis ranges are padded
/// so that both axes keep the same scale).
const PLOT_HEIGHT: std::ops::RangeInclusive<u32> = 360..=900;
/// Height of the strip with the title and the note under it, in pixels.
const TITLE_HEIGHT: u32 = 72;
/// Width of the colour bar with its labels, in pixels.
const COLOUR_BAR_WIDTH: u32 = 150;
/// Margin around the chart and width of its y-label area, height of its x-label area.
const MARGIN: u32 = 12;
const Y_LABEL_AREA: u32 = 80;
const X_LABEL_AREA: u32 = 52;
/// Length of the two strokes of an arrow head, as a fraction of the drawn arrow.
const HEAD_FRACTION: f64 = 0.35;
/// Angle between an arrow head's strokes and the arrow [rad] (25°).
const HEAD_ANGLE: f64 = 25.0 * std::f64::consts::PI / 180.0;

/// What to draw: unit directions at points, each arrow coloured by a scalar.
#[derive(Debug, Clone)]
pub struct GlyphView<'a> {
    /// First line of the title, e.g. "Fiber directions of muscle.inp".
    pub title: String,
    /// Arrow positions [m], e.g. element centroids. Each arrow is centred on its point.
    pub points: &'a [Vector3<f64>],
    /// Unit direction of each arrow.
    pub directions: &'a [Vector3<f64>],
    /// The scalar that colours each arrow.
    pub colour_values: &'a [f64],
    /// Name and unit of the scalar, for the colour bar, e.g. "potential φ [1]".
    pub colour_label: String,
    /// Length of every arrow in 3-D [m] (its projection is drawn).
    pub arrow_length: f64,
    /// Most arrows drawn: above it every k-th point is drawn, k the smallest stride that
    /// keeps the count at or below it (deterministic).
    pub max_glyphs: usize,
}

/// The principal axes of a point cloud: its centroid and the eigenvectors of its
/// covariance, by decreasing variance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrincipalAxes {
    /// Mean of the points [m].
    pub centroid: Vector3<f64>,
    /// Unit axes, by decreasing variance; `axes[2] = axes[0] × axes[1]`, and the largest
    /// component of `axes[0]` and of `axes[1]` is positive (so the frame is reproducible).
    pub axes: [Vector3<f64>; 3],
    /// Variance of the points along each axis [m²].
    pub variances: [f64; 3],
}

impl PrincipalAxes {
    /// The principal axes of `points` (the coordinate axes around the centroid if the
    /// covariance is zero, e.g. for one point). `None` for no point.
    pub fn of(points: &[Vector3<f64>]) -> Option<Self> {
        if points.is_empty() {
            return None;
        }
        let centroid = points.iter().sum::<Vector3<f64>>() / points.len() as f64;
        let covariance = points
            .iter()
            .map(|p| (p - centroid) * (p - centroid).transpose())
            .sum::<Matrix3<f64>>()
            / points.len() as f64;
        let eigen = SymmetricEigen::new(covariance);
        let mut order = [0, 1, 2];
        order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
        let oriented = |v: Vector3<f64>| {
            let largest = v
                .iter()
                .copied()
                .fold(0.0, |m: f64, c| if c.abs() > m.abs() { c } else { m });
            if largest < 0.0 { -v } else { v }
        };
        let first = oriented(eigen.eigenvectors.column(order[0]).into_owned());
        let second = oriented(eigen.eigenvectors.column(order[1]).into_owned());
        Some(PrincipalAxes {
            centroid,
            axes: [first, second, first.cross(&second)],
            variances: order.map(|i| eigen.eigenvalues[i].max(0.0)),
        })
    }

    /// Coordinates of `x` along the three axes, from the centroid [m].
    pub fn coordinates(&self, x: Vector3<f64>) -> Vector3<f64> {
        let r = x - self.centroid;
        Vector3::new(
            r.dot(&self.axes[0]),
            r.dot(&self.axes[1]),
            r.dot(&self.axes[2]),
        )
    }
}

/// Indices of the points drawn: every k-th, k = ⌈count / max_glyphs⌉.
pub fn subsample(count: usize, max_glyphs: usize) -> Vec<usize> {
    let stride = count.div_ceil(max_glyphs.max(1)).max(1);
    (0..count).step_by(stride).collect()
}

/// The laid-out picture: axis ranges with equal scales and the sizes in pixels.
struct Layout {
    u_range: std::ops::Range<f64>,
    v_range: std::ops::Range<f64>,
    plot_height: u32,
}

impl Layout {
    /// Ranges that hold every (u, v) with a margin of `pad` [m] and a 3 % border, padded
    /// on the shorter side so that one metre is as many pixels along both axes.
    fn new(coordinates: &[Vector3<f64>], pad: f64) -> Self {
        let range = |k: usize| {
            let (lo, hi) = coordinates
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), c| {
                    (lo.min(c[k]), hi.max(c[k]))
                });
            (lo - pad, hi + pad)
        };
        let ((u0, u1), (v0, v1)) = (range(0), range(1));
        let border = 0.03 * (u1 - u0).max(v1 - v0).max(f64::MIN_POSITIVE);
        let (mut u0, mut u1, mut v0, mut v1) = (u0 - border, u1 + border, v0 - border, v1 + border);
        let wanted = f64::from(PLOT_WIDTH) * (v1 - v0) / (u1 - u0);
        let plot_height = (wanted.round() as u32).clamp(*PLOT_HEIGHT.start(), *PLOT_HEIGHT.end());
        let metres_per_pixel =
            ((u1 - u0) / f64::from(PLOT_WIDTH)).max((v1 - v0) / f64::from(plot_height));
        let widen = |lo: &mut f64, hi: &mut f64, pixels: u32| {
            let extra = 0.5 * (metres_per_pixel * f64::from(pixels) - (*hi - *lo));
            *lo -= extra;
            *hi += extra;
        };
        widen(&mut u0, &mut u1, PLOT_WIDTH);
        widen(&mut v0, &mut v1, plot_height);
        Layout {
            u_range: u0..u1,
            v_range: v0..v1,
            plot_height,
        }
    }

    fn chart_size(&self) -> (u32, u32) {
        (
            PLOT_WIDTH + 2 * MARGIN + Y_LABEL_AREA,
            self.plot_height + 2 * MARGIN + X_LABEL_AREA,
        )
    }

    /// Size of the whole picture in pixels.
    fn size(&self) -> (u32, u32) {
        let (w, h) = self.chart_size();
        (w + COLOUR_BAR_WIDTH, h + TITLE_HEIGHT)
    }
}

/// Render the arrows of `view` into a staged PNG for `path` (commit it with
/// [`PendingFile::commit`]). Errors, naming the file: a name not ending in .png, no
/// point, slices of different lengths, a point that is not finite, an arrow length that
/// is not positive, and a failure to draw or write.
pub fn stage_glyph_png(path: &Path, view: &GlyphView) -> Result<PendingFile, OutputError> {
    let plot_error = |message: String| OutputError::Plot {
        path: path.to_path_buf(),
        message,
    };
    check_png_path(path)?;
    let n = view.points.len();
    if n == 0 {
        return Err(plot_error("no point to draw".to_string()));
    }
    if view.directions.len() != n || view.colour_values.len() != n {
        return Err(plot_error(format!(
            "{n} points but {} directions and {} colour values",
            view.directions.len(),
            view.colour_values.len()
        )));
    }
    if let Some(p) = view
        .points
        .iter()
        .find(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(plot_error(format!(
            "point ({}, {}, {}) is not finite",
            p.x, p.y, p.z
        )));
    }
    if !(view.arrow_length > 0.0 && view.arrow_length.is_finite()) {
        return Err(plot_error(format!(
            "arrow length {} m must be positive",
            view.arrow_length
        )));
    }
    ensure_font().map_err(plot_error)?;
    PendingFile::stage(path, |temp| render(temp, view).map_err(plot_error))
}

/// One arrow in the plane of the picture.
struct Arrow {
    tail: Vector2<f64>,
    tip: Vector2<f64>,
    colour: RGBColor,
    depth: f64,
}

fn render(file: &Path, view: &GlyphView) -> Result<(), String> {
    let frame = PrincipalAxes::of(view.points).ok_or("no point to draw")?;
    let selected = subsample(view.points.len(), view.max_glyphs);
    let (c_lo, c_hi) = view
        .colour_values
        .iter()
        .copied()
        .filter(|c| c.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), c| {
            (lo.min(c), hi.max(c))
        });
    let (c_lo, c_hi) = if c_lo < c_hi {
        (c_lo, c_hi)
    } else if c_lo.is_finite() {
        (c_lo - 0.5, c_lo + 0.5)
    } else {
        (0.0, 1.0)
    };

    let half = 0.5 * view.arrow_length;
    let mut arrows: Vec<Arrow> = selected
        .iter()
        .map(|&i| {
            let at = frame.coordinates(view.points[i]);
            let d = view.directions[i];
            let along = Vector2::new(d.dot(&frame.axes[0]), d.dot(&frame.axes[1])) * half;
            let centre = Vector2::new(at.x, at.y);
            Arrow {
                tail: centre - along,
                tip: centre + along,
                colour: viridis((view.colour_values[i] - c_lo) / (c_hi - c_lo)),
                depth: at.z,
            }
        })
        .collect();
    // Farther (smaller third coordinate) first, so nearer arrows are drawn over them.
    arrows.sort_by(|a, b| a.depth.total_cmp(&b.depth));

    let coordinates: Vec<Vector3<f64>> = selected
        .iter()
        .map(|&i| frame.coordinates(view.points[i]))
        .collect();
    let layout = Layout::new(&coordinates, half);
    let root = BitMapBackend::new(file, layout.size()).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (strip, body) = root.split_vertically(TITLE_HEIGHT);
    let third = rounded_axis(&frame.axes[2]);
    let note = format!(
        "{} of {} arrows, each {} m long in 3-D, projected onto the plane of the points' two \
         principal axes (PCA), seen from axis 3 = ({:.2}, {:.2}, {:.2})",
        selected.len(),
        view.points.len(),
        tick_label(view.arrow_length, view.arrow_length),
        third.x,
        third.y,
        third.z
    );
    strip
        .titled(&view.title, (FONT_FAMILY, 24))
        .and_then(|rest| rest.titled(&note, (FONT_FAMILY, 15)))
        .map_err(|e| e.to_string())?;
    let (chart_area, bar_area) = body.split_horizontally(layout.chart_size().0);
    draw_arrows(&chart_area, &layout, &frame, &arrows, selected.len())
        .map_err(|e| format!("arrows: {e}"))?;
    let bar = ColourBar {
        label: view.colour_label.clone(),
        range: c_lo..c_hi,
        above: None,
        below: None,
    };
    draw_colour_bar(&bar_area, &bar).map_err(|e| format!("colour bar: {e}"))?;
    root.present().map_err(|e| e.to_string())
}

/// An axis rounded to two decimals, so that a tiny negative component prints as 0.00,
/// not -0.00.
fn rounded_axis(axis: &Vector3<f64>) -> Vector3<f64> {
    axis.map(|c| (c * 100.0).round() / 100.0 + 0.0)
}

/// Axis label: "principal axis k = (ax, ay, az), from the centroid [m]".
fn axis_label(k: usize, axis: &Vector3<f64>) -> String {
    let c = rounded_axis(axis);
    format!(
        "principal axis {k} = ({:.2}, {:.2}, {:.2}), from the centroid [m]",
        c.x, c.y, c.z
    )
}

fn draw_arrows<'a>(
    area: &DrawingArea<BitMapBackend<'a>, Shift>,
    layout: &Layout,
    frame: &PrincipalAxes,
    arrows: &[Arrow],
    count: usize,
) -> Result<(), Box<dyn std::error::Error + 'a>> {
    let (u_span, v_span) = (
        layout.u_range.end - layout.u_range.start,
        layout.v_range.end - layout.v_range.start,
    );
    let mut chart = ChartBuilder::on(area)
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(layout.u_range.clone(), layout.v_range.clone())?;
    let (x_desc, y_desc) = (axis_label(1, &frame.axes[0]), axis_label(2, &frame.axes[1]));
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_labels(9)
        .y_labels(9)
        .x_label_formatter(&|x| tick_label(*x, u_span))
        .y_label_formatter(&|y| tick_label(*y, v_span))
        .label_style((FONT_FAMILY, 14))
        .axis_desc_style((FONT_FAMILY, 16))
        .light_line_style(RGBColor(245, 245, 245))
        .bold_line_style(RGBColor(225, 225, 225))
        .draw()?;
    let width = if count > 1000 { 1 } else { 2 };
    let (sin, cos) = HEAD_ANGLE.sin_cos();
    for arrow in arrows {
        let back = (arrow.tail - arrow.tip) * HEAD_FRACTION;
        let left = Vector2::new(cos * back.x - sin * back.y, sin * back.x + cos * back.y);
        let right = Vector2::new(cos * back.x + sin * back.y, -sin * back.x + cos * back.y);
        let point = |v: Vector2<f64>| (v.x, v.y);
        let style = arrow.colour.stroke_width(width);
        chart.draw_series([
            PathElement::new(vec![point(arrow.tail), point(arrow.tip)], style),
            PathElement::new(
                vec![
                    point(arrow.tip + left),
                    point(arrow.tip),
                    point(arrow.tip + right),
                ],
                style,
            ),
        ])?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atomic::tests::test_dir;

    /// Points on a flat, tilted grid: 4 m along a, 2 m along b, 0.1 m along a × b.
    fn tilted_slab() -> (Vec<Vector3<f64>>, [Vector3<f64>; 3]) {
        let a = Vector3::new(1.0, 1.0, 0.0).normalize();
        let b = Vector3::new(-1.0, 1.0, 1.0).normalize();
        let c = a.cross(&b);
        let centre = Vector3::new(5.0, -3.0, 2.0);
        let mut points = Vec::new();
        for i in 0..=40 {
            for j in 0..=20 {
                for k in 0..=1 {
                    let (s, t, w) = (0.1 * i as f64 - 2.0, 0.1 * j as f64 - 1.0, 0.1 * k as f64);
                    points.push(centre + s * a + t * b + (w - 0.05) * c);
                }
            }
        }
        (points, [a, b, c])
    }

    #[test]
    fn principal_axes_follow_the_extent() {
        let (points, [a, b, c]) = tilted_slab();
        let frame = PrincipalAxes::of(&points).unwrap();
        assert!((frame.centroid - Vector3::new(5.0, -3.0, 2.0)).norm() < 1e-12);
        // Up to sign, the first axis is a, the second b; the frame is right-handed.
        assert!(
            (frame.axes[0].dot(&a).abs() - 1.0).abs() < 1e-12,
            "{}",
            frame.axes[0]
        );
        assert!(
            (frame.axes[1].dot(&b).abs() - 1.0).abs() < 1e-12,
            "{}",
            frame.axes[1]
        );
        assert!(
            (frame.axes[2].dot(&c).abs() - 1.0).abs() < 1e-12,
            "{}",
            frame.axes[2]
        );
        assert!(frame.variances[0] > frame.variances[1] && frame.variances[1] > frame.variances[2]);
        // Grid of 41 values from −2 to 2: variance (n² − 1)/12 · h², n = 41, h = 0.1.
        assert!((frame.variances[0] - (41.0f64.powi(2) - 1.0) / 12.0 * 0.01).abs() < 1e-12);
        let local = frame.coordinates(points[0]);
        assert!((local.norm() - (points[0] - frame.centroid).norm()).abs() < 1e-12);
        assert!(PrincipalAxes::of(&[]).is_none());
        let one = PrincipalAxes::of(&[Vector3::new(1.0, 2.0, 3.0)]).unwrap();
        assert_eq!(one.variances, [0.0; 3]);
    }

    #[test]
    fn subsampling_is_a_fixed_stride_within_the_limit() {
        assert_eq!(subsample(5, 3000), vec![0, 1, 2, 3, 4]);
        assert_eq!(subsample(10, 4), vec![0, 3, 6, 9]);
        for count in [2999, 3000, 3001, 6001, 1_000_000] {
            let picked = subsample(count, 3000);
            assert!(picked.len() <= 3000 && picked.len() >= 1500, "{count}");
            assert_eq!(picked, subsample(count, 3000));
        }
    }

    #[test]
    fn writes_a_png_with_equal_scales_and_refuses_bad_input() {
        let dir = test_dir("plot-glyphs");
        let (points, [a, _, _]) = tilted_slab();
        let directions = vec![a; points.len()];
        let colour: Vec<f64> = points.iter().map(|p| p.x).collect();
        let view = GlyphView {
            title: "A tilted slab".to_string(),
            points: &points,
            directions: &directions,
            colour_values: &colour,
            colour_label: "x [m]".to_string(),
            arrow_length: 0.06,
            max_glyphs: 500,
        };
        let path = dir.join("glyphs.png");
        stage_glyph_png(&path, &view).unwrap().commit().unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        let width = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
        let height = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
        // 4 m by 2 m, widened by an arrow length (0.06 m) and a 3 % border of the larger
        // span on each side: the plot's height over its width is the ratio of the spans.
        let border = 2.0 * 0.03 * 4.06;
        let expected = f64::from(PLOT_WIDTH) * (2.06 + border) / (4.06 + border);
        let plot_height = height - TITLE_HEIGHT - 2 * MARGIN - X_LABEL_AREA;
        assert_eq!(
            width,
            PLOT_WIDTH + 2 * MARGIN + Y_LABEL_AREA + COLOUR_BAR_WIDTH
        );
        assert!(
            (f64::from(plot_height) - expected).abs() < 1.0,
            "{plot_height} vs {expected}"
        );

        let short = GlyphView {
            directions: &directions[1..],
            ..view.clone()
        };
        let err = stage_glyph_png(&dir.join("short.png"), &short).unwrap_err();
        assert!(err.to_string().contains("short.png"), "{err}");
        let zero = GlyphView {
            arrow_length: 0.0,
            ..view.clone()
        };
        assert!(stage_glyph_png(&dir.join("zero.png"), &zero).is_err());
        assert!(stage_glyph_png(&dir.join("glyphs.jpg"), &view).is_err());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
    }
}
