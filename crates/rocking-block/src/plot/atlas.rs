//! The atlas figure: each sheet's charts (their polygons in the (omega, alpha) plane) filled
//! by Amp, unstable ones dotted, boundary charts marked by their edge, Fig. 6's curves over it.

use super::atlas_shading::Shading;
use super::fine::Pen;
use super::key::{Mark, colour_bar, curve_colour, draw_key};
use super::plot_err;
use crate::continuation::{AMP, ATLAS_WINDOW, Curve};
use crate::error::Result;
use hycont_continuation::OrbitAtlas;
use hycont_continuation::atlas::{AtlasChart, Edge};
use plotters::prelude::*;
use std::path::Path;

/// Viridis-like colour of `v` in [0, 1] (dark blue to yellow), by linear interpolation.
fn amp_colour(v: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let x = v.clamp(0.0, 1.0) * 4.0;
    let k = (x.floor() as usize).min(3);
    let t = x - k as f64;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    let mix = |p: f64, q: f64| (p + t * (q - p)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// A chart's polygon in (omega, alpha).
fn polygon(atlas: &OrbitAtlas, c: &AtlasChart) -> Vec<(f64, f64)> {
    let [p, q] = atlas.atlas.unknown_params;
    let u = &c.point.u;
    c.polygon
        .iter()
        .map(|v| {
            let at = |k: usize| u[k] + c.point.tangent[k] * v[0] + c.tangent2[k] * v[1];
            (at(p), at(q))
        })
        .collect()
}

/// The edge marks: label, colour.
fn edge_mark(edge: Edge) -> (String, RGBColor) {
    match edge {
        Edge::Bound { .. } => ("boundary chart on a bound".into(), BLACK),
        Edge::Special { kind } => (
            format!("boundary chart on {}", kind.label()),
            curve_colour(kind),
        ),
        _ => ("boundary chart".into(), BLACK),
    }
}

/// The atlas figure: a panel per sheet, the Amp scale and the key beside them.
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written.
pub fn atlas_svg(path: &Path, title: &str, sheets: &[OrbitAtlas], curves: &[Curve]) -> Result<()> {
    let amp_max = sheets
        .iter()
        .flat_map(|a| a.atlas.charts.iter())
        .filter_map(|c| c.point.get(AMP))
        .fold(0.0f64, f64::max)
        .max(1e-9);
    super::titled_picture(path, (1500, 700), title, |root, fine| {
        let (panels, side) = root.split_horizontally(1230);
        let areas = panels.split_evenly((1, sheets.len().max(1)));
        let mut entries: Vec<(String, Mark)> = Vec::new();
        for (area, atlas) in areas.iter().zip(sheets) {
            sheet_panel(path, area, fine, atlas, curves, amp_max, &mut entries)?;
        }
        fine.here(root, path)?;
        let (scale, key) = side.split_vertically(300);
        amp_scale(&scale, amp_max).map_err(|e| plot_err(path, e))?;
        entries.push(("unstable orbit (chart centre)".into(), Mark::Dot(BLACK, 1)));
        let mut seen = std::collections::HashSet::new();
        entries.retain(|(l, _)| seen.insert(l.clone()));
        draw_key(&key, "key", &entries).map_err(|e| plot_err(path, e))?;
        Ok(())
    })
}

fn sheet_panel(
    path: &Path,
    area: &super::Area<'_>,
    fine: &mut super::fine::Fine,
    atlas: &OrbitAtlas,
    curves: &[Curve],
    amp_max: f64,
    entries: &mut Vec<(String, Mark)>,
) -> Result<()> {
    let [(w0, w1), (a0, a1)] = ATLAS_WINDOW;
    let caption = format!(
        "sheet: {} ({} charts)",
        atlas.atlas.name,
        atlas.atlas.charts.len()
    );
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 15))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(w0 - 0.1..w1 + 0.1, a0 - 0.03..a1 + 0.03)
        .map_err(|e| plot_err(path, e))?;
    chart
        .configure_mesh()
        .x_desc(super::key::axis("omega"))
        .y_desc(super::key::axis("alpha"))
        .draw()
        .map_err(|e| plot_err(path, e))?;
    shade(path, &chart, atlas, amp_max)?;
    let centre = |c: &AtlasChart| (c.point[crate::OMEGA], c.point[crate::ALPHA]);
    let unstable = atlas.atlas.charts.iter().filter(|c| !c.point.stable());
    chart
        .draw_series(unstable.map(|c| Circle::new(centre(c), 1, BLACK.filled())))
        .map_err(|e| plot_err(path, e))?;
    for c in atlas.atlas.boundary() {
        let (label, colour) = edge_mark(c.edge.expect("a boundary chart"));
        chart
            .draw_series(std::iter::once(Circle::new(centre(c), 3, colour.filled())))
            .map_err(|e| plot_err(path, e))?;
        entries.push((label, Mark::Dot(colour, 3)));
    }
    let frame = fine.frame(&chart);
    for c in curves {
        let col = curve_colour(c.kind);
        fine.line(&frame, c.points(), Pen::new(col, 1.5));
        entries.push((
            format!("Fig. 6 {} curve", super::key::spelled(c.kind.label())),
            Mark::Line(col),
        ));
    }
    Ok(())
}

