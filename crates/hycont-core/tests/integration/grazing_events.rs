//! Grazing-safe event detection: impacts at low approach velocity, whose event function dips
//! through zero and back inside one step, are found with default settings.
//!
//! Two references, both in closed form:
//! - **Constant deceleration** toward a wall: $\ddot x = a$ with $x(0) = x_0$,
//!   $\dot x(0) = -v_0$. Then $x(t) = x_0 - v_0 t + a t^2 / 2$ reaches $x = 0$ first at
//!   $t^* = (v_0 - v)/a$ with approach velocity $v = \sqrt{v_0^2 - 2 a x_0}$. The integrator is
//!   exact on quadratics (up to rounding), so the only error is rounding: a position error of a
//!   few ulps of $x_0$ moves the crossing by that over $v$, and the event tolerance adds
//!   $10^{-13} \max(1, t)$. Without the dip test a step of length $O(1)$ spans the whole
//!   excursion below the wall (of duration $2v/a$) and the impact is missed.
//! - **A harmonic oscillator against a wall with restitution**: $\ddot x = -\omega^2 (x - c)$,
//!   impact at $x = 0$ (falling), $\dot x^+ = -e \dot x^-$. Leaving the wall with velocity $u$,
//!   the motion is $x = c + R\cos\theta$ with $R = \sqrt{c^2 + u^2/\omega^2}$ and
//!   $\theta = \omega t - \theta^*$; it returns to the wall at $\theta = \theta^*$,
//!   $\theta^* = \arccos(-c/R)$, after $2\theta^*/\omega$, with the same speed $u$ (energy is
//!   conserved between impacts). So impact $k$ has approach velocity $e^k u_0$: ever more grazing
//!   impacts, at closed-form times.

use hycont_core::{
    Direction, EventAction, EventId, EventSpec, HybridSystem, Mode, SimulationSettings, Simulator,
    StopReason,
};
use proptest::prelude::*;

/// $\ddot x = p_0$ (mode 0) or $\ddot x = -p_1^2 (x - p_2)$ (mode 1), impact at $x = 0$ falling
/// with restitution $p_3$ (or terminal when `terminal`). `hinted` declares the event as the
/// coordinate $x_0$ (exact rates); otherwise the simulator differentiates it numerically.
struct Wall {
    harmonic: bool,
    hinted: bool,
    terminal: bool,
}

impl HybridSystem for Wall {
    fn state_dim(&self) -> usize {
        2
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["a", "omega", "c", "e"]
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
            name: "impact",
            direction: Direction::Falling,
            action: if self.terminal {
                EventAction::Terminal
            } else {
                EventAction::Jump { to: Mode(0) }
            },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        out[0] = x[1];
        out[1] = if self.harmonic {
            -p[1] * p[1] * (x[0] - p[2])
        } else {
            p[0]
        };
    }
    fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 {
        x[0]
    }
    fn reset(&self, _: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        out[0] = 0.0;
        out[1] = -p[3] * x[1];
    }
    fn event_component(&self, _: EventId) -> Option<usize> {
        self.hinted.then_some(0)
    }
}

/// The constant-deceleration case at approach velocity `v` (a = 1, v0 = 1): the first event's
/// time and velocity against the closed form.
fn decelerating_impact(v: f64, hinted: bool) {
    let wall = Wall {
        harmonic: false,
        hinted,
        terminal: true,
    };
    let x0 = 0.5 - 0.5 * v * v;
    // x0 in [1/4, 1]: 0.5 - x0 is exact (Sterbenz), so the reference uses the stored x0.
    let v_exact = (2.0 * (0.5 - x0)).sqrt();
    let t_ref = 1.0 - v_exact;
    let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
    let traj = sim
        .run(&wall, Mode(0), 0.0, &[x0, -1.0], &[1.0, 0.0, 0.0, 0.0], 3.0)
        .unwrap();
    assert!(
        matches!(traj.stop, StopReason::TerminalEvent { .. }),
        "approach velocity {v:e} (hinted: {hinted}): impact missed, {:?}",
        traj.stop
    );
    // Rounding of x (a few ulps of x0) over the approach velocity, plus the event tolerance.
    let tol = 1e-13 + 16.0 * f64::EPSILON / v_exact;
    assert!(
        (traj.t_final - t_ref).abs() <= tol,
        "v = {v:e}: t = {} vs {t_ref} (tol {tol:e})",
        traj.t_final
    );
    let v_sim = -traj.events[0].state_before[1];
    assert!(
        (v_sim - v_exact).abs() <= tol + 1e-15,
        "v = {v:e}: approach velocity {v_sim:e} vs {v_exact:e}"
    );
}

