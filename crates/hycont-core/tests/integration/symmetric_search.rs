//! The generic search for symmetric orbits against a closed form.
//!
//! Model: the Hopf normal form $x' = y + x(a - x^2 - y^2)$, $y' = -x + y(a - x^2 - y^2)$, which
//! is symmetric under $S = -I$. In polar form $r' = r(a - r^2)$, $\theta' = -1$: the circle
//! $r = \sqrt a$ is the only periodic orbit, with period $2\pi$, and it is symmetric (half a
//! turn is a rotation by $\pi$, which is $S$). The half orbit from $y = 0$ to $y = 0$ lasts $\pi$.
//! Radial perturbations decay as $e^{-2at}$, and the half map $S \circ \phi_\pi$ maps a radial
//! perturbation to a radial one of the same sign: its non-trivial multiplier is
//! $\mu = e^{-2\pi a}$, the full period's $\lambda = \mu^2 = e^{-4\pi a}$.
//!
//! With `wall = Some(w)` the mode also has two switching surfaces $x = \mp w$ (crossed rising
//! and falling respectively, identity jumps; $S$ swaps them). For $w > \sqrt a$ the circle
//! never meets them.

use approx::assert_abs_diff_eq;
use hycont_core::orbit::{
    Closure, SegmentEnd, SegmentSpec, Signature, SymmetricSearch, find_symmetric_orbit,
};
use hycont_core::{
    Direction, Error, EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode,
    Z2Symmetry,
};
use std::f64::consts::PI;

struct Hopf {
    wall: Option<f64>,
}

const HOPF: Hopf = Hopf { wall: None };
const SWITCHES: [EventId; 2] = [EventId(0), EventId(1)];

