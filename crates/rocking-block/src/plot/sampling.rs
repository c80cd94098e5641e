//! Brute-force diagrams, basins, class grids, probability maps and marginals.

use super::fine::{Chart, Fine, Pen};
use super::key::{Mark, class_colour, class_entries, colour_bar, curve_colour, draw_key};
use super::{plot_err, range};
use crate::error::Result;
use plotters::prelude::*;
use std::path::Path;

/// Fig. 5: psi at the stroboscopic samples against alpha (sweep up: dark, down: red), with a
/// blow-up of [0.73, 0.79]; dashed vertical lines at the special points `markers` (name,
/// alpha) and crosses in a strip under the data where a sweep overturned (`overturned(point)`:
/// no samples there; sweep up's row above sweep down's).
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written.
pub fn brute_force_svg(
    path: &Path,
    title: &str,
    up: &[hycont_sample::sweep::SweepPoint],
    down: &[hycont_sample::sweep::SweepPoint],
    markers: &[(&str, f64)],
    overturned: &dyn Fn(&hycont_sample::sweep::SweepPoint) -> bool,
) -> Result<()> {
    super::picture(path, (1290, 900), |root, _| {
        let (charts, key) = root.split_horizontally(1000);
        draw_key(&key, "key", &sweep_entries()).map_err(|e| plot_err(path, e))?;
        let (top, bottom) = charts.split_vertically(450);
        for (area, (lo, hi), title) in [
            (&top, (0.5, 0.8), title),
            (
                &bottom,
                (0.73, 0.79),
                "blow-up of [0.73, 0.79]: period doubling to chaos",
            ),
        ] {
            let pts = || {
                up.iter()
                    .map(|p| (p, BLACK.mix(0.8)))
                    .chain(down.iter().map(|p| (p, RGBColor(214, 39, 40).mix(0.5))))
                    .filter(move |(p, _)| p.value >= lo && p.value <= hi)
            };
            let (y_lo, y_data) = range(pts().flat_map(|(p, _)| p.samples.iter().map(|s| s[1])));
            // A band above the data for the special points' names, a strip under it for the
            // overturned values (one row per sweep).
            let y_hi = y_data + 0.2 * (y_data - y_lo);
            let y_min = y_lo - 0.12 * (y_data - y_lo);
            let mut chart = ChartBuilder::on(area)
                .caption(title, ("sans-serif", 16))
                .margin(10)
                .x_label_area_size(35)
                .y_label_area_size(55)
                .build_cartesian_2d(lo..hi, y_min..y_hi)
                .map_err(|e| plot_err(path, e))?;
            chart
                .configure_mesh()
                .x_desc(super::key::axis("alpha"))
                .y_desc(super::key::axis("psi"))
                .draw()
                .map_err(|e| plot_err(path, e))?;
            for (p, colour) in pts() {
                chart
                    .draw_series(
                        p.samples
                            .iter()
                            .map(|s| Circle::new((p.value, s[1]), 1, colour.filled())),
                    )
                    .map_err(|e| plot_err(path, e))?;
            }
            annotate_sweeps(
                &mut chart,
                (lo, hi),
                (y_min, y_lo, y_hi),
                up,
                down,
                markers,
                overturned,
            )
            .map_err(|e| plot_err(path, e))?;
        }
        Ok(())
    })
}

/// Where the names of sorted vertical lines go: `(alpha, name, row)`, rows from the top.
/// Lines closer than `gap` form a cluster whose names take a row each (up to three); a larger
/// cluster names its first two alone and the rest together, first to last.
fn marker_labels(lines: &[(&str, f64)], gap: f64) -> Vec<(f64, String, u8)> {
    let mut clusters: Vec<Vec<(&str, f64)>> = Vec::new();
    for &line in lines {
        match clusters.last_mut() {
            Some(c) if line.1 - c.last().map_or(f64::NEG_INFINITY, |l| l.1) < gap => c.push(line),
            _ => clusters.push(vec![line]),
        }
    }
    let mut out = Vec::new();
    for c in clusters {
        if c.len() <= 3 {
            out.extend(
                (0u8..)
                    .zip(&c)
                    .map(|(row, &(name, at))| (at, name.to_string(), row)),
            );
        } else {
            out.push((c[0].1, c[0].0.to_string(), 0));
            out.push((c[1].1, c[1].0.to_string(), 1));
            let last = c[c.len() - 1].0;
            out.push((c[2].1, format!("{}-{last}", c[2].0), 2));
        }
    }
    out
}

