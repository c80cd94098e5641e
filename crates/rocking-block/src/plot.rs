//! SVG figures (plotters, SVG backend only: no system libraries needed).

use crate::error::{Error, Result};
use crate::model::{MINUS, PLUS, Parameters};
use hycont_core::orbit::PeriodicOrbit;
use hycont_core::{Mode, SimulationSettings, Trajectory};
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

/// Draws the time series $\varphi(t)$ (top) and the phase portrait $(\varphi, \psi)$ (bottom) of a
/// simulation with dense samples, segments coloured by mode and impacts drawn as jumps; the
/// static boundary $\pm(\pi/2 - \theta_b)$ is marked.
///
/// # Errors
/// [`Error::Plot`] if the file cannot be written.
pub fn trajectory_svg(
    path: &Path,
    title: &str,
    traj: &Trajectory,
    params: &Parameters,
) -> Result<()> {
    let (pieces, jumps) = pieces(traj);
    let root = SVGBackend::new(path, (1000, 900)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let (upper, lower) = root.split_vertically(420);
    let boundary = params.static_boundary();

    let t0 = pieces
        .first()
        .and_then(|p| p.points.first())
        .map_or(0.0, |p| p.0);
    let t1 = traj.t_final.max(t0 + 1e-9);
    let (phi_lo, phi_hi) = range(
        pieces
            .iter()
            .flat_map(|p| p.points.iter().map(|q| q.1))
            .chain([boundary, -boundary]),
    );
    let mut chart = ChartBuilder::on(&upper)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(t0..t1, phi_lo..phi_hi)
        .map_err(|e| plot_err(path, e))?;
    chart
        .configure_mesh()
        .x_desc("t")
        .y_desc("phi")
        .draw()
        .map_err(|e| plot_err(path, e))?;
    for b in [boundary, -boundary] {
        chart
            .draw_series(LineSeries::new(
                [(t0, b), (t1, b)],
                ShapeStyle::from(&BLACK.mix(0.4)).stroke_width(1),
            ))
            .map_err(|e| plot_err(path, e))?;
    }
    for piece in &pieces {
        chart
            .draw_series(LineSeries::new(
                piece.points.iter().map(|q| (q.0, q.1)),
                mode_colour(piece.mode).stroke_width(2),
            ))
            .map_err(|e| plot_err(path, e))?;
    }

    let (psi_lo, psi_hi) = range(pieces.iter().flat_map(|p| p.points.iter().map(|q| q.2)));
    let mut phase = ChartBuilder::on(&lower)
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(phi_lo..phi_hi, psi_lo..psi_hi)
        .map_err(|e| plot_err(path, e))?;
    phase
        .configure_mesh()
        .x_desc("phi")
        .y_desc("psi")
        .draw()
        .map_err(|e| plot_err(path, e))?;
    for piece in &pieces {
        phase
            .draw_series(LineSeries::new(
                piece.points.iter().map(|q| (q.1, q.2)),
                mode_colour(piece.mode).stroke_width(2),
            ))
            .map_err(|e| plot_err(path, e))?;
    }
    for (pre, post) in &jumps {
        phase
            .draw_series(LineSeries::new(
                [*pre, *post],
                ShapeStyle::from(&BLACK.mix(0.5)).stroke_width(1),
            ))
            .map_err(|e| plot_err(path, e))?;
    }
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
}

/// Draws periodic orbits: phase portraits $(\varphi, \psi)$ (top, segments coloured by mode,
/// impacts as thin grey jumps, the first orbit thick, the others thin) and $\varphi(t)$ over
/// one period (bottom), with the static boundary marked.
///
/// # Errors
/// [`Error::Plot`] if the file cannot be written; integration failures while sampling.
pub fn orbits_svg(
    path: &Path,
    title: &str,
    orbits: &[(&str, PeriodicOrbit)],
    params: &Parameters,
) -> Result<()> {
    let settings = SimulationSettings::default().rtol(1e-12).atol(1e-14);
    let mut sampled = Vec::new();
    for (name, o) in orbits {
        sampled.push((*name, o.sample(&crate::RockingBlock, 60, &settings)?));
    }
    let boundary = params.static_boundary();
    let all = || {
        sampled
            .iter()
            .flat_map(|(_, s)| s.iter())
            .flat_map(|ts| ts.iter())
    };
    let (phi_lo, phi_hi) = range(all().map(|(_, _, x)| x[0]).chain([boundary, -boundary]));
    let (psi_lo, psi_hi) = range(all().map(|(_, _, x)| x[1]));
    let t_hi = all().map(|(t, _, _)| t).fold(0.0, f64::max);

    let root = SVGBackend::new(path, (1000, 1000)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let (upper, lower) = root.split_vertically(560);
    let mut phase = ChartBuilder::on(&upper)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(phi_lo..phi_hi, psi_lo..psi_hi)
        .map_err(|e| plot_err(path, e))?;
    phase
        .configure_mesh()
        .x_desc("phi")
        .y_desc("psi")
        .draw()
        .map_err(|e| plot_err(path, e))?;
    for b in [boundary, -boundary] {
        phase
            .draw_series(LineSeries::new(
                [(b, psi_lo), (b, psi_hi)],
                ShapeStyle::from(&BLACK.mix(0.4)).stroke_width(1),
            ))
            .map_err(|e| plot_err(path, e))?;
    }
    for (mode, label) in [
        (PLUS, "mode + (right corner)"),
        (MINUS, "mode - (left corner)"),
    ] {
        let colour = mode_colour(mode);
        phase
            .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
            .map_err(|e| plot_err(path, e))?
            .label(label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
    }
    for (idx, (_, segments)) in sampled.iter().enumerate() {
        let width = if idx == 0 { 3 } else { 1 };
        for (k, ts) in segments.iter().enumerate() {
            let colour = mode_colour(ts.mode.first().copied().unwrap_or(PLUS));
            phase
                .draw_series(LineSeries::new(
                    ts.iter().map(|(_, _, x)| (x[0], x[1])),
                    colour.stroke_width(width),
                ))
                .map_err(|e| plot_err(path, e))?;
            // The jump at the end of the segment, to the next segment's start.
            let next = &segments[(k + 1) % segments.len()];
            if let (Some(end), Some(start)) = (ts.iter().last(), next.iter().next()) {
                phase
                    .draw_series(LineSeries::new(
                        [(end.2[0], end.2[1]), (start.2[0], start.2[1])],
                        ShapeStyle::from(&BLACK.mix(0.5)).stroke_width(1),
                    ))
                    .map_err(|e| plot_err(path, e))?;
            }
        }
    }
    phase
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .map_err(|e| plot_err(path, e))?;

    let mut series = ChartBuilder::on(&lower)
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0..t_hi.max(1e-9), phi_lo..phi_hi)
        .map_err(|e| plot_err(path, e))?;
    series
        .configure_mesh()
        .x_desc("t (one period)")
        .y_desc("phi")
        .draw()
        .map_err(|e| plot_err(path, e))?;
    for (idx, (_, segments)) in sampled.iter().enumerate() {
        let width = if idx == 0 { 3 } else { 1 };
        for ts in segments {
            let colour = mode_colour(ts.mode.first().copied().unwrap_or(PLUS));
            series
                .draw_series(LineSeries::new(
                    ts.iter().map(|(t, _, x)| (t, x[0])),
                    colour.stroke_width(width),
                ))
                .map_err(|e| plot_err(path, e))?;
        }
    }
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
}

/// Colour of a branch by index (symmetric, asymmetric, period-2, ...).
fn branch_colour(i: usize) -> RGBColor {
    [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(148, 103, 189),
    ][i % 4]
}

/// A bifurcation diagram: `Amp` against the continuation parameter for each branch (stable
/// solid, unstable dashed), labelled special points, and the static boundary.
///
/// # Errors
/// [`Error::Plot`] if the file cannot be written.
pub fn branches_svg(
    path: &Path,
    title: &str,
    branches: &[hycont_continuation::Branch],
    free: crate::continuation::Free,
    labels: &[(hycont_continuation::SpecialKind, f64, f64, String)],
    boundary: f64,
) -> Result<()> {
    use crate::continuation::AMP;
    let q = free.id().index();
    let xs = || {
        branches
            .iter()
            .flat_map(|b| b.points.iter().map(move |p| p.params[q]))
    };
    let ys = || {
        branches
            .iter()
            .flat_map(|b| b.points.iter().map(|p| p[AMP]))
    };
    let (x_lo, x_hi) = range(xs());
    let (_, y_hi) = range(ys().chain([boundary]));
    let root = SVGBackend::new(path, (1000, 700)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(x_lo..x_hi, 0.0..y_hi)
        .map_err(|e| plot_err(path, e))?;
    chart
        .configure_mesh()
        .x_desc(free.name())
        .y_desc("Amp = max |phi|")
        .draw()
        .map_err(|e| plot_err(path, e))?;
    chart
        .draw_series(LineSeries::new(
            [(x_lo, boundary), (x_hi, boundary)],
            ShapeStyle::from(&BLACK.mix(0.5)).stroke_width(1),
        ))
        .map_err(|e| plot_err(path, e))?
        .label("static boundary pi/2 - theta_b")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.mix(0.5)));
    for (i, b) in branches.iter().enumerate() {
        let colour = branch_colour(i);
        // Runs of equal stability, overlapping by one point so the curve is continuous.
        let mut start = 0;
        for k in 1..=b.points.len() {
            let end_run = k == b.points.len() || b.points[k].stable() != b.points[start].stable();
            if !end_run {
                continue;
            }
            let stop = k.min(b.points.len() - 1);
            let pts: Vec<(f64, f64)> = b.points[start..=stop]
                .iter()
                .map(|p| (p.params[q], p[AMP]))
                .collect();
            if b.points[start].stable() {
                chart
                    .draw_series(LineSeries::new(pts, colour.stroke_width(2)))
                    .map_err(|e| plot_err(path, e))?;
            } else {
                chart
                    .draw_series(DashedLineSeries::new(pts, 6, 4, colour.stroke_width(2)))
                    .map_err(|e| plot_err(path, e))?;
            }
            start = k;
        }
        chart
            .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
            .map_err(|e| plot_err(path, e))?
            .label(format!("{} (solid: stable, dashed: unstable)", b.name))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
    }
    for (_, x, y, text) in labels {
        chart
            .draw_series(std::iter::once(Circle::new((*x, *y), 4, BLACK.filled())))
            .map_err(|e| plot_err(path, e))?;
        chart
            .draw_series(std::iter::once(Text::new(
                text.clone(),
                (*x, *y + 0.02 * y_hi),
                ("sans-serif", 14),
            )))
            .map_err(|e| plot_err(path, e))?;
    }
    let points: Vec<(f64, f64)> = xs().zip(ys()).collect();
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.85))
        .position(emptiest_corner(&points, (x_lo, x_hi), (0.0, y_hi)))
        .draw()
        .map_err(|e| plot_err(path, e))?;
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
}

