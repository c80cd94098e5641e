//! A cusp (CP) on a fold curve against its closed form. A clocked scalar system,
//! $\dot x = -k (x^3 - p_1 x - p_2)$, $\dot\theta = 1$, with the clock wrapping at
//! $\theta = 2\pi$ (an event and a reset): its periodic orbits (period $2\pi$) sit at the roots
//! $x^*$ of the cubic, with the non-trivial multiplier $e^{-2\pi k (3 x^{*2} - p_1)}$. Folds
//! are where $3 x^{*2} = p_1$: the fold curve $p_1 = 3 x^2$, $p_2 = -2 x^3$, smooth in $x$ and
//! a cusp in the parameter plane at $x = 0$, $(p_1, p_2) = (0, 0)$, where both parameters are
//! stationary along it. Elsewhere the curve has no turning point in $p_1$ that is not the cusp:
//! there is one, in $p_2$ too, only there.

use approx::assert_abs_diff_eq;
use hycont::hycont_continuation::{CurveSpec, OrbitRun, RunDirection, SpecialKind};
use hycont::orbit::{
    CollocationSettings, OrbitMethod, PeriodicOrbit, SegmentEnd, SegmentSpec, ShootingSettings,
    Signature,
};
use hycont::{
    Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode, ParamId,
    SimulationSettings, check_derivatives,
};
use std::f64::consts::PI;

const P1: ParamId = ParamId(0);
const P2: ParamId = ParamId(1);
const WRAP: EventId = EventId(0);
const M: Mode = Mode(0);

/// State `(x, theta)`, parameters `(p1, p2, k)`.
struct Cubic;

impl HybridSystem for Cubic {
    fn state_dim(&self) -> usize {
        2
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["p1", "p2", "k"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "clocked"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[WRAP]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "clock wrap",
            direction: Direction::Rising,
            action: EventAction::Jump { to: M },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        f[0] = -p[2] * (x[0].powi(3) - p[0] * x[0] - p[1]);
        f[1] = 1.0;
    }
    fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 {
        x[1] - 2.0 * PI
    }
    fn reset(&self, _: EventId, x: &[f64], _: &[f64], out: &mut [f64]) {
        out[0] = x[0];
        out[1] = x[1] - 2.0 * PI;
    }
}

impl HybridJacobians for Cubic {
    fn vector_field_jacobian(
        &self,
        _: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.fill(0.0);
        dx[0] = -p[2] * (3.0 * x[0] * x[0] - p[0]);
        if let Some(dp) = dp {
            // Column-major 2 x 3: columns p1, p2, k.
            dp.fill(0.0);
            dp[0] = p[2] * x[0];
            dp[2] = p[2];
            dp[4] = -(x[0].powi(3) - p[0] * x[0] - p[1]);
        }
    }
    fn event_gradient(
        &self,
        _: EventId,
        _: &[f64],
        _: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx[0] = 0.0;
        dx[1] = 1.0;
        if let Some(dp) = dp {
            dp.fill(0.0);
        }
    }
}

/// The orbit at the root `x` of the cubic for `p1` (`p2` from the cubic), one turn of the
/// clock.
fn orbit(x: f64, p1: f64) -> PeriodicOrbit {
    let p2 = x.powi(3) - p1 * x;
    let sig = Signature::new(
        &Cubic,
        vec![SegmentSpec {
            mode: M,
            end: SegmentEnd::Event(WRAP),
        }],
    )
    .unwrap();
    PeriodicOrbit::from_initial_state(
        &Cubic,
        sig,
        &[x, 0.0],
        &[p1, p2, 0.2],
        3.0 * PI,
        &SimulationSettings::default(),
    )
    .unwrap()
}

#[test]
fn the_jacobians_match_differences() {
    let check = check_derivatives(&Cubic, M, &[0.3, 1.0], &[0.4, -0.1, 0.2]).unwrap();
    assert!(check.max_error() < 1e-7, "{check:?}");
}

/// From the fold of the branch in p1 at p2 = 0.1 (x = -(0.05)^(1/3)), the fold curve in
/// (p1, p2) follows p1 = 3 x^2, p2 = -2 x^3 through the cusp at (0, 0), detected and located
/// there (and nowhere else) by both discretisations.
#[test]
fn the_fold_curve_has_its_cusp_at_the_origin() {
    for method in [
        OrbitMethod::Shooting(ShootingSettings::default()),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ] {
        let mut run = OrbitRun::new(&Cubic, P1).unwrap();
        run.method(method).bounds(-1.0, 2.0);
        // The stable root x = -0.8 at p2 = 0.1 (p1 = x^2 - p2 / x); the branch of negative
        // roots folds at x^3 = -p2 / 2.
        let x = -0.8;
        let branch = run
            .run("equilibria", &orbit(x, x * x - 0.1 / x), RunDirection::Both)
            .unwrap();
        let fold = branch.first(SpecialKind::Fold).unwrap();
        let x_fold = -(0.05f64).cbrt();
        assert_abs_diff_eq!(fold.point[P1], 3.0 * x_fold * x_fold, epsilon = 1e-8);
        let spec = CurveSpec::new(P2).bounds(-1.0, 1.0);
        let curve = run
            .curve_at("SN", &branch, fold.point.label, &spec)
            .unwrap();
        for p in &curve.branch.points {
            let xs = curve.orbit_of(p).unwrap().starts[0][0];
            assert_abs_diff_eq!(p[P1], 3.0 * xs * xs, epsilon = 1e-8);
            assert_abs_diff_eq!(p[P2], -2.0 * xs.powi(3), epsilon = 1e-8);
        }
        let cusps: Vec<_> = curve.special(SpecialKind::Cusp).collect();
        assert_eq!(cusps.len(), 1, "{:?}", curve.branch.special_points);
        assert!(cusps[0].located);
        assert_abs_diff_eq!(cusps[0].point[P1], 0.0, epsilon = 1e-8);
        assert_abs_diff_eq!(cusps[0].point[P2], 0.0, epsilon = 1e-8);
        let xc = curve.orbit_of(&cusps[0].point).unwrap().starts[0][0];
        assert_abs_diff_eq!(xc, 0.0, epsilon = 1e-6);
    }
}
