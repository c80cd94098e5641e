//! Curves with sub-pixel coordinates. plotters maps every coordinate to a whole pixel, which
//! makes a smooth orbit zig-zag by a pixel; the curves of the figures are therefore written as
//! SVG paths with coordinates to 1/100 px, clipped to the plotting area of their chart, into the
//! SVG plotters drew.

use super::plot_err;
use crate::error::Result;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// A chart's affine map from data to pixels, and its clip rectangle.
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    /// Pixel `x = x.0 + x.1 * value`.
    x: (f64, f64),
    /// Pixel `y = y.0 + y.1 * value`.
    y: (f64, f64),
    /// Index of the clip path.
    clip: usize,
}

impl Frame {
    fn map(&self, (u, v): (f64, f64)) -> (f64, f64) {
        (self.x.0 + self.x.1 * u, self.y.0 + self.y.1 * v)
    }
}

/// Where a group of curves goes in the SVG: at a marker drawn by [`Fine::here`] (under what
/// plotters draws afterwards, such as a legend box), or at the end.
struct Group {
    marker: Option<String>,
    elements: String,
}

/// The curves of one picture, written into plotters' SVG by [`Fine::write`].
pub(super) struct Fine {
    clips: String,
    frames: usize,
    groups: Vec<Group>,
}

impl Default for Fine {
    fn default() -> Self {
        Fine {
            clips: String::new(),
            frames: 0,
            groups: vec![Group {
                marker: None,
                elements: String::new(),
            }],
        }
    }
}

/// The chart type every figure draws on.
pub(super) type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A line's look: colour (with opacity), width in px and an optional dash pattern
/// (dash, gap) in px.
#[derive(Debug, Clone, Copy)]
pub(super) struct Pen {
    colour: RGBAColor,
    width: f64,
    dash: Option<(f64, f64)>,
}

impl Pen {
    /// A solid line.
    pub(super) fn new(colour: impl Color, width: f64) -> Self {
        Pen {
            colour: colour.to_rgba(),
            width,
            dash: None,
        }
    }

    /// The line dashed: `dash` px drawn, `gap` px left out.
    pub(super) fn dashed(self, dash: f64, gap: f64) -> Self {
        Pen {
            dash: Some((dash, gap)),
            ..self
        }
    }
}

impl Fine {
    /// The frame of `chart`: its data-to-pixel map (exactly plotters' at the corners of the
    /// ranges, linear in between) and a clip path for its plotting area.
    pub(super) fn frame<DB: DrawingBackend>(&mut self, chart: &Chart<'_, DB>) -> Frame {
        let (xr, yr) = (chart.x_range(), chart.y_range());
        let (x0, y0) = chart.backend_coord(&(xr.start, yr.start));
        let (x1, y1) = chart.backend_coord(&(xr.end, yr.end));
        let affine = |p0: i32, p1: i32, v0: f64, v1: f64| {
            let slope = if v1 == v0 {
                0.0
            } else {
                f64::from(p1 - p0) / (v1 - v0)
            };
            (f64::from(p0) - slope * v0, slope)
        };
        let clip = self.frames;
        self.frames += 1;
        let (left, right) = (x0.min(x1), x0.max(x1));
        let (top, bottom) = (y0.min(y1), y0.max(y1));
        let _ = write!(
            self.clips,
            "<clipPath id=\"fine-clip-{clip}\"><rect x=\"{left}\" y=\"{top}\" width=\"{}\" height=\"{}\"/></clipPath>",
            right - left + 1,
            bottom - top + 1
        );
        Frame {
            x: affine(x0, x1, xr.start, xr.end),
            y: affine(y0, y1, yr.start, yr.end),
            clip,
        }
    }

    /// Adds the polyline through `points` (data coordinates; a non-finite point breaks it).
    pub(super) fn line(
        &mut self,
        frame: &Frame,
        points: impl IntoIterator<Item = (f64, f64)>,
        pen: Pen,
    ) {
        let mut d = String::new();
        let mut pen_down = false;
        for p in points {
            if !(p.0.is_finite() && p.1.is_finite()) {
                pen_down = false;
                continue;
            }
            let (x, y) = frame.map(p);
            let _ = write!(d, "{}{x:.2} {y:.2}", if pen_down { " L" } else { " M" });
            pen_down = true;
        }
        if d.is_empty() {
            return;
        }
        let c = pen.colour;
        let dash = pen
            .dash
            .map(|(on, off)| format!(" stroke-dasharray=\"{on} {off}\""))
            .unwrap_or_default();
        let group = self.groups.last_mut().expect("there is always a group");
        let _ = writeln!(
            group.elements,
            "<path d=\"{}\" fill=\"none\" stroke=\"#{:02X}{:02X}{:02X}\" stroke-opacity=\"{}\" stroke-width=\"{}\" stroke-linejoin=\"round\" stroke-linecap=\"round\"{dash} clip-path=\"url(#fine-clip-{})\"/>",
            d.trim_start(),
            c.0,
            c.1,
            c.2,
            c.3,
            pen.width,
            frame.clip
        );
    }