/// The corner of the plot area whose quarter (the outer 45 % in x, 30 % in y) holds the fewest
/// data points, for the legend (so that it does not hide the branches).
fn emptiest_corner(
    points: &[(f64, f64)],
    (x_lo, x_hi): (f64, f64),
    (y_lo, y_hi): (f64, f64),
) -> SeriesLabelPosition {
    let (wx, wy) = (0.45 * (x_hi - x_lo), 0.3 * (y_hi - y_lo));
    let count = |right: bool, upper: bool| {
        points
            .iter()
            .filter(|(x, y)| {
                let in_x = if right {
                    *x >= x_hi - wx
                } else {
                    *x <= x_lo + wx
                };
                let in_y = if upper {
                    *y >= y_hi - wy
                } else {
                    *y <= y_lo + wy
                };
                in_x && in_y
            })
            .count()
    };
    [
        (SeriesLabelPosition::UpperRight, count(true, true)),
        (SeriesLabelPosition::UpperLeft, count(false, true)),
        (SeriesLabelPosition::LowerRight, count(true, false)),
        (SeriesLabelPosition::LowerLeft, count(false, false)),
    ]
    .into_iter()
    .min_by_key(|(_, c)| *c)
    .map_or(SeriesLabelPosition::UpperRight, |(p, _)| p)
}

