//! Keys drawn beside the sampling figures: a swatch per solution class drawn, a line per curve.

use plotters::coord::Shift;
use plotters::prelude::*;

/// How an entry of a key is marked.
#[derive(Debug, Clone, Copy)]
pub(super) enum Mark {
    /// A filled square (a class's colour).
    Swatch(RGBColor),
    /// A line (a curve's colour).
    Line(RGBColor),
    /// A dashed line.
    Dashed(RGBColor),
    /// A cross (a marked point).
    Cross(RGBColor),
    /// A dot of a radius (px).
    Dot(RGBColor, i32),
    /// No mark: the entry continues the one above.
    Blank,
}

/// `c` over white at opacity `a` (as drawn with `c.mix(a)`).
pub(super) fn over_white(c: RGBColor, a: f64) -> RGBColor {
    let f = |v: u8| (a * f64::from(v) + (1.0 - a) * 255.0).round() as u8;
    RGBColor(f(c.0), f(c.1), f(c.2))
}

/// The solution classes in the order keys list them, with their colours.
const CLASSES: [(&str, RGBColor); 8] = [
    ("symmetric_p1", RGBColor(255, 200, 0)),
    ("asymmetric_p1_pos", RGBColor(31, 119, 180)),
    ("asymmetric_p1_neg", RGBColor(214, 39, 40)),
    ("period2", RGBColor(44, 160, 44)),
    ("other", RGBColor(148, 103, 189)),
    ("equilibrium", RGBColor(0, 0, 0)),
    ("overturn_pos", RGBColor(140, 200, 140)),
    ("overturn_neg", RGBColor(200, 140, 200)),
];

/// The colour every figure draws a two-parameter curve of `kind` in.
pub(super) fn curve_colour(kind: hycont_continuation::SpecialKind) -> RGBColor {
    use hycont_continuation::SpecialKind;
    match kind {
        SpecialKind::Fold => RGBColor(255, 127, 14),
        SpecialKind::PeriodDoubling => RGBColor(44, 160, 44),
        SpecialKind::BranchPoint => RGBColor(148, 103, 189),
        SpecialKind::BoundaryTouch => RGBColor(214, 39, 40),
        _ => RGBColor(140, 86, 75),
    }
}

/// The colour of a class (white for an unknown name).
pub(super) fn class_colour(name: &str) -> RGBColor {
    CLASSES
        .iter()
        .find(|(n, _)| *n == name)
        .map_or(RGBColor(255, 255, 255), |(_, c)| *c)
}

/// The study's description of a class, with its name in the JSON.
fn class_label(name: &str) -> String {
    let words = match name {
        "symmetric_p1" => "symmetric period 1",
        "asymmetric_p1_pos" => "asymmetric period 1, phi > 0",
        "asymmetric_p1_neg" => "asymmetric period 1, phi < 0",
        "period2" => "period 2",
        "other" => "other (longer period, chaotic)",
        "equilibrium" => "rest on the ground",
        "overturn_pos" => "overturn, phi > 0",
        "overturn_neg" => "overturn, phi < 0",
        _ => return name.to_string(),
    };
    format!("{words} ({name})")
}

/// Key entries for the classes among `drawn`, in the study's order.
pub(super) fn class_entries<'a>(drawn: impl IntoIterator<Item = &'a str>) -> Vec<(String, Mark)> {
    let drawn: Vec<&str> = drawn.into_iter().collect();
    CLASSES
        .iter()
        .filter(|(n, _)| drawn.contains(n))
        .map(|(n, c)| (class_label(n), Mark::Swatch(*c)))
        .collect()
}

