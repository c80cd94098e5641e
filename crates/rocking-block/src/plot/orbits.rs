//! Time series, phase portraits and orbits.

use super::fine::Pen;
use super::{emptiest_corner, mode_colour, pieces, plot_err, range};
use crate::error::Result;
use crate::model::{MINUS, PLUS, Parameters};
use hycont_core::orbit::PeriodicOrbit;
use hycont_core::{SimulationSettings, Trajectory};
use plotters::prelude::*;
use std::path::Path;

/// Draws the time series $\varphi(t)$ (top) and the phase portrait $(\varphi, \psi)$ (bottom) of a
/// simulation with dense samples, segments coloured by mode and impacts drawn as jumps; the
/// static boundary $\pm(\pi/2 - \theta_b)$ is marked.
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written.
pub fn trajectory_svg(
    path: &Path,
    title: &str,
    traj: &Trajectory,
    params: &Parameters,
) -> Result<()> {
    let (pieces, jumps) = pieces(traj);
    super::picture(path, (1000, 900), |root, fine| {
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
            .x_desc(super::key::axis("t"))
            .y_desc(super::key::axis("phi"))
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
        let frame = fine.frame(&chart);
        for piece in &pieces {
            let pen = Pen::new(mode_colour(piece.mode), 2.0);
            fine.line(&frame, piece.points.iter().map(|q| (q.0, q.1)), pen);
        }
        mode_key(path, &mut chart, (t0, t1), (phi_lo, phi_hi), &pieces)?;

        let (psi_lo, psi_hi) = range(pieces.iter().flat_map(|p| p.points.iter().map(|q| q.2)));
        let mut phase = ChartBuilder::on(&lower)
            .margin(12)
            .x_label_area_size(35)
            .y_label_area_size(55)
            .build_cartesian_2d(phi_lo..phi_hi, psi_lo..psi_hi)
            .map_err(|e| plot_err(path, e))?;
        phase
            .configure_mesh()
            .x_desc(super::key::axis("phi"))
            .y_desc(super::key::axis("psi"))
            .draw()
            .map_err(|e| plot_err(path, e))?;
        let frame = fine.frame(&phase);
        for piece in &pieces {
            let pen = Pen::new(mode_colour(piece.mode), 2.0);
            fine.line(&frame, piece.points.iter().map(|q| (q.1, q.2)), pen);
        }
        for (pre, post) in &jumps {
            fine.line(&frame, [*pre, *post], Pen::new(BLACK.mix(0.5), 1.0));
        }
        if !jumps.is_empty() {
            // The jumps' key, where the portrait leaves room (over the curves drawn so far).
            fine.here(root, path)?;
            let jump = "impact at phi = 0: psi jumps (thin grey line, before to after)";
            key_line(path, &mut phase, jump, BLACK.mix(0.5))?;
            let points: Vec<(f64, f64)> = (pieces.iter())
                .flat_map(|p| p.points.iter().map(|q| (q.1, q.2)))
                .collect();
            phase
                .configure_series_labels()
                .border_style(BLACK)
                .background_style(WHITE.mix(0.85))
                .position(emptiest_corner(&points, (phi_lo, phi_hi), (psi_lo, psi_hi)))
                .draw()
                .map_err(|e| plot_err(path, e))?;
        }
        Ok(())
    })
}

/// The static boundary's key entry.
const BOUNDARY: &str = "static boundary +-(pi/2 - theta_b)";

/// A key entry of `chart`: a short line in `style` and `label`.
fn key_line<'a, DB: DrawingBackend + 'a>(
    path: &Path,
    chart: &mut super::fine::Chart<'a, DB>,
    label: &str,
    style: impl Into<ShapeStyle>,
) -> Result<()> {
    let style = style.into();
    chart
        .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
        .map_err(|e| plot_err(path, e))?
        .label(label)
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
    Ok(())
}

