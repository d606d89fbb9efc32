//! PNG charts: one or more panels (side by side, or in a grid), each with any number of
//! named line series, a title, axis labels with units and a legend; grouped bar charts
//! ([`bars`]); pictures of direction fields in 3-D as arrows ([`glyphs`]); and pictures
//! of a deformed solid coloured by a value per cell ([`mesh_picture`], with the feature
//! `results`). Pictures coloured by a scalar share the colour map and bar of
//! [`colour_bar`].
//!
//! Text is drawn with DejaVu Sans, bundled in the crate (`assets/DejaVuSans.ttf`, licence
//! in `assets/DejaVuSans-LICENSE.txt`) and registered with plotters' `ab_glyph` backend
//! under the family name [`FONT_FAMILY`], so no system font or fontconfig is needed.
//! Charts are written through a temporary file and a rename, like every output.

use std::path::Path;
use std::sync::OnceLock;

use musclefem_materials::driver::UniaxialRow;
use plotters::coord::{CoordTranslate, Shift};
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use crate::OutputError;
use crate::atomic::PendingFile;

pub mod bars;
pub mod colour_bar;
pub mod glyphs;
#[cfg(feature = "results")]
pub mod mesh_picture;

pub use bars::{BarChart, BarPanel, BarSeries, stage_bar_png};
pub use colour_bar::{ColourBar, viridis};
pub use glyphs::{GlyphView, PrincipalAxes, stage_glyph_png};

/// Font family under which the bundled font is registered (plotters' default family, so
/// text styles that name no family use it too).
pub const FONT_FAMILY: &str = "sans-serif";

static FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Register the bundled font with plotters (once per process).
fn ensure_font() -> Result<(), String> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            register_font(FONT_FAMILY, FontStyle::Normal, FONT_BYTES)
                .map_err(|_| "the bundled font DejaVuSans.ttf could not be parsed".to_string())
        })
        .clone()
}

/// Line colours: the Okabe–Ito palette (distinguishable with colour-vision deficiency).
const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

/// One named curve: (x, y) points joined by straight lines (and/or marked, see
/// [`SeriesStyle`]). Non-finite points are skipped, and so are non-positive ones on a
/// logarithmic axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend entry ("" for none).
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: SeriesStyle,
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SeriesStyle {
    /// Straight lines between the points.
    #[default]
    Line,
    /// Lines, with a filled circle on every point.
    LineWithMarkers,
    /// Only an open black square around every point, whatever the series' colour (to mark
    /// a subset of the other series, e.g. a Pareto front).
    Markers,
    /// Only a filled dot in the series' colour on every point (measured data).
    Dots,
}

impl Series {
    pub fn new(label: impl Into<String>, points: impl IntoIterator<Item = (f64, f64)>) -> Self {
        Series {
            label: label.into(),
            points: points.into_iter().collect(),
            style: SeriesStyle::Line,
        }
    }

    pub fn with_style(mut self, style: SeriesStyle) -> Self {
        self.style = style;
        self
    }
}

/// The axes' scales.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Axes {
    /// Both axes linear.
    #[default]
    Linear,
    /// Both axes logarithmic (decades), e.g. for error against cost.
    LogLog,
}

/// Where a panel's legend goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LegendPosition {
    #[default]
    UpperLeft,
    UpperRight,
    LowerLeft,
    LowerRight,
    /// No legend.
    Hidden,
}

/// One chart: axes, series and legend.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    pub title: String,
    /// x-axis label with its unit, e.g. "time [s]".
    pub x_label: String,
    /// y-axis label with its unit, e.g. "engineering stress [kPa]".
    pub y_label: String,
    pub series: Vec<Series>,
    pub legend: LegendPosition,
    pub axes: Axes,
}

impl Panel {
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Panel {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            legend: LegendPosition::default(),
            axes: Axes::default(),
        }
    }

    pub fn with_axes(mut self, axes: Axes) -> Self {
        self.axes = axes;
        self
    }

    pub fn with_series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    pub fn with_legend(mut self, legend: LegendPosition) -> Self {
        self.legend = legend;
        self
    }
}

