//! Continuation of the rocking block against the study's published special points (Figs. 3, 4).

use crate::common;
use approx::assert_abs_diff_eq;

use common::{RunOk, bin};

use hycont_continuation::observe::Silent;
use hycont_continuation::{
    Branch, ContinuationSettings, OrbitContinuation, OrbitMethod, Quantity, RunDirection,
    SpecialKind, continue_branch,
};
use hycont_core::orbit::{CollocationSettings, PeriodicOrbit};
use rocking_block::block::Block;
use rocking_block::continuation::{AMP, Free, GRAZED, default_method, study_branches, study_run};
use rocking_block::figures::branches::figure_labels;
use rocking_block::orbits::{OrbitKind, orbit};
use rocking_block::{ALPHA, OMEGA, Parameters, RockingBlock};

/// The study's start: the symmetric orbit at (omega, alpha) = (1.3, 0.66) (Fig. 2).
fn fig2_symmetric() -> PeriodicOrbit {
    orbit(&Parameters::new(1.3, 0.66), OrbitKind::Symmetric, None)
        .unwrap()
        .solution
        .orbit
}

fn label_value(labels: &[(SpecialKind, f64, f64, String)], name: &str) -> f64 {
    labels
        .iter()
        .find(|l| l.3 == name)
        .unwrap_or_else(|| panic!("no {name} in {labels:?}"))
        .1
}

#[test]
fn figure_3_special_points_match_the_study() {
    let runs = study_branches(Free::Omega, &Block::default(), &mut Silent).unwrap();
    let labels = figure_labels(&runs, Free::Omega, &[]);
    let branches: Vec<Branch> = runs.into_iter().map(|b| b.branch).collect();
    let names: Vec<&str> = labels.iter().map(|l| l.3.as_str()).collect();
    assert_eq!(
        names,
        [
            "SN1", "BP1", "GR1", "SB1", "SB2", "BP2", "GR1:SN", "GR1:BP", "GR1:GR"
        ],
        "{labels:?}"
    );
    // Printed in the study: SN1 ~ 0.9096; SB2 ~ 2.6635 (to ~3e-3: the study's Amp was a mesh max).
    assert_abs_diff_eq!(label_value(&labels, "SN1"), 0.9096, epsilon = 5e-5);
    assert_abs_diff_eq!(label_value(&labels, "SB2"), 2.6635, epsilon = 3e-3);
    // Not printed in the study; found here (regression values of this implementation).
    for (name, value) in [
        ("BP1", 1.142_793_27),
        ("GR1", 1.236_048_01),
        ("SB1", 1.530_342_22),
        ("BP2", 3.746_735_33),
    ] {
        assert_abs_diff_eq!(label_value(&labels, name), value, epsilon = 1e-6);
    }
    // Every special point (but the end points and the asymmetric branch's end) is located to 1e-9.
    for b in &branches {
        for s in b
            .special_points
            .iter()
            .filter(|s| s.kind != SpecialKind::EndPoint)
        {
            assert!(
                s.located && s.accuracy < 1e-9,
                "{} {:?} not located: {}",
                b.name,
                s.kind,
                s.accuracy
            );
        }
    }
    // The symmetric branch is stable between SN1 and BP1, unstable on BP1..BP2, stable above BP2.
    let sym = &branches[0];
    for p in &sym.points {
        let (w, amp) = (p.params[0], p[AMP]);
        if amp > 0.35 && w > 0.95 && w < 1.12 {
            assert!(p.stable(), "omega {w}");
        }
        if amp > 0.35 && w > 1.17 && w < 3.7 {
            assert!(!p.stable(), "omega {w}");
        }
    }
    // The asymmetric branch (stable where it exists below the static boundary) joins BP1 and BP2.
    let asym = &branches[1];
    let first = asym.points.first().unwrap().params[0];
    let last = asym.points.last().unwrap().params[0];
    assert!((first - 1.142_793_27).abs() < 1e-6 && (last - 3.746_735_33).abs() < 1e-6);
    // GR1 ends the lower symmetric sheet where a flight's interior dip touches phi = 0
    // (terminal: beyond it phi changes sign inside the flight). Checked independently of the
    // grazing margin by dense samples of the orbit: the smallest s phi inside the flights is 0.
    let template = fig2_symmetric();
    let gr = sym.special(SpecialKind::Grazing).next().unwrap();
    // The branch does not go on past it (no lower-sheet orbit beyond GR1).
    assert!(
        sym.points
            .iter()
            .filter(|p| p[AMP] < 0.2)
            .all(|p| p.params[0] <= gr.point.params[0] + 1e-9)
    );
    let interior_min = |u: &[f64]| {
        let o = hycont_core::orbit::unpack(&template, u);
        let samples = o
            .sample(
                &RockingBlock,
                4001,
                &hycont_core::SimulationSettings::default()
                    .rtol(1e-11)
                    .atol(1e-13),
            )
            .unwrap();
        let mut lowest = f64::INFINITY;
        for (k, ts) in samples.iter().enumerate() {
            let sign = if o.signature.segments()[k].mode == rocking_block::PLUS {
                1.0
            } else {
                -1.0
            };
            let n = ts.len();
            for j in n / 100..n - n / 100 {
                lowest = lowest.min(sign * ts.state(j)[0]);
            }
        }
        lowest
    };
    let at_gr = interior_min(&gr.point.u);
    assert!(at_gr.abs() < 1e-7, "interior min of s phi at GR1: {at_gr}");
    // Before it (towards SN1 on the lower sheet) the dip is clear of the impact surface.
    let before = sym
        .points
        .iter()
        .find(|p| p[AMP] < 0.2 && p.params[0] < gr.point.params[0] - 0.02)
        .unwrap();
    assert!(interior_min(&before.u) > 1e-4);
}

