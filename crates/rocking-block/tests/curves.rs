//! Two-parameter curves (Fig. 6): each passes through the one-parameter special points it
//! started from, and its user points (UZ) where it crosses alpha = 0.66 and omega = 1.3 are the
//! special points of Figs. 3 and 4 there, to 1e-9; a curve meets a separate one-parameter run.

use approx::assert_abs_diff_eq;
use hycont_continuation::observe::Silent;
use hycont_continuation::{CurveSpec, MeasureId, OrbitMethod, RunDirection, SpecialKind};
use hycont_core::orbit::CollocationSettings;
use rocking_block::continuation::{Free, default_method, study_branches, study_curves, study_run};
use rocking_block::orbits::{OrbitKind, orbit};
use rocking_block::{ALPHA, OMEGA, Parameters};
use std::f64::consts::PI;

#[test]
fn the_curves_meet_the_special_points_of_figures_3_and_4() {
    let fig3 = study_branches(Free::Omega, &mut Silent).unwrap();
    let fig4 = study_branches(Free::Alpha, &mut Silent).unwrap();
    let specials = |branches: &[hycont_continuation::OrbitBranch], k: SpecialKind, q| {
        branches
            .iter()
            .flat_map(|b| b.special(k))
            .map(|s| s.point[q])
            .collect::<Vec<f64>>()
    };
    let curves = study_curves(&mut Silent).unwrap();
    let kinds: Vec<SpecialKind> = curves.iter().map(|c| c.kind).collect();
    use SpecialKind::{BoundaryTouch as SB, BranchPoint as BP, Fold as SN, Grazing as GR};
    assert_eq!(kinds, [SN, BP, SB, GR, SpecialKind::PeriodDoubling]);
    // How many special points of its kind each curve meets on alpha = 0.66 and omega = 1.3:
    // SN1 | SN2; BP1, BP2 | BP3; SB1, SB2 | SB3; GR1 | GR2; PD1.
    let expected = [(1, 1), (2, 1), (2, 1), (1, 1), (0, 1)];
    for (c, (n_alpha, n_omega)) in curves.iter().zip(expected) {
        let uz: Vec<_> = c.branch.special(SpecialKind::UserPoint).collect();
        let on_alpha: Vec<f64> = uz
            .iter()
            .filter(|s| (s.point[ALPHA] - 0.66).abs() < 1e-9)
            .map(|s| s.point[OMEGA])
            .collect();
        let on_omega: Vec<f64> = uz
            .iter()
            .filter(|s| (s.point[OMEGA] - 1.3).abs() < 1e-9)
            .map(|s| s.point[ALPHA])
            .collect();
        assert_eq!(
            (on_alpha.len(), on_omega.len()),
            (n_alpha, n_omega),
            "{}",
            c.kind
        );
        for (values, fig, q) in [(on_alpha, &fig3, OMEGA), (on_omega, &fig4, ALPHA)] {
            let reference = specials(fig, c.kind, q);
            for v in values {
                let nearest = reference
                    .iter()
                    .map(|r| (r - v).abs())
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    nearest < 1e-9,
                    "{} UZ at {v}: {nearest:e} from Fig. 3/4",
                    c.kind
                );
            }
        }
        // Every point is a period-1 orbit of the forcing (half-orbit curves report the full
        // period), and the curve lies in the study's window.
        for p in &c.branch.branch.points {
            let forcing = 2.0 * PI / p[OMEGA];
            assert_abs_diff_eq!(p[MeasureId::PERIOD], forcing, epsilon = 1e-8 * forcing);
            assert!(p[OMEGA] >= 0.5 - 1e-9 && p[OMEGA] <= 4.0 + 1e-9);
        }
    }
}

#[test]
fn the_period_doubling_curve_meets_a_separate_alpha_continuation() {
    // The PD curve from PD1 (omega = 1.3), with a user point at omega = 2, against the PD
    // found by an alpha continuation of the asymmetric orbit at omega = 2.
    let params = Parameters::new(1.3, 0.66);
    let fig4 = study_branches(Free::Alpha, &mut Silent).unwrap();
    let pd1 = fig4[1].special(SpecialKind::PeriodDoubling).next().unwrap();
    let mut run = study_run(Free::Alpha, &params, Free::Alpha.range(), default_method()).unwrap();
    let spec = CurveSpec::new(OMEGA)
        .bounds(0.5, 4.0)
        .user_points(OMEGA, [2.0]);
    let c = run
        .curve_at("PD", &fig4[1], pd1.point.label, &spec)
        .unwrap();
    let uz = c.special(SpecialKind::UserPoint).next().unwrap();
    let alpha_curve = uz.point[ALPHA];
    let asym = orbit(&Parameters::new(2.0, 0.7), OrbitKind::AsymmetricPos, None)
        .unwrap()
        .solution
        .orbit;
    let mut run = study_run(Free::Alpha, &params, (0.5, 1.06), default_method()).unwrap();
    let b = run.run("asym", &asym, RunDirection::Up).unwrap();
    let pd = b.special(SpecialKind::PeriodDoubling).next().unwrap().point[ALPHA];
    assert_abs_diff_eq!(pd, alpha_curve, epsilon = 1e-9);
}

/// The symmetry-breaking curve by collocation (its own branch and curve on NTST 20, NCOL 4)
/// meets the shooting branch point BP3 at omega = 1.3 to the discretisation's accuracy.
#[test]
fn a_collocation_curve_agrees_with_shooting() {
    let params = Parameters::new(1.3, 0.66);
    let start = orbit(&params, OrbitKind::Symmetric, None)
        .unwrap()
        .solution
        .orbit;
    let method = OrbitMethod::Collocation(CollocationSettings::default());
    let mut run = study_run(Free::Omega, &params, (1.0, 1.35), method).unwrap();
    let b = run.run("symmetric", &start, RunDirection::Down).unwrap();
    let bp1 = b.special(SpecialKind::BranchPoint).next().unwrap();
    assert_abs_diff_eq!(bp1.point[OMEGA], 1.142_793_27, epsilon = 1e-7);
    let spec = CurveSpec::new(ALPHA)
        .bounds(0.01, 1.06)
        .user_points(OMEGA, [1.3])
        .direction(RunDirection::Up);
    let c = run.curve_at("BP", &b, bp1.point.label, &spec).unwrap();
    let bp3 = c.special(SpecialKind::UserPoint).next().unwrap().point[ALPHA];
    let fig4 = study_branches(Free::Alpha, &mut Silent).unwrap();
    let shooting = fig4[0]
        .special(SpecialKind::BranchPoint)
        .next()
        .unwrap()
        .point[ALPHA];
    assert_abs_diff_eq!(bp3, shooting, epsilon = 1e-7);
}