/// A picture of one or more panels under an optional title.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Title above all panels ("" for none).
    pub title: String,
    pub panels: Vec<Panel>,
    /// Panels per row; `None` puts all panels in one row.
    pub columns: Option<usize>,
    /// Size of one panel in pixels (width, height).
    pub panel_size: (u32, u32),
}

impl Figure {
    pub fn new(title: impl Into<String>) -> Self {
        Figure {
            title: title.into(),
            panels: Vec::new(),
            columns: None,
            panel_size: (640, 480),
        }
    }

    pub fn with_panel(mut self, panel: Panel) -> Self {
        self.panels.push(panel);
        self
    }

    /// (rows, columns) of the panel grid.
    fn grid(&self) -> (usize, usize) {
        let n = self.panels.len().max(1);
        let columns = self.columns.unwrap_or(n).clamp(1, n);
        (n.div_ceil(columns), columns)
    }

    /// Height of the title strip in pixels.
    fn title_height(&self) -> u32 {
        if self.title.is_empty() { 0 } else { 44 }
    }

    /// Size of the whole picture in pixels.
    pub fn size(&self) -> (u32, u32) {
        let (rows, columns) = self.grid();
        (
            self.panel_size.0 * columns as u32,
            self.panel_size.1 * rows as u32 + self.title_height(),
        )
    }
}

/// The material-point driver's standard chart of one or more runs: engineering stress
/// [kPa] against stretch (left) and against time (right).
pub fn uniaxial_figure(title: &str, runs: &[(&str, &[UniaxialRow])]) -> Figure {
    let stress_kpa = "engineering stress P₁₁ [kPa]";
    let mut against_stretch = Panel::new("Stress–stretch", "fiber stretch λ [1]", stress_kpa);
    let mut against_time = Panel::new("Stress history", "time [s]", stress_kpa);
    for (label, rows) in runs {
        against_stretch.series.push(Series::new(
            *label,
            rows.iter().map(|r| (r.stretch, r.engineering_stress / 1e3)),
        ));
        against_time.series.push(Series::new(
            *label,
            rows.iter().map(|r| (r.time, r.engineering_stress / 1e3)),
        ));
    }
    Figure::new(title)
        .with_panel(against_stretch)
        .with_panel(against_time)
}

/// Render `figure` into a staged PNG for `path` (commit it with [`PendingFile::commit`]).
pub fn stage_png(path: &Path, figure: &Figure) -> Result<PendingFile, OutputError> {
    let plot_error = |message: String| OutputError::Plot {
        path: path.to_path_buf(),
        message,
    };
    check_png_path(path)?;
    if figure.panels.is_empty() {
        return Err(plot_error("the figure has no panel".to_string()));
    }
    let (width, height) = figure.size();
    if width == 0 || height == 0 || width > 16_384 || height > 16_384 {
        return Err(plot_error(format!(
            "picture size {width}x{height} px is outside 1..16384"
        )));
    }
    ensure_font().map_err(plot_error)?;
    PendingFile::stage(path, |temp| render(temp, figure).map_err(plot_error))
}

/// Errors unless the file name of `path` ends in .png (any letter case).
fn check_png_path(path: &Path) -> Result<(), OutputError> {
    let is_png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if is_png {
        Ok(())
    } else {
        Err(OutputError::Plot {
            path: path.to_path_buf(),
            message: "the file name must end in .png".to_string(),
        })
    }
}

/// Write `figure` as a PNG to `path` atomically.
pub fn write_png(path: &Path, figure: &Figure) -> Result<(), OutputError> {
    stage_png(path, figure)?.commit()
}

/// Draw `figure` into the PNG file `file`.
fn render(file: &Path, figure: &Figure) -> Result<(), String> {
    let root = BitMapBackend::new(file, figure.size()).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let body = if figure.title.is_empty() {
        root.clone()
    } else {
        let (top, rest) = root.split_vertically(figure.title_height());
        top.titled(&figure.title, (FONT_FAMILY, 26))
            .map_err(|e| e.to_string())?;
        rest
    };
    let areas = body.split_evenly(figure.grid());
    for (panel, area) in figure.panels.iter().zip(&areas) {
        draw_panel(area, panel).map_err(|e| format!("panel '{}': {e}", panel.title))?;
    }
    root.present().map_err(|e| e.to_string())
}

