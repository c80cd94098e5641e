//! Branches with their special points, two-parameter curves and test points.

use super::fine::Pen;
use super::key::{Mark, curve_colour, draw_key, over_white};
use super::{emptiest_corner, mode_colour, pieces, plot_err, range};
use crate::error::Result;
use crate::model::Parameters;
use crate::simulation::Outcome;
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

/// A zoomed view drawn beside a bifurcation diagram: the window it shows (data coordinates:
/// the continued parameter, `Amp`) and its title. The diagram marks the window and leaves the
/// labels inside it to the zoom.
#[derive(Debug, Clone, PartialEq)]
pub struct Zoom {
    /// The continued parameter's range.
    pub x: (f64, f64),
    /// The range of `Amp`.
    pub y: (f64, f64),
    /// The zoom's title.
    pub title: String,
}

impl Zoom {
    fn holds(&self, (x, y): (f64, f64)) -> bool {
        (self.x.0..=self.x.1).contains(&x) && (self.y.0..=self.y.1).contains(&y)
    }
}

/// Special points' labels: kind, parameter, `Amp`, text.
type Labels = [(hycont_continuation::SpecialKind, f64, f64, String)];

/// A bifurcation diagram: `Amp` against the continuation parameter for each branch (stable
/// solid, unstable dashed), labelled special points, and the static boundary; with `zoom`, a
/// zoomed view of a window beside it.
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written.
pub fn branches_svg(
    path: &Path,
    title: &str,
    branches: &[hycont_continuation::Branch],
    free: crate::continuation::Free,
    labels: &Labels,
    boundary: f64,
    zoom: Option<&Zoom>,
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
    let size = if zoom.is_some() {
        (1480, 700)
    } else {
        (1000, 700)
    };
    super::picture(path, size, |root, fine| {
        let (main, side) = match zoom {
            Some(_) => {
                let (main, side) = root.split_horizontally(1000);
                (main, Some(side))
            }
            None => (root.clone(), None),
        };
        let mut chart = ChartBuilder::on(&main)
            .caption(title, ("sans-serif", 18))
            .margin(15)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(x_lo..x_hi, 0.0..y_hi)
            .map_err(|e| plot_err(path, e))?;
        chart
            .configure_mesh()
            .x_desc(super::key::axis(free.name()))
            .y_desc(super::key::axis("Amp"))
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
        chart
            .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
            .map_err(|e| plot_err(path, e))?
            .label(
                "SN: fold, BP: branch point, PD: period doubling, SB: Amp at the boundary, GR: grazing",
            )
            .legend(|(x, y)| Text::new("", (x, y), ("sans-serif", 1)));
        draw_branch_lines(path, &mut chart, fine, branches, q, true)?;
        fine.here(&main, path)?;
        let outside = |x: f64, y: f64| zoom.is_none_or(|z| !z.holds((x, y)));
        draw_labels(path, &mut chart, labels, 0.02 * y_hi, outside)?;
        if let Some(z) = zoom {
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(z.x.0, z.y.0), (z.x.1, z.y.1)],
                    BLACK.mix(0.7).stroke_width(1),
                )))
                .map_err(|e| plot_err(path, e))?;
            chart
                .draw_series(std::iter::once(Text::new(
                    "zoom at right",
                    (z.x.1, z.y.1 + 0.02 * y_hi),
                    ("sans-serif", 13),
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
        if let (Some(z), Some(side)) = (zoom, side) {
            let mut chart = ChartBuilder::on(&side)
                .caption(&z.title, ("sans-serif", 16))
                .margin(15)
                .margin_top(40)
                .x_label_area_size(40)
                .y_label_area_size(60)
                .build_cartesian_2d(z.x.0..z.x.1, z.y.0..z.y.1)
                .map_err(|e| plot_err(path, e))?;
            chart
                .configure_mesh()
                .x_desc(super::key::axis(free.name()))
                .y_desc(super::key::axis("Amp"))
                .x_labels(5)
                .draw()
                .map_err(|e| plot_err(path, e))?;
            draw_branch_lines(path, &mut chart, fine, branches, q, false)?;
            let lift = 0.02 * (z.y.1 - z.y.0);
            draw_labels(path, &mut chart, labels, lift, |x, y| z.holds((x, y)))?;
        }
        Ok(())
    })
}