/// The key of a trajectory's colours (the modes it visits, the static boundary), in the
/// corner of the plot its curve leaves freest.
fn mode_key<'a, DB: DrawingBackend + 'a>(
    path: &Path,
    chart: &mut super::fine::Chart<'a, DB>,
    (t0, t1): (f64, f64),
    (phi_lo, phi_hi): (f64, f64),
    pieces: &[super::Piece],
) -> Result<()> {
    use crate::model::REST;
    for (mode, what) in [
        (PLUS, "mode + (rocking about the right corner, phi > 0)"),
        (MINUS, "mode - (rocking about the left corner, phi < 0)"),
        (REST, "at rest on the base"),
    ] {
        if !pieces.iter().any(|p| p.mode == mode) {
            continue;
        }
        let colour = mode_colour(mode);
        key_line(path, chart, what, colour.stroke_width(2))?;
    }
    key_line(path, chart, BOUNDARY, BLACK.mix(0.4))?;
    let points: Vec<(f64, f64)> = pieces
        .iter()
        .flat_map(|p| p.points.iter().map(|q| (q.0, q.1)))
        .collect();
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.85))
        .position(emptiest_corner(&points, (t0, t1), (phi_lo, phi_hi)))
        .draw()
        .map_err(|e| plot_err(path, e))
}

/// Draws periodic orbits: phase portraits $(\varphi, \psi)$ (top, segments coloured by mode,
/// impacts as thin grey jumps, the first orbit thick, the others thin) and $\varphi(t)$ over
/// one period (bottom), with the static boundary marked.
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written; integration failures while sampling.
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

    super::picture(path, (1000, 1000), |root, fine| {
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
            .x_desc(super::key::axis("phi"))
            .y_desc(super::key::axis("psi"))
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
            key_line(path, &mut phase, label, colour.stroke_width(2))?;
        }
        let jump = "impact at phi = 0: psi jumps (thin grey)";
        key_line(path, &mut phase, jump, BLACK.mix(0.5))?;
        key_line(path, &mut phase, BOUNDARY, BLACK.mix(0.4))?;
        let frame = fine.frame(&phase);
        for (idx, (_, segments)) in sampled.iter().enumerate() {
            let width = if idx == 0 { 3.0 } else { 1.0 };
            for (k, ts) in segments.iter().enumerate() {
                let colour = mode_colour(ts.mode.first().copied().unwrap_or(PLUS));
                let points = ts.iter().map(|(_, _, x)| (x[0], x[1]));
                fine.line(&frame, points, Pen::new(colour, width));
                // The jump at the end of the segment, to the next segment's start.
                let next = &segments[(k + 1) % segments.len()];
                if let (Some(end), Some(start)) = (ts.iter().last(), next.iter().next()) {
                    let jump = [(end.2[0], end.2[1]), (start.2[0], start.2[1])];
                    fine.line(&frame, jump, Pen::new(BLACK.mix(0.5), 1.0));
                }
            }
        }
        fine.here(root, path)?;
        phase
            .configure_series_labels()
            .border_style(BLACK)
            .background_style(WHITE.mix(0.8))
            .position(emptiest_corner(
                &all().map(|(_, _, x)| (x[0], x[1])).collect::<Vec<_>>(),
                (phi_lo, phi_hi),
                (psi_lo, psi_hi),
            ))
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
            .x_desc(format!("{} over one period", super::key::axis("t")))
            .y_desc(super::key::axis("phi"))
            .draw()
            .map_err(|e| plot_err(path, e))?;
        let frame = fine.frame(&series);
        for (idx, (_, segments)) in sampled.iter().enumerate() {
            let width = if idx == 0 { 3.0 } else { 1.0 };
            for ts in segments {
                let colour = mode_colour(ts.mode.first().copied().unwrap_or(PLUS));
                let points = ts.iter().map(|(t, _, x)| (t, x[0]));
                fine.line(&frame, points, Pen::new(colour, width));
            }
        }
        Ok(())
    })
}
