//! Figs. 3 and 4: one-parameter continuation of the period-1 orbits (and the period-2 orbits
//! from the first period doubling), with special points.

use super::{FigureFiles, write_json};
use crate::continuation::{AMP, Free, study_branches_with};
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
    let labels = study_labels(&branches, free, &offsets);
    let json = json!({
        "figure": n,
        "parameters": {"omega": params.omega, "alpha": params.alpha, "xi": params.xi, "theta_b": params.theta_b},
        "static_boundary": params.static_boundary(),
        "branches": branches.iter().map(|b| branch_json(b, free)).collect::<Vec<_>>(),
        "labels": labels.iter().map(|(k, p, a, l)| json!({"label": l, "kind": k.label(), free.name(): p, "amp": a})).collect::<Vec<_>>(),
    });
    let json_path = out.join(format!("fig{n}.json"));
    write_json(&json_path, &provenance.insert_into(json))?;
    let plain: Vec<_> = branches.iter().map(|b| b.branch.clone()).collect();
    let pictures = out.picture(&format!("fig{n}"), |p| {
        let title = format!("{title}{}", provenance.block.note());
        plot::branches_svg(p, &title, &plain, free, &labels, params.static_boundary())
    })?;
    Ok(FigureFiles {
        figure: n,
        files: [vec![json_path], pictures].concat(),
    })
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