/// Each branch's curve on `chart` (stable solid, unstable dashed, in the branch's colour),
/// with a legend entry per branch if `legend`.
fn draw_branch_lines<DB: DrawingBackend>(
    path: &Path,
    chart: &mut super::fine::Chart<'_, DB>,
    fine: &mut super::fine::Fine,
    branches: &[hycont_continuation::Branch],
    q: usize,
    legend: bool,
) -> Result<()> {
    use crate::continuation::AMP;
    let frame = fine.frame(chart);
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
            let pen = Pen::new(colour, 2.0);
            let pen = if b.points[start].stable() {
                pen
            } else {
                pen.dashed(6.0, 4.0)
            };
            fine.line(&frame, pts, pen);
            start = k;
        }
        if legend {
            chart
                .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
                .map_err(|e| plot_err(path, e))?
                .label(format!("{} (solid: stable, dashed: unstable)", b.name))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
        }
    }
    Ok(())
}

/// The labels for which `keep(parameter, Amp)` holds: a dot at the point, its text `lift`
/// above.
fn draw_labels<DB: DrawingBackend>(
    path: &Path,
    chart: &mut super::fine::Chart<'_, DB>,
    labels: &Labels,
    lift: f64,
    keep: impl Fn(f64, f64) -> bool,
) -> Result<()> {
    for (_, x, y, text) in labels.iter().filter(|l| keep(l.1, l.2)) {
        chart
            .draw_series(std::iter::once(Circle::new((*x, *y), 4, BLACK.filled())))
            .map_err(|e| plot_err(path, e))?;
        chart
            .draw_series(std::iter::once(Text::new(
                text.clone(),
                (*x, *y + lift),
                ("sans-serif", 14),
            )))
            .map_err(|e| plot_err(path, e))?;
    }
    Ok(())
}

/// Fig. 6: the curves in the (omega, alpha) plane, the regions of stable symmetric (between the
/// SN and BP curves) and stable asymmetric (between the BP and PD curves) period-1 orbits, the
/// lines of Figs. 3 and 4, and the test points; titled `title`.
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written.
pub fn curves_svg(
    path: &Path,
    title: &str,
    curves: &[crate::continuation::Curve],
    tests: &[crate::figures::fig6::TestPoint],
    params: &Parameters,
) -> Result<()> {
    draw_curves(path, title, curves, tests, params)
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
    super::picture(path, (1240, 750), |root, fine| {
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
            .x_desc(super::key::axis("omega"))
            .y_desc(super::key::axis("alpha"))
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
        let frame = fine.frame(&chart);
        for c in curves {
            let col = curve_colour(c.kind);
            fine.line(&frame, c.points(), Pen::new(col, 2.0));
            entries.push((
                format!("{} curve", super::key::spelled(c.kind.label())),
                Mark::Line(col),
            ));
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
            fine.line(&frame, line, Pen::new(dashed, 1.0).dashed(5.0, 5.0));
            entries.push((label, Mark::Dashed(RGBColor(102, 102, 102))));
        }
        fine.here(root, path)?;
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
        // The curves' codimension-two points (R1, LPPD, R2, LPNS, PDNS), labelled.
        let codim2: Vec<(f64, f64, &str)> = curves
            .iter()
            .flat_map(|c| &c.branch.branch.special_points)
            .filter(|s| CODIM2.contains(&s.kind))
            .map(|s| (s.point[crate::OMEGA], s.point[crate::ALPHA], s.kind.label()))
            .collect();
        let red = RGBColor(170, 0, 0);
        if !codim2.is_empty() {
            entries.push(("codimension-two point".into(), Mark::Cross(red)));
        }
        for (omega, alpha, label) in codim2 {
            chart
                .draw_series(std::iter::once(Cross::new(
                    (omega, alpha),
                    6,
                    red.stroke_width(2),
                )))
                .map_err(|e| plot_err(path, e))?;
            chart
                .draw_series(std::iter::once(Text::new(
                    label.to_string(),
                    (omega + 0.03, alpha + 0.01),
                    ("sans-serif", 13).into_font().color(&red),
                )))
                .map_err(|e| plot_err(path, e))?;
        }
        draw_user_points(path, &mut chart, curves, &mut entries)?;
        draw_key(&key, "key", &entries).map_err(|e| plot_err(path, e))?;
        Ok(())
    })
}

