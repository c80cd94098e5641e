//! The study's atlas (`rocking-block figure atlas`): the symmetric period-one orbits over
//! (omega, alpha) as two sheets joined along the fold. Checked against independent
//! computations: every boundary chart on the fold (SN) or the grazing (GR) edge lies on the
//! SN or GR curve continued from Fig. 3's points (its user point at the chart's alpha has the
//! chart's omega to 1e-6), bound charts lie on their bounds, and every other chart of both
//! sheets (all but those on or beside a fold or grazing edge) is the orbit that one-parameter
//! branches reach at the same (omega, alpha), chart to neighbouring chart from the sheet's
//! start; four of them also by two long branches from the Fig. 2 orbit (in alpha at
//! omega = 1.3, then in omega): Amp and period to 1e-9.

use hycont_continuation::atlas::{AtlasEnd, Edge};
use hycont_continuation::observe::Silent;
use hycont_continuation::{CurveSpec, MeasureId, OrbitAtlas, RunDirection, SpecialKind};
use hycont_core::orbit::PeriodicOrbit;
use rocking_block::RockingBlock;
use rocking_block::block::Block;
use rocking_block::continuation::{
    AMP, ATLAS_WINDOW, Recipe, default_method, study_branches_from, study_run, study_start,
};
use rocking_block::figures::atlas::study_sheets;
use rocking_block::model::{ALPHA, Free, OMEGA, Parameters};
use std::sync::OnceLock;

fn sheets() -> &'static [OrbitAtlas] {
    static SHEETS: OnceLock<Vec<OrbitAtlas>> = OnceLock::new();
    SHEETS.get_or_init(|| study_sheets(&Block::default(), &mut Silent).unwrap())
}

#[test]
fn both_sheets_are_covered_within_the_window() {
    let [(w0, w1), (a0, a1)] = ATLAS_WINDOW;
    for sheet in sheets() {
        let atlas = &sheet.atlas;
        assert_eq!(atlas.end, AtlasEnd::Covered, "{}", atlas.name);
        for c in &atlas.charts {
            let (w, a) = (c.point[OMEGA], c.point[ALPHA]);
            assert!(w >= w0 - 1e-9 && w <= w1 + 1e-9 && a >= a0 - 1e-9 && a <= a1 + 1e-9);
            // Located to the location tolerance (relative to the radius) in arclength, which
            // bounds the change of a parameter or of Amp (weight 1).
            if let Some(Edge::Bound { on, level }) = c.edge {
                let tol = atlas.settings.locate_tol * c.radius;
                assert!((c.point.value(on).unwrap() - level).abs() <= tol, "{level}");
            }
        }
        assert!(
            atlas.edge_charts(SpecialKind::Fold).count() >= 10,
            "{}",
            atlas.name
        );
    }
    // The sheet beyond the fold ends on the grazing curve; the first does not reach it.
    assert!(sheets()[1].atlas.edge_charts(SpecialKind::Grazing).count() >= 10);
    assert_eq!(
        sheets()[0].atlas.edge_charts(SpecialKind::Grazing).count(),
        0
    );
}

/// The omega of each user point of the curve of `kind` (from Fig. 3's symmetric branch) at
/// the alphas asked for.
fn curve_omegas(kind: SpecialKind, alphas: &[f64]) -> Vec<(f64, f64)> {
    let block = Block::default();
    let start = study_start(&block).unwrap();
    let fig3 =
        study_branches_from(Free::Omega, &block, &Recipe::default(), &start, &mut Silent).unwrap();
    let params = block.at(1.3, 0.66);
    let mut run = study_run(Free::Omega, &params, Free::Omega.range(), default_method()).unwrap();
    let spec = CurveSpec::new(ALPHA)
        .bounds(0.05, 0.95)
        .user_points(ALPHA, alphas.iter().copied());
    let label = fig3[0].first(kind).unwrap().point.label;
    let curve = run.curve_at(kind.label(), &fig3[0], label, &spec).unwrap();
    curve
        .special(SpecialKind::UserPoint)
        .map(|s| (s.point[ALPHA], s.point[OMEGA]))
        .collect()
}