type Chart2d<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// Fig. 5's annotations: the special points' lines and names, and the overturned values (the
/// key beside the charts says what each is).
#[allow(clippy::too_many_arguments)]
fn annotate_sweeps<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart2d<'a, DB>,
    (lo, hi): (f64, f64),
    (y_min, y_lo, y_hi): (f64, f64, f64),
    up: &[hycont_sample::sweep::SweepPoint],
    down: &[hycont_sample::sweep::SweepPoint],
    markers: &[(&str, f64)],
    overturned: &dyn Fn(&hycont_sample::sweep::SweepPoint) -> bool,
) -> std::result::Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let grey = RGBColor(90, 90, 90);
    let mut shown: Vec<(&str, f64)> = markers
        .iter()
        .copied()
        .filter(|m| m.1 > lo && m.1 < hi)
        .collect();
    shown.sort_by(|a, b| a.1.total_cmp(&b.1));
    for &(_, alpha) in &shown {
        chart
            .draw_series(DashedLineSeries::new(
                vec![(alpha, y_min), (alpha, y_hi)],
                6,
                4,
                grey.stroke_width(1),
            ))
            .map_err(err)?;
    }
    // Names go in the band above the data (the chart's top sixth), one row each within a
    // cluster of lines closer than 4 % of the axis; a cluster of more than three gives its
    // first two a row each and the rest one name for all ("PD3-PD6"), so no names overlap.
    let labels = marker_labels(&shown, 0.04 * (hi - lo));
    let label_y = |row: u8| y_hi - (y_hi - y_lo) * (0.02 + 0.05 * f64::from(row));
    for (at, name, row) in labels {
        let y = label_y(row);
        chart
            .draw_series(std::iter::once(Text::new(
                format!(" {name}"),
                (at, y),
                ("sans-serif", 13).into_font().color(&grey),
            )))
            .map_err(err)?;
    }
    // The strip under the data: sweep up's crosses at a third of it, sweep down's at two.
    let strip = |k: f64| y_lo - (y_lo - y_min) * k / 3.0;
    for (sweep, colour, y) in [(up, UP, strip(1.0)), (down, DOWN, strip(2.0))] {
        let gone = (sweep.iter()).filter(|p| overturned(p) && p.value >= lo && p.value <= hi);
        chart
            .draw_series(gone.map(|p| Cross::new((p.value, y), 3, colour.stroke_width(1))))
            .map_err(err)?;
    }
    Ok(())
}

/// Sweep up's colour (its samples drawn at opacity 0.8, its overturns opaque).
const UP: RGBColor = RGBColor(40, 40, 40);
/// Sweep down's colour (its samples drawn at opacity 0.5, its overturns opaque).
const DOWN: RGBColor = RGBColor(214, 39, 40);

/// Fig. 5's key: the two sweeps' samples and overturns, the special points' lines.
fn sweep_entries() -> Vec<(String, Mark)> {
    use super::key::{over_white, spelled};
    vec![
        (
            "sweep up (alpha increasing)".into(),
            Mark::Dot(over_white(BLACK, 0.8), 3),
        ),
        (
            "sweep down (alpha decreasing)".into(),
            Mark::Dot(over_white(DOWN, 0.5), 3),
        ),
        ("sweep up overturned (no samples;".into(), Mark::Cross(UP)),
        ("   the row under the data)".into(), Mark::Blank),
        (
            "sweep down overturned (no samples;".into(),
            Mark::Cross(DOWN),
        ),
        ("   the lowest row)".into(), Mark::Blank),
        (
            "special point of Fig. 4's branch:".into(),
            Mark::Dashed(RGBColor(90, 90, 90)),
        ),
        (format!("   {}", spelled("BP")), Mark::Blank),
        (format!("   {}", spelled("PD")), Mark::Blank),
    ]
}