/// Fig. 6: the curves in the (omega, alpha) plane, the regions of stable symmetric (between the
/// SN and BP curves) and stable asymmetric (between the BP and PD curves) period-1 orbits, the
/// lines of Figs. 3 and 4, and the test points.
///
/// # Errors
/// [`Error::Plot`] if the file cannot be written.
pub fn curves_svg(
    path: &Path,
    curves: &[crate::continuation::Curve],
    tests: &[crate::figures::fig6::TestPoint],
    params: &Parameters,
) -> Result<()> {
    use hycont_continuation::SpecialKind;
    let colour = |k: SpecialKind| match k {
        SpecialKind::Fold => RGBColor(255, 127, 14),
        SpecialKind::PeriodDoubling => RGBColor(44, 160, 44),
        SpecialKind::BranchPoint => RGBColor(148, 103, 189),
        SpecialKind::BoundaryTouch => RGBColor(214, 39, 40),
        _ => RGBColor(140, 86, 75),
    };
    let root = SVGBackend::new(path, (1000, 750)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Fig. 6: two-parameter curves (omega, alpha)",
            ("sans-serif", 18),
        )
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(55)
        .build_cartesian_2d(0.5..4.0, 0.0..1.06)
        .map_err(|e| plot_err(path, e))?;
    chart
        .configure_mesh()
        .x_desc("omega")
        .y_desc("alpha")
        .draw()
        .map_err(|e| plot_err(path, e))?;
    let by_kind = |k: SpecialKind| curves.iter().find(|c| c.kind == k);
    // Regions: sampled in omega between two curves.
    let region = |lower: SpecialKind, upper: SpecialKind| -> Vec<(f64, f64, f64)> {
        let (Some(lo), Some(hi)) = (by_kind(lower), by_kind(upper)) else {
            return Vec::new();
        };
        (0..=350)
            .map(|i| 0.5 + 3.5 * f64::from(i) / 350.0)
            .filter_map(|w| Some((w, lo.alpha_at(w)?, hi.alpha_at(w)?)))
            .filter(|(_, a, b)| b > a)
            .collect()
    };
    for (lower, upper, fill, label) in [
        (
            SpecialKind::Fold,
            SpecialKind::BranchPoint,
            RGBColor(255, 230, 80),
            "stable symmetric period 1",
        ),
        (
            SpecialKind::BranchPoint,
            SpecialKind::PeriodDoubling,
            RGBColor(190, 190, 190),
            "stable asymmetric period 1",
        ),
    ] {
        let band = region(lower, upper);
        for w in band.windows(2) {
            let ((w0, a0, b0), (w1, a1, b1)) = (w[0], w[1]);
            if w1 - w0 > 0.02 {
                continue;
            }
            chart
                .draw_series(std::iter::once(Polygon::new(
                    vec![(w0, a0), (w1, a1), (w1, b1), (w0, b0)],
                    fill.mix(0.6).filled(),
                )))
                .map_err(|e| plot_err(path, e))?;
        }
        chart
            .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
            .map_err(|e| plot_err(path, e))?
            .label(label)
            .legend(move |(x, y)| {
                Rectangle::new([(x, y - 5), (x + 20, y + 5)], fill.mix(0.6).filled())
            });
    }
    for c in curves {
        let col = colour(c.kind);
        chart
            .draw_series(LineSeries::new(c.points(), col.stroke_width(2)))
            .map_err(|e| plot_err(path, e))?
            .label(format!("{} curve", c.kind.label()))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(2)));
    }
    for line in [
        vec![(0.5, params.alpha), (4.0, params.alpha)],
        vec![(params.omega, 0.0), (params.omega, 1.06)],
    ] {
        chart
            .draw_series(DashedLineSeries::new(
                line,
                5,
                5,
                BLACK.mix(0.6).stroke_width(1),
            ))
            .map_err(|e| plot_err(path, e))?;
    }
    for t in tests {
        chart
            .draw_series(std::iter::once(Cross::new(
                (t.omega, t.alpha),
                5,
                BLACK.stroke_width(2),
            )))
            .map_err(|e| plot_err(path, e))?;
        chart
            .draw_series(std::iter::once(Text::new(
                format!("{} {:?}", t.label, t.outcome),
                (t.omega + 0.03, t.alpha - 0.02),
                ("sans-serif", 12),
            )))
            .map_err(|e| plot_err(path, e))?;
    }
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.85))
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|e| plot_err(path, e))?;
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
}