#[test]
fn figure_4_special_points_match_the_study() {
    let runs = study_branches(Free::Alpha, &Block::default(), &mut Silent).unwrap();
    let offsets = [
        (SpecialKind::BranchPoint, 2),
        (SpecialKind::BoundaryTouch, 2),
        (SpecialKind::Fold, 1),
        (SpecialKind::Grazing, 1),
    ];
    let labels = figure_labels(&runs, Free::Alpha, &offsets);
    let branches: Vec<Branch> = runs.into_iter().map(|b| b.branch).collect();
    // Branches end on the special points their runs ended at: the symmetric branch runs from
    // GR2 (terminal) to the bound alpha = 1.06, the asymmetric branch from BP3 to the bound, the
    // period-2 branch to the bound (the branch past GR2 turns back from it: `tests/integration/grazing.rs`).
    let alpha = |p: &hycont_continuation::BranchPoint| p.params[1];
    let gr2 = branches[0].special(SpecialKind::Grazing).next().unwrap();
    assert_eq!(branches[0].points[0].u, gr2.point.u);
    for b in branches.iter().filter(|b| b.name != GRAZED) {
        assert_abs_diff_eq!(alpha(b.points.last().unwrap()), 1.06, epsilon = 1e-9);
    }
    let names: Vec<&str> = labels.iter().map(|l| l.3.as_str()).collect();
    assert_eq!(
        names,
        [
            "SN2", "GR2", "BP3", "SB3", "PD1", "PD2", "GR2:SN", "GR2:BP", "GR2:GR"
        ],
        "{labels:?}"
    );
    for (name, value) in [
        ("BP3", 0.6279),
        ("SB3", 0.6819),
        ("PD1", 0.7365),
        ("PD2", 0.7542),
    ] {
        assert_abs_diff_eq!(label_value(&labels, name), value, epsilon = 5e-5);
    }
    // PD2 is on the period-2 branch, born at PD1 with twice the period.
    let p2 = branches.iter().find(|b| b.name == "period-2").unwrap();
    assert!(
        p2.special(SpecialKind::PeriodDoubling)
            .any(|s| (s.point.params[1] - 0.7542).abs() < 5e-5)
    );
    let period1 = branches[1].points[1].monitors[0];
    assert_abs_diff_eq!(p2.points[1].monitors[0], 2.0 * period1, epsilon = 1e-6);
    // At PD1 a non-trivial multiplier is -1; at PD2 too (of the period-2 orbit).
    for s in branches
        .iter()
        .flat_map(|b| b.special(SpecialKind::PeriodDoubling))
    {
        let m = s
            .point
            .multipliers
            .iter()
            .zip(&s.point.trivial)
            .filter(|(_, t)| !**t)
            .map(|(m, _)| m.0)
            .fold(f64::INFINITY, f64::min);
        assert!((m + 1.0).abs() < 1e-6, "{m}");
    }
}