/// The curves' user points (UZ: where a curve meets the lines of Figs. 3 and 4), as dots in
/// their curve's colour, with a key entry if there are any.
fn draw_user_points<DB: DrawingBackend>(
    path: &Path,
    chart: &mut super::fine::Chart<'_, DB>,
    curves: &[crate::continuation::Curve],
    entries: &mut Vec<(String, Mark)>,
) -> Result<()> {
    use hycont_continuation::SpecialKind;
    let mut any = false;
    for c in curves {
        let colour = curve_colour(c.kind);
        for s in c.branch.special(SpecialKind::UserPoint) {
            let at = (s.point[crate::OMEGA], s.point[crate::ALPHA]);
            chart
                .draw_series([
                    Circle::new(at, 5, colour.filled()),
                    Circle::new(at, 5, BLACK.stroke_width(1)),
                ])
                .map_err(|e| plot_err(path, e))?;
            any = true;
        }
    }
    if any {
        let text = "UZ (user point): on a dashed line";
        entries.push((text.into(), Mark::Dot(RGBColor(90, 90, 90), 5)));
    }
    Ok(())
}

/// The kinds of codimension-two points curves carry.
const CODIM2: [hycont_continuation::SpecialKind; 5] = [
    hycont_continuation::SpecialKind::Resonance1,
    hycont_continuation::SpecialKind::FoldFlip,
    hycont_continuation::SpecialKind::Resonance2,
    hycont_continuation::SpecialKind::FoldTorus,
    hycont_continuation::SpecialKind::FlipTorus,
];

/// The test points' time series $\varphi(t)$, one panel each, under `title`.
///
/// # Errors
/// [`crate::Error::Plot`] if the file cannot be written.
pub fn test_points_svg(
    path: &Path,
    title: &str,
    tests: &[crate::figures::fig6::TestPoint],
    trajectories: &[Trajectory],
) -> Result<()> {
    super::titled_picture(path, (1000, 930), title, |root, fine| {
        let panels = root.split_evenly((3, 2));
        for ((panel, t), traj) in panels.iter().zip(tests).zip(trajectories) {
            let (pieces, _) = pieces(traj);
            // A block that settles is shown until a little after it comes to rest for good,
            // not over the flat rest of the simulated window.
            let rest = t
                .rest_times
                .last()
                .copied()
                .filter(|_| t.outcome == Outcome::Rest);
            let t1 = rest
                .map_or(traj.t_final, |r| (1.3 * r).min(traj.t_final))
                .max(1e-9);
            let phi_max = (pieces.iter().flat_map(|p| &p.points))
                .filter(|q| q.0 <= t1)
                .fold(0.05_f64, |m, q| m.max(q.1.abs()));
            let y = 1.15 * phi_max;
            let settled = rest.map_or(String::new(), |r| {
                format!(
                    ", at rest from t = {r:.2} (of {:.0} simulated)",
                    traj.t_final
                )
            });
            let mut chart = ChartBuilder::on(panel)
                .caption(
                    format!(
                        "{}: omega {:.2}, alpha {:.3}: {:?}{settled}",
                        t.label, t.omega, t.alpha, t.outcome
                    ),
                    ("sans-serif", 13),
                )
                .margin(8)
                .x_label_area_size(38)
                .y_label_area_size(50)
                .build_cartesian_2d(0.0..t1, -y..y)
                .map_err(|e| plot_err(path, e))?;
            chart
                .configure_mesh()
                .x_desc(super::key::axis("t"))
                .y_desc(super::key::axis("phi"))
                .draw()
                .map_err(|e| plot_err(path, e))?;
            let frame = fine.frame(&chart);
            for piece in &pieces {
                let pen = Pen::new(mode_colour(piece.mode), 1.0);
                fine.line(&frame, piece.points.iter().map(|q| (q.0, q.1)), pen);
            }
        }
        Ok(())
    })
}
