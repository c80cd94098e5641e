//! SVG figures (plotters, SVG backend only: no system libraries needed): trajectories and
//! orbits ([`trajectory_svg`], [`orbits_svg`]), branches and curves ([`branches_svg`],
//! [`curves_svg`], [`test_points_svg`]), sampling maps ([`basins_svg`] and the others).

mod atlas;
mod atlas_shading;
mod basin;
mod branches;
mod fine;
mod key;
mod orbits;
mod png;
mod sampling;

pub use atlas::atlas_svg;
pub use basin::basin_svg;
pub use branches::{Zoom, branches_svg, curve_svg, curves_svg, test_points_svg};
pub use orbits::{orbits_svg, trajectory_svg};
pub use png::svg_to_png;
pub use sampling::{
    Marginal, basins_svg, brute_force_svg, class_grid_svg, marginals_svg, probability_grid_svg,
};

use crate::error::Error;
use crate::model::{MINUS, PLUS};
use fine::Fine;
use hycont_core::{Mode, Trajectory};
use plotters::prelude::*;
use std::path::Path;

/// The whole picture plotters draws on.
type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

/// [`picture`] with `title` above what `draw` draws (on the area below it).
fn titled_picture(
    path: &Path,
    size: (u32, u32),
    title: &str,
    draw: impl FnOnce(&Area<'_>, &mut Fine) -> crate::error::Result<()>,
) -> crate::error::Result<()> {
    picture(path, size, |root, fine| {
        let below = root
            .titled(title, ("sans-serif", 18))
            .map_err(|e| plot_err(path, e))?;
        draw(&below, fine)
    })
}

/// Draws a picture of `size` px on white with `draw` (plotters' SVG backend, and curves with
/// sub-pixel coordinates added to `fine`) and writes it to `path` as SVG.
fn picture(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&Area<'_>, &mut Fine) -> crate::error::Result<()>,
) -> crate::error::Result<()> {
    let mut svg = String::new();
    let mut fine = Fine::default();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
        draw(&root, &mut fine)?;
        root.present().map_err(|e| plot_err(path, e))?;
    }
    fine.write(path, svg)
}

/// Colour of a mode: `+` blue, `-` red, rest grey.
fn mode_colour(mode: Mode) -> RGBColor {
    match mode {
        PLUS => RGBColor(31, 119, 180),
        MINUS => RGBColor(214, 39, 40),
        _ => RGBColor(110, 110, 110),
    }
}

/// A piece of trajectory in one mode: `(t, phi, psi)` points.
struct Piece {
    mode: Mode,
    points: Vec<(f64, f64, f64)>,
}

/// A jump in the phase plane: `(pre, post)` points `(phi, psi)`.
type Jump = ((f64, f64), (f64, f64));

/// Splits a trajectory's dense samples at its events into single-mode pieces, and returns the
/// jumps `(pre, post)` in the phase plane.
fn pieces(traj: &Trajectory) -> (Vec<Piece>, Vec<Jump>) {
    let mut pieces = Vec::new();
    let mut jumps = Vec::new();
    let mut samples = traj.samples.iter().peekable();
    let mut current = Piece {
        mode: traj
            .samples
            .mode
            .first()
            .copied()
            .unwrap_or(traj.mode_final),
        points: Vec::new(),
    };
    let mut breaks: Vec<(f64, Mode, Vec<f64>, Vec<f64>)> = traj
        .events
        .iter()
        .filter_map(|e| {
            e.mode_after
                .map(|m| (e.t, m, e.state_before.clone(), e.state_after.clone()))
        })
        .collect();
    breaks.extend(traj.zeno.iter().map(|z| {
        (
            z.t,
            z.mode_after,
            z.state_after.clone(),
            z.state_after.clone(),
        )
    }));
    breaks.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (t, mode_after, pre, post) in breaks {
        while let Some((ts, _, x)) = samples.next_if(|(ts, _, _)| *ts < t) {
            current.points.push((ts, x[0], x[1]));
        }
        current.points.push((t, pre[0], pre[1]));
        jumps.push(((pre[0], pre[1]), (post[0], post[1])));
        let next = Piece {
            mode: mode_after,
            points: vec![(t, post[0], post[1])],
        };
        pieces.push(std::mem::replace(&mut current, next));
    }
    for (ts, _, x) in samples {
        current.points.push((ts, x[0], x[1]));
    }
    current
        .points
        .push((traj.t_final, traj.state_final[0], traj.state_final[1]));
    pieces.push(current);
    (pieces, jumps)
}

fn plot_err(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Plot {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !lo.is_finite() || !hi.is_finite() {
        return (-1.0, 1.0);
    }
    let pad = 0.05 * (hi - lo).max(1e-3);
    (lo - pad, hi + pad)
}

/// The corner of the plot area whose quarter (the outer 45 % in x, 30 % in y) holds the fewest
/// data points, for the legend (so that it does not hide the branches); or the middle of the
/// left or right side (30 % in y around the centre) where that holds fewer still.
fn emptiest_corner(
    points: &[(f64, f64)],
    (x_lo, x_hi): (f64, f64),
    (y_lo, y_hi): (f64, f64),
) -> SeriesLabelPosition {
    let (wx, wy) = (0.45 * (x_hi - x_lo), 0.3 * (y_hi - y_lo));
    let count = |right: bool, upper: Option<bool>| {
        points
            .iter()
            .filter(|(x, y)| {
                let in_x = if right {
                    *x >= x_hi - wx
                } else {
                    *x <= x_lo + wx
                };
                let in_y = match upper {
                    Some(true) => *y >= y_hi - wy,
                    Some(false) => *y <= y_lo + wy,
                    None => (*y - 0.5 * (y_lo + y_hi)).abs() <= 0.5 * wy,
                };
                in_x && in_y
            })
            .count()
    };
    // Corners first: a middle place is taken only where it hides strictly fewer points.
    [
        (SeriesLabelPosition::UpperRight, count(true, Some(true))),
        (SeriesLabelPosition::UpperLeft, count(false, Some(true))),
        (SeriesLabelPosition::LowerRight, count(true, Some(false))),
        (SeriesLabelPosition::LowerLeft, count(false, Some(false))),
        (SeriesLabelPosition::MiddleLeft, count(false, None)),
        (SeriesLabelPosition::MiddleRight, count(true, None)),
    ]
    .into_iter()
    .min_by_key(|(_, c)| *c)
    .map_or(SeriesLabelPosition::UpperRight, |(p, _)| p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_legend_goes_to_the_emptiest_corner() {
        // A branch rising to the upper right (Fig. 4): the legend must not cover it.
        let rising: Vec<(f64, f64)> = (0..50).map(|i| (f64::from(i), f64::from(i))).collect();
        let corner = emptiest_corner(&rising, (0.0, 49.0), (0.0, 49.0));
        assert!(matches!(
            corner,
            SeriesLabelPosition::UpperLeft | SeriesLabelPosition::LowerRight
        ));
        // Data everywhere but the lower left.
        let mut others: Vec<(f64, f64)> = Vec::new();
        for (x, y) in [(45.0, 45.0), (5.0, 45.0), (45.0, 5.0)] {
            others.extend(std::iter::repeat_n((x, y), 3));
        }
        let corner = emptiest_corner(&others, (0.0, 50.0), (0.0, 50.0));
        assert!(matches!(corner, SeriesLabelPosition::LowerLeft));
    }
}