#[test]
fn fold_and_grazing_charts_lie_on_the_curves() {
    assert_edge_on_curve(&sheets()[0], SpecialKind::Fold);
    assert_edge_on_curve(&sheets()[1], SpecialKind::Fold);
    assert_edge_on_curve(&sheets()[1], SpecialKind::Grazing);
}

/// Every boundary chart of `sheet` on the edge `kind` (away from the window's corners, where a
/// chart may sit on a bound and the edge) has the omega of the `kind` curve at its alpha, to
/// 1e-6 (the location tolerance is 1e-6 of a radius in arclength).
fn assert_edge_on_curve(sheet: &OrbitAtlas, kind: SpecialKind) {
    let charts: Vec<(f64, f64)> = sheet
        .atlas
        .edge_charts(kind)
        .map(|c| (c.point[ALPHA], c.point[OMEGA]))
        .filter(|(a, _)| *a > 0.12 && *a < 0.88)
        .collect();
    assert!(charts.len() >= 8, "{} {kind:?}", sheet.atlas.name);
    let alphas: Vec<f64> = charts.iter().map(|c| c.0).collect();
    let uz = curve_omegas(kind, &alphas);
    for (alpha, omega) in charts {
        let nearest = uz
            .iter()
            .filter(|(a, _)| (a - alpha).abs() < 1e-9)
            .map(|(_, w)| (w - omega).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 1e-6,
            "{kind:?} chart at ({omega}, {alpha}): {nearest:e}"
        );
    }
}

/// The orbit at (omega, alpha) nearest in Amp to `amp`, by two one-parameter branches: in
/// alpha at omega = 1.3 from the Fig. 2 orbit to alpha (the sheet through it), then in omega
/// at alpha both ways (it turns at the fold onto the other sheet): Amp and period there.
fn by_branches(omega: f64, alpha: f64, amp: f64) -> (f64, f64) {
    let block = Block::default();
    let start = study_start(&block).unwrap();
    let params = Parameters::from_vec(&start.params);
    let mut run = study_run(Free::Alpha, &params, ATLAS_WINDOW[1], default_method()).unwrap();
    run.add_user_points(ALPHA, [alpha]).unwrap();
    let in_alpha = run.run("alpha", &start, RunDirection::Both).unwrap();
    let uz = in_alpha
        .special(SpecialKind::UserPoint)
        .max_by(|a, b| a.point[AMP].total_cmp(&b.point[AMP]))
        .unwrap();
    let there = in_alpha.orbit_of(&uz.point).unwrap();
    let params = Parameters::from_vec(&there.params);
    let mut run = study_run(Free::Omega, &params, ATLAS_WINDOW[0], default_method()).unwrap();
    run.add_user_points(OMEGA, [omega]).unwrap();
    let in_omega = run.run("omega", &there, RunDirection::Both).unwrap();
    let uz = in_omega
        .special(SpecialKind::UserPoint)
        .min_by(|a, b| {
            (a.point[AMP] - amp)
                .abs()
                .total_cmp(&(b.point[AMP] - amp).abs())
        })
        .unwrap();
    (uz.point[AMP], uz.point[MeasureId::PERIOD])
}

#[test]
fn charts_are_the_orbits_of_one_parameter_branches() {
    for sheet in sheets() {
        let interior: Vec<_> = sheet
            .atlas
            .charts
            .iter()
            // Not next to an edge: a user point a hair from a fold is stepped over with it.
            .filter(|c| {
                let beside_edge = c
                    .neighbours
                    .iter()
                    .any(|&n| sheet.atlas.charts[n].is_boundary());
                !c.is_boundary() && !beside_edge && c.point[ALPHA] > 0.5
            })
            .collect();
        // Four charts spread over the sheet (not its first, where the branches start: a user
        // point at a run's start is not a crossing).
        for k in 1..=4 {
            let c = interior[k * (interior.len() - 1) / 4];
            let (omega, alpha, amp) = (c.point[OMEGA], c.point[ALPHA], c.point[AMP]);
            let (b_amp, b_period) = by_branches(omega, alpha, amp);
            assert!(
                (b_amp - amp).abs() < 1e-9,
                "{}: ({omega}, {alpha}) amp {amp} vs {b_amp}",
                sheet.atlas.name
            );
            assert!((b_period - c.point[MeasureId::PERIOD]).abs() < 1e-9);
        }
    }
}

