//! Symmetry breaking of periodic orbits against closed forms: half-orbit continuation, the
//! symmetry-breaking branch point, switching, the mirrored partners and the branch-point curve.
//!
//! Model: a Hopf circle times a pitchfork,
//! $x_1' = x_2 + x_1(a - |x|^2)$, $x_2' = -x_1 + x_2(a - |x|^2)$, $y' = y(\mu - y^2)$,
//! symmetric under $S = -I$. Its periodic orbits are the circle $|x| = \sqrt a$ (period $2\pi$)
//! with $y \equiv y^*$, $y^* \in \{0, \pm\sqrt\mu\}$. The orbit with $y^* = 0$ is symmetric
//! (half a turn is the rotation by $\pi$, i.e. $S$, on the circle, and $S$ keeps $y = 0$); the
//! half map $S \circ \phi_\pi$ multiplies a $y$ perturbation by $-e^{\pi\mu}$, which is $-1$ at
//! $\mu = 0$: the symmetry-breaking branch point, for every $a$. The orbits born there have
//! $y^* = \pm\sqrt\mu$ (mirror images of each other) and the multiplier $e^{-4\pi\mu}$ in $y$.

use approx::assert_abs_diff_eq;
use hycont_continuation::{CurveSpec, OrbitRun, RunDirection, SpecialKind};
use hycont_core::orbit::{PeriodicOrbit, SegmentEnd, SegmentSpec, Signature};
use hycont_core::{EventId, EventSpec, HybridJacobians, HybridSystem, Mode, ParamId, Z2Symmetry};
use std::f64::consts::PI;

const A: ParamId = ParamId(0);
const MU: ParamId = ParamId(1);

struct HopfPitchfork;

impl HybridSystem for HopfPitchfork {
    fn state_dim(&self) -> usize {
        3
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["a", "mu"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "smooth"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        unreachable!("no events")
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        let r = p[0] - x[0] * x[0] - x[1] * x[1];
        f[0] = x[1] + x[0] * r;
        f[1] = -x[0] + x[1] * r;
        f[2] = x[2] * (p[1] - x[2] * x[2]);
    }
    fn event(&self, _: EventId, _: &[f64], _: &[f64]) -> f64 {
        unreachable!("no events")
    }
    fn symmetry(&self) -> Option<Z2Symmetry> {
        let mut matrix = vec![0.0; 9];
        for i in 0..3 {
            matrix[i + 3 * i] = -1.0;
        }
        Some(Z2Symmetry {
            matrix,
            modes: vec![Mode(0)],
            events: vec![],
        })
    }
}

impl HybridJacobians for HopfPitchfork {
    fn vector_field_jacobian(
        &self,
        _: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        let r = p[0] - x[0] * x[0] - x[1] * x[1];
        dx.fill(0.0);
        dx[0] = r - 2.0 * x[0] * x[0];
        dx[1] = -1.0 - 2.0 * x[0] * x[1];
        dx[3] = 1.0 - 2.0 * x[0] * x[1];
        dx[4] = r - 2.0 * x[1] * x[1];
        dx[8] = p[1] - 3.0 * x[2] * x[2];
        if let Some(dp) = dp {
            dp.fill(0.0);
            dp[0] = x[0];
            dp[1] = x[1];
            dp[5] = x[2];
        }
    }
    fn event_gradient(
        &self,
        _: EventId,
        _: &[f64],
        _: &[f64],
        _: &mut [f64],
        _: Option<&mut [f64]>,
    ) {
    }
}

/// The orbit on the circle of radius sqrt(a) at height y, as two half turns between the
/// crossings of x2 = 0 (a signature whose second half is the image of the first, so that a
/// symmetric orbit is recognised as one).
fn circle(a: f64, mu: f64, y: f64) -> PeriodicOrbit {
    let half = SegmentSpec {
        mode: Mode(0),
        end: SegmentEnd::Interior {
            component: 1,
            value: 0.0,
        },
    };
    let sig = Signature::new(&HopfPitchfork, vec![half, half]).unwrap();
    PeriodicOrbit::new(
        &HopfPitchfork,
        sig,
        vec![vec![a.sqrt(), 0.0, y], vec![-a.sqrt(), 0.0, y]],
        vec![PI, PI],
        vec![a, mu],
    )
    .unwrap()
}

fn run() -> OrbitRun<'static, HopfPitchfork> {
    let mut run = OrbitRun::new(&HopfPitchfork, MU).unwrap();
    run.bounds(-0.5, 0.5);
    run
}

