//! The picture of a basin-stability result: class fractions with their 95 % intervals
//! (unbinned), fractions against the binned variable (1-D), or the dominant class per cell
//! (2-D); a key beside the plot names every class drawn.

use super::fine::{Fine, Pen};
use super::key::{Mark, class_colour, class_entries, draw_key};
use super::{Area, plot_err};
use crate::error::Result;
use hycont_sample::basin::{Counts, Study};
use plotters::prelude::*;
use std::path::Path;

/// Draws `counts` (folded onto the study's classes, see [`crate::basin::folded`]) of `study`.
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written.
pub fn basin_svg(path: &Path, title: &str, study: &Study, counts: &Counts) -> Result<()> {
    super::picture(path, (1220, 640), |root, fine| {
        let (plot, key) = root.split_horizontally(860);
        // A map shows each cell's dominant class only; bars and profiles show every class counted.
        let shown = |k: usize| {
            counts
                .counts
                .iter()
                .any(|row| row[k] > 0 && (study.axes.len() < 2 || dominant_class(row) == Some(k)))
        };
        let drawn: Vec<&str> = counts
            .classes
            .iter()
            .enumerate()
            .filter(|(k, _)| shown(*k))
            .map(|(_, c)| c.as_str())
            .collect();
        let mut entries = class_entries(drawn.iter().copied());
        let r = match study.axes.len() {
            0 => {
                entries.push(("95 % interval".into(), Mark::Line(BLACK)));
                fractions(&plot, title, counts)
            }
            1 => {
                entries = entries
                    .into_iter()
                    .map(|(l, m)| match m {
                        Mark::Swatch(c) => (l, Mark::Line(c)),
                        m => (l, m),
                    })
                    .collect();
                profile(&plot, fine, title, study, counts)
            }
            _ => {
                entries.push(("no trials in the cell".into(), Mark::Swatch(WHITE)));
                dominant(&plot, title, study, counts)
            }
        };
        r.map_err(|e| plot_err(path, e))?;
        let heading = if study.axes.len() == 2 {
            "dominant class"
        } else {
            "class"
        };
        draw_key(&key, heading, &entries).map_err(|e| plot_err(path, e))?;
        Ok(())
    })
}

/// Unbinned: one bar per class with its 95 % Wilson interval, named above the bar with its
/// fraction and interval.
fn fractions(area: &Area<'_>, title: &str, counts: &Counts) -> std::result::Result<(), String> {
    let err = |e: DrawingAreaErrorKind<_>| e.to_string();
    let n = counts.classes.len();
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 16))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(10)
        .build_cartesian_2d(0.0..1.0, 0.0..n as f64)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("fraction of trials")
        .y_labels(0)
        .disable_y_mesh()
        .draw()
        .map_err(err)?;
    let font = ("sans-serif", 13).into_font();
    for (k, class) in counts.classes.iter().enumerate() {
        let (p, lo, hi) = counts.fraction(0, k);
        let y = (n - k - 1) as f64;
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(0.0, y + 0.15), (p, y + 0.6)],
                class_colour(class).filled(),
            )))
            .map_err(err)?;
        chart
            .draw_series(LineSeries::new(
                [(lo, y + 0.375), (hi, y + 0.375)],
                BLACK.stroke_width(2),
            ))
            .map_err(err)?;
        chart
            .draw_series(std::iter::once(Text::new(
                format!("{class}: {p:.4} [{lo:.4}, {hi:.4}]"),
                (0.005, y + 0.95),
                font.clone(),
            )))
            .map_err(err)?;
    }
    Ok(())
}

type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// A titled chart over `x` and `y` (`(lo, hi, label)` each), its mesh drawn.
fn chart<'a, 'b>(
    area: &'a Area<'b>,
    title: &str,
    (x_lo, x_hi, x_name): (f64, f64, &str),
    (y_lo, y_hi, y_name): (f64, f64, &str),
) -> std::result::Result<Chart<'a, 'b>, String> {
    let err = |e: DrawingAreaErrorKind<_>| e.to_string();
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 16))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(55)
        .build_cartesian_2d(x_lo..x_hi, y_lo..y_hi)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(super::key::axis(x_name))
        .y_desc(super::key::axis(y_name))
        .draw()
        .map_err(err)?;
    Ok(chart)
}

/// One binned variable: each class's fraction per bin, at the bins' centres.
fn profile(
    area: &Area<'_>,
    fine: &mut Fine,
    title: &str,
    study: &Study,
    counts: &Counts,
) -> std::result::Result<(), String> {
    let axis = study.axes[0];
    let x = (axis.lo, axis.hi, study.names[axis.variable].as_str());
    let chart = chart(area, title, x, (0.0, 1.0, "fraction of trials"))?;
    let frame = fine.frame(&chart);
    let w = (axis.hi - axis.lo) / axis.bins as f64;
    for (k, class) in counts.classes.iter().enumerate() {
        if counts.counts.iter().all(|row| row[k] == 0) {
            continue;
        }
        let pts: Vec<(f64, f64)> = (0..axis.bins)
            .filter(|&c| counts.trials(c) > 0)
            .map(|c| (axis.lo + w * (c as f64 + 0.5), counts.fraction(c, k).0))
            .collect();
        fine.line(&frame, pts, Pen::new(class_colour(class), 2.0));
    }
    Ok(())
}

/// Two binned variables: the dominant class of each cell.
fn dominant(
    area: &Area<'_>,
    title: &str,
    study: &Study,
    counts: &Counts,
) -> std::result::Result<(), String> {
    let err = |e: DrawingAreaErrorKind<_>| e.to_string();
    let (ax, ay) = (study.axes[0], study.axes[1]);
    let mut chart = chart(
        area,
        title,
        (ax.lo, ax.hi, study.names[ax.variable].as_str()),
        (ay.lo, ay.hi, study.names[ay.variable].as_str()),
    )?;
    let (dx, dy) = (
        (ax.hi - ax.lo) / ax.bins as f64,
        (ay.hi - ay.lo) / ay.bins as f64,
    );
    for i in 0..ax.bins {
        for j in 0..ay.bins {
            let row = &counts.counts[i * ay.bins + j];
            let Some(k) = dominant_class(row) else {
                continue;
            };
            let (x0, y0) = (ax.lo + i as f64 * dx, ay.lo + j as f64 * dy);
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(x0, y0), (x0 + dx, y0 + dy)],
                    class_colour(&counts.classes[k]).filled(),
                )))
                .map_err(err)?;
        }
    }
    Ok(())
}

/// The class with the most trials in a cell (the last of equals, as Fig. 7), if any.
fn dominant_class(row: &[u64]) -> Option<usize> {
    row.iter()
        .enumerate()
        .filter(|(_, n)| **n > 0)
        .max_by_key(|(_, n)| **n)
        .map(|(k, _)| k)
}
