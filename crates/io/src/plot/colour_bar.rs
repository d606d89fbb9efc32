//! The colour map of every picture that colours by a scalar, and its colour bar.
//!
//! [`viridis`] maps t ∈ [0, 1] from dark blue through green to yellow: lightness rises
//! monotonically, so the order of the values reads in grey too and with colour-vision
//! deficiency. [`draw_colour_bar`] draws the bar in a strip of a picture, in pixel
//! coordinates that [`ColourBarLayout`] states (so a test can read the bar's pixels):
//! the scalar's name and unit on top, then the notes of values beyond the range, then the
//! bar with ticks on its right.

use std::ops::Range;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{FONT_FAMILY, tick_label};

/// Colour of `t` ∈ [0, 1] on the viridis map (dark blue → green → yellow), interpolated
/// linearly between five of its colours; `t` outside [0, 1] is clamped, NaN is 0.
pub fn viridis(t: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let s = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    } * 4.0;
    let i = (s.floor() as usize).min(3);
    let f = s - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let mix = |p: f64, q: f64| (p + f * (q - p)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// A colour bar: what it shows, over which range, and what lies beyond.
#[derive(Debug, Clone, PartialEq)]
pub struct ColourBar {
    /// The scalar's name and unit, e.g. "von Mises stress [kPa]".
    pub label: String,
    /// The values at the bottom and the top of the bar, in the label's unit.
    pub range: Range<f64>,
    /// A note above the bar for values above the range (drawn in the top colour), e.g.
    /// "≥ 450: 37 cells".
    pub above: Option<String>,
    /// A note above the bar for values below the range (drawn in the bottom colour).
    pub below: Option<String>,
}

/// Where the parts of a colour bar go in a strip of `width` × `height` pixels, relative
/// to the strip's top-left corner.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ColourBarLayout {
    /// Left and right pixel columns of the bar (right exclusive).
    pub bar_x: (i32, i32),
    /// Top and bottom pixel rows of the bar (bottom exclusive): the top row has the
    /// colour of the range's end, the bottom row (`bar_y.1 − 1`) that of its start.
    pub bar_y: (i32, i32),
}

/// Rows from the top of the strip to the label's centre, and the height of a note line.
const LABEL_Y: i32 = 16;
const NOTE_HEIGHT: i32 = 18;
/// Left margin and width of the bar, and the margin below it.
const BAR_LEFT: i32 = 24;
const BAR_WIDTH: i32 = 26;
const BOTTOM_MARGIN: i32 = 30;

impl ColourBarLayout {
    /// The layout in a strip of `width` × `height` pixels, leaving room for `notes` note
    /// lines between the label and the bar.
    pub fn new(height: u32, notes: usize) -> Self {
        let top = LABEL_Y + 18 + NOTE_HEIGHT * notes as i32 + 8;
        let bottom = (height as i32 - BOTTOM_MARGIN).max(top + 2);
        ColourBarLayout {
            bar_x: (BAR_LEFT, BAR_LEFT + BAR_WIDTH),
            bar_y: (top, bottom),
        }
    }

    /// The map's parameter t ∈ [0, 1] at pixel row `y` of the bar (1 on the top row, 0 on
    /// the bottom row).
    pub fn t_at_row(&self, y: i32) -> f64 {
        let (top, bottom) = self.bar_y;
        let last = (bottom - 1 - top).max(1);
        (f64::from(bottom - 1 - y) / f64::from(last)).clamp(0.0, 1.0)
    }
}