/// Fig. 7: one raster of the dominant class per (phi0, psi0) cell for each omega, under
/// `title`.
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written.
pub fn basins_svg(
    path: &Path,
    title: &str,
    rasters: &[(f64, Vec<Vec<Option<&str>>>)],
    boundary: f64,
) -> Result<()> {
    super::titled_picture(path, (1390, 790), title, |root, _| {
        let (maps, key) = root.split_horizontally(1050);
        let panels = maps.split_evenly((2, 3));
        let drawn = rasters
            .iter()
            .flat_map(|(_, r)| r.iter().flatten().flatten().copied());
        let mut entries = class_entries(drawn);
        // White cells only where a run of few trials left cells without any.
        let empty = (rasters.iter()).any(|(_, r)| r.iter().flatten().any(Option::is_none));
        if empty {
            entries.push(("no trials in the cell".into(), Mark::Swatch(WHITE)));
        }
        draw_key(&key, "dominant class", &entries).map_err(|e| plot_err(path, e))?;
        for (panel, (omega, raster)) in panels.iter().zip(rasters) {
            let n = raster.len().max(1);
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("omega = {omega}"), ("sans-serif", 14))
                .margin(8)
                .x_label_area_size(28)
                .y_label_area_size(40)
                .build_cartesian_2d(-boundary..boundary, -1.0..1.0)
                .map_err(|e| plot_err(path, e))?;
            chart
                .configure_mesh()
                .x_desc(super::key::axis("phi0"))
                .y_desc(super::key::axis("psi0"))
                .draw()
                .map_err(|e| plot_err(path, e))?;
            let (dx, dy) = (2.0 * boundary / n as f64, 2.0 / n as f64);
            for (i, row) in raster.iter().enumerate() {
                for (j, c) in row.iter().enumerate() {
                    let Some(c) = c else { continue };
                    let (x0, y0) = (-boundary + i as f64 * dx, -1.0 + j as f64 * dy);
                    chart
                        .draw_series(std::iter::once(Rectangle::new(
                            [(x0, y0), (x0 + dx, y0 + dy)],
                            class_colour(c).filled(),
                        )))
                        .map_err(|e| plot_err(path, e))?;
                }
            }
        }
        Ok(())
    })
}

/// Draws the two-parameter curves on a chart of the (omega, alpha) plane.
fn overlay_curves<DB: DrawingBackend>(
    fine: &mut Fine,
    chart: &Chart<'_, DB>,
    curves: &[crate::continuation::Curve],
) {
    let frame = fine.frame(chart);
    for c in curves {
        if let Some((_, col)) = curve_styles().into_iter().find(|(k, _)| *k == c.kind) {
            fine.line(&frame, c.points(), Pen::new(col, 2.0));
        }
    }
}

/// Fig. 8: the class of each grid cell, one panel per beta, with the SN, BP and PD curves, under
/// `title`.
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written.
pub fn class_grid_svg(
    path: &Path,
    title: &str,
    omegas: &[f64],
    alphas: &[f64],
    grids: &[(f64, Vec<Vec<&str>>)],
    curves: &[crate::continuation::Curve],
) -> Result<()> {
    super::titled_picture(path, (1440, 550), title, |root, fine| {
        let (maps, key) = root.split_horizontally(1100);
        let panels = maps.split_evenly((1, 2));
        let drawn = grids.iter().flat_map(|(_, g)| g.iter().flatten().copied());
        let mut entries = class_entries(drawn);
        entries.extend(curve_entries(curves));
        draw_key(&key, "final class", &entries).map_err(|e| plot_err(path, e))?;
        let (dw, da) = (3.5 / omegas.len() as f64, 0.8 / alphas.len() as f64);
        for (panel, (beta, grid)) in panels.iter().zip(grids) {
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("beta = {beta:.4}"), ("sans-serif", 14))
                .margin(8)
                .x_label_area_size(30)
                .y_label_area_size(40)
                .build_cartesian_2d(0.5..4.0, 0.1..0.9)
                .map_err(|e| plot_err(path, e))?;
            chart
                .configure_mesh()
                .x_desc(super::key::axis("omega"))
                .y_desc(super::key::axis("alpha"))
                .draw()
                .map_err(|e| plot_err(path, e))?;
            for (i, col) in grid.iter().enumerate() {
                for (j, c) in col.iter().enumerate() {
                    let (x0, y0) = (omegas[i] - 0.5 * dw, alphas[j] - 0.5 * da);
                    chart
                        .draw_series(std::iter::once(Rectangle::new(
                            [(x0, y0), (x0 + dw, y0 + da)],
                            class_colour(c).filled(),
                        )))
                        .map_err(|e| plot_err(path, e))?;
                }
            }
            overlay_curves(fine, &chart, curves);
        }
        Ok(())
    })
}