#[test]
fn reversing_the_direction_finds_the_same_special_points() {
    // Continue the symmetric branch downwards from omega = 1.3 (BP1, then SN1), and from a point
    // of the lower sheet upwards through SN1 and back to BP1: the same points to 1e-8.
    let start = fig2_symmetric();
    let way = |name, start: &PeriodicOrbit, range| {
        let params = Parameters::from_vec(&start.params);
        let mut run = study_run(Free::Omega, &params, range, default_method()).unwrap();
        let b = run.run(name, start, RunDirection::Down).unwrap();
        let at = |k| b.special(k).next().unwrap().point[OMEGA];
        (at(SpecialKind::Fold), at(SpecialKind::BranchPoint), b)
    };
    let (sn, bp, down) = way("down", &start, (0.5, 4.0));
    // A point on the lower sheet, past the fold.
    let lower = down.branch.points.iter().find(|p| p[AMP] < 0.2).unwrap();
    let (sn2, bp2, _) = way("back", &down.orbit_of(lower).unwrap(), (0.5, 1.3));
    assert_abs_diff_eq!(sn, sn2, epsilon = 1e-8);
    assert_abs_diff_eq!(bp, bp2, epsilon = 1e-8);
}

/// Symmetric orbits are continued on their half orbit (half the segments; the symmetry-breaking
/// branch points from the half map's multiplier -1). Against the same branch continued on the
/// full orbit: the same points (the half problem weighs its unknowns so that arclength is the
/// full problem's), the same special points and the same multipliers, to the integration's
/// accuracy (rtol 1e-10), and the same multipliers flagged trivial (where that is defined);
/// the points convert to the full orbit's unknowns.
#[test]
fn half_orbit_and_full_orbit_continuations_agree() {
    let params = Parameters::new(1.3, 0.66);
    let start = fig2_symmetric();
    let mut run = study_run(Free::Omega, &params, (0.5, 4.0), default_method()).unwrap();
    let (half, _) = run.problem(&start).unwrap();
    assert!(half.is_half_orbit());
    drop(half);
    let on_half = run.run("half", &start, RunDirection::Both).unwrap().branch;
    run.half_orbits(false);
    let (full, _) = run.problem(&start).unwrap();
    assert!(!full.is_half_orbit());
    drop(full);
    let on_full = run.run("full", &start, RunDirection::Both).unwrap().branch;
    let kinds = |b: &Branch| b.special_points.iter().map(|s| s.kind).collect::<Vec<_>>();
    assert_eq!(kinds(&on_half), kinds(&on_full));
    assert!(
        on_half
            .special_points
            .iter()
            .any(|s| s.kind == SpecialKind::BranchPoint)
    );
    assert_eq!(on_half.points.len(), on_full.points.len());
    let close = |a: &[f64], b: &[f64], tol: f64| {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(x, y)| (x - y).abs() <= tol * (1.0 + y.abs()))
    };
    let points = |b: &Branch| {
        let mut all: Vec<_> = b.points.clone();
        all.extend(b.special_points.iter().map(|s| s.point.clone()));
        all
    };
    for (h, f) in points(&on_half).iter().zip(&points(&on_full)) {
        // The unknowns in the full orbit's layout, the parameters to the location tolerance.
        assert!(close(&h.u, &f.u, 1e-8), "{:?} vs {:?}", h.u, f.u);
        assert!(close(&h.params, &f.params, 1e-9));
        assert!(close(&h.monitors, &f.monitors, 1e-8));
        assert_eq!(h.unstable, f.unstable);
        // Multipliers with their trivial flags, in the same order.
        let sorted = |p: &hycont_continuation::BranchPoint| {
            let mut m: Vec<_> = p
                .multipliers
                .iter()
                .copied()
                .zip(p.trivial.clone())
                .collect();
            m.sort_by(|a, b| a.0.0.total_cmp(&b.0.0).then(a.0.1.total_cmp(&b.0.1)));
            m
        };
        let (mh, mf) = (sorted(h), sorted(f));
        let flat = |m: &[((f64, f64), bool)]| {
            m.iter()
                .flat_map(|((a, b), _)| [*a, *b])
                .collect::<Vec<_>>()
        };
        assert!(close(&flat(&mh), &flat(&mf), 1e-8), "{mh:?} vs {mf:?}");
        // The same multipliers are flagged trivial, except between multipliers that coincide
        // (at a branch point two are 1 to the location's accuracy, and the trivial value 1
        // claims either): there only the number flagged must agree.
        let coincide = |i: usize| {
            let m = mh[i].0;
            mh.iter()
                .enumerate()
                .any(|(j, o)| j != i && (o.0.0 - m.0).hypot(o.0.1 - m.1) <= 1e-8)
        };
        assert!(
            mh.iter()
                .zip(&mf)
                .enumerate()
                .all(|(i, (a, b))| a.1 == b.1 || coincide(i)),
            "{mh:?} vs {mf:?}"
        );
        let flagged = |m: &[((f64, f64), bool)]| m.iter().filter(|x| x.1).count();
        assert_eq!(flagged(&mh), flagged(&mf), "{mh:?} vs {mf:?}");
    }
}

