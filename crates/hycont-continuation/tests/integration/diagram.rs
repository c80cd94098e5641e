//! Whole diagrams in one call against closed forms: a Hopf circle times a pitchfork loop,
//! $x_1' = x_2 + x_1(a - |x|^2)$, $x_2' = -x_1 + x_2(a - |x|^2)$, $y' = y(g(\mu) - y^2)$ with
//! $g(\mu) = \mu(c - \mu)$, symmetric under $S = -I$.
//!
//! Its periodic orbits are the circle $|x| = \sqrt a$ (period $2\pi$) at a constant height
//! $y^*$ with $y^*(g(\mu) - y^{*2}) = 0$. The symmetric orbits ($y^* = 0$) have the half-map
//! multiplier $-e^{\pi g(\mu)}$ in $y$, which is $-1$ where $g = 0$: two symmetry-breaking
//! branch points, at $\mu = 0$ and $\mu = c$. The orbits born there, $y^{*2} = \mu(c - \mu)$,
//! form one closed loop through both: a diagram must switch at the first, follow the loop
//! once, and recognise the second as a point of the loop it already has.

use approx::assert_abs_diff_eq;
use hycont_continuation::observe::Observer;
use hycont_continuation::{
    Branch, Diagram, DiagramBranchId, DiagramSettings, EndReason, SpecialKind, SwitchOutcome,
};

use crate::common;
use common::{C, MU, circle, run};

/// Counts the branches it hears of.
#[derive(Default)]
struct Branches(Vec<String>);

impl Observer for Branches {
    fn branch(&mut self, branch: &Branch) {
        self.0.push(branch.name.clone());
    }
}

fn diagram(depth: usize) -> Diagram {
    let settings = DiagramSettings {
        depth,
        ..DiagramSettings::default()
    };
    run()
        .diagram("symmetric", &circle(-0.3, 0.0), &settings)
        .unwrap()
}

#[test]
fn the_loop_between_two_branch_points_is_followed_once() {
    let mut heard = Branches::default();
    let mut run = run();
    run.observer(Box::new(&mut heard));
    let d = run
        .diagram("symmetric", &circle(-0.3, 0.0), &DiagramSettings::default())
        .unwrap();
    drop(run);
    // The symmetric branch's two branch points, at g(mu) = 0.
    let root = &d.branches[0].branch;
    let bps: Vec<f64> = root
        .special(SpecialKind::BranchPoint)
        .map(|s| s.point[MU])
        .collect();
    assert_eq!(bps.len(), 2, "{bps:?}");
    assert_abs_diff_eq!(bps[0], 0.0, epsilon = 1e-8);
    assert_abs_diff_eq!(bps[1], C, epsilon = 1e-8);
    // One more branch: the loop, switched on at the first, closed, every orbit at
    // y^2 = mu (c - mu).
    assert_eq!(d.branches.len(), 2, "{:?}", d.switches);
    assert_eq!(
        heard.0,
        ["symmetric", d.branches[1].branch.branch.name.as_str()]
    );
    let loop_ = &d.branches[1];
    let first_bp = root.first(SpecialKind::BranchPoint).unwrap().point.label;
    assert_eq!(loop_.origin, Some((DiagramBranchId(0), first_bp)));
    assert_eq!(loop_.depth, 1);
    assert_eq!(loop_.branch.branch.end, EndReason::Closed);
    let mut span = (f64::INFINITY, f64::NEG_INFINITY);
    for p in &loop_.branch.branch.points {
        let y = loop_.branch.orbit_of(p).unwrap().starts[0][2];
        assert_abs_diff_eq!(y * y, p[MU] * (C - p[MU]), epsilon = 1e-8);
        span = (span.0.min(p[MU]), span.1.max(p[MU]));
    }
    assert!(
        span.0 < 0.01 && span.1 > C - 0.01,
        "the loop spans {span:?}"
    );
    // The second branch point is the loop's: known, not switched at again; nothing failed.
    let second = d
        .switches
        .iter()
        .find(|r| r.branch == DiagramBranchId(0) && (r.parameter - C).abs() < 1e-6)
        .unwrap();
    assert!(
        matches!(second.outcome, SwitchOutcome::Known { branch, .. } if branch == DiagramBranchId(1)),
        "{second:?}"
    );
    assert_eq!(
        d.children(DiagramBranchId(0)).collect::<Vec<_>>(),
        [DiagramBranchId(1)]
    );
    assert!(
        d.switches.iter().all(|r| !matches!(
            r.outcome,
            SwitchOutcome::Failed(_) | SwitchOutcome::Duplicate(_)
        )),
        "{:?}",
        d.switches
    );
}

#[test]
fn a_diagram_extended_deeper_is_the_deeper_diagram_and_survives_json() {
    let shallow = diagram(0);
    assert_eq!(shallow.branches.len(), 1);
    assert!(
        shallow
            .switches
            .iter()
            .all(|r| r.outcome == SwitchOutcome::DepthLimit)
    );
    assert_eq!(shallow.switches.len(), 2);
    let mut read = Diagram::from_json(&shallow.to_json().unwrap()).unwrap();
    assert_eq!(read, shallow);
    run()
        .extend_diagram(&mut read, &DiagramSettings::default())
        .unwrap();
    let deep = diagram(2);
    assert_eq!(read.branches.len(), deep.branches.len());
    let (a, b) = (
        &read.branches[1].branch.branch,
        &deep.branches[1].branch.branch,
    );
    assert_eq!(a.points.len(), b.points.len());
    for (p, q) in a.points.iter().zip(&b.points) {
        assert_abs_diff_eq!(p[MU], q[MU], epsilon = 1e-12);
    }
}

#[test]
fn the_branch_limit_is_recorded_and_bad_settings_are_errors() {
    let limited = DiagramSettings {
        max_branches: 1,
        ..DiagramSettings::default()
    };
    let d = run()
        .diagram("symmetric", &circle(-0.3, 0.0), &limited)
        .unwrap();
    assert_eq!(d.branches.len(), 1);
    assert!(
        d.switches
            .iter()
            .all(|r| r.outcome == SwitchOutcome::BranchLimit)
    );
    for bad in [
        DiagramSettings {
            kinds: vec![SpecialKind::Fold],
            ..DiagramSettings::default()
        },
        DiagramSettings {
            max_branches: 0,
            ..DiagramSettings::default()
        },
        DiagramSettings {
            same_point_tol: 0.0,
            ..DiagramSettings::default()
        },
    ] {
        assert!(
            run().diagram("x", &circle(-0.3, 0.0), &bad).is_err(),
            "{bad:?}"
        );
    }
}