/// Draws `title` and the entries, one per row, from the top of `area`.
pub(super) fn draw_key<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    entries: &[(String, Mark)],
) -> Result<(), String> {
    let font = ("sans-serif", 13).into_font();
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    area.draw(&Text::new(
        title.to_string(),
        (8, 10),
        font.clone().style(FontStyle::Bold),
    ))
    .map_err(err)?;
    for (k, (label, mark)) in entries.iter().enumerate() {
        let y = 40 + 22 * k as i32;
        match *mark {
            Mark::Swatch(c) => area
                .draw(&Rectangle::new([(8, y - 7), (24, y + 7)], c.filled()))
                .and_then(|()| {
                    area.draw(&Rectangle::new(
                        [(8, y - 7), (24, y + 7)],
                        BLACK.mix(0.4).stroke_width(1),
                    ))
                }),
            Mark::Line(c) => area.draw(&PathElement::new(vec![(6, y), (26, y)], c.stroke_width(2))),
            Mark::Dashed(c) => area
                .draw(&PathElement::new(vec![(6, y), (12, y)], c.stroke_width(1)))
                .and_then(|()| {
                    area.draw(&PathElement::new(vec![(17, y), (23, y)], c.stroke_width(1)))
                }),
            Mark::Cross(c) => area.draw(&Cross::new((16, y), 5, c.stroke_width(2))),
            Mark::Dot(c, r) => area.draw(&Circle::new((16, y), r, c.filled())),
            Mark::Blank => Ok(()),
        }
        .map_err(err)?;
        area.draw(&Text::new(label.clone(), (32, y - 7), font.clone()))
            .map_err(err)?;
    }
    Ok(())
}

/// A vertical colour scale from 0 to `max` under `caption`, `colour` of the fraction of
/// `max`, in `steps` bands with `labels` ticks (the room right of it: `margin_right` px).
pub(super) fn colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    caption: &str,
    max: f64,
    (steps, labels, margin_right): (u32, usize, u32),
    colour: impl Fn(f64) -> RGBColor,
) -> Result<(), String> {
    let mut bar = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 14))
        .margin(10)
        .margin_right(margin_right)
        .y_label_area_size(40)
        .build_cartesian_2d(0.0..1.0, 0.0..max)
        .map_err(|e| e.to_string())?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(labels)
        .y_label_style(("sans-serif", 13))
        .y_label_formatter(&|v| format!("{v:.2}"))
        .draw()
        .map_err(|e| e.to_string())?;
    bar.draw_series((0..steps).map(|k| {
        let (lo, hi) = (
            f64::from(k) / f64::from(steps),
            f64::from(k + 1) / f64::from(steps),
        );
        Rectangle::new([(0.0, lo * max), (1.0, hi * max)], colour(lo).filled())
    }))
    .map_err(|e| e.to_string())?;
    // The top of the bar, ticked right of it, unless a tick (of 0.1) is there already.
    if (max * 10.0 - (max * 10.0).round()).abs() > 0.02 {
        let (px, py) = bar.backend_coord(&(1.0, max));
        let (bx, by) = area.get_base_pixel();
        let (x, y) = (px - bx, py - by);
        area.draw(&PathElement::new(
            vec![(x, y), (x + 5, y)],
            BLACK.stroke_width(1),
        ))
        .map_err(|e| e.to_string())?;
        let font = ("sans-serif", 13).into_font();
        area.draw(&Text::new(format!("{max:.3} (max)"), (x + 8, y - 2), font))
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// A special point's label with what it stands for, for keys: `SN (fold)`, ...
pub(super) fn spelled(label: &str) -> String {
    let meaning = match label {
        "SN" => "fold, saddle-node",
        "BP" => "branch point",
        "PD" => "period doubling",
        "TR" => "torus",
        "SB" => "Amp at the boundary",
        "GR" => "grazing",
        "DB" => "domain boundary",
        "UZ" => "user point",
        "EP" => "end point",
        "OV" => "overturn test point",
        "R1" => "1:1 resonance",
        "R2" => "1:2 resonance",
        "LPPD" => "fold-flip",
        "LPNS" => "fold-torus",
        "PDNS" => "flip-torus",
        "CP" => "cusp",
        _ => return label.to_string(),
    };
    format!("{label} ({meaning})")
}

/// An axis's title: the study's variable with its meaning and unit (every quantity of the
/// study is dimensionless, angles in radians).
pub(super) fn axis(name: &str) -> String {
    let meaning = match name {
        "omega" => "forcing frequency / Omega0, dimensionless",
        "alpha" => "forcing amplitude / R, dimensionless",
        "beta" => "forcing phase, rad",
        "phi" => "rotation angle, rad",
        "phi0" => "initial rotation angle, rad",
        "psi" => "angular velocity, rad per unit time",
        "psi0" => "initial angular velocity, rad per unit time",
        "t" => "time x Omega0, dimensionless",
        "Amp" => "max |phi| over the orbit, rad",
        _ => return name.to_string(),
    };
    format!("{name} ({meaning})")
}
