//! Two-parameter curves (Fig. 6): each passes through the one-parameter points it started from
//! and through the corresponding points of the other one-parameter run, to 1e-6.

use hycont_continuation::observe::Silent;
use hycont_continuation::{Condition, SpecialKind};
use hycont_core::orbit::unpack;
use rocking_block::continuation::{Free, curve, study_branches};
use rocking_block::orbits::{OrbitKind, orbit};
use rocking_block::{Parameters, RockingBlock};

/// The alpha of a curve where it ends on the bound omega = 1.3 (located exactly).
fn alpha_at_end(c: &rocking_block::continuation::Curve) -> f64 {
    let ep = c
        .branch
        .special(SpecialKind::EndPoint)
        .find(|s| (s.point.params[0] - 1.3).abs() < 1e-9)
        .unwrap_or_else(|| panic!("{:?} curve does not reach omega = 1.3", c.kind));
    ep.point.params[1]
}

#[test]
fn curves_started_in_figure_3_pass_through_the_points_of_figure_4() {
    let params = Parameters::new(1.3, 0.66);
    let fig3 = study_branches(Free::Omega, &mut Silent).unwrap();
    let fig4 = study_branches(Free::Alpha, &mut Silent).unwrap();
    let template = orbit(&params, OrbitKind::Symmetric, None)
        .unwrap()
        .solution
        .orbit;
    let point = |b: &hycont_continuation::Branch, k: SpecialKind| {
        b.special(k).next().unwrap().point.clone()
    };
    // Curves from alpha = 0.66 (Fig. 3) to omega = 1.3 (Fig. 4's line), exact end points there.
    let cases = [
        (
            SpecialKind::Fold,
            Condition::SymmetricFold,
            (0.5, 1.3),
            true,
        ),
        (
            SpecialKind::BranchPoint,
            Condition::SymmetryBreaking,
            (0.5, 1.3),
            true,
        ),
        (
            SpecialKind::Grazing,
            Condition::Grazing { index: 1 },
            (0.5, 1.3),
            true,
        ),
    ];
    for (kind, condition, range, symmetric) in cases {
        let start = point(&fig3[0], kind);
        let mut o = unpack(&template, &start.u);
        for d in &mut o.durations {
            if d.abs() < 1e-8 {
                *d = 0.0;
            }
        }
        let o = if symmetric {
            o.half_of_symmetric(&RockingBlock, 1e-5).unwrap()
        } else {
            o
        };
        let condition = match condition {
            Condition::Collapse { .. } => Condition::Collapse {
                segment: o
                    .durations
                    .iter()
                    .enumerate()
                    .min_by(|a, b| a.1.total_cmp(b.1))
                    .unwrap()
                    .0,
            },
            c => c,
        };
        let c = curve(kind.label(), &o, condition, range, &mut Silent).unwrap();
        // Through its start...
        assert!(
            c.branch
                .points
                .iter()
                .any(|p| (p.params[0] - start.params[0]).abs() < 1e-9
                    && (p.params[1] - 0.66).abs() < 1e-9)
        );
        // ...and through Fig. 4's point of the same kind at omega = 1.3.
        let expected = point(&fig4[0], kind).params[1];
        let got = alpha_at_end(&c);
        assert!(
            (got - expected).abs() < 1e-6,
            "{kind:?}: curve alpha {got} vs Fig. 4 {expected}"
        );
        // The full orbit's period on every point (half-orbit curves included): one forcing
        // period, 2 pi / omega.
        for p in &c.branch.points {
            let forcing = 2.0 * std::f64::consts::PI / p.params[0];
            assert!(
                (p.monitors[0] - forcing).abs() < 1e-8 * forcing,
                "{kind:?}: period {} at omega {}",
                p.monitors[0],
                p.params[0]
            );
        }
    }
    // The SB curve from SB2 (asymmetric branch of Fig. 3) reaches SB3 of Fig. 4.
    let sb2 = fig3[1]
        .special(SpecialKind::BoundaryTouch)
        .last()
        .unwrap()
        .point
        .clone();
    let c = curve(
        "SB",
        &unpack(&template, &sb2.u),
        Condition::Monitor {
            index: 0,
            level: params.static_boundary(),
        },
        (1.3, 4.0),
        &mut Silent,
    )
    .unwrap();
    let sb3 = fig4[1]
        .special(SpecialKind::BoundaryTouch)
        .next()
        .unwrap()
        .point
        .params[1];
    assert!((alpha_at_end(&c) - sb3).abs() < 1e-6);
}