/// Axis range covering `values` with a 4 % margin (a unit-wide range when empty).
fn axis_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return 0.0..1.0;
    }
    let span = hi - lo;
    let margin = if span > 0.0 {
        0.04 * span
    } else if lo != 0.0 {
        0.05 * lo.abs()
    } else {
        1.0
    };
    (lo - margin)..(hi + margin)
}

/// Tick label: as few digits as tell neighbouring ticks apart.
fn tick_label(value: f64, span: f64) -> String {
    if value == 0.0 || span <= 0.0 {
        return "0".to_string();
    }
    let magnitude = value.abs().max(span);
    if !(1e-3..1e6).contains(&magnitude) {
        return format!("{value:.2e}");
    }
    let decimals = (2.0 - span.log10().floor()).clamp(0.0, 8.0) as usize;
    let text = format!("{value:.decimals$}");
    if text.contains('.') {
        let trimmed = text.trim_end_matches('0').trim_end_matches('.');
        if trimmed == "-0" {
            "0".to_string()
        } else {
            trimmed.to_string()
        }
    } else {
        text
    }
}

fn draw_panel<'a>(
    area: &DrawingArea<BitMapBackend<'a>, Shift>,
    panel: &Panel,
) -> Result<(), Box<dyn std::error::Error + 'a>> {
    match panel.axes {
        Axes::Linear => draw_linear_panel(area, panel),
        Axes::LogLog => draw_log_log_panel(area, panel),
    }
}

fn draw_linear_panel<'a>(
    area: &DrawingArea<BitMapBackend<'a>, Shift>,
    panel: &Panel,
) -> Result<(), Box<dyn std::error::Error + 'a>> {
    let points = || panel.series.iter().flat_map(|s| s.points.iter());
    let x_range = axis_range(points().map(|p| p.0));
    let y_range = axis_range(points().map(|p| p.1));
    let (x_span, y_span) = (x_range.end - x_range.start, y_range.end - y_range.start);

    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, (FONT_FAMILY, 21))
        .margin(12)
        .x_label_area_size(52)
        .y_label_area_size(76)
        .build_cartesian_2d(x_range, y_range)?;
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .x_labels(7)
        .y_labels(7)
        .x_label_formatter(&|x| tick_label(*x, x_span))
        .y_label_formatter(&|y| tick_label(*y, y_span))
        .label_style((FONT_FAMILY, 15))
        .axis_desc_style((FONT_FAMILY, 17))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()?;
    draw_series(&mut chart, panel, |_| true)
}

/// Logarithmic range covering the positive `values` with a margin of a tenth of a decade
/// each side, widened to at least a decade (one decade around 1 when there are none).
fn log_axis_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return 0.1..10.0;
    }
    let margin = 10f64.powf(0.1);
    let (lo, hi) = (lo / margin, hi * margin);
    // At least a decade, so that a power of ten (a labelled tick) is on the axis.
    if hi / lo >= 10.0 {
        return lo..hi;
    }
    let centre = (lo * hi).sqrt();
    (centre / 10f64.sqrt())..(centre * 10f64.sqrt())
}

fn draw_log_log_panel<'a>(
    area: &DrawingArea<BitMapBackend<'a>, Shift>,
    panel: &Panel,
) -> Result<(), Box<dyn std::error::Error + 'a>> {
    let points = || panel.series.iter().flat_map(|s| s.points.iter());
    let x_range = log_axis_range(points().map(|p| p.0));
    let y_range = log_axis_range(points().map(|p| p.1));
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, (FONT_FAMILY, 21))
        .margin(12)
        .x_label_area_size(52)
        .y_label_area_size(76)
        .build_cartesian_2d(x_range.log_scale(), y_range.log_scale())?;
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .x_label_formatter(&|x| log_tick_label(*x))
        .y_label_formatter(&|y| log_tick_label(*y))
        .label_style((FONT_FAMILY, 15))
        .axis_desc_style((FONT_FAMILY, 17))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()?;
    draw_series(&mut chart, panel, |&(x, y)| x > 0.0 && y > 0.0)
}

