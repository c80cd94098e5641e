//! An impact oscillator at and past grazing: the branch of period-1 impacting orbits ends at a
//! located GR where the impact velocity vanishes, at the closed-form wall position; continued
//! past it (admissibility off), neither discretisation reports a period doubling through the
//! multiplier's pole.
//!
//! # The model and its closed forms
//! $\ddot x + 2\zeta\dot x + x = A\cos\theta$, $\dot\theta = \omega$, with a wall at $x = d$
//! (impact when $x$ rises through $d$: $\dot x \mapsto -e\dot x$) and the phase wrapped from
//! $2\pi$ to $0$. Without impacts the orbit is $x = R\cos(\theta - \varphi)$ with
//! $$R = \frac{A}{\sqrt{(1-\omega^2)^2 + (2\zeta\omega)^2}}.$$
//! The period-1 impacting orbit touches the wall with vanishing velocity when it becomes this
//! free orbit, at $d = R$ (grazing): for $d < R$ the wall cuts the free orbit and the
//! impacting orbit has impact velocity $v > 0$, which tends to 0 as $d \to R$.
//!
//! # Why a false period doubling is possible
//! The saltation matrix of an impact is
//! $S = I + (f^+ - R_x f^-)\,\nabla g^T / (\nabla g \cdot f^-)$ with $\nabla g\cdot f^- = -v$:
//! as $v \to 0$ a Floquet multiplier runs to infinity, and past grazing (the "impact" now met
//! with $v < 0$, inadmissible) it comes back from infinity with the other sign. The PD test
//! function $\prod_i (\mu_i + 1)$ changes sign through that pole, which is not a bifurcation:
//! the detector must discard it ([`hycont::hycont_continuation::RunStatistics`] counts it).

use approx::assert_abs_diff_eq;
use hycont::hycont_continuation::{
    EndReason, MeasureId, OrbitBranch, OrbitRun, RunDirection, SpecialKind,
};
use hycont::orbit::{
    CollocationSettings, OrbitMethod, PeriodicOrbit, SegmentEnd, SegmentSpec, SegmentValue,
    ShootingSettings, Signature,
};
use hycont::{
    Direction, EventAction, EventId, EventSpec, FiniteDifferences, HybridSystem, Mode, ParamId,
    SimulationSettings,
};
use std::f64::consts::TAU;

const D: ParamId = ParamId(0);
const IMPACT: EventId = EventId(0);
const WRAP: EventId = EventId(1);
/// `(d, A, omega, zeta, e)`.
const P: [f64; 5] = [2.0, 1.0, 1.2, 0.05, 0.8];

struct Oscillator;

