//! Filling triangles into a pixel image with a depth buffer.
//!
//! Each pixel keeps the nearest triangle drawn over it (the largest height towards the
//! viewer, interpolated linearly across the triangle, which is exact for an orthographic
//! projection), so the order in which triangles come does not matter and faces that cut
//! through each other (a bone pressed into a muscle) are drawn as they are. The image is
//! drawn at `SUPERSAMPLING` × the picture's resolution and averaged down, which smooths
//! the silhouettes and the outlines.
//!
//! A pixel is covered when its centre is inside the triangle or on its edge, so two
//! triangles that share an edge leave no gap between them.

use nalgebra::Vector3;
use plotters::style::RGBColor;

/// Samples per pixel along each axis.
pub const SUPERSAMPLING: usize = 2;

/// One triangle on the screen: corners in (sample) pixels, x to the right, y down, and the
/// height towards the viewer as the third coordinate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScreenTriangle {
    pub corners: [Vector3<f64>; 3],
    pub colour: RGBColor,
    /// Whether edge k (opposite corner k) is drawn as an outline.
    pub outline: [bool; 3],
}

/// An image with a depth per pixel; pixels nothing was drawn over are `None`.
#[derive(Debug, Clone, PartialEq)]
pub struct Raster {
    pub width: usize,
    pub height: usize,
    pixels: Vec<Option<RGBColor>>,
    depth: Vec<f64>,
}

/// Width of an outline in samples, and how much it darkens the colour (a factor).
const OUTLINE_WIDTH: f64 = 1.1;
const OUTLINE_SHADE: f64 = 0.6;

impl Raster {
    /// An empty image of `width` × `height` pixels.
    pub fn new(width: usize, height: usize) -> Self {
        Raster {
            width,
            height,
            pixels: vec![None; width * height],
            depth: vec![f64::NEG_INFINITY; width * height],
        }
    }

    /// The colour at pixel (x, y), if something was drawn there.
    pub fn pixel(&self, x: usize, y: usize) -> Option<RGBColor> {
        self.pixels[y * self.width + x]
    }

    /// Draw `triangle` where it is nearer than what is there; outlines (when `outlines`)
    /// darken the samples within [`OUTLINE_WIDTH`] of an outlined edge.
    pub fn fill(&mut self, triangle: &ScreenTriangle, outlines: bool) {
        let [a, b, c] = triangle.corners;
        // Twice the signed area; a triangle seen edge-on covers nothing.
        let area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        if area.abs() < 1e-12 || !area.is_finite() {
            return;
        }
        let lengths = [
            (c - b).xy().norm(),
            (a - c).xy().norm(),
            (b - a).xy().norm(),
        ];
        let x0 = a.x.min(b.x).min(c.x).floor().max(0.0) as usize;
        let y0 = a.y.min(b.y).min(c.y).floor().max(0.0) as usize;
        let x1 = (a.x.max(b.x).max(c.x).ceil() as usize).min(self.width);
        let y1 = (a.y.max(b.y).max(c.y).ceil() as usize).min(self.height);
        let darker = scaled(triangle.colour, OUTLINE_SHADE);
        for y in y0..y1 {
            let py = y as f64 + 0.5;
            for x in x0..x1 {
                let px = x as f64 + 0.5;
                // Barycentric weights: w_k is the area opposite corner k over the whole.
                let w = [
                    ((c.x - b.x) * (py - b.y) - (c.y - b.y) * (px - b.x)) / area,
                    ((a.x - c.x) * (py - c.y) - (a.y - c.y) * (px - c.x)) / area,
                    ((b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x)) / area,
                ];
                if w.iter().any(|&w| w < -1e-9) {
                    continue;
                }
                let depth = w[0] * a.z + w[1] * b.z + w[2] * c.z;
                let i = y * self.width + x;
                if depth < self.depth[i] {
                    continue;
                }
                self.depth[i] = depth;
                // Distance to edge k = w_k × the height of the triangle over that edge.
                let on_outline = outlines
                    && (0..3).any(|k| {
                        triangle.outline[k] && w[k] * area.abs() / lengths[k] < OUTLINE_WIDTH
                    });
                self.pixels[i] = Some(if on_outline { darker } else { triangle.colour });
            }
        }
    }