/// Ticks for `range`: multiples of 1, 2 or 5 × 10ᵏ, the finest step that gives at most
/// `most` ticks inside the range (its ends included).
pub fn nice_ticks(range: &Range<f64>, most: usize) -> Vec<f64> {
    let (lo, hi) = (range.start, range.end);
    let span = hi - lo;
    if !(span > 0.0 && span.is_finite()) || most < 2 {
        return vec![lo];
    }
    let rough = span / (most - 1) as f64;
    let decade = 10f64.powf(rough.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * decade)
        .find(|&s| ((span / s).floor() as usize) < most)
        .unwrap_or(10.0 * decade);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// Draw `bar` into `area` (a strip of the picture, e.g. to the right of the plot).
pub fn draw_colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    bar: &ColourBar,
) -> Result<(), String> {
    let (width, height) = area.dim_in_pixel();
    let notes: Vec<&String> = [&bar.above, &bar.below].into_iter().flatten().collect();
    let layout = ColourBarLayout::new(height, notes.len());
    let error = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let centred = |size: u32| {
        TextStyle::from((FONT_FAMILY, size).into_font())
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Center))
    };
    area.draw(&Text::new(bar.label.as_str(), (8, LABEL_Y), centred(16)))
        .map_err(error)?;
    for (k, note) in notes.iter().enumerate() {
        let y = LABEL_Y + 18 + NOTE_HEIGHT * k as i32 + NOTE_HEIGHT / 2;
        area.draw(&Text::new(note.as_str(), (8, y), centred(13)))
            .map_err(error)?;
    }
    let ((x0, x1), (top, bottom)) = (layout.bar_x, layout.bar_y);
    for y in top..bottom {
        let colour = viridis(layout.t_at_row(y));
        area.draw(&PathElement::new(vec![(x0, y), (x1 - 1, y)], colour))
            .map_err(error)?;
    }
    let span = bar.range.end - bar.range.start;
    if !(span > 0.0 && span.is_finite()) {
        return Ok(());
    }
    let room = (bottom - top) / 40;
    let label_width = (width as i32 - x1 - 12).max(0);
    for value in nice_ticks(&bar.range, room.clamp(2, 9) as usize) {
        let t = (value - bar.range.start) / span;
        let y = bottom - 1 - (t * f64::from(bottom - 1 - top)).round() as i32;
        area.draw(&PathElement::new(vec![(x1, y), (x1 + 5, y)], BLACK))
            .map_err(error)?;
        if label_width > 0 {
            area.draw(&Text::new(
                tick_label(value, span),
                (x1 + 8, y),
                centred(14),
            ))
            .map_err(error)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_map_runs_from_dark_blue_to_yellow() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(0.5), RGBColor(33, 145, 140));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
        assert_eq!(viridis(7.0), viridis(1.0));
        // Lightness (here the sum of the channels) rises along the map.
        let sum = |c: RGBColor| u32::from(c.0) + u32::from(c.1) + u32::from(c.2);
        let sums: Vec<u32> = (0..=20).map(|k| sum(viridis(k as f64 / 20.0))).collect();
        assert!(sums.windows(2).all(|w| w[0] <= w[1]), "{sums:?}");
    }

    #[test]
    fn ticks_are_round_and_inside_the_range() {
        assert_eq!(
            nice_ticks(&(0.0..500.0), 9),
            vec![0.0, 100.0, 200.0, 300.0, 400.0, 500.0]
        );
        let tenths = nice_ticks(&(0.0..1.0), 6);
        let expected = [0.0, 0.2, 0.4, 0.6, 0.8, 1.0];
        assert_eq!(tenths.len(), expected.len(), "{tenths:?}");
        assert!(
            tenths
                .iter()
                .zip(expected)
                .all(|(a, b)| (a - b).abs() < 1e-12)
        );
        let ticks = nice_ticks(&(0.93..1.27), 8);
        assert!(ticks.len() <= 8 && ticks.len() >= 3, "{ticks:?}");
        assert!(ticks.iter().all(|t| (0.93..=1.27).contains(t)), "{ticks:?}");
        assert_eq!(nice_ticks(&(3.0..3.0), 5), vec![3.0]);
    }

    #[test]
    fn the_bar_runs_from_the_start_colour_at_the_bottom_to_the_end_colour_on_top() {
        let layout = ColourBarLayout::new(600, 1);
        let (top, bottom) = layout.bar_y;
        assert!(bottom - top > 400, "{layout:?}");
        assert_eq!(layout.t_at_row(top), 1.0);
        assert_eq!(layout.t_at_row(bottom - 1), 0.0);
        assert!((layout.t_at_row((top + bottom - 1) / 2) - 0.5).abs() < 0.01);
        // A note moves the bar down.
        assert!(ColourBarLayout::new(600, 2).bar_y.0 > top);
    }
}