/// One one-parameter branch of the study's recipe from `from` in `free` to `to`: the run goes
/// that way only, bounded a little past `to`, and the orbit, Amp and period of its user point
/// at `to` are returned (`from` itself when it is already there).
fn leg(from: &PeriodicOrbit, free: Free, to: f64) -> Option<(PeriodicOrbit, f64, f64)> {
    const PAST: f64 = 1e-2;
    let at = from.params[free.id().index()];
    let params = Parameters::from_vec(&from.params);
    let (range, direction) = if to >= at {
        ((at - PAST, to + PAST), RunDirection::Up)
    } else {
        ((to - PAST, at + PAST), RunDirection::Down)
    };
    let mut run = study_run(free, &params, range, default_method()).ok()?;
    if to == at {
        let branch = run.run("here", from, RunDirection::Up).ok()?;
        let p = branch.branch.points.first()?;
        return Some((from.clone(), p[AMP], p[MeasureId::PERIOD]));
    }
    run.add_user_points(free.id(), [to]).ok()?;
    let branch = run.run("leg", from, direction).ok()?;
    let uz = branch.special(SpecialKind::UserPoint).next()?;
    let orbit = branch.orbit_of(&uz.point).ok()?;
    Some((orbit, uz.point[AMP], uz.point[MeasureId::PERIOD]))
}

/// `from` continued to (omega, alpha) by two one-parameter branches: in alpha, then in omega
/// (or the other way round when that path leaves the sheet).
fn continued(from: &PeriodicOrbit, omega: f64, alpha: f64) -> Option<(PeriodicOrbit, f64, f64)> {
    let path = |first: Free, second: Free| {
        let value = |f: Free| if f == Free::Alpha { alpha } else { omega };
        let (there, ..) = leg(from, first, value(first))?;
        leg(&there, second, value(second))
    };
    path(Free::Alpha, Free::Omega).or_else(|| path(Free::Omega, Free::Alpha))
}

/// Every chart of both sheets, except those on a fold or grazing edge and their neighbours
/// (those are checked against the SN and GR curves above; a user point a hair from a fold is
/// ill-posed for a one-parameter branch), is the orbit that one-parameter branches reach at its
/// (omega, alpha): from the sheet's start (the Fig. 2 orbit; Fig. 3's orbit beyond the fold),
/// chart to neighbouring chart, each reference orbit continued from its parent's reference (not
/// from a chart) by a branch in alpha and one in omega. Amp and period to 1e-9.
#[test]
fn every_chart_is_the_orbit_of_one_parameter_branches() {
    for sheet in sheets() {
        let charts = &sheet.atlas.charts;
        let on_curve = |i: usize| matches!(charts[i].edge, Some(Edge::Special { .. }));
        let checked = |i: usize| !on_curve(i) && !charts[i].neighbours.iter().any(|&n| on_curve(n));
        let root = sheet.orbit_of(&RockingBlock, &charts[0]).unwrap();
        let mut reached = vec![false; charts.len()];
        reached[0] = true;
        let (mut worst, mut compared): (f64, usize) = (0.0, 0);
        let mut queue = std::collections::VecDeque::from([(0, root)]);
        while let Some((i, reference)) = queue.pop_front() {
            for &n in &charts[i].neighbours {
                if reached[n] || !checked(n) {
                    continue;
                }
                let c = &charts[n];
                let (omega, alpha) = (c.point[OMEGA], c.point[ALPHA]);
                let Some((orbit, amp, period)) = continued(&reference, omega, alpha) else {
                    continue; // tried again from another neighbour
                };
                let name = &sheet.atlas.name;
                worst = worst
                    .max((amp - c.point[AMP]).abs())
                    .max((period - c.point[MeasureId::PERIOD]).abs());
                assert!(
                    (amp - c.point[AMP]).abs() < 1e-9,
                    "{name} chart {n} at ({omega}, {alpha}): Amp {} vs {amp}",
                    c.point[AMP]
                );
                assert!((period - c.point[MeasureId::PERIOD]).abs() < 1e-9);
                reached[n] = true;
                compared += 1;
                queue.push_back((n, orbit));
            }
        }
        let eligible = (0..charts.len()).filter(|&i| checked(i)).count();
        eprintln!(
            "{}: {compared} charts of {} compared (and the start), worst difference {worst:.1e}",
            sheet.atlas.name,
            charts.len()
        );
        let missed: Vec<usize> = (0..charts.len())
            .filter(|&i| checked(i) && !reached[i])
            .collect();
        assert!(
            missed.is_empty(),
            "{}: {} of {eligible} charts not reached: {missed:?}",
            sheet.atlas.name,
            missed.len()
        );
    }
}