    /// Puts the curves added so far here, under whatever `area` gets drawn on afterwards (a
    /// legend box), instead of on top of the whole picture.
    pub(super) fn here<DB: DrawingBackend>(
        &mut self,
        area: &DrawingArea<DB, plotters::coord::Shift>,
        path: &Path,
    ) -> Result<()> {
        let marker = format!("fine-curves-{}", self.groups.len());
        area.draw(&Text::new(marker.clone(), (0, 0), ("sans-serif", 1)))
            .map_err(|e| plot_err(path, e))?;
        let group = self.groups.last_mut().expect("there is always a group");
        group.marker = Some(marker);
        self.groups.push(Group {
            marker: None,
            elements: String::new(),
        });
        Ok(())
    }

    /// Writes plotters' `svg` with the curves in it to `path` (and tick labels `-0.0` read
    /// `0.0`).
    ///
    /// # Errors
    /// [`crate::Error::Plot`] if `svg` lacks a marker or its end; [`crate::Error::Io`].
    pub(super) fn write(self, path: &Path, mut svg: String) -> Result<()> {
        svg = without_negative_zero(&svg);
        for group in self.groups {
            let at = match &group.marker {
                Some(marker) => {
                    let needle = format!(">\n{marker}\n</text>\n");
                    let end = svg.find(&needle).map(|i| i + needle.len());
                    let start = end.and_then(|e| svg[..e].rfind("<text"));
                    let (Some(start), Some(end)) = (start, end) else {
                        return Err(plot_err(path, format!("marker {marker} not drawn")));
                    };
                    svg.replace_range(start..end, "");
                    start
                }
                None => svg
                    .rfind("</svg>")
                    .ok_or_else(|| plot_err(path, "the SVG has no end"))?,
            };
            svg.insert_str(at, &group.elements);
        }
        if !self.clips.is_empty() {
            let at = svg
                .find(">\n")
                .ok_or_else(|| plot_err(path, "the SVG has no root element"))?;
            svg.insert_str(at + 2, &format!("<defs>{}</defs>\n", self.clips));
        }
        std::fs::write(path, svg).map_err(|source| crate::Error::Io {
            path: path.to_path_buf(),
            source,
        })
    }
}

/// `svg` with every text `-0`, `-0.0`, `-0.00`, ... (a tick at zero that plotters formats with
/// the sign of a rounding error) without its sign.
fn without_negative_zero(svg: &str) -> String {
    let mut out = String::with_capacity(svg.len());
    let mut rest = svg;
    while let Some(at) = rest.find(">\n-0") {
        let (before, after) = rest.split_at(at + 2);
        out.push_str(before);
        let digits = &after[1..];
        let end = digits.find('\n').unwrap_or(digits.len());
        let zero = digits[..end].trim_start_matches('0');
        let zero =
            zero.is_empty() || (zero.starts_with('.') && zero[1..].chars().all(|c| c == '0'));
        if zero && digits[end..].starts_with("\n</text>") {
            rest = digits;
        } else {
            out.push('-');
            rest = digits;
        }
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The frame reproduces plotters' pixel of every corner of the ranges and maps linearly in
    /// between, so fine curves meet plotters' markers within a pixel.
    #[test]
    fn the_frame_agrees_with_plotters_within_a_pixel() {
        let mut svg = String::new();
        let root = SVGBackend::with_string(&mut svg, (400, 300)).into_drawing_area();
        let chart = ChartBuilder::on(&root)
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(40)
            .build_cartesian_2d(-1.5..2.0, 0.25..3.0)
            .unwrap();
        let mut fine = Fine::default();
        let frame = fine.frame(&chart);
        for k in 0..=50 {
            let u = -1.5 + 3.5 * f64::from(k) / 50.0;
            let v = 0.25 + 2.75 * f64::from(50 - k) / 50.0;
            let (px, py) = chart.backend_coord(&(u, v));
            let (fx, fy) = frame.map((u, v));
            assert!((fx - f64::from(px)).abs() < 1.0, "x {u}: {fx} vs {px}");
            assert!((fy - f64::from(py)).abs() < 1.0, "y {v}: {fy} vs {py}");
        }
        // Exact at the corners.
        for (u, v) in [(-1.5, 0.25), (2.0, 3.0), (-1.5, 3.0), (2.0, 0.25)] {
            let (px, py) = chart.backend_coord(&(u, v));
            assert_eq!(frame.map((u, v)), (f64::from(px), f64::from(py)));
        }
    }

    #[test]
    fn only_a_negative_zero_loses_its_sign() {
        let text = |t: &str| format!("<text x=\"1\">\n{t}\n</text>\n");
        for (given, shown) in [
            ("-0.0", "0.0"),
            ("-0", "0"),
            ("-0.00", "0.00"),
            ("-0.5", "-0.5"),
            ("-0.05", "-0.05"),
            ("-10", "-10"),
            ("-0.0 and more", "-0.0 and more"),
        ] {
            assert_eq!(without_negative_zero(&text(given)), text(shown), "{given}");
        }
    }
}