impl HybridSystem for Hopf {
    fn state_dim(&self) -> usize {
        2
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["a"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "smooth"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        if self.wall.is_some() { &SWITCHES } else { &[] }
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        EventSpec {
            name: "switch",
            direction: if e == SWITCHES[0] {
                Direction::Rising
            } else {
                Direction::Falling
            },
            action: EventAction::Jump { to: Mode(0) },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        let r = p[0] - x[0] * x[0] - x[1] * x[1];
        f[0] = x[1] + x[0] * r;
        f[1] = -x[0] + x[1] * r;
    }
    fn event(&self, e: EventId, x: &[f64], _: &[f64]) -> f64 {
        let w = self.wall.unwrap_or(f64::INFINITY);
        if e == SWITCHES[0] { x[0] + w } else { x[0] - w }
    }
    fn symmetry(&self) -> Option<Z2Symmetry> {
        Some(Z2Symmetry {
            matrix: vec![-1.0, 0.0, 0.0, -1.0],
            modes: vec![Mode(0)],
            events: if self.wall.is_some() {
                vec![SWITCHES[1], SWITCHES[0]]
            } else {
                vec![]
            },
        })
    }
}

impl HybridJacobians for Hopf {
    fn vector_field_jacobian(
        &self,
        _: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        let r = p[0] - x[0] * x[0] - x[1] * x[1];
        dx[0] = r - 2.0 * x[0] * x[0];
        dx[1] = -1.0 - 2.0 * x[0] * x[1];
        dx[2] = 1.0 - 2.0 * x[0] * x[1];
        dx[3] = r - 2.0 * x[1] * x[1];
        if let Some(dp) = dp {
            dp[0] = x[0];
            dp[1] = x[1];
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
        dx.copy_from_slice(&[1.0, 0.0]);
        if let Some(dp) = dp {
            dp.fill(0.0);
        }
    }
}

fn half_signature(system: &Hopf) -> Signature {
    Signature::with_closure(
        system,
        vec![SegmentSpec {
            mode: Mode(0),
            end: SegmentEnd::Interior {
                component: 1,
                value: 0.0,
            },
        }],
        Closure::Symmetric,
    )
    .unwrap()
}

#[test]
fn the_circle_is_found_from_a_grid_of_seeds() {
    let a = 1.44;
    let seeds: Vec<Vec<f64>> = [0.3, 0.8, 2.5].iter().map(|&x| vec![x, 0.0]).collect();
    let search = SymmetricSearch::new(seeds).half_period(PI);
    let sol = find_symmetric_orbit(&HOPF, &half_signature(&HOPF), &[a], &search).unwrap();
    assert_abs_diff_eq!(sol.half.starts[0][0].abs(), a.sqrt(), epsilon = 1e-10);
    assert_abs_diff_eq!(sol.half.period(), PI, epsilon = 1e-10);
    assert!(sol.full.orbit.is_symmetric(&HOPF, 1e-9));
    let mu: Vec<_> = sol.half_floquet.nontrivial().collect();
    assert_eq!(mu.len(), 1);
    assert_abs_diff_eq!(mu[0].0, (-2.0 * PI * a).exp(), epsilon = 1e-10);
    let lambda: Vec<_> = sol.full.floquet.nontrivial().collect();
    assert_abs_diff_eq!(lambda[0].0, (-4.0 * PI * a).exp(), epsilon = 1e-12);
}

/// `solve_orbit` solves a symmetric orbit on its half orbit (either method) and an orbit that
/// is not symmetric on the full problem.
#[test]
fn symmetric_orbits_are_solved_on_their_half_orbit() {
    use hycont_core::orbit::{CollocationSettings, OrbitMethod, PeriodicOrbit, solve_orbit};
    use hycont_core::problem::NewtonSettings;
    let a: f64 = 1.44;
    let seg = half_signature(&HOPF).segments()[0];
    let full = Signature::new(&HOPF, vec![seg, seg]).unwrap();
    let r = 1.1; // off the circle: Newton finds it
    let guess = PeriodicOrbit::new(
        &HOPF,
        full,
        vec![vec![r, 0.0], vec![-r, 0.0]],
        vec![PI, PI],
        vec![a],
    )
    .unwrap();
    for method in [
        OrbitMethod::Shooting(Default::default()),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ] {
        let s = solve_orbit(&HOPF, &guess, &method, &NewtonSettings::default(), 1e-6).unwrap();
        let mu: Vec<_> = s
            .half_floquet
            .expect("solved on the half orbit")
            .nontrivial()
            .collect();
        assert_abs_diff_eq!(mu[0].0, (-2.0 * PI * a).exp(), epsilon = 1e-8);
        assert_abs_diff_eq!(s.solution.orbit.starts[0][0], a.sqrt(), epsilon = 1e-8);
        assert_eq!(s.solution.orbit.segment_count(), 2);
    }
    // Not symmetric (the second start is not the first's image): the full problem.
    let mut lopsided = guess.clone();
    lopsided.starts[1][0] = -0.9;
    let s = solve_orbit(
        &HOPF,
        &lopsided,
        &OrbitMethod::default(),
        &NewtonSettings::default(),
        1e-6,
    )
    .unwrap();
    assert!(s.half_floquet.is_none());
    assert_abs_diff_eq!(s.solution.orbit.starts[0][0], a.sqrt(), epsilon = 1e-8);
}

#[test]
fn bad_searches_are_errors() {
    let search = SymmetricSearch::new(vec![vec![1.0]]);
    assert!(matches!(
        find_symmetric_orbit(&HOPF, &half_signature(&HOPF), &[1.0], &search),
        Err(Error::DimensionMismatch { what: "seed", .. })
    ));
    let search = SymmetricSearch::new(vec![vec![f64::NAN, 0.0]]);
    assert!(matches!(
        find_symmetric_orbit(&HOPF, &half_signature(&HOPF), &[1.0], &search),
        Err(Error::NonFinite { .. })
    ));
    let periodic = Signature::new(&HOPF, half_signature(&HOPF).segments().to_vec()).unwrap();
    let search = SymmetricSearch::new(vec![vec![1.0, 0.0]]);
    assert!(find_symmetric_orbit(&HOPF, &periodic, &[1.0], &search).is_err());
    // The expected half period is wrong: no guess qualifies.
    let search = SymmetricSearch::new(vec![vec![1.0, 0.0]]).half_period(1.0);
    assert!(find_symmetric_orbit(&HOPF, &half_signature(&HOPF), &[1.0], &search).is_err());
}

/// A seed whose flow meets another event of its mode before the segment's end leaves the half
/// orbit's signature and is dropped: with switching surfaces at $x = \mp 1.4$ ($a = 1$: the
/// circle $r = 1$ stays between them), the seed $(-1.5, 0)$ crosses $x = -1.4$ at once (there
/// $\dot x = x (a - r^2) = 1.875 > 0$), while $(-1.2, 0)$ turns half round to $x \approx 1$
/// without meeting either.
#[test]
fn seeds_that_leave_the_signature_are_dropped() {
    let walled = Hopf { wall: Some(1.4) };
    let half = half_signature(&walled);
    let outside = SymmetricSearch::new(vec![vec![-1.5, 0.0]]).half_period(PI);
    assert!(matches!(
        find_symmetric_orbit(&walled, &half, &[1.0], &outside),
        Err(Error::NotPeriodic { .. })
    ));
    // Without the surfaces the same seed leads to the circle.
    let sol = find_symmetric_orbit(&HOPF, &half_signature(&HOPF), &[1.0], &outside).unwrap();
    assert_abs_diff_eq!(sol.half.starts[0][0].abs(), 1.0, epsilon = 1e-10);
    let both = SymmetricSearch::new(vec![vec![-1.5, 0.0], vec![-1.2, 0.0]]).half_period(PI);
    let sol = find_symmetric_orbit(&walled, &half, &[1.0], &both).unwrap();
    assert_abs_diff_eq!(sol.half.starts[0][0].abs(), 1.0, epsilon = 1e-10);
}