/// Probabilities per group (name, one value per cell) for one beta.
pub type GroupPanel<'a> = (f64, Vec<(&'a str, Vec<f64>)>);

/// Fig. 9: probability heat maps per group and beta (rows: groups; columns: beta) over the
/// (omega, alpha) grid, with the SN, BP and PD curves; a colour scale and the curves' legend
/// in a column on the right; `title` above.
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written.
pub fn probability_grid_svg(
    path: &Path,
    title: &str,
    panels: &[GroupPanel<'_>],
    curves: &[crate::continuation::Curve],
) -> Result<()> {
    let groups = panels.first().map_or(0, |p| p.1.len());
    super::titled_picture(
        path,
        (1040, 50 + 300 * groups as u32),
        title,
        |root, fine| {
            let (maps, key) = root.split_horizontally(900);
            let areas = maps.split_evenly((groups, panels.len()));
            for (g, row) in
                (0..groups).map(|g| (g, &areas[g * panels.len()..(g + 1) * panels.len()]))
            {
                for (area, (beta, probs)) in row.iter().zip(panels) {
                    let (name, p) = &probs[g];
                    let mut chart = ChartBuilder::on(area)
                        .caption(format!("{name}, beta = {beta:.4}"), ("sans-serif", 13))
                        .margin(6)
                        .x_label_area_size(35)
                        .y_label_area_size(45)
                        .build_cartesian_2d(0.5..4.0, 0.1..0.9)
                        .map_err(|e| plot_err(path, e))?;
                    chart
                        .configure_mesh()
                        .disable_mesh()
                        .x_desc(super::key::axis("omega"))
                        .y_desc(super::key::axis("alpha"))
                        .draw()
                        .map_err(|e| plot_err(path, e))?;
                    let side = (p.len() as f64).sqrt().round().max(1.0) as usize;
                    let (dw, da) = (3.5 / side as f64, 0.8 / side as f64);
                    for (cell, v) in p.iter().enumerate() {
                        if v.is_nan() {
                            continue;
                        }
                        let (i, j) = (cell / side, cell % side);
                        let (x0, y0) = (0.5 + dw * i as f64, 0.1 + da * j as f64);
                        chart
                            .draw_series(std::iter::once(Rectangle::new(
                                [(x0, y0), (x0 + dw, y0 + da)],
                                probability_colour(*v).filled(),
                            )))
                            .map_err(|e| plot_err(path, e))?;
                    }
                    overlay_curves(fine, &chart, curves);
                }
            }
            probability_key(&key, curves).map_err(|e| plot_err(path, e))?;
            Ok(())
        },
    )
}

/// White (0) to blue (1).
fn probability_colour(v: f64) -> RGBColor {
    let shade = (255.0 * (1.0 - v.clamp(0.0, 1.0))) as u8;
    RGBColor(shade, shade, 255)
}

/// The colour scale (probability 0 to 1, ticked) and the legend of the curves drawn.
fn probability_key<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    curves: &[crate::continuation::Curve],
) -> std::result::Result<(), String> {
    let (scale, legend) = area.split_vertically(320);
    let legend = &legend;
    colour_bar(&scale, "probability", 1.0, (50, 5, 70), probability_colour)?;
    draw_key(legend, "curves", &curve_entries(curves))
}

/// Key entries for the curves drawn.
fn curve_entries(curves: &[crate::continuation::Curve]) -> Vec<(String, Mark)> {
    curve_styles()
        .into_iter()
        .filter(|(kind, _)| curves.iter().any(|c| c.kind == *kind))
        .map(|(kind, colour)| {
            (
                format!("{} curve", super::key::spelled(kind.label())),
                Mark::Line(colour),
            )
        })
        .collect()
}

/// The curves the sampling figures overlay, with their colours.
fn curve_styles() -> [(hycont_continuation::SpecialKind, RGBColor); 3] {
    use hycont_continuation::SpecialKind::{BranchPoint, Fold, PeriodDoubling};
    [Fold, BranchPoint, PeriodDoubling].map(|k| (k, curve_colour(k)))
}