/// Tick label on a logarithmic axis: plain for 0.01–10⁴, else in e-notation.
fn log_tick_label(value: f64) -> String {
    if (1e-2..1e4).contains(&value.abs()) {
        let text = format!("{value:.3}");
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{value:.0e}")
    }
}

/// Draw `panel`'s series (the points `drawable` accepts, finite ones only) and legend.
fn draw_series<'a, DB: DrawingBackend + 'a, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    panel: &Panel,
    drawable: impl Fn(&(f64, f64)) -> bool,
) -> Result<(), Box<dyn std::error::Error + 'a>>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
    DB::ErrorType: 'a,
{
    for (i, series) in panel.series.iter().enumerate() {
        let color = match series.style {
            SeriesStyle::Markers => BLACK,
            _ => PALETTE[i % PALETTE.len()],
        };
        let finite: Vec<(f64, f64)> = series
            .points
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite() && drawable(p))
            .collect();
        let drawn = match series.style {
            SeriesStyle::Line => {
                chart.draw_series(LineSeries::new(finite, color.stroke_width(2)))?
            }
            SeriesStyle::LineWithMarkers => {
                chart.draw_series(LineSeries::new(finite.clone(), color.stroke_width(2)))?;
                chart.draw_series(
                    finite
                        .into_iter()
                        .map(move |p| Circle::new(p, 4, color.filled())),
                )?
            }
            SeriesStyle::Markers => chart.draw_series(finite.into_iter().map(move |p| {
                EmptyElement::at(p) + Rectangle::new([(-9, -9), (9, 9)], color.stroke_width(2))
            }))?,
            SeriesStyle::Dots => chart.draw_series(
                finite
                    .into_iter()
                    .map(move |p| Circle::new(p, 3, color.filled())),
            )?,
        };
        if series.label.is_empty() {
            continue;
        }
        let drawn = drawn.label(series.label.as_str());
        match series.style {
            SeriesStyle::Line => drawn.legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(3))
            }),
            SeriesStyle::LineWithMarkers => drawn.legend(move |(x, y)| {
                EmptyElement::at((x + 12, y))
                    + PathElement::new(vec![(-12, 0), (12, 0)], color.stroke_width(3))
                    + Circle::new((0, 0), 4, color.filled())
            }),
            SeriesStyle::Markers => drawn.legend(move |(x, y)| {
                EmptyElement::at((x + 12, y))
                    + Rectangle::new([(-7, -7), (7, 7)], color.stroke_width(2))
            }),
            SeriesStyle::Dots => {
                drawn.legend(move |(x, y)| Circle::new((x + 12, y), 4, color.filled()))
            }
        };
    }

    if panel.series.iter().any(|s| !s.label.is_empty()) {
        draw_legend(chart, panel.legend)?;
    }
    Ok(())
}

