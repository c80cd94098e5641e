//! The stroboscopic classifier against closed forms, on a system that is not the rocking block.
//!
//! Model: the forced damped oscillator $x'' + 2\zeta x' + x = f r$ driven by the oscillator
//! $r' = r + \omega s - r(r^2+s^2)$, $s' = s - \omega r - s(r^2+s^2)$ (on its cycle
//! $r = \sin(\omega t + \beta)$), with a terminal event where $x$ reaches a limit $L$. Every
//! motion tends to the steady state $x = (f/D)\sin(\omega t + \beta - \phi)$,
//! $D = \sqrt{(1-\omega^2)^2 + (2\zeta\omega)^2}$: a period-1 orbit of the stroboscopic map,
//! symmetric under $S = -I$ (half a period later the state is the negative), with mean 0. Where
//! $f/D > L$ (and the start is below $L$) the motion reaches the limit first: terminal.

use hycont_core::{
    Direction, EventAction, EventId, EventSpec, FiniteDifferences, HybridSystem, Mode, Z2Symmetry,
};
use hycont_sample::classify::{Attractor, Decision, PeriodicallyForced, StrobeSettings, classify};
use std::f64::consts::PI;

/// Parameters (f, omega, zeta, limit).
struct Forced;

impl HybridSystem for Forced {
    fn state_dim(&self) -> usize {
        4
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["f", "omega", "zeta", "limit"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "free"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[EventId(0)]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "limit",
            direction: Direction::Rising,
            action: EventAction::Terminal,
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        let rho = x[2] * x[2] + x[3] * x[3];
        out[0] = x[1];
        out[1] = -x[0] - 2.0 * p[2] * x[1] + p[0] * x[2];
        out[2] = x[2] + p[1] * x[3] - x[2] * rho;
        out[3] = x[3] - p[1] * x[2] - x[3] * rho;
    }
    fn event(&self, _: EventId, x: &[f64], p: &[f64]) -> f64 {
        x[0] - p[3]
    }
    fn symmetry(&self) -> Option<Z2Symmetry> {
        let mut matrix = vec![0.0; 16];
        for i in 0..4 {
            matrix[i + 4 * i] = -1.0;
        }
        Some(Z2Symmetry {
            matrix,
            modes: vec![Mode(0)],
            events: vec![EventId(0)],
        })
    }
}

/// The forcing period 2 pi / omega; the strobes compare (x, v).
impl PeriodicallyForced for Forced {
    fn forcing_period(&self, p: &[f64]) -> f64 {
        2.0 * PI / p[1]
    }
    fn strobe_components(&self) -> &[usize] {
        &[0, 1]
    }
    fn mode_at(&self, _: &[f64], _: &[f64]) -> Mode {
        Mode(0)
    }
}

fn gain(omega: f64, zeta: f64) -> f64 {
    ((1.0 - omega * omega).powi(2) + (2.0 * zeta * omega).powi(2)).sqrt()
}

#[test]
fn the_steady_state_is_a_symmetric_period_one_orbit() {
    let system = FiniteDifferences::new(Forced);
    let (omega, zeta) = (0.8, 0.1);
    let p = [0.3, omega, zeta, 10.0];
    for x0 in [[0.0, 0.0, 0.0, 1.0], [2.0, -1.0, 1.0, 0.0]] {
        let c = classify(&system, &p, Mode(0), &x0, &StrobeSettings::default()).unwrap();
        assert_eq!(
            c.attractor,
            Attractor::Periodic {
                period: 1,
                symmetric: true
            }
        );
        assert!(matches!(
            c.decision,
            Decision::Converged | Decision::Extrapolated | Decision::Newton
        ));
        // The mean of x and v over a period: 0 (to the sampling's trapezoid error, and the
        // distance to the limit, well below the amplitude).
        assert!(
            c.mean
                .iter()
                .all(|m| m.abs() < 1e-2 * 0.3 / gain(omega, zeta)),
            "{:?}",
            c.mean
        );
        assert_eq!(c.modes, [Mode(0)]);
    }
}

#[test]
fn amplitudes_beyond_the_limit_are_terminal() {
    let system = FiniteDifferences::new(Forced);
    let (omega, zeta) = (0.8, 0.1);
    // The steady amplitude f / D at f = 0.3 is 0.3 / 0.394 = 0.76: a limit at 0.6 is reached,
    // one at 1.0 is not.
    let amplitude = 0.3 / gain(omega, zeta);
    assert!(amplitude > 0.6 && amplitude < 1.0);
    let x0 = [0.0, 0.0, 0.0, 1.0];
    let terminal = classify(
        &system,
        &[0.3, omega, zeta, 0.6],
        Mode(0),
        &x0,
        &StrobeSettings::default(),
    )
    .unwrap();
    assert_eq!(
        terminal.attractor,
        Attractor::Terminal { event: EventId(0) }
    );
    assert_eq!(terminal.decision, Decision::Event);
    let periodic = classify(
        &system,
        &[0.3, omega, zeta, 1.0],
        Mode(0),
        &x0,
        &StrobeSettings::default(),
    )
    .unwrap();
    assert!(matches!(
        periodic.attractor,
        Attractor::Periodic { period: 1, .. }
    ));
}

/// Higher periods by repetition. Undamped and unforced ($\zeta = 0$, $f = 0$) the oscillator
/// moves as $x = A\sin(t + c)$ with period $2\pi$; forced with $\omega = k$ (an integer, the
/// forcing's period $2\pi/k$), the strobe map is the rotation by $2\pi/k$ of the $(x, v)$ plane:
/// every start other than the origin is periodic with period exactly $k$ forcing periods.
/// With the forcing on ($f \ne 0$, $\omega = k \ne 1$) the motion adds the period-1 steady
/// state to the free oscillation: still period $k$.
#[test]
fn integer_frequency_ratios_are_higher_periods() {
    let system = FiniteDifferences::new(Forced);
    let settings = StrobeSettings::default();
    let x0 = [0.4, 0.0, 0.0, 1.0];
    for k in [3usize, 5, 8] {
        for f in [0.0, 0.3] {
            let c = classify(&system, &[f, k as f64, 0.0, 10.0], Mode(0), &x0, &settings).unwrap();
            assert_eq!(
                c.attractor,
                Attractor::Periodic {
                    period: k,
                    symmetric: false
                },
                "omega = {k}, f = {f}"
            );
            assert_eq!(c.decision, Decision::Converged);
        }
    }
    // Period 9 is beyond the default max_period = 8: undecided after max_periods; at
    // max_period = 9 it is found.
    let p9 = [0.0, 9.0, 0.0, 10.0];
    let short = StrobeSettings {
        max_periods: 60,
        ..settings
    };
    let c = classify(&system, &p9, Mode(0), &x0, &short).unwrap();
    assert_eq!(c.attractor, Attractor::Undecided);
    assert_eq!(c.periods, 60);
    let nine = StrobeSettings {
        max_period: 9,
        ..short
    };
    let c = classify(&system, &p9, Mode(0), &x0, &nine).unwrap();
    assert!(matches!(c.attractor, Attractor::Periodic { period: 9, .. }));
    // At rest at the origin the unforced oscillator is period 1.
    let c = classify(
        &system,
        &[0.0, 3.0, 0.0, 10.0],
        Mode(0),
        &[0.0, 0.0, 0.0, 1.0],
        &settings,
    )
    .unwrap();
    assert!(matches!(c.attractor, Attractor::Periodic { period: 1, .. }));
}

#[test]
fn bad_settings_and_inputs_are_errors() {
    let system = FiniteDifferences::new(Forced);
    let bad = StrobeSettings {
        tol: -1.0,
        ..StrobeSettings::default()
    };
    let x0 = [0.0, 0.0, 0.0, 1.0];
    assert!(classify(&system, &[0.3, 0.8, 0.1, 1.0], Mode(0), &x0, &bad).is_err());
    // A step budget below what a period takes: an error naming it, not a wait (the first
    // chunk runs period by period, so the first period already exceeds it).
    let starved = StrobeSettings {
        max_steps_per_period: 1,
        ..StrobeSettings::default()
    };
    assert!(matches!(
        classify(&system, &[0.3, 0.8, 0.1, 1.0], Mode(0), &x0, &starved),
        Err(hycont_sample::Error::StepBudget { steps: 1, periods: 1, t }) if t == 0.0
    ));

    let no_period = StrobeSettings {
        max_period: 0,
        ..StrobeSettings::default()
    };
    assert!(classify(&system, &[0.3, 0.8, 0.1, 1.0], Mode(0), &x0, &no_period).is_err());
    assert!(
        classify(
            &system,
            &[0.3, 0.0, 0.1, 1.0],
            Mode(0),
            &x0,
            &StrobeSettings::default()
        )
        .is_err()
    );
    assert!(
        classify(
            &system,
            &[0.3, 0.8, 0.1, 1.0],
            Mode(0),
            &[f64::NAN, 0.0, 0.0, 1.0],
            &StrobeSettings::default()
        )
        .is_err()
    );
}

/// No doubling where there is none. The damped oscillator's strobe map is affine with the
/// multipliers $\mu = e^{(-\zeta \pm i\sqrt{1-\zeta^2})T}$, $T = 2\pi/\omega$: every start tends
/// to the one period-1 orbit, spiralling in when $\arg\mu$ is near $\pi$ (each period flips the
/// deviation nearly over). Then $x_k - x_{k-2}$ is much smaller than $x_k - x_{k-1}$
/// (by $|1-\mu^2|/|1-\mu| \approx 1 - |\mu|$ at $\arg\mu = \pi$), so the strobes repeat with
/// period 2 to the tolerance well before they repeat with period 1; a classifier that takes
/// that repetition for a period-2 orbit reports a doubling that does not exist. Every start,
/// for multipliers of modulus 0.5 to 0.95 at arguments from 0.8 pi to pi, must be period 1.
#[test]
fn a_period_one_orbit_approached_by_flips_is_not_period_two() {
    let system = FiniteDifferences::new(Forced);
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for modulus in [0.5_f64, 0.8, 0.95] {
        for turn in [0.8, 0.9, 1.0] {
            // arg = sqrt(1 - zeta^2) T = turn pi and |mu| = exp(-zeta T).
            let ratio = -modulus.ln() / (turn * PI); // zeta / sqrt(1 - zeta^2)
            let zeta = ratio / (1.0 + ratio * ratio).sqrt();
            let omega = 2.0 * (1.0 - zeta * zeta).sqrt() / turn;
            let p = [0.3, omega, zeta, 1e3];
            for newton_every in [30, 0] {
                let settings = StrobeSettings {
                    newton_every,
                    ..StrobeSettings::default()
                };
                for _ in 0..20 {
                    let x0 = [4.0 * uniform() - 2.0, 4.0 * uniform() - 2.0, 0.0, 1.0];
                    let c = classify(&system, &p, Mode(0), &x0, &settings).unwrap();
                    assert!(
                        matches!(c.attractor, Attractor::Periodic { period: 1, .. }),
                        "|mu| = {modulus}, arg = {turn} pi, start {x0:?}: {:?} ({:?})",
                        c.attractor,
                        c.decision
                    );
                }
            }
        }
    }
}