/// Unstable asymmetric orbits, which no simulation settles on, are found by continuation from
/// a symmetry-breaking branch point of the symmetric orbits: at (omega, alpha) = (1.3, 1.0),
/// past PD1, on Fig. 4's asymmetric branch (continued down from there, it has PD1 at the
/// study's 0.7365), leaning to the requested sides. Below BP3 there is none.
#[test]
fn unstable_asymmetric_orbits_are_found_by_continuation() {
    use rocking_block::orbits::mean_phi;
    let params = Parameters::new(1.3, 1.0);
    let pos = orbit(&params, OrbitKind::AsymmetricPos, None).unwrap();
    let amplitude = |o: &PeriodicOrbit| {
        use hycont_core::orbit::{Extremum, Measure};
        Extremum::max_abs(0).evaluate(&RockingBlock, o).unwrap()
    };
    let neg = orbit(&params, OrbitKind::AsymmetricNeg, None).unwrap();
    for (o, sign) in [(&pos, 1.0), (&neg, -1.0)] {
        assert!(o.solution.floquet.unstable > 0);
        assert!(!o.solution.orbit.is_symmetric(&RockingBlock, 1e-6));
        assert!(sign * mean_phi(&o.solution.orbit).unwrap() > 1e-3);
        assert_abs_diff_eq!(o.solution.orbit.params[1], 1.0, epsilon = 1e-12);
    }
    let amp = |o: &rocking_block::orbits::RockingOrbit| amplitude(&o.solution.orbit);
    assert_abs_diff_eq!(amp(&pos), amp(&neg), epsilon = 1e-9);
    let mut run = study_run(Free::Alpha, &params, (0.7, 1.06), default_method()).unwrap();
    let b = run
        .run("asymmetric", &pos.solution.orbit, RunDirection::Down)
        .unwrap();
    let pd = b.special(SpecialKind::PeriodDoubling).next().unwrap();
    assert_abs_diff_eq!(pd.point[ALPHA], 0.7365, epsilon = 5e-5);
    let none = orbit(&Parameters::new(1.3, 0.5), OrbitKind::AsymmetricPos, None);
    assert!(matches!(
        none,
        Err(rocking_block::Error::NoOrbit(ref m)) if m.contains("no asymmetric")
    ));
}

/// The default shooting and collocation on a coarse mesh (NTST 10 per segment, NCOL 4).
fn shooting_and_collocation() -> [OrbitMethod; 2] {
    [
        default_method(),
        OrbitMethod::Collocation(CollocationSettings {
            ntst: 10,
            ncol: 4,
            adapt: 1,
        }),
    ]
}

/// The symmetric branch from `start`, continued down in omega by `method` until its fold.
fn down_to_the_fold(start: &PeriodicOrbit, method: &OrbitMethod) -> Branch {
    down_to_the_fold_on(start, method).0
}

/// As [`down_to_the_fold`], with the problem it was continued on (the half-orbit problem).
fn down_to_the_fold_on(
    start: &PeriodicOrbit,
    method: &OrbitMethod,
) -> (Branch, OrbitContinuation<'static, RockingBlock>) {
    let params = Parameters::new(1.3, 0.66);
    let run = study_run(Free::Omega, &params, (0.5, 4.0), *method).unwrap();
    let (mut cp, u0) = run.problem(start).unwrap();
    let s = ContinuationSettings::default()
        .parameter_bounds(0.5, 4.0)
        .steps(0.02, 1e-8, 0.1)
        .stop_at(SpecialKind::Fold);
    let b = continue_branch(&mut cp, "sym", &u0, -1.0, &s, &mut Silent).unwrap();
    (b, cp)
}