/// Draw the legend of `chart`'s labelled series at `legend` (nothing if hidden).
pub(crate) fn draw_legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    legend: LegendPosition,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let position = match legend {
        LegendPosition::UpperLeft => SeriesLabelPosition::UpperLeft,
        LegendPosition::UpperRight => SeriesLabelPosition::UpperRight,
        LegendPosition::LowerLeft => SeriesLabelPosition::LowerLeft,
        LegendPosition::LowerRight => SeriesLabelPosition::LowerRight,
        LegendPosition::Hidden => return Ok(()),
    };
    chart
        .configure_series_labels()
        .position(position)
        .margin(10)
        .label_font((FONT_FAMILY, 15))
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(160, 160, 160))
        .draw()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atomic::tests::test_dir;

    fn sample_rows(activation: f64) -> Vec<UniaxialRow> {
        (0..=200)
            .map(|i| {
                let time = i as f64 * 0.01;
                let stretch = 1.0 + 0.1 * time;
                let p = 1e4 * (stretch - stretch.powi(-2)) + activation * 1e5 * time.min(0.5);
                UniaxialRow {
                    time,
                    stretch,
                    engineering_stress: p,
                    cauchy_stress: p * stretch,
                    jacobian: 1.0,
                }
            })
            .collect()
    }

    #[test]
    fn writes_a_valid_png() {
        let dir = test_dir("plot-png");
        let path = dir.join("curves.png");
        let passive = sample_rows(0.0);
        let active = sample_rows(1.0);
        let figure = uniaxial_figure(
            "Uniaxial stress along the fiber",
            &[("passive", &passive), ("active, n2 = 1", &active)],
        );
        write_png(&path, &figure).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        assert!(bytes.len() > 10_000, "{} bytes", bytes.len());
        // IHDR: width and height, big-endian, at bytes 16..24.
        let width = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
        let height = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
        assert_eq!((width, height), figure.size());
        assert_eq!((width, height), (1280, 524));
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 1, "{names:?}");
    }

    #[test]
    fn grid_and_degenerate_data() {
        let dir = test_dir("plot-grid");
        let path = dir.join("grid.png");
        let mut figure = Figure::new("");
        for i in 0..3 {
            figure = figure.with_panel(
                Panel::new(format!("panel {i}"), "x [m]", "y [Pa]")
                    .with_series(Series::new("", [(1.0, 2.0), (f64::NAN, 3.0)]))
                    .with_series(
                        Series::new("dots", [(1.0, 2.5), (2.0, 3.0)]).with_style(SeriesStyle::Dots),
                    )
                    .with_legend(LegendPosition::LowerRight),
            );
        }
        figure.columns = Some(2);
        figure.panel_size = (320, 240);
        assert_eq!(figure.size(), (640, 480));
        write_png(&path, &figure).unwrap();
        assert!(std::fs::metadata(&path).unwrap().len() > 2_000);
    }

    #[test]
    fn bad_figures_are_errors_naming_the_file() {
        let dir = test_dir("plot-bad");
        let err = write_png(&dir.join("empty.png"), &Figure::new("t")).unwrap_err();
        assert!(err.to_string().contains("empty.png"), "{err}");
        let one = Figure::new("").with_panel(Panel::new("p", "x", "y"));
        let err = write_png(&dir.join("chart.jpg"), &one).unwrap_err();
        assert!(err.to_string().contains(".png"), "{err}");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    }

    #[test]
    fn log_log_panels_with_markers_skip_non_positive_points() {
        let dir = test_dir("plot-log-log");
        let path = dir.join("work.png");
        let panel = Panel::new("cube", "wall time [s]", "error [1]")
            .with_axes(Axes::LogLog)
            .with_series(
                Series::new("implicit", [(0.01, 0.5), (0.1, 0.05), (1.0, 0.0)])
                    .with_style(SeriesStyle::LineWithMarkers),
            )
            .with_series(Series::new("front", [(0.01, 0.5)]).with_style(SeriesStyle::Markers));
        write_png(&path, &Figure::new("").with_panel(panel)).unwrap();
        assert!(std::fs::metadata(&path).unwrap().len() > 2_000);
        assert_eq!(log_axis_range([0.0, -1.0].into_iter()), 0.1..10.0);
        let narrow = log_axis_range([2.5, 6.6].into_iter());
        assert!((narrow.end / narrow.start - 10.0).abs() < 1e-9 && narrow.contains(&10.0));
        assert_eq!(log_tick_label(0.05), "0.05");
        assert_eq!(log_tick_label(1e-5), "1e-5");
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick_label(1.0 + 0.1 + 1e-15, 0.2), "1.1");
        assert_eq!(tick_label(0.30000000000000004, 2.0), "0.3");
        assert_eq!(tick_label(250.0, 300.0), "250");
        assert_eq!(tick_label(-0.0001, 0.2), "0");
        assert_eq!(tick_label(2.5e-7, 1e-6), "2.50e-7");
    }
}