#[test]
fn the_period_doubling_curve_meets_a_separate_alpha_continuation() {
    // The PD curve from PD1 (omega = 1.3) followed to omega = 2.0, against the PD found by an
    // alpha-continuation of the asymmetric orbit at omega = 2.0.
    use rocking_block::continuation::{Direction, continue_orbit, default_method};
    let params = Parameters::new(1.3, 0.66);
    let fig4 = study_branches(Free::Alpha, &mut Silent).unwrap();
    let template = orbit(&params, OrbitKind::Symmetric, None)
        .unwrap()
        .solution
        .orbit;
    let pd1 = fig4[1]
        .special(SpecialKind::PeriodDoubling)
        .next()
        .unwrap()
        .point
        .clone();
    let c = curve(
        "PD",
        &unpack(&template, &pd1.u),
        Condition::PeriodDoubling,
        (0.5, 2.0),
        &mut Silent,
    )
    .unwrap();
    let ep = c
        .branch
        .special(SpecialKind::EndPoint)
        .find(|s| (s.point.params[0] - 2.0).abs() < 1e-9)
        .unwrap();
    let alpha_curve = ep.point.params[1];
    let asym = orbit(&Parameters::new(2.0, 0.7), OrbitKind::AsymmetricPos, None)
        .unwrap()
        .solution
        .orbit;
    let b = continue_orbit(
        "asym",
        &asym,
        Free::Alpha,
        0.5,
        1.06,
        Direction::Up,
        &default_method(),
        &mut Silent,
    )
    .unwrap();
    let pd = b
        .special(SpecialKind::PeriodDoubling)
        .next()
        .unwrap()
        .point
        .params[1];
    assert!((pd - alpha_curve).abs() < 1e-6, "{pd} vs {alpha_curve}");
}

#[test]
fn named_constructors_build_the_same_curves() {
    use hycont_continuation::{Codim2, ContinuationProblem, continue_branch, curve_settings};
    use hycont_core::orbit::ShootingSettings;
    use rocking_block::continuation::measures;
    use rocking_block::{ALPHA, OMEGA};
    let params = Parameters::new(1.3, 0.66);
    let fig3 = study_branches(Free::Omega, &mut Silent).unwrap();
    let template = orbit(&params, OrbitKind::Symmetric, None)
        .unwrap()
        .solution
        .orbit;
    let bp = fig3[0]
        .special(SpecialKind::BranchPoint)
        .next()
        .unwrap()
        .point
        .clone();
    let half = unpack(&template, &bp.u)
        .half_of_symmetric(&RockingBlock, 1e-5)
        .unwrap();
    let settings = ShootingSettings {
        rtol: 1e-10,
        atol: 1e-12,
    };
    let (mut cp, u0) =
        Codim2::from_branch_point(&RockingBlock, &half, settings, OMEGA, ALPHA, measures())
            .unwrap();
    let alpha_monitor = cp.monitor_names().len() - 1;
    let s = curve_settings()
        .parameter_bounds(1.0, 1.3)
        .monitor_bounds(alpha_monitor, 0.01, 1.06);
    let b = continue_branch(&mut cp, "BP", &u0, 1.0, &s, &mut Silent).unwrap();
    let end = b
        .special(SpecialKind::EndPoint)
        .next()
        .unwrap()
        .point
        .params[1];
    let bp3 = study_branches(Free::Alpha, &mut Silent).unwrap()[0]
        .special(SpecialKind::BranchPoint)
        .next()
        .unwrap()
        .point
        .params[1];
    assert!((end - bp3).abs() < 1e-6, "{end} vs {bp3}");
}