/// Cells of this many pixels square are shaded with one colour.
const CELL: i32 = 2;

/// Fills the area the sheet's charts cover with Amp interpolated between the chart centres
/// ([`Shading`]): cells of [`CELL`] pixels, a row's neighbours of the same colour (of the
/// colour bar's 150 steps) drawn as one rectangle.
fn shade<DB: DrawingBackend>(
    path: &Path,
    chart: &super::fine::Chart<'_, DB>,
    atlas: &OrbitAtlas,
    amp_max: f64,
) -> Result<()> {
    // A chart whose polygon its neighbours cut away entirely covers nothing of its own.
    let charts: Vec<&AtlasChart> = (atlas.atlas.charts.iter())
        .filter(|c| c.polygon.len() >= 3)
        .collect();
    let centres: Vec<(f64, f64)> = (charts.iter())
        .map(|c| (c.point[crate::OMEGA], c.point[crate::ALPHA]))
        .collect();
    let values: Vec<f64> = (charts.iter())
        .map(|c| c.point.get(AMP).unwrap_or(0.0) / amp_max)
        .collect();
    let polygons: Vec<Vec<(f64, f64)>> = charts.iter().map(|c| polygon(atlas, c)).collect();
    let (xr, yr) = (chart.x_range(), chart.y_range());
    let shading = Shading::new(
        &centres,
        &values,
        &polygons,
        [(xr.start, xr.end), (yr.start, yr.end)],
    );
    let area = chart.plotting_area().strip_coord_spec();
    let (w, h) = area.dim_in_pixel();
    let (w, h) = (i32::try_from(w).unwrap_or(0), i32::try_from(h).unwrap_or(0));
    // The colour bar's bands: band k of 150 is the colour of k / 150.
    let level = |v: f64| ((v.clamp(0.0, 1.0) * 150.0).floor() as u32).min(149);
    let mut cells = Vec::new();
    for py in (0..h).step_by(CELL as usize) {
        let y =
            yr.end - (f64::from(py) + 0.5 * f64::from(CELL)) / f64::from(h) * (yr.end - yr.start);
        let mut run: Option<(i32, u32)> = None;
        for px in (0..w).step_by(CELL as usize).chain([w]) {
            let x = xr.start
                + (f64::from(px) + 0.5 * f64::from(CELL)) / f64::from(w) * (xr.end - xr.start);
            let here = (px < w)
                .then(|| shading.value_at(x, y))
                .flatten()
                .map(level);
            if run.map(|r| Some(r.1)) != Some(here) {
                if let Some((start, l)) = run.take() {
                    cells.push(([(start, py), (px, py + CELL)], l));
                }
                run = here.map(|l| (px, l));
            }
        }
    }
    for (corners, l) in cells {
        let colour = amp_colour(f64::from(l) / 150.0);
        area.draw(&Rectangle::new(corners, colour.filled()))
            .map_err(|e| plot_err(path, e))?;
    }
    Ok(())
}

/// The colour scale of Amp (0 to `amp_max`, rad).
fn amp_scale<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    amp_max: f64,
) -> std::result::Result<(), String> {
    colour_bar(
        area,
        "Amp = max |phi| (rad)",
        amp_max,
        (60, 6, 150),
        amp_colour,
    )
}