/// By collocation (the study's mesh), the sheet through the Fig. 2 orbit has the same fold
/// edge: its SN charts lie on the SN curve continued by shooting (to 1e-6, the location
/// tolerance; the discretisations agree to ~1e-10 here).
#[test]
fn collocation_covers_the_sheet_with_the_same_fold() {
    use hycont_continuation::OrbitMethod;
    use hycont_core::orbit::CollocationSettings;
    let block = Block::default();
    let start = study_start(&block).unwrap();
    let method = OrbitMethod::Collocation(CollocationSettings::default());
    let settings = rocking_block::continuation::atlas_settings();
    let sheet = rocking_block::continuation::study_atlas(
        "collocation",
        &start,
        method,
        &settings,
        &mut Silent,
    )
    .unwrap();
    assert_eq!(sheet.atlas.end, AtlasEnd::Covered);
    assert_edge_on_curve(&sheet, SpecialKind::Fold);
}

use crate::common;

/// `rocking-block figure atlas --out DIR --format both` writes `atlas.json` with every chart
/// of both sheets (omega, alpha, Amp, stability, edge, polygon) inside the window, and the
/// picture as SVG and PNG; `figure atlas` with a recipe option of the branch figures is refused
/// in one line naming the figure (exit 2).
#[test]
fn the_cli_writes_the_atlas_figure() {
    use common::{RunOk, bin, json, scratch};
    let dir = scratch("atlas-figure");
    bin()
        .args(["figure", "atlas", "--format", "both", "--out"])
        .arg(&dir)
        .run_ok();
    let v = json(&dir.join("atlas.json"));
    let charts = v["charts"].as_array().unwrap();
    let sheets = v["sheets"].as_array().unwrap();
    assert_eq!(sheets.len(), 2);
    let counted: u64 = sheets.iter().map(|s| s["charts"].as_u64().unwrap()).sum();
    assert_eq!(charts.len() as u64, counted);
    let [(w0, w1), (a0, a1)] = ATLAS_WINDOW;
    for c in charts {
        let (w, a) = (c["omega"].as_f64().unwrap(), c["alpha"].as_f64().unwrap());
        assert!(w >= w0 - 1e-9 && w <= w1 + 1e-9 && a >= a0 - 1e-9 && a <= a1 + 1e-9);
        assert!(c["amp"].as_f64().unwrap() > 0.0);
        assert!(c["stable"].is_boolean());
    }
    let edges = |e: &str| charts.iter().filter(|c| c["edge"] == e).count();
    assert!(edges("SN") >= 20 && edges("GR") >= 10 && edges("EP") >= 20);
    assert!(dir.join("atlas.svg").exists() && dir.join("atlas.png").exists());
    let out = bin()
        .args(["figure", "atlas", "--method", "collocation", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    common::fails(&out, 2, "figures atlas");
    std::fs::remove_dir_all(&dir).ok();
}
