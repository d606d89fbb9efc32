//! Grouped bar charts: panels in a grid, each with named categories along x (e.g. joint
//! angles) and, within every category, one bar per series side by side (e.g. "passive"
//! and "active"), each series in its palette colour, with a legend.
//!
//! Category `i` spans x ∈ [i, i + 1]; its bars fill the middle [`GROUP_WIDTH`] of that
//! span and the category name is the tick label at its centre. The y axis runs from 0 to
//! 1.1 × the largest value of the panel (or of the whole chart with
//! [`BarChart::shared_y`]). A value that is not finite draws no bar.

use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint};
use plotters::prelude::*;

use super::{FONT_FAMILY, LegendPosition, PALETTE, check_png_path, ensure_font, tick_label};
use crate::OutputError;
use crate::atomic::PendingFile;

/// Fraction of a category's width taken by its group of bars.
const GROUP_WIDTH: f64 = 0.8;
/// Fraction of a bar's slot that is filled (the rest separates neighbouring bars).
const BAR_FILL: f64 = 0.9;
/// Head room above the largest value: the y axis ends at this multiple of it.
const HEAD_ROOM: f64 = 1.1;

/// One named set of bars: one value per category of its panel.
#[derive(Debug, Clone, PartialEq)]
pub struct BarSeries {
    /// Legend entry, e.g. "passive" ("" for none).
    pub label: String,
    /// One value per category; a value that is not finite (e.g. NaN) draws no bar.
    /// Finite values must not be negative.
    pub values: Vec<f64>,
}

impl BarSeries {
    pub fn new(label: impl Into<String>, values: impl IntoIterator<Item = f64>) -> Self {
        BarSeries {
            label: label.into(),
            values: values.into_iter().collect(),
        }
    }
}

/// One bar chart: categories along x, one bar per series in each category.
#[derive(Debug, Clone, PartialEq)]
pub struct BarPanel {
    pub title: String,
    /// x-axis label, e.g. "knee angle" ("" for none).
    pub x_label: String,
    /// y-axis label with its unit, e.g. "peak stress [kPa]".
    pub y_label: String,
    /// Names of the groups along x, e.g. "30°", "45°", "60°", "90°".
    pub categories: Vec<String>,
    pub series: Vec<BarSeries>,
    pub legend: LegendPosition,
}

impl BarPanel {
    pub fn new(
        title: impl Into<String>,
        y_label: impl Into<String>,
        categories: impl IntoIterator<Item = impl Into<String>>,
    ) -> Self {
        BarPanel {
            title: title.into(),
            x_label: String::new(),
            y_label: y_label.into(),
            categories: categories.into_iter().map(Into::into).collect(),
            series: Vec::new(),
            legend: LegendPosition::default(),
        }
    }

    pub fn with_x_label(mut self, x_label: impl Into<String>) -> Self {
        self.x_label = x_label.into();
        self
    }

    pub fn with_series(mut self, series: BarSeries) -> Self {
        self.series.push(series);
        self
    }

    pub fn with_legend(mut self, legend: LegendPosition) -> Self {
        self.legend = legend;
        self
    }

    /// Largest finite value over all series (`None` without any).
    fn max_value(&self) -> Option<f64> {
        self.series
            .iter()
            .flat_map(|s| s.values.iter().copied())
            .filter(|v| v.is_finite())
            .reduce(f64::max)
    }
}

/// A picture of bar panels in a grid under an optional title.
#[derive(Debug, Clone, PartialEq)]
pub struct BarChart {
    /// Title above all panels ("" for none).
    pub title: String,
    pub panels: Vec<BarPanel>,
    /// Panels per row (clamped to 1..=number of panels).
    pub columns: usize,
    /// One y range for all panels (up to 1.1 × the largest value of the chart) instead of
    /// one per panel.
    pub shared_y: bool,
    /// Size of one panel in pixels (width, height).
    pub panel_size: (u32, u32),
}

impl BarChart {
    /// An empty chart: two columns, a y range per panel, 640 × 480 px panels.
    pub fn new(title: impl Into<String>) -> Self {
        BarChart {
            title: title.into(),
            panels: Vec::new(),
            columns: 2,
            shared_y: false,
            panel_size: (640, 480),
        }
    }

    pub fn with_panel(mut self, panel: BarPanel) -> Self {
        self.panels.push(panel);
        self
    }

    pub fn with_columns(mut self, columns: usize) -> Self {
        self.columns = columns;
        self
    }

    pub fn with_shared_y(mut self, shared_y: bool) -> Self {
        self.shared_y = shared_y;
        self
    }

