//! SVG figures (plotters, SVG backend only: no system libraries needed): trajectories and
//! orbits ([`trajectory_svg`], [`orbits_svg`]), branches and curves ([`branches_svg`],
//! [`curves_svg`], [`test_points_svg`]), sampling maps ([`basins_svg`] and the others).

mod basin;
mod branches;
mod key;
mod orbits;
mod sampling;

pub use basin::basin_svg;
pub use branches::{branches_svg, curve_svg, curves_svg, test_points_svg};
pub use orbits::{orbits_svg, trajectory_svg};
pub use sampling::{
    basins_svg, brute_force_svg, class_grid_svg, marginals_svg, probability_grid_svg,
};

use crate::error::Error;
use crate::model::{MINUS, PLUS};
use hycont_core::{Mode, Trajectory};
use plotters::prelude::*;
use std::path::Path;

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
