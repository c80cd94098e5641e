//! Figs. 3 and 4: one-parameter continuation of the period-1 orbits (and the period-2 orbits
//! from the first period doubling), with special points.

use super::{FigureFiles, write_json};
use crate::continuation::{AMP, Free, GRAZED, past_grazing, study_branches_with};
use crate::error::Result;
use crate::output::OutDir;
use crate::plot;
use crate::provenance::Provenance;
use crate::report::branch_json;
use hycont_continuation::OrbitBranch;
use hycont_continuation::SpecialKind;
use hycont_continuation::observe::Observer;
use serde_json::json;

/// Writes `fig3.json`/`fig3.svg` (free = omega at alpha = 0.66) or `fig4.json`/`fig4.svg`
/// (free = alpha at omega = 1.3).
///
/// # Errors
/// Numerical or I/O failures.
pub fn branches_figure(
    free: Free,
    out: &OutDir,
    provenance: &Provenance,
    observer: &mut dyn Observer,
) -> Result<FigureFiles> {
    let params = provenance.block.at(1.3, 0.66);
    let recipe = provenance.recipe();
    let branches = study_branches_with(free, &provenance.block, &recipe, observer)?;
    let n = if free == crate::continuation::Free::Omega {
        3
    } else {
        4
    };
    super::stopped_by(observer, n)?;
    let (n, offsets, title) = match free {
        Free::Omega => (3, vec![], "Fig. 3: continuation in omega at alpha = 0.66"),
        Free::Alpha => (
            4,
            // The study numbers special points across figures: Fig. 4's BP and SB follow Fig. 3's
            // two each, its fold and grazing Fig. 3's one each.
            vec![
                (SpecialKind::BranchPoint, 2),
                (SpecialKind::BoundaryTouch, 2),
                (SpecialKind::Fold, 1),
                (SpecialKind::Grazing, 1),
            ],
            "Fig. 4: continuation in alpha at omega = 1.3",
        ),
    };
    let labels = figure_labels(&branches, free, &offsets);
    let past = past_grazing_note(free, provenance, &branches, observer)?;
    let json = json!({
        "figure": n,
        "parameters": {"omega": params.omega, "alpha": params.alpha, "xi": params.xi, "theta_b": params.theta_b},
        "static_boundary": params.static_boundary(),
        "branches": branches.iter().map(|b| branch_json(b, free)).collect::<Vec<_>>(),
        "labels": labels.iter().map(|(k, p, a, l)| json!({"label": l, "kind": k.label(), free.name(): p, "amp": a})).collect::<Vec<_>>(),
        "past_grazing": past,
    });
    let json_path = out.join(format!("fig{n}.json"));
    write_json(&json_path, &provenance.insert_into(json))?;
    let plain: Vec<_> = branches.iter().map(|b| b.branch.clone()).collect();
    let zoom = grazing_zoom(&branches, free, &labels);
    let pictures = out.picture(&format!("fig{n}"), |p| {
        let failed = if past.starts_with("switch failed") {
            " (no branch past grazing: the switch failed)"
        } else {
            ""
        };
        let title = format!("{title}{}{failed}", provenance.block.note());
        plot::branches_svg(
            p,
            &title,
            &plain,
            free,
            &labels,
            params.static_boundary(),
            zoom.as_ref(),
        )
    })?;
    Ok(FigureFiles {
        figure: n,
        files: [vec![json_path], pictures].concat(),
    })
}

/// What became of the branch past grazing: "followed", "no grazing point", or "switch failed:
/// " and why (asked again of [`past_grazing`], which fails as the recipe's switch did).
fn past_grazing_note(
    free: Free,
    provenance: &Provenance,
    branches: &[OrbitBranch],
    observer: &mut dyn Observer,
) -> Result<String> {
    if branches.iter().any(|b| b.branch.name == GRAZED) {
        return Ok("followed".into());
    }
    let recipe = provenance.recipe();
    match past_grazing(free, &provenance.block, &recipe, &branches[0], observer) {
        Ok(None) => Ok("no grazing point".into()),
        Ok(Some(_)) => Ok("followed".into()),
        Err(crate::Error::Interrupted { detail }) => Err(crate::Error::Interrupted { detail }),
        Err(e) => Ok(format!("switch failed: {e}")),
    }
}