/// The points of a half-orbit branch, unfolded, solve the full orbit's problem, for both
/// discretisations (shooting starts, collocation nodes), and the unfolded tangent is its
/// tangent (J t = 0).
#[test]
fn unfolded_half_orbit_points_solve_the_full_problem() {
    let start = fig2_symmetric();
    for method in shooting_and_collocation() {
        let (b, cp) = down_to_the_fold_on(&start, &method);
        assert!(cp.is_half_orbit());
        // A point, the symmetry-breaking branch point BP1 (where the half problem is regular:
        // its own tangent is kept) and the fold.
        let kinds: Vec<_> = b.special_points.iter().map(|s| s.kind).collect();
        assert_eq!(kinds, [SpecialKind::BranchPoint, SpecialKind::Fold]);
        let specials = b.special_points.iter().map(|s| &s.point);
        for p in std::iter::once(&b.points[b.points.len() / 2]).chain(specials) {
            let mut full = cp.full_orbit_problem_of(p).unwrap();
            let problem = full.problem_mut();
            let q = cp.full_point(p);
            assert_eq!(q.u.len(), problem.unknowns());
            assert_eq!(q.u.len(), 2 * p.u.len() - 5); // 4 parameters and the active slot
            let mut r = vec![0.0; problem.equations()];
            let mut jac = Vec::new();
            problem.evaluate(&q.u, &mut r, Some(&mut jac)).unwrap();
            let res = r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            assert!(res < 1e-8, "{method:?}: full residual {res:e}");
            // J t = 0 for the unfolded tangent.
            let dense = problem.dense_jacobian(&q.u).unwrap();
            let jt = dense
                .iter()
                .map(|row| row.iter().zip(&q.tangent).map(|(a, t)| a * t).sum::<f64>())
                .fold(0.0f64, |m, x| m.max(x.abs()));
            assert!(jt < 1e-6, "{method:?}: |J t| = {jt:e}");
        }
    }
}

#[test]
fn collocation_and_shooting_continuations_agree_on_the_fold() {
    let start = fig2_symmetric();
    let mut folds = Vec::new();
    for method in shooting_and_collocation() {
        let b = down_to_the_fold(&start, &method);
        let sn = b.special(SpecialKind::Fold).next().unwrap();
        folds.push((
            sn.point[OMEGA],
            sn.point.unstable,
            sn.point.multipliers.clone(),
        ));
    }
    assert_abs_diff_eq!(folds[0].0, folds[1].0, epsilon = 1e-7);
    // The critical multiplier 1 is on the unit circle up to each method's rounding: it is
    // neutral for both (`NEUTRAL_BAND`), so both classify the fold alike.
    assert_eq!(folds[0].1, folds[1].1, "{folds:?}");
}

/// The arclength of collocation weighs each segment's nodes by 1 / nodes (an L2 norm of the
/// orbit, as AUTO's), so refining the mesh does not shrink the steps: the same branch piece
/// takes about as many points with 4 times the mesh. (With the plain Euclidean norm of all
/// unknowns the steps shrink like 1 / sqrt(nodes): about twice the points.)
#[test]
fn collocation_steps_do_not_depend_on_the_mesh() {
    let start = fig2_symmetric();
    let mut points = Vec::new();
    for ntst in [10, 40] {
        let method = OrbitMethod::Collocation(CollocationSettings {
            ntst,
            ncol: 4,
            adapt: 1,
        });
        let b = down_to_the_fold(&start, &method);
        assert_eq!(
            b.end,
            hycont_continuation::EndReason::Reached(SpecialKind::Fold)
        );
        points.push(b.points.len() as f64);
    }
    assert!(
        points[1] <= 1.25 * points[0] && points[1] >= 0.8 * points[0],
        "points with NTST 10 and 40: {points:?}"
    );
}

/// Orbits whose amplitude reaches pi/2 overturn: the symmetric branch continued in alpha at
/// omega = 1.3 far beyond the study's range ends there, with a located end point on the amp
/// bound (without the bound it ran on through overturning orbits to alpha = 20).
#[test]
fn a_branch_ends_where_the_amplitude_reaches_pi_over_2() {
    let start = fig2_symmetric();
    let params = Parameters::new(1.3, 0.66);
    let mut run = study_run(Free::Alpha, &params, (0.01, 20.0), default_method()).unwrap();
    let b = run.run("sym", &start, RunDirection::Up).unwrap().branch;
    assert_eq!(b.end, hycont_continuation::EndReason::Bound);
    let ep = b.special_points.last().unwrap();
    assert_eq!(
        (ep.kind, ep.on),
        (SpecialKind::EndPoint, Some(Quantity::Measure(AMP)))
    );
    assert!(ep.located);
    assert_abs_diff_eq!(ep.point[AMP], std::f64::consts::FRAC_PI_2, epsilon = 1e-9);
    let alpha = ep.point.params[1];
    assert!(alpha > 3.0 && alpha < 5.0, "alpha {alpha}");
    // The branch reaches its end point; every orbit before it stands.
    let (last, before) = b.points.split_last().unwrap();
    assert_eq!(last.u, ep.point.u);
    assert!(before.iter().all(|p| p[AMP] < std::f64::consts::FRAC_PI_2));
}