/// Approach velocities $10^{-2}$ to $10^{-7}$ with default settings, with the event's rate
/// given by the structural hint.
#[test]
fn low_velocity_impacts_are_found_with_an_exact_rate() {
    for k in 2..=7 {
        decelerating_impact(10f64.powi(-k), true);
    }
}

/// The same without the hint: the rate comes from central differences of the event function.
#[test]
fn low_velocity_impacts_are_found_with_a_differenced_rate() {
    for k in 2..=7 {
        decelerating_impact(10f64.powi(-k), false);
    }
}

/// A trajectory that comes within $10^{-3}$ of the wall and turns back has no event.
#[test]
fn a_near_miss_is_not_an_impact() {
    let wall = Wall {
        harmonic: false,
        hinted: false,
        terminal: true,
    };
    let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
    let traj = sim
        .run(
            &wall,
            Mode(0),
            0.0,
            &[0.5 + 1e-3, -1.0],
            &[1.0, 0.0, 0.0, 0.0],
            3.0,
        )
        .unwrap();
    assert_eq!(traj.stop, StopReason::EndReached);
    assert!(traj.events.is_empty());
}

/// Starts within rounding of the wall, at rest, under a pull toward it ($\ddot x = -1$): from
/// $x_0 = 10^{-30}$ the crossing is at $t^* = \sqrt{2 x_0} \approx 1.4 \cdot 10^{-15}$, from
/// $x_0 = -10^{-30}$ (just past the wall, moving further) at $t = 0$, and from $x_0 = 0$ at
/// $t = 0$. A terminal event fires there, not after the run has left the domain; a jump with
/// restitution then jumps again at the same instant, which is a Zeno accumulation at $t = 0$.
#[test]
fn a_start_within_rounding_of_the_surface_is_never_stepped_over() {
    let p = [-1.0, 0.0, 0.0, 0.5];
    for x0 in [1e-30, 0.0, -1e-30] {
        for terminal in [true, false] {
            let wall = Wall {
                harmonic: false,
                hinted: false,
                terminal,
            };
            let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
            let traj = sim.run(&wall, Mode(0), 0.0, &[x0, 0.0], &p, 3.0).unwrap();
            let (what, t) = match traj.stop {
                StopReason::TerminalEvent { t, .. } => ("terminal", t),
                StopReason::ZenoAccumulation { t, .. } => ("zeno", t),
                other => panic!("x0 = {x0:e}, terminal {terminal}: missed, {other:?}"),
            };
            assert_eq!(what, if terminal { "terminal" } else { "zeno" });
            // Located within the default event tolerance, 1e-13 (times max(1, t)).
            assert!(t <= 1e-13, "x0 = {x0:e}: event at t = {t:e}, expected ~0");
            assert!(traj.state_final[0].abs() <= 1e-29, "{:?}", traj.state_final);
        }
    }
}