/// A zoom on the branch past grazing (its points and labels, the parent's grazing among
/// them): it lies within a few hundredths of the grazing parameter and Amp, too small for the
/// figure's scale.
fn grazing_zoom(
    branches: &[OrbitBranch],
    free: Free,
    labels: &[(SpecialKind, f64, f64, String)],
) -> Option<plot::Zoom> {
    let grazed = branches.iter().find(|b| b.branch.name == GRAZED)?;
    let q = free.id().index();
    let points = grazed.branch.points.iter().map(|p| (p.params[q], p[AMP]));
    let parent = labels
        .iter()
        .find_map(|l| l.3.split_once(':').map(|(gr, _)| gr))
        .unwrap_or("GR");
    let marked = labels
        .iter()
        .filter(|l| l.3 == parent || l.3.starts_with(&format!("{parent}:")))
        .map(|l| (l.1, l.2));
    let (mut x, mut y) = (
        (f64::INFINITY, f64::NEG_INFINITY),
        (f64::INFINITY, f64::NEG_INFINITY),
    );
    for (p, a) in points.chain(marked) {
        (x, y) = ((x.0.min(p), x.1.max(p)), (y.0.min(a), y.1.max(a)));
    }
    let pad = |(lo, hi): (f64, f64), f: f64| (lo - f * (hi - lo), hi + f * (hi - lo));
    Some(plot::Zoom {
        x: pad(x, 0.1),
        y: pad(y, 0.15),
        title: format!("past {parent}: the dip's two extra impacts"),
    })
}

/// The labels of a figure's special points: the study's ([`study_labels`]) on the study's
/// branches, and on the branch past grazing ([`GRAZED`]) its own points named after the
/// grazing it starts from (`GR1:SN`, `GR1:BP`, ...; a second of a kind `GR1:SN2`), so that the
/// study's numbering stays the study's.
#[must_use]
pub fn figure_labels(
    branches: &[OrbitBranch],
    free: Free,
    offsets: &[(SpecialKind, usize)],
) -> Vec<(SpecialKind, f64, f64, String)> {
    let (grazed, study): (Vec<_>, Vec<_>) = branches
        .iter()
        .cloned()
        .partition(|b| b.branch.name == GRAZED);
    let mut labels = study_labels(&study, free, offsets);
    for b in &grazed {
        let start = &b.branch.points[0];
        let (p0, a0) = (start.params[free.id().index()], start[AMP]);
        let parent = labels
            .iter()
            .find(|(k, p, a, _)| {
                *k == SpecialKind::Grazing && (p - p0).abs() < 1e-6 && (a - a0).abs() < 1e-4
            })
            .map_or_else(|| "GR".to_string(), |l| l.3.clone());
        for (k, p, a, n) in study_labels(std::slice::from_ref(b), free, &[]) {
            let n = n.trim_start_matches(k.label());
            let n = if n == "1" { "" } else { n };
            labels.push((k, p, a, format!("{parent}:{}{n}", k.label())));
        }
    }
    labels
}

/// Study labels (SN1, BP1, ...) for the special points of a figure's branches: numbered per kind
/// in increasing parameter order, starting after `offsets` (Fig. 4 continues Fig. 3's
/// numbering), with points that appear on two branches (e.g. a branch point) counted once.
#[must_use]
pub fn study_labels(
    branches: &[OrbitBranch],
    free: Free,
    offsets: &[(SpecialKind, usize)],
) -> Vec<(SpecialKind, f64, f64, String)> {
    let mut all: Vec<(SpecialKind, f64, f64)> = Vec::new();
    for s in branches.iter().flat_map(|b| &b.branch.special_points) {
        if matches!(s.kind, SpecialKind::EndPoint | SpecialKind::UserPoint) {
            continue;
        }
        let (p, amp) = (s.point[free.id()], s.point[AMP]);
        if !all
            .iter()
            .any(|(k, x, a)| *k == s.kind && (x - p).abs() < 1e-6 && (a - amp).abs() < 1e-4)
        {
            all.push((s.kind, p, amp));
        }
    }
    all.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut counts: Vec<(SpecialKind, usize)> = offsets.to_vec();
    all.into_iter()
        .map(|(k, p, a)| {
            let n = match counts.iter_mut().find(|(kk, _)| *kk == k) {
                Some((_, c)) => {
                    *c += 1;
                    *c
                }
                None => {
                    counts.push((k, 1));
                    1
                }
            };
            (k, p, a, format!("{}{n}", k.label()))
        })
        .collect()
}