/// The asymmetric branch in omega is a closed curve: through BP2 onto its mirror image and back
/// through BP1. Continued both ways from a point on it, the first run goes all the way round,
/// and the branch is that loop once (not twice, joined with a second run). The start can be
/// the orbit a simulation settles on, from --phi0/--psi0/--beta.
#[test]
fn a_closed_branch_is_traversed_once() {
    let out = bin()
        .args(["continue", "--free", "omega", "--kind", "simulate"])
        .args([
            "--phi0",
            "0.01",
            "--psi0",
            "0",
            "--beta",
            "1.5707963267948966",
        ])
        .arg("--json")
        .run_ok();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["end"], "Closed");
    let kinds: Vec<&str> = v["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["kind"].as_str().unwrap())
        .collect();
    let count = |k: &str| kinds.iter().filter(|&&x| x == k).count();
    assert_eq!((count("BP"), count("SB")), (2, 4), "{kinds:?}");
}

#[test]
fn continue_cli_saves_and_restarts() {
    let dir = std::env::temp_dir().join(format!("rocking-block-cont-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = dir.join("run.json");
    let out = bin()
        .args([
            "continue",
            "--free",
            "omega",
            "--direction",
            "down",
            "--json",
            "--out",
        ])
        .arg(&run)
        .run_ok();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["free"][0], "omega");
    let kinds: Vec<&str> = v["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["kind"].as_str().unwrap())
        .collect();
    assert_eq!(kinds, ["BP", "SN", "GR"]);
    let out = bin()
        .args(["continue", "--free", "omega", "--json", "--restart"])
        .arg(&run)
        .args(["--label", "20"])
        .run_ok();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let sn = v["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["kind"] == "SN")
        .unwrap();
    assert_abs_diff_eq!(sn["omega"].as_f64().unwrap(), 0.909_619_23, epsilon = 1e-7);
    // The saved run knows its parameter: without --free the restart is the same run.
    let implied = bin()
        .args(["continue", "--json", "--restart"])
        .arg(&run)
        .args(["--label", "20"])
        .run_ok();
    let w: serde_json::Value = serde_json::from_slice(&implied.stdout).unwrap();
    assert_eq!(w["free"], v["free"]);
    assert_eq!(w["special_points"], v["special_points"]);
    // A fresh start must name it.
    let unnamed = bin().args(["continue", "--json"]).output().unwrap();
    assert_eq!(unnamed.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&unnamed.stderr).contains("--free"));
    let bad = bin()
        .args(["continue", "--free", "omega", "--restart"])
        .arg(&run)
        .args(["--label", "9999"])
        .output()
        .unwrap();
    assert_ne!(bad.status.code(), Some(0));
    assert_eq!(
        String::from_utf8_lossy(&bad.stderr)
            .trim_end()
            .lines()
            .count(),
        1
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Down in alpha from the asymmetric orbit, the branch passes BP3 onto the mirror-image
/// orbits, whose SB, PD and EP repeat the first ones' values: the summary says so for each,
/// naming the first point and the BP, and says nothing of the points before the BP.
#[test]
fn continue_names_the_mirror_images_past_a_branch_point() {
    let out = bin()
        .args(["continue", "--free", "alpha", "--kind", "asymmetric-pos"])
        .run_ok();
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let lines: Vec<&str> = text.lines().filter(|l| l.contains(" label ")).collect();
    let label = |l: &str| l.split_whitespace().nth(2).unwrap().to_string();
    let bp = lines
        .iter()
        .position(|l| l.trim_start().starts_with("BP"))
        .expect("BP3");
    assert!(lines[..=bp].iter().all(|l| !l.contains("mirror")), "{text}");
    for line in &lines[bp + 1..] {
        let kind = line.split_whitespace().next().unwrap();
        let first = lines[..bp]
            .iter()
            .find(|l| l.trim_start().starts_with(kind))
            .expect(kind);
        let note = format!(
            "(as label {}: past BP label {}",
            label(first),
            label(lines[bp])
        );
        assert!(line.contains(&note), "{line} lacks {note}");
    }
}
