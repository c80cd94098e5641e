//! Branches with their special points, two-parameter curves and test points.

use super::key::{Mark, curve_colour, draw_key, over_white};
use super::{mode_colour, pieces, plot_err, range};
use crate::error::Result;
use crate::model::Parameters;
use hycont_core::Trajectory;
use plotters::prelude::*;
use std::path::Path;

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
/// [`crate::Error::Plot`] if the file cannot be written.
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
/// [`crate::Error::Plot`] if the file cannot be written.
pub fn curves_svg(
    path: &Path,
    curves: &[crate::continuation::Curve],
    tests: &[crate::figures::fig6::TestPoint],
    params: &Parameters,
) -> Result<()> {
    draw_curves(
        path,
        "Fig. 6: two-parameter curves (omega, alpha)",
        curves,
        tests,
        params,
    )
}

/// One two-parameter curve (`rocking-block curve`) in the (omega, alpha) plane, as Fig. 6 draws
/// its curves, titled `title`.
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written.
pub fn curve_svg(
    path: &Path,
    title: &str,
    curve: &crate::continuation::Curve,
    params: &Parameters,
) -> Result<()> {
    draw_curves(path, title, std::slice::from_ref(curve), &[], params)
}

fn draw_curves(
    path: &Path,
    title: &str,
    curves: &[crate::continuation::Curve],
    tests: &[crate::figures::fig6::TestPoint],
    params: &Parameters,
) -> Result<()> {
    use hycont_continuation::SpecialKind;
    let root = SVGBackend::new(path, (1240, 750)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    let (plot_area, key) = root.split_horizontally(1000);
    let mut entries: Vec<(String, Mark)> = Vec::new();
    let mut chart = ChartBuilder::on(&plot_area)
        .caption(title, ("sans-serif", 18))
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
        if band.is_empty() {
            continue; // no legend for a region not drawn (a single curve)
        }
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
        entries.push((label.to_string(), Mark::Swatch(over_white(fill, 0.6))));
    }
    for c in curves {
        let col = curve_colour(c.kind);
        chart
            .draw_series(LineSeries::new(c.points(), col.stroke_width(2)))
            .map_err(|e| plot_err(path, e))?;
        entries.push((format!("{} curve", c.kind.label()), Mark::Line(col)));
    }
    // The one-parameter lines through the start (the study's: Fig. 3 at alpha = 0.66, Fig. 4
    // at omega = 1.3).
    let dashed = BLACK.mix(0.6);
    for (line, label) in [
        (
            vec![(0.5, params.alpha), (4.0, params.alpha)],
            format!("line alpha = {}", params.alpha),
        ),
        (
            vec![(params.omega, 0.0), (params.omega, 1.06)],
            format!("line omega = {}", params.omega),
        ),
    ] {
        chart
            .draw_series(DashedLineSeries::new(line, 5, 5, dashed.stroke_width(1)))
            .map_err(|e| plot_err(path, e))?;
        entries.push((label, Mark::Dashed(RGBColor(102, 102, 102))));
    }
    if !tests.is_empty() {
        entries.push(("test point (its outcome)".into(), Mark::Cross(BLACK)));
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
    draw_key(&key, "key", &entries).map_err(|e| plot_err(path, e))?;
    root.present().map_err(|e| plot_err(path, e))?;
    Ok(())
}

/// The test points' time series $\varphi(t)$, one panel each.
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written.
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