/// A start on the wall moving away from it ($\dot x_0 = 1$, $\ddot x = -1$) has its first
/// impact at $t = 2$, not at the start.
#[test]
fn a_start_on_the_surface_moving_into_the_domain_has_no_event_at_the_start() {
    let wall = Wall {
        harmonic: false,
        hinted: false,
        terminal: true,
    };
    let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
    let traj = sim
        .run(
            &wall,
            Mode(0),
            0.0,
            &[0.0, 1.0],
            &[-1.0, 0.0, 0.0, 0.0],
            3.0,
        )
        .unwrap();
    let StopReason::TerminalEvent { t, .. } = traj.stop else {
        panic!("{:?}", traj.stop)
    };
    approx::assert_abs_diff_eq!(t, 2.0, epsilon = 1e-12);
}

/// A marker: the jump at the surface keeps the velocity ($e = -1$, $\dot x^+ = \dot x^-$), so
/// the flow goes on past the surface. Falling at unit speed from $x_0 = 1$, it crosses once, at
/// $t = 1$, and the segment after the jump (starting on the surface, moving past it) is not a
/// new crossing.
#[test]
fn a_marker_event_fires_once_and_the_flow_goes_on() {
    let wall = Wall {
        harmonic: false,
        hinted: false,
        terminal: false,
    };
    let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
    let traj = sim
        .run(
            &wall,
            Mode(0),
            0.0,
            &[1.0, -1.0],
            &[0.0, 0.0, 0.0, -1.0],
            3.0,
        )
        .unwrap();
    assert_eq!(traj.stop, StopReason::EndReached);
    assert_eq!(traj.events.len(), 1);
    approx::assert_abs_diff_eq!(traj.events[0].t, 1.0, epsilon = 1e-12);
    approx::assert_abs_diff_eq!(traj.state_final[0], -2.0, epsilon = 1e-12);
}

/// Closed-form impact times of the harmonic oscillator leaving the wall with velocity `u0`:
/// impact $k$ (approach velocity $e^k u_0$) while that velocity is at least `v_min`.
fn harmonic_impacts(omega: f64, c: f64, e: f64, u0: f64, v_min: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let (mut t, mut u) = (0.0, u0);
    while u >= v_min {
        let r = (c * c + (u / omega).powi(2)).sqrt();
        t += 2.0 * (-c / r).acos() / omega;
        out.push((t, u));
        u *= e;
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Random oscillators (frequency, rest position, restitution, launch velocity): every impact
    /// whose approach velocity is at least $10^{-4}$ (excursion below the wall
    /// $\ge 5 \times 10^{-9} / \omega^2$, far above the integration error at the default
    /// tolerances) is found at its closed-form time, and no other event is reported. The run
    /// ends halfway between the last such impact and the next one.
    #[test]
    fn event_counts_match_the_closed_form(
        omega in 0.5f64..3.0,
        c in 0.05f64..1.0,
        e in 0.05f64..0.6,
        u0 in 0.1f64..2.0,
        hinted in any::<bool>(),
    ) {
        let v_min = 1e-4;
        let reference = harmonic_impacts(omega, c, e, u0, v_min);
        let t_last = reference.last().map_or(0.0, |r| r.0);
        // The next impact (approach velocity below v_min) lies more than half a period later;
        // stop halfway to it.
        let u = u0 * e.powi(reference.len() as i32);
        let r = (c * c + (u / omega).powi(2)).sqrt();
        let t_end = t_last + (-c / r).acos() / omega;
        let wall = Wall { harmonic: true, hinted, terminal: false };
        let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
        let traj = sim
            .run(&wall, Mode(0), 0.0, &[0.0, u0], &[0.0, omega, c, e], t_end)
            .unwrap();
        prop_assert_eq!(traj.events.len(), reference.len());
        for (ev, (t_ref, u_ref)) in traj.events.iter().zip(&reference) {
            // Integration error ~1e-9 in x over the approach velocity, at most.
            let tol = 1e-8 / u_ref;
            prop_assert!((ev.t - t_ref).abs() <= tol, "t = {} vs {} (u = {:e})", ev.t, t_ref, u_ref);
        }
    }
}