    /// The image averaged over blocks of `factor` × `factor` samples (a block partly
    /// drawn is blended with `background`); the result's size is the size over `factor`.
    pub fn downsampled(&self, factor: usize, background: RGBColor) -> Raster {
        let (width, height) = (self.width / factor, self.height / factor);
        let mut out = Raster::new(width, height);
        for y in 0..height {
            for x in 0..width {
                let mut sum = [0u32; 3];
                let mut drawn = false;
                for sy in 0..factor {
                    for sx in 0..factor {
                        let sample = self.pixel(factor * x + sx, factor * y + sy);
                        drawn |= sample.is_some();
                        let RGBColor(r, g, b) = sample.unwrap_or(background);
                        sum[0] += u32::from(r);
                        sum[1] += u32::from(g);
                        sum[2] += u32::from(b);
                    }
                }
                if drawn {
                    let n = (factor * factor) as u32;
                    let mean = |s: u32| ((s + n / 2) / n) as u8;
                    out.pixels[y * width + x] =
                        Some(RGBColor(mean(sum[0]), mean(sum[1]), mean(sum[2])));
                }
            }
        }
        out
    }
}

/// `colour` with each channel times `factor` (in [0, 1]).
pub fn scaled(colour: RGBColor, factor: f64) -> RGBColor {
    let f = factor.clamp(0.0, 1.0);
    let channel = |c: u8| (f64::from(c) * f).round() as u8;
    RGBColor(channel(colour.0), channel(colour.1), channel(colour.2))
}

#[cfg(test)]
mod tests {
    use super::*;

    const RED: RGBColor = RGBColor(200, 0, 0);
    const BLUE: RGBColor = RGBColor(0, 0, 200);

    fn square(depth: f64, colour: RGBColor, from: f64, to: f64) -> [ScreenTriangle; 2] {
        let p = |x: f64, y: f64| Vector3::new(x, y, depth);
        [
            ScreenTriangle {
                corners: [p(from, from), p(to, from), p(to, to)],
                colour,
                outline: [true, false, true],
            },
            ScreenTriangle {
                corners: [p(from, from), p(to, to), p(from, to)],
                colour,
                outline: [true, true, false],
            },
        ]
    }

    /// The nearer square wins wherever they overlap, whichever is drawn first; two
    /// triangles sharing a diagonal leave no gap on it.
    #[test]
    fn the_nearer_face_covers_the_farther_in_either_order() {
        for near_first in [true, false] {
            let mut raster = Raster::new(40, 40);
            let near = square(1.0, RED, 10.0, 30.0);
            let far = square(-1.0, BLUE, 0.0, 40.0);
            let order: Vec<&ScreenTriangle> = if near_first {
                near.iter().chain(&far).collect()
            } else {
                far.iter().chain(&near).collect()
            };
            for t in order {
                raster.fill(t, false);
            }
            for y in 0..40 {
                for x in 0..40 {
                    let inside = (10..30).contains(&x) && (10..30).contains(&y);
                    let expected = if inside { RED } else { BLUE };
                    assert_eq!(raster.pixel(x, y), Some(expected), "({x}, {y})");
                }
            }
        }
    }

    #[test]
    fn outlines_darken_the_edges_but_not_the_diagonal_and_downsampling_averages() {
        let mut raster = Raster::new(40, 40);
        for t in &square(0.0, RED, 10.0, 30.0) {
            raster.fill(t, true);
        }
        let dark = scaled(RED, OUTLINE_SHADE);
        assert_eq!(raster.pixel(10, 20), Some(dark), "left edge");
        assert_eq!(raster.pixel(20, 29), Some(dark), "bottom edge");
        assert_eq!(raster.pixel(20, 20), Some(RED), "on the diagonal");
        assert_eq!(raster.pixel(5, 5), None);
        let small = raster.downsampled(2, RGBColor(255, 255, 255));
        assert_eq!((small.width, small.height), (20, 20));
        assert_eq!(small.pixel(10, 10), Some(RED));
        // Samples 10 (outline, 120) and 11 (inside, 200) of each row: their mean.
        assert_eq!(small.pixel(5, 10), Some(RGBColor(160, 0, 0)));
        assert_eq!(small.pixel(1, 1), None);
    }
}