/// One panel of Fig. 10: the group probabilities per bin of a variable over `range`, and the
/// bins' trials (for the 95 % Wilson intervals drawn around them).
pub struct Marginal<'a> {
    /// The binned variable.
    pub name: &'a str,
    /// Its range.
    pub range: (f64, f64),
    /// Each group's probability per bin.
    pub probabilities: Vec<(&'static str, Vec<f64>)>,
    /// Trials per bin.
    pub trials: Vec<u64>,
}

/// Fig. 10: group probabilities against each binned variable, with their 95 % Wilson intervals
/// shaded, under `title`.
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written.
pub fn marginals_svg(path: &Path, title: &str, panels: &[Marginal<'_>]) -> Result<()> {
    super::titled_picture(path, (1420, 450), title, |root, fine| {
        let (plots, key) = root.split_horizontally(1200);
        let areas = plots.split_evenly((1, panels.len()));
        let colours = [
            RGBColor(255, 200, 0),
            RGBColor(31, 119, 180),
            RGBColor(140, 200, 140),
            RGBColor(0, 0, 0),
            RGBColor(148, 103, 189),
        ];
        for (area, panel) in areas.iter().zip(panels) {
            let (lo, hi) = panel.range;
            let mut chart = ChartBuilder::on(area)
                .caption(format!("against {}", panel.name), ("sans-serif", 13))
                .margin(8)
                .x_label_area_size(30)
                .y_label_area_size(40)
                .build_cartesian_2d(lo..hi, 0.0..1.0)
                .map_err(|e| plot_err(path, e))?;
            chart
                .configure_mesh()
                .x_desc(super::key::axis(panel.name))
                .y_desc("probability")
                .draw()
                .map_err(|e| plot_err(path, e))?;
            let n = panel.trials.len().max(1);
            let x = |i: usize| lo + (hi - lo) * (i as f64 + 0.5) / n as f64;
            for ((_, p), col) in panel.probabilities.iter().zip(colours) {
                let band = wilson_band(p, &panel.trials, x);
                chart
                    .draw_series(std::iter::once(Polygon::new(band, col.mix(0.2).filled())))
                    .map_err(|e| plot_err(path, e))?;
            }
            let frame = fine.frame(&chart);
            for ((_, p), col) in panel.probabilities.iter().zip(colours) {
                let pts: Vec<(f64, f64)> = (p.iter().enumerate())
                    .filter(|(_, v)| v.is_finite())
                    .map(|(i, v)| (x(i), *v))
                    .collect();
                fine.line(&frame, pts, Pen::new(col, 2.0));
            }
        }
        let groups = panels
            .first()
            .map(|p| &p.probabilities[..])
            .unwrap_or_default();
        let mut entries: Vec<(String, Mark)> = groups
            .iter()
            .zip(colours)
            .map(|((group, _), col)| ((*group).to_string(), Mark::Line(col)))
            .collect();
        entries.push((
            "shaded: 95 % Wilson interval".into(),
            Mark::Swatch(super::key::over_white(RGBColor(90, 90, 90), 0.2)),
        ));
        // The key beside the panels (inside, it would cover the curves).
        draw_key(&key, "solution group", &entries).map_err(|e| plot_err(path, e))?;
        Ok(())
    })
}

/// The polygon of the 95 % Wilson intervals of probabilities `p` over bins of `trials` trials
/// (bin `i` at `x(i)`): the upper ends left to right, then the lower ends back.
fn wilson_band(p: &[f64], trials: &[u64], x: impl Fn(usize) -> f64) -> Vec<(f64, f64)> {
    let ends: Vec<(f64, f64, f64)> = (p.iter().zip(trials).enumerate())
        .filter(|(_, (v, n))| v.is_finite() && **n > 0)
        .map(|(i, (v, &n))| {
            let (lo, hi) = hycont_sample::basin::wilson((v * n as f64).round() as u64, n);
            (x(i), lo, hi)
        })
        .collect();
    let upper = ends.iter().map(|&(x, _, hi)| (x, hi));
    let lower = ends.iter().rev().map(|&(x, lo, _)| (x, lo));
    upper.chain(lower).collect()
}