impl HybridSystem for Oscillator {
    fn state_dim(&self) -> usize {
        3
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["d", "A", "omega", "zeta", "e"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "free"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[IMPACT, WRAP]
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        EventSpec {
            name: if e == IMPACT { "impact" } else { "wrap" },
            direction: if e == IMPACT {
                Direction::Falling
            } else {
                Direction::Rising
            },
            action: EventAction::Jump { to: Mode(0) },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
        f[0] = x[1];
        f[1] = -x[0] - 2.0 * p[3] * x[1] + p[1] * x[2].cos();
        f[2] = p[2];
    }
    fn event(&self, e: EventId, x: &[f64], p: &[f64]) -> f64 {
        if e == IMPACT { p[0] - x[0] } else { x[2] - TAU }
    }
    fn reset(&self, e: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        out.copy_from_slice(x);
        if e == IMPACT {
            out[1] = -p[4] * x[1];
        } else {
            out[2] = x[2] - TAU;
        }
    }
}

fn grazing_wall() -> f64 {
    let [_, a, w, z, _] = P;
    a / ((1.0 - w * w).powi(2) + (2.0 * z * w).powi(2)).sqrt()
}

/// A guess of the period-1 orbit through grazing at `d = R - 0.002` (there it meets the wall
/// from above, inadmissible): the free orbit $x = R\cos(\theta - \varphi)$,
/// $\tan\varphi = 2\zeta\omega/(1-\omega^2)$, cut by the wall where it rises through $d$
/// (post-impact velocity $-e\,R\omega\sin\alpha$, $\cos\alpha = d/R$).
fn impacting_orbit() -> (PeriodicOrbit, [f64; 5]) {
    let [_, _, w, z, e] = P;
    let r = grazing_wall();
    let d = r - 0.002;
    let p = [d, P[1], w, z, e];
    let lag = (2.0 * z * w).atan2(1.0 - w * w);
    let alpha = (d / r).acos();
    let theta = (lag - alpha).rem_euclid(TAU);
    let x0 = [d, -e * r * w * alpha.sin(), theta];
    let sig = Signature::new(
        &Oscillator,
        [WRAP, IMPACT]
            .map(|ev| SegmentSpec {
                mode: Mode(0),
                end: SegmentEnd::Event(ev),
            })
            .to_vec(),
    )
    .unwrap();
    let guess = PeriodicOrbit::from_initial_state(
        &Oscillator,
        sig,
        &x0,
        &p,
        20.0,
        &SimulationSettings::default(),
    )
    .unwrap();
    (guess, p)
}

fn methods() -> [OrbitMethod; 2] {
    [
        OrbitMethod::Shooting(ShootingSettings::default()),
        OrbitMethod::Collocation(CollocationSettings::default()),
    ]
}

/// The branch through grazing, admissibility off, over $[R - 0.05, R + 0.3]$, with the impact
/// velocity measured.
fn through_grazing(
    sys: &FiniteDifferences<Oscillator>,
    method: &OrbitMethod,
) -> (OrbitBranch, MeasureId) {
    let mut run = OrbitRun::new(sys, D).unwrap();
    run.method(*method)
        .bounds(grazing_wall() - 0.05, grazing_wall() + 0.3)
        .admissibility(false)
        .unwrap();
    let v = run
        .add_measure("impact velocity", SegmentValue::end(1, 1))
        .unwrap();
    let (guess, _) = impacting_orbit();
    (
        run.run("through grazing", &guess, RunDirection::Both)
            .unwrap(),
        v,
    )
}

/// Past grazing a multiplier crosses infinity (from about -2800 to +2200 between neighbouring
/// points): the PD test function changes sign there and the detector discards it. Any PD
/// reported has its multiplier at -1 and lies away from the grazing.
#[test]
fn no_period_doubling_through_the_pole_at_grazing() {
    let sys = FiniteDifferences::new(Oscillator);
    let r = grazing_wall();
    for method in methods() {
        let (b, v) = through_grazing(&sys, &method);
        let ds: Vec<f64> = b.branch.points.iter().map(|p| p[D]).collect();
        let (lo, hi) = ds
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, c), &d| (a.min(d), c.max(d)));
        assert!(lo < r - 0.04 && hi > r + 0.29, "{method:?}: [{lo}, {hi}]");
        // The impact velocity changes sign at the grazing.
        let below = b
            .branch
            .points
            .iter()
            .filter(|p| p[D] < r)
            .all(|p| p[v] < 0.0);
        let above = b
            .branch
            .points
            .iter()
            .filter(|p| p[D] > r)
            .all(|p| p[v] > 0.0);
        assert!(below && above, "{method:?}");
        for s in b.branch.special(SpecialKind::PeriodDoubling) {
            let (re, im) = s.critical.expect("located points report their multiplier");
            assert!(
                (re + 1.0).abs() < 1e-3 && im == 0.0,
                "{method:?}: PD at d = {} with multiplier {re}{im:+}i",
                s.point[D]
            );
            assert!(
                (s.point[D] - r).abs() > 1e-3,
                "{method:?}: PD at the grazing"
            );
        }
        assert!(
            b.branch.statistics.discarded_tests > 0,
            "{method:?}: the pole at grazing was not seen"
        );
    }
}

/// With admissibility (the default), the branch from an impacting orbit at $d = R + 0.2$ down
/// ends at a located GR where the impact velocity vanishes, at the closed-form $d = R$.
#[test]
fn the_branch_ends_at_the_grazing_wall_position() {
    let sys = FiniteDifferences::new(Oscillator);
    let r = grazing_wall();
    for method in methods() {
        let (b, _) = through_grazing(&sys, &method);
        let start = b
            .branch
            .points
            .iter()
            .min_by(|p, q| (p[D] - r - 0.2).abs().total_cmp(&(q[D] - r - 0.2).abs()))
            .unwrap();
        let orbit = b.orbit_of(start).unwrap();
        let mut run = OrbitRun::new(&sys, D).unwrap();
        run.method(method).bounds(r - 0.05, r + 0.3);
        let v = run
            .add_measure("impact velocity", SegmentValue::end(1, 1))
            .unwrap();
        let down = run.run("to grazing", &orbit, RunDirection::Down).unwrap();
        assert_eq!(
            down.branch.end,
            EndReason::Inadmissible(SpecialKind::Grazing),
            "{method:?}"
        );
        let gr = down.first(SpecialKind::Grazing).unwrap();
        assert!(gr.located, "{method:?}");
        assert_abs_diff_eq!(gr.point[D], r, epsilon = 1e-6);
        assert_abs_diff_eq!(gr.point[v], 0.0, epsilon = 1e-5);
    }
}