#[test]
fn symmetric_orbits_break_their_symmetry_at_mu_zero() {
    let mut run = run();
    let start = circle(1.0, -0.3, 0.0);
    assert!(run.problem(&start).unwrap().0.is_half_orbit());
    let sym = run.run("symmetric", &start, RunDirection::Up).unwrap();
    let bp: Vec<_> = sym.special(SpecialKind::BranchPoint).collect();
    assert_eq!(bp.len(), 1);
    assert!(bp[0].located);
    assert_abs_diff_eq!(bp[0].point[MU], 0.0, epsilon = 1e-8);
    // The same on the full orbit's problem (the branch point from the determinant's sign).
    run.half_orbits(false);
    let full = run.run("full", &start, RunDirection::Up).unwrap();
    let bp_full = full.special(SpecialKind::BranchPoint).next().unwrap();
    assert_abs_diff_eq!(bp_full.point[MU], 0.0, epsilon = 1e-8);
    // Switching both ways through it: the broken orbits y = +-sqrt(mu), with the multiplier
    // exp(-4 pi mu) in y.
    let broken = run
        .switch_at("broken", &sym, bp[0].point.label, RunDirection::Both)
        .unwrap();
    let (mut above, mut below) = (0, 0);
    for p in &broken.branch.points {
        let y = broken.orbit_of(p).unwrap().starts[0][2];
        assert_abs_diff_eq!(y * y, p[MU], epsilon = 1e-8);
        if y > 1e-3 {
            above += 1;
        } else if y < -1e-3 {
            below += 1;
        }
        if p[MU] > 1e-3 {
            let m = (-4.0 * PI * p[MU]).exp();
            assert!(
                p.multipliers.iter().any(|l| (l.0 - m).abs() < 1e-8),
                "{:?}",
                p.multipliers
            );
        }
    }
    assert!(above > 3 && below > 3, "{above} above, {below} below");
}

#[test]
fn the_broken_pair_is_reached_at_a_parameter_value() {
    let mut run = run();
    let (found, mirror) = run
        .symmetry_broken_at(&circle(1.0, -0.3, 0.0), 0.25)
        .unwrap()
        .expect("a broken pair");
    for o in [&found, &mirror] {
        assert_abs_diff_eq!(o.starts[0][2].abs(), 0.5, epsilon = 1e-8);
        assert_abs_diff_eq!(o.params[MU.index()], 0.25, epsilon = 1e-9);
        assert!(!o.is_symmetric(&HopfPitchfork, 1e-6));
    }
    assert_abs_diff_eq!(found.starts[0][2], -mirror.starts[0][2], epsilon = 1e-12);
    // Where the symmetric orbits do not break (mu below 0 only): none.
    let mut run = OrbitRun::new(&HopfPitchfork, MU).unwrap();
    run.bounds(-0.5, -0.1);
    assert!(
        run.symmetry_broken_at(&circle(1.0, -0.3, 0.0), -0.2)
            .unwrap()
            .is_none()
    );
}

#[test]
fn the_branch_point_curve_stays_at_mu_zero() {
    let mut run = run();
    let sym = run
        .run("symmetric", &circle(1.0, -0.3, 0.0), RunDirection::Up)
        .unwrap();
    let bp = sym.special(SpecialKind::BranchPoint).next().unwrap();
    let spec = CurveSpec::new(A).bounds(0.5, 2.0).user_points(A, [1.5]);
    let c = run.curve_at("BP", &sym, bp.point.label, &spec).unwrap();
    assert_eq!(c.special(SpecialKind::UserPoint).count(), 1);
    assert!(c.branch.points.len() > 3);
    for p in &c.branch.points {
        assert_abs_diff_eq!(p[MU], 0.0, epsilon = 1e-8);
        // On the circle of radius sqrt(a).
        let o = c.orbit_of(p).unwrap();
        assert_abs_diff_eq!(o.starts[0][0].abs(), p[A].sqrt(), epsilon = 1e-8);
    }
}

/// A run both ways is the backward run reversed, then the forward one: the two directions share
/// one driver (its layout and its first chart, the tangent and the determinant's sign reversed
/// for the second direction), and give the same points and special points as two separate runs,
/// with the same location work. A wrong sign of the reused determinant would change the fold
/// test's sign in the first forward step (a location, discarded or not); on the full orbit's
/// problem the branch point at mu = 0 is the determinant's sign change.
#[test]
fn a_run_both_ways_is_the_two_separate_runs() {
    for half in [true, false] {
        let mut run = run();
        run.half_orbits(half);
        let start = circle(1.0, -0.3, 0.0);
        let both = run.run("both", &start, RunDirection::Both).unwrap().branch;
        let down = run.run("down", &start, RunDirection::Down).unwrap().branch;
        let up = run.run("up", &start, RunDirection::Up).unwrap().branch;
        // (Each run's points end with its end point; the start once.)
        let separate: Vec<f64> = (down.points.iter().rev())
            .chain(up.points.iter().skip(1))
            .map(|p| p[MU])
            .collect();
        let joined: Vec<f64> = both.points.iter().map(|p| p[MU]).collect();
        assert_eq!(joined.len(), separate.len());
        for (a, b) in joined.iter().zip(&separate) {
            assert_abs_diff_eq!(a, b, epsilon = 1e-14);
        }
        let specials = |b: &hycont_continuation::Branch| -> Vec<(SpecialKind, f64)> {
            b.special_points
                .iter()
                .map(|s| (s.kind, s.point[MU]))
                .collect()
        };
        let mut expected = specials(&down);
        expected.reverse();
        expected.extend(specials(&up));
        assert_eq!(specials(&both), expected);
        let bp: Vec<f64> = both
            .special(SpecialKind::BranchPoint)
            .map(|s| s.point[MU])
            .collect();
        assert_eq!(bp.len(), 1, "half orbits: {half}");
        assert_abs_diff_eq!(bp[0], 0.0, epsilon = 1e-8);
        let (s, d, u) = (both.statistics, down.statistics, up.statistics);
        assert_eq!(
            s.location_jacobians,
            d.location_jacobians + u.location_jacobians
        );
        assert_eq!(s.discarded_tests, d.discarded_tests + u.discarded_tests);
        // The second direction's first chart is the first's: no work for it.
        assert!(s.jacobians < d.jacobians + u.jacobians);
    }
}