    /// (rows, columns) of the panel grid.
    fn grid(&self) -> (usize, usize) {
        let n = self.panels.len().max(1);
        let columns = self.columns.clamp(1, n);
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

    /// Top of each panel's y axis: 1.1 × its largest value (or the chart's with
    /// `shared_y`); 1 for a panel without a positive value.
    fn y_tops(&self) -> Vec<f64> {
        let top = |max: Option<f64>| match max {
            Some(m) if m > 0.0 => HEAD_ROOM * m,
            _ => 1.0,
        };
        let chart_max = self
            .panels
            .iter()
            .filter_map(BarPanel::max_value)
            .reduce(f64::max);
        self.panels
            .iter()
            .map(|p| {
                top(if self.shared_y {
                    chart_max
                } else {
                    p.max_value()
                })
            })
            .collect()
    }

    /// Errors unless the chart can be drawn: a panel, as many values as categories in every
    /// series, no negative value and at least one finite value.
    fn check(&self) -> Result<(), String> {
        if self.panels.is_empty() {
            return Err("the bar chart has no panel".to_string());
        }
        for panel in &self.panels {
            if panel.categories.is_empty() {
                return Err(format!("panel '{}' has no category", panel.title));
            }
            for series in &panel.series {
                if series.values.len() != panel.categories.len() {
                    return Err(format!(
                        "panel '{}': series '{}' has {} values for {} categories",
                        panel.title,
                        series.label,
                        series.values.len(),
                        panel.categories.len()
                    ));
                }
                if let Some(v) = series.values.iter().find(|v| **v < 0.0) {
                    return Err(format!(
                        "panel '{}': series '{}' has the negative value {v} (bars start at 0)",
                        panel.title, series.label
                    ));
                }
            }
        }
        if self.panels.iter().all(|p| p.max_value().is_none()) {
            return Err("the bar chart has no finite value".to_string());
        }
        Ok(())
    }
}

/// Render `chart` into a staged PNG for `path` (commit it with [`PendingFile::commit`]).
/// Errors, naming the file: a name not ending in .png, no panel, a panel without
/// categories, a series with a value count other than its panel's category count, a
/// negative value, no finite value at all, a picture size outside 1..16384 px, and a
/// failure to draw or write.
pub fn stage_bar_png(path: &Path, chart: &BarChart) -> Result<PendingFile, OutputError> {
    let plot_error = |message: String| OutputError::Plot {
        path: path.to_path_buf(),
        message,
    };
    check_png_path(path)?;
    chart.check().map_err(plot_error)?;
    let (width, height) = chart.size();
    if width == 0 || height == 0 || width > 16_384 || height > 16_384 {
        return Err(plot_error(format!(
            "picture size {width}x{height} px is outside 1..16384"
        )));
    }
    ensure_font().map_err(plot_error)?;
    PendingFile::stage(path, |temp| {
        let root = BitMapBackend::new(temp, chart.size()).into_drawing_area();
        render(root, chart).map_err(plot_error)
    })
}

/// Draw `chart` on `root` (the whole picture) and present it.
fn render<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    chart: &BarChart,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let body = if chart.title.is_empty() {
        root.clone()
    } else {
        let (top, rest) = root.split_vertically(chart.title_height());
        top.titled(&chart.title, (FONT_FAMILY, 26))
            .map_err(|e| e.to_string())?;
        rest
    };
    let areas = body.split_evenly(chart.grid());
    for ((panel, area), y_top) in chart.panels.iter().zip(&areas).zip(chart.y_tops()) {
        draw_panel(area, panel, y_top).map_err(|e| format!("panel '{}': {e}", panel.title))?;
    }
    root.present().map_err(|e| e.to_string())
}

/// The x axis of a bar panel with `n` categories: x ∈ [0, n], ticks at the category
/// centres i + 0.5 (labelled with the category names by the mesh's formatter).
struct CategoryAxis(usize);

impl Ranged for CategoryAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let fraction = value / self.0.max(1) as f64;
        limit.0 + (fraction * f64::from(limit.1 - limit.0)).round() as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            (0..self.0).map(|c| c as f64 + 0.5).collect()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        0.0..self.0 as f64
    }
}

/// x extent of the bar of series `s` (of `n`) in category `c`.
fn bar_span(c: usize, s: usize, n: usize) -> (f64, f64) {
    let slot = GROUP_WIDTH / n as f64;
    let left = c as f64 + 0.5 * (1.0 - GROUP_WIDTH) + s as f64 * slot;
    let gap = 0.5 * (1.0 - BAR_FILL) * slot;
    (left + gap, left + slot - gap)
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &BarPanel,
    y_top: f64,
) -> Result<(), String> {
    let n_categories = panel.categories.len();
    let x_range = CategoryAxis(n_categories);
    let category_of = |x: &f64| {
        let c = x.floor();
        if c >= 0.0 && (c as usize) < n_categories {
            panel.categories[c as usize].clone()
        } else {
            String::new()
        }
    };

    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, (FONT_FAMILY, 21))
        .margin(12)
        .x_label_area_size(if panel.x_label.is_empty() { 36 } else { 52 })
        .y_label_area_size(76)
        .build_cartesian_2d(x_range, 0.0..y_top)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .y_labels(7)
        .x_label_formatter(&category_of)
        .y_label_formatter(&|y| tick_label(*y, y_top))
        .label_style((FONT_FAMILY, 15))
        .axis_desc_style((FONT_FAMILY, 17))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(|e| e.to_string())?;

    let n_series = panel.series.len();
    for (s, series) in panel.series.iter().enumerate() {
        let color = PALETTE[s % PALETTE.len()];
        let bars = series
            .values
            .iter()
            .enumerate()
            .filter(|(_, v)| v.is_finite())
            .map(move |(c, &v)| {
                let (x0, x1) = bar_span(c, s, n_series);
                Rectangle::new([(x0, 0.0), (x1, v)], color.filled())
            });
        let drawn = chart.draw_series(bars).map_err(|e| e.to_string())?;
        if !series.label.is_empty() {
            drawn.label(series.label.as_str()).legend(move |(x, y)| {
                Rectangle::new([(x, y - 6), (x + 16, y + 6)], color.filled())
            });
        }
    }

    if panel.series.iter().any(|s| !s.label.is_empty()) {
        super::draw_legend(&mut chart, panel.legend).map_err(|e| e.to_string())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests;