/// The test points' time series $\varphi(t)$, one panel each.
///
/// # Errors
/// [`Error::Plot`] if the file cannot be written.
pub fn test_points_svg(
    path: &Path,
    tests: &[crate::figures::fig6::TestPoint],
    trajectories: &[Trajectory],
) -> Result<()> {
    let root = SVGBackend::new(path, (1000, 900)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let panels = root.split_evenly((3, 2));
    for ((panel, t), traj) in panels.iter().zip(tests).zip(trajectories) {
        let (pieces, _) = pieces(traj);
        let t1 = traj.t_final.max(1e-9);
        let mut chart = ChartBuilder::on(panel)
            .caption(
                format!(
                    "{}: omega {:.2}, alpha {:.3}: {:?}",
                    t.label, t.omega, t.alpha, t.outcome
                ),
                ("sans-serif", 13),
            )
            .margin(8)
            .x_label_area_size(25)
            .y_label_area_size(40)
            .build_cartesian_2d(0.0..t1, -1.6..1.6)
            .map_err(|e| plot_err(path, e))?;
        chart
            .configure_mesh()
            .draw()
            .map_err(|e| plot_err(path, e))?;
        for piece in &pieces {
            chart
                .draw_series(LineSeries::new(
                    piece.points.iter().map(|q| (q.0, q.1)),
                    mode_colour(piece.mode).stroke_width(1),
                ))
                .map_err(|e| plot_err(path, e))?;
        }
    }
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
}

/// Fig. 5: psi at the stroboscopic samples against alpha (sweep up: dark, down: light), with a
/// blow-up of [0.73, 0.79].
///
/// # Errors
/// [`Error::Plot`] if the file cannot be written.
pub fn brute_force_svg(
    path: &Path,
    up: &[hycont_sample::sweep::SweepPoint],
    down: &[hycont_sample::sweep::SweepPoint],
) -> Result<()> {
    let root = SVGBackend::new(path, (1000, 900)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let (top, bottom) = root.split_vertically(450);
    for (area, (lo, hi), title) in [
        (
            &top,
            (0.5, 0.8),
            "Fig. 5: brute-force diagram, omega = 1.3 (psi at t = 2 pi k / omega)",
        ),
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
        let (y_lo, y_hi) = range(pts().flat_map(|(p, _)| p.samples.iter().map(|s| s[1])));
        let mut chart = ChartBuilder::on(area)
            .caption(title, ("sans-serif", 16))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(55)
            .build_cartesian_2d(lo..hi, y_lo..y_hi)
            .map_err(|e| plot_err(path, e))?;
        chart
            .configure_mesh()
            .x_desc("alpha")
            .y_desc("psi")
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
    }
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
}

fn class_colour(name: &str) -> RGBColor {
    match name {
        "equilibrium" => RGBColor(0, 0, 0),
        "symmetric_p1" => RGBColor(255, 200, 0),
        "asymmetric_p1_pos" => RGBColor(31, 119, 180),
        "asymmetric_p1_neg" => RGBColor(214, 39, 40),
        "period2" => RGBColor(44, 160, 44),
        "other" => RGBColor(148, 103, 189),
        "overturn_pos" => RGBColor(140, 200, 140),
        "overturn_neg" => RGBColor(200, 140, 200),
        _ => RGBColor(255, 255, 255),
    }
}

/// Fig. 7: one raster of the dominant class per (phi0, psi0) cell for each omega.
///
/// # Errors
/// [`Error::Plot`] if the file cannot be written.
pub fn basins_svg(
    path: &Path,
    rasters: &[(f64, Vec<Vec<Option<&str>>>)],
    boundary: f64,
) -> Result<()> {
    let root = SVGBackend::new(path, (1050, 760)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let panels = root.split_evenly((2, 3));
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
            .x_desc("phi0")
            .y_desc("psi0")
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
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
}

fn overlay_curves<DB: DrawingBackend>(
    chart: &mut ChartContext<
        '_,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    curves: &[crate::continuation::Curve],
) -> std::result::Result<(), String> {
    use hycont_continuation::SpecialKind;
    for c in curves {
        let col = match c.kind {
            SpecialKind::Fold => RGBColor(255, 127, 14),
            SpecialKind::PeriodDoubling => RGBColor(44, 160, 44),
            SpecialKind::BranchPoint => RGBColor(148, 103, 189),
            _ => continue,
        };
        chart
            .draw_series(LineSeries::new(c.points(), col.stroke_width(2)))
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Fig. 8: the class of each grid cell, one panel per beta, with the SN, BP and PD curves.
///
/// # Errors
/// [`Error::Plot`] if the file cannot be written.
pub fn class_grid_svg(
    path: &Path,
    omegas: &[f64],
    alphas: &[f64],
    grids: &[(f64, Vec<Vec<&str>>)],
    curves: &[crate::continuation::Curve],
) -> Result<()> {
    let root = SVGBackend::new(path, (1100, 520)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let panels = root.split_evenly((1, 2));
    let (dw, da) = (3.5 / omegas.len() as f64, 0.8 / alphas.len() as f64);
    for (panel, (beta, grid)) in panels.iter().zip(grids) {
        let mut chart = ChartBuilder::on(panel)
            .caption(
                format!("Fig. 8: final class from phi0 = 0.01, beta = {beta:.4}"),
                ("sans-serif", 14),
            )
            .margin(8)
            .x_label_area_size(30)
            .y_label_area_size(40)
            .build_cartesian_2d(0.5..4.0, 0.1..0.9)
            .map_err(|e| plot_err(path, e))?;
        chart
            .configure_mesh()
            .x_desc("omega")
            .y_desc("alpha")
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
        overlay_curves(&mut chart, curves).map_err(|e| plot_err(path, e))?;
    }
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
}

/// Probabilities per group (name, one value per cell) for one beta.
pub type GroupPanel<'a> = (f64, Vec<(&'a str, Vec<f64>)>);

/// Fig. 9: probability heat maps per group and beta (rows: groups; columns: beta).
///
/// # Errors
/// [`Error::Plot`] if the file cannot be written.
pub fn probability_grid_svg(
    path: &Path,
    panels: &[GroupPanel<'_>],
    curves: &[crate::continuation::Curve],
) -> Result<()> {
    let groups = panels.first().map_or(0, |p| p.1.len());
    let root = SVGBackend::new(path, (900, 300 * groups as u32)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let areas = root.split_evenly((groups, panels.len()));
    for (g, row) in (0..groups).map(|g| (g, &areas[g * panels.len()..(g + 1) * panels.len()])) {
        for (area, (beta, probs)) in row.iter().zip(panels) {
            let (name, p) = &probs[g];
            let mut chart = ChartBuilder::on(area)
                .caption(format!("{name}, beta = {beta:.4}"), ("sans-serif", 13))
                .margin(6)
                .x_label_area_size(25)
                .y_label_area_size(35)
                .build_cartesian_2d(0.5..4.0, 0.1..0.9)
                .map_err(|e| plot_err(path, e))?;
            chart
                .configure_mesh()
                .disable_mesh()
                .draw()
                .map_err(|e| plot_err(path, e))?;
            for (cell, v) in p.iter().enumerate() {
                if v.is_nan() {
                    continue;
                }
                let (i, j) = (cell / 30, cell % 30);
                let (x0, y0) = (0.5 + 3.5 * i as f64 / 30.0, 0.1 + 0.8 * j as f64 / 30.0);
                let shade = (255.0 * (1.0 - v)) as u8;
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(x0, y0), (x0 + 3.5 / 30.0, y0 + 0.8 / 30.0)],
                        RGBColor(shade, shade, 255).filled(),
                    )))
                    .map_err(|e| plot_err(path, e))?;
            }
            overlay_curves(&mut chart, curves).map_err(|e| plot_err(path, e))?;
        }
    }
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
}

/// Fig. 10: group probabilities against each binned variable.
///
/// # Errors
/// [`Error::Plot`] if the file cannot be written.
#[allow(clippy::type_complexity)]
pub fn marginals_svg(
    path: &Path,
    panels: &[(&str, f64, f64, Vec<(&str, Vec<f64>)>)],
) -> Result<()> {
    let root = SVGBackend::new(path, (1200, 420)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let areas = root.split_evenly((1, panels.len()));
    let colours = [
        RGBColor(255, 200, 0),
        RGBColor(31, 119, 180),
        RGBColor(140, 200, 140),
        RGBColor(0, 0, 0),
        RGBColor(148, 103, 189),
    ];
    for (area, (name, lo, hi, probs)) in areas.iter().zip(panels) {
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!("Fig. 10: probability against {name}"),
                ("sans-serif", 13),
            )
            .margin(8)
            .x_label_area_size(30)
            .y_label_area_size(40)
            .build_cartesian_2d(*lo..*hi, 0.0..1.0)
            .map_err(|e| plot_err(path, e))?;
        chart
            .configure_mesh()
            .x_desc(*name)
            .draw()
            .map_err(|e| plot_err(path, e))?;
        for ((group, p), col) in probs.iter().zip(colours) {
            let n = p.len().max(1);
            let pts: Vec<(f64, f64)> = p
                .iter()
                .enumerate()
                .filter(|(_, v)| v.is_finite())
                .map(|(i, v)| (lo + (hi - lo) * (i as f64 + 0.5) / n as f64, *v))
                .collect();
            chart
                .draw_series(LineSeries::new(pts, col.stroke_width(2)))
                .map_err(|e| plot_err(path, e))?
                .label(*group)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .border_style(BLACK)
            .background_style(WHITE.mix(0.85))
            .draw()
            .map_err(|e| plot_err(path, e))?;
    }
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
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
