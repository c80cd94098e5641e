//! The harmonically forced rocking rigid block (the study's dimensionless eqs. (6)-(12)).
//!
//! State $z = (\varphi, \psi, r, s)$; parameters $p = (\omega, \alpha, \xi, \theta_b)$ in that
//! order ([`OMEGA`], [`ALPHA`], [`XI`], [`THETA_B`]). The forcing phase $\beta$ is an initial
//! condition, $(r, s) = (\sin\beta, \cos\beta)$, see [`initial_state`].
//!
//! Modes: [`PLUS`] (rocking about the right corner, $\varphi > 0$), [`MINUS`] (left corner,
//! $\varphi < 0$) and [`REST`] (the block sits flat, $\varphi = \psi = 0$):
//! $$\dot\varphi = \psi,\quad
//!   \dot\psi = \tfrac34\left(\alpha\omega^2 r \sin(\theta_b \pm \varphi) \mp \cos(\theta_b \pm
//!   \varphi) - \xi\psi\right)\ \text{(mode } \pm),$$
//! $$\dot r = r + \omega s - r(r^2+s^2),\qquad \dot s = s - \omega r - s(r^2+s^2),$$
//! with $\dot\varphi = \dot\psi = 0$ at rest. Events: impacts at $\varphi = 0$ (mode $+$ falling,
//! mode $-$ rising) with reset $\psi \mapsto e\psi$ and a switch of sides, where
//! $e = 1 - \tfrac32\sin^2(\pi/2 - \theta_b)$; overturning at $\varphi = \pm\pi/2$ (terminal);
//! lift-off from rest when $\alpha\omega^2 r \tan\theta_b$ crosses $\pm 1$. Accumulating impacts
//! (chatter) switch to [`REST`] (see [`hycont_core::ZenoSettings`] for the criterion).

use hycont_core::{
    Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode, ParamId,
    Z2Symmetry,
};
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_2;

pub use crate::parameters::{DEFAULT_THETA_B, DEFAULT_XI, MAX_SCALE, Parameters, restitution};

/// Rocking about the right corner ($\varphi > 0$).
pub const PLUS: Mode = Mode(0);
/// Rocking about the left corner ($\varphi < 0$).
pub const MINUS: Mode = Mode(1);
/// At rest on the ground ($\varphi = \psi = 0$).
pub const REST: Mode = Mode(2);

/// Impact ending a flight in mode `+` ($\varphi \downarrow 0$); continues in mode `-`.
pub const IMPACT_PLUS: EventId = EventId(0);
/// Impact ending a flight in mode `-` ($\varphi \uparrow 0$); continues in mode `+`.
pub const IMPACT_MINUS: EventId = EventId(1);
/// Overturning to the right, $\varphi \uparrow \pi/2$ (terminal).
pub const OVERTURN_POS: EventId = EventId(2);
/// Overturning to the left, $\varphi \downarrow -\pi/2$ (terminal).
pub const OVERTURN_NEG: EventId = EventId(3);
/// Lift-off from rest into mode `+` ($\alpha\omega^2 r\tan\theta_b \uparrow 1$).
pub const LIFT_OFF_PLUS: EventId = EventId(4);
/// Lift-off from rest into mode `-` ($\alpha\omega^2 r\tan\theta_b \downarrow -1$).
pub const LIFT_OFF_MINUS: EventId = EventId(5);

/// Handle of the forcing frequency $\omega$.
pub const OMEGA: ParamId = ParamId(0);
/// Handle of the forcing amplitude $\alpha$.
pub const ALPHA: ParamId = ParamId(1);
/// Handle of the damping $\xi$.
pub const XI: ParamId = ParamId(2);
/// Handle of the slenderness angle $\theta_b$.
pub const THETA_B: ParamId = ParamId(3);

const NAMES: [&str; 4] = ["omega", "alpha", "xi", "theta_b"];
const EVENTS_PLUS: [EventId; 2] = [IMPACT_PLUS, OVERTURN_POS];
const EVENTS_MINUS: [EventId; 2] = [IMPACT_MINUS, OVERTURN_NEG];
const EVENTS_REST: [EventId; 2] = [LIFT_OFF_PLUS, LIFT_OFF_MINUS];

/// $de/d\theta_b = 3 \sin(\pi/2-\theta_b)\cos(\pi/2-\theta_b)$.
fn restitution_derivative(theta_b: f64) -> f64 {
    let a = FRAC_PI_2 - theta_b;
    3.0 * a.sin() * a.cos()
}

/// The initial state $(\varphi_0, \psi_0, \sin\beta, \cos\beta)$ for forcing phase $\beta$.
#[must_use]
pub fn initial_state(phi0: f64, psi0: f64, beta: f64) -> [f64; 4] {
    [phi0, psi0, beta.sin(), beta.cos()]
}

/// Angles and angular velocities within this of zero are zero up to rounding (the resolution of
/// an $O(1)$ angle): a start there is on the ground.
pub const ON_GROUND: f64 = f64::EPSILON;

/// The mode a state starts in: by the sign of $\varphi$, then of $\psi$; at
/// $\varphi = \psi = 0$ rest, unless the forcing already exceeds the lift-off threshold. Values
/// within [`ON_GROUND`] of zero count as zero, so a start at $\varphi_0 = \pm 10^{-30}$ is the
/// start at $\varphi_0 = 0$.
///
/// ```
/// use rocking_block::{initial_mode, initial_state, Parameters, REST};
/// let params = Parameters::new(1.3, 0.66);
/// assert_eq!(initial_mode(&initial_state(-1e-30, 0.0, 0.0), &params), REST);
/// ```
#[must_use]
pub fn initial_mode(x: &[f64; 4], params: &Parameters) -> Mode {
    let snap = |v: f64| if v.abs() <= ON_GROUND { 0.0 } else { v };
    let [phi, psi, r, _] = *x;
    let (phi, psi) = (snap(phi), snap(psi));
    if phi > 0.0 || (phi == 0.0 && psi > 0.0) {
        PLUS
    } else if phi < 0.0 || (phi == 0.0 && psi < 0.0) {
        MINUS
    } else {
        rest_or_lift_off(params.alpha, params.omega, params.theta_b, r)
    }
}

/// How far the forcing must exceed the lift-off threshold, $|\alpha\omega^2 r\tan\theta_b| > 1$,
/// for a block at rest to lift off: a few dozen rounding errors of that product. At the
/// threshold itself ($\alpha\omega^2\tan\theta_b = 1$, the peak $r = \pm 1$) the exact
/// excess is zero and the block stays at rest, as it does just below; computed in floating
/// point the product can exceed 1 by rounding alone, and a lift-off without excess acceleration
/// falls straight back onto its corner, a chattering that never ends (each Zeno transition
/// lifted it off again at the same instant). The lift-off events and the Zeno transition use
/// this margin alike.
pub const LIFT_OFF_MARGIN: f64 = 64.0 * f64::EPSILON;

/// The forcing's phase variable $r = \sin(\omega t + \beta)$ as the lift-off conditions read
/// it: clamped to $[-1, 1]$. On the forcing's cycle $|r| \le 1$; an integrator leaves it by
/// about its tolerance (`1e-8` at `rtol = 1e-7`), which at the threshold
/// $\alpha\omega^2\tan\theta_b = 1$ would exceed [`LIFT_OFF_MARGIN`] and lift the block off
/// with no excess acceleration (the chattering the margin is there to prevent).
fn forcing_phase(r: f64) -> f64 {
    r.clamp(-1.0, 1.0)
}

fn rest_or_lift_off(alpha: f64, omega: f64, theta_b: f64, r: f64) -> Mode {
    let c = alpha * omega * omega * forcing_phase(r) * theta_b.tan();
    if c > 1.0 + LIFT_OFF_MARGIN {
        PLUS
    } else if c < -1.0 - LIFT_OFF_MARGIN {
        MINUS
    } else {
        REST
    }
}

/// The rocking block as a [`HybridSystem`] with analytic [`HybridJacobians`].
///
/// ```
/// use hycont_core::{SimulationSettings, Simulator};
/// use rocking_block::{initial_mode, initial_state, Parameters, RockingBlock};
/// let params = Parameters::new(1.3, 0.66);
/// let x0 = initial_state(0.01, 0.0, 0.0);
/// let mut sim = Simulator::new(SimulationSettings::default()).unwrap();
/// let traj = sim
///     .run(&RockingBlock, initial_mode(&x0, &params), 0.0, &x0, &params.to_vec(), 50.0)
///     .unwrap();
/// assert!(traj.stats.jumps > 0);
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RockingBlock;

/// $(\sin, \cos)$ of the pivot angle $\theta_b \pm \varphi$ and the sign $\pm 1$ of mode
/// `mode` (zeros at rest).
///
/// By the `libm` crate's `sincos` (within an ulp, as glibc's): glibc's saves and restores the
/// rounding mode on every call, which made it a fifth of a shooting branch's time, and
/// `libm`'s takes about 60 % of its time.
#[inline(always)]
fn pivot(mode: Mode, phi: f64, theta_b: f64) -> (f64, f64, f64) {
    match mode {
        PLUS => {
            let (sn, cs) = libm::sincos(theta_b + phi);
            (sn, cs, 1.0)
        }
        MINUS => {
            let (sn, cs) = libm::sincos(theta_b - phi);
            (sn, cs, -1.0)
        }
        _ => (0.0, 0.0, 0.0),
    }
}

/// The vector field with the pivot's `(sin, cos, sign)` given (see [`pivot`]).
#[inline(always)]
fn field(mode: Mode, x: &[f64], p: &[f64], (sn, cs, sign): (f64, f64, f64), out: &mut [f64]) {
    let (psi, r, s) = (x[1], x[2], x[3]);
    let (omega, alpha, xi) = (p[0], p[1], p[2]);
    let rho2 = r * r + s * s;
    out[2] = r + omega * s - r * rho2;
    out[3] = s - omega * r - s * rho2;
    if mode == PLUS || mode == MINUS {
        // psi' = 3/4 (a sin(tb + sign phi) - sign cos(tb + sign phi) - xi psi)
        let a = alpha * omega * omega * r;
        out[0] = psi;
        out[1] = 0.75 * (a * sn - sign * cs - xi * psi);
    } else {
        out[0] = 0.0;
        out[1] = 0.0;
    }
}

/// The vector field's Jacobians with the pivot's `(sin, cos, sign)` given (see [`pivot`]).
#[inline(always)]
fn jacobian(
    mode: Mode,
    x: &[f64],
    p: &[f64],
    (sn, cs, sign): (f64, f64, f64),
    dx: &mut [f64],
    dp: Option<&mut [f64]>,
) {
    let (psi, r, s) = (x[1], x[2], x[3]);
    let (omega, alpha, xi) = (p[0], p[1], p[2]);
    dx.fill(0.0);
    // Column-major, 4 x 4: dx[i + 4 j] = d f_i / d x_j.
    dx[2 + 4 * 2] = 1.0 - 3.0 * r * r - s * s;
    dx[2 + 4 * 3] = omega - 2.0 * r * s;
    dx[3 + 4 * 2] = -omega - 2.0 * r * s;
    dx[3 + 4 * 3] = 1.0 - r * r - 3.0 * s * s;
    let aw2 = alpha * omega * omega;
    let moving = mode == PLUS || mode == MINUS;
    if moving {
        dx[4] = 1.0; // d phi' / d psi
        // psi' = 3/4 (aw2 r sin(tb + sign phi) - sign cos(tb + sign phi) - xi psi)
        dx[1] = 0.75 * (aw2 * r * cs * sign + sn);
        dx[1 + 4] = -0.75 * xi;
        dx[1 + 4 * 2] = 0.75 * aw2 * sn;
    }
    if let Some(dp) = dp {
        dp.fill(0.0);
        // Column-major, 4 x 4: dp[i + 4 q].
        dp[2] = s;
        dp[3] = -r;
        if moving {
            dp[1] = 0.75 * 2.0 * alpha * omega * r * sn;
            dp[1 + 4] = 0.75 * omega * omega * r * sn;
            dp[1 + 4 * 2] = -0.75 * psi;
            dp[1 + 4 * 3] = 0.75 * (aw2 * r * cs + sign * sn);
        }
    }
}

impl HybridSystem for RockingBlock {
    fn state_dim(&self) -> usize {
        4
    }

    fn parameter_names(&self) -> &[&'static str] {
        &NAMES
    }

    fn mode_count(&self) -> usize {
        3
    }

    fn mode_name(&self, mode: Mode) -> &'static str {
        match mode {
            PLUS => "+",
            MINUS => "-",
            _ => "rest",
        }
    }

    fn events(&self, mode: Mode) -> &[EventId] {
        match mode {
            PLUS => &EVENTS_PLUS,
            MINUS => &EVENTS_MINUS,
            _ => &EVENTS_REST,
        }
    }

    fn event_spec(&self, event: EventId) -> EventSpec {
        match event {
            IMPACT_PLUS => EventSpec {
                name: "impact+",
                direction: Direction::Falling,
                action: EventAction::Jump { to: MINUS },
            },
            IMPACT_MINUS => EventSpec {
                name: "impact-",
                direction: Direction::Rising,
                action: EventAction::Jump { to: PLUS },
            },
            OVERTURN_POS => EventSpec {
                name: "overturn+",
                direction: Direction::Rising,
                action: EventAction::Terminal,
            },
            OVERTURN_NEG => EventSpec {
                name: "overturn-",
                direction: Direction::Falling,
                action: EventAction::Terminal,
            },
            LIFT_OFF_PLUS => EventSpec {
                name: "lift-off+",
                direction: Direction::Rising,
                action: EventAction::Jump { to: PLUS },
            },
            _ => EventSpec {
                name: "lift-off-",
                direction: Direction::Falling,
                action: EventAction::Jump { to: MINUS },
            },
        }
    }

    #[inline]
    fn vector_field(&self, mode: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        field(mode, x, p, pivot(mode, x[0], p[3]), out);
    }

    fn event(&self, event: EventId, x: &[f64], p: &[f64]) -> f64 {
        match event {
            IMPACT_PLUS | IMPACT_MINUS => x[0],
            OVERTURN_POS => x[0] - FRAC_PI_2,
            OVERTURN_NEG => x[0] + FRAC_PI_2,
            LIFT_OFF_PLUS => {
                p[1] * p[0] * p[0] * forcing_phase(x[2]) * p[3].tan() - (1.0 + LIFT_OFF_MARGIN)
            }
            _ => p[1] * p[0] * p[0] * forcing_phase(x[2]) * p[3].tan() + (1.0 + LIFT_OFF_MARGIN),
        }
    }

    fn reset(&self, event: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        out.copy_from_slice(x);
        if event == IMPACT_PLUS || event == IMPACT_MINUS {
            out[1] = restitution(p[3]) * x[1];
        }
    }

    /// $\dot\varphi = \psi$ in both flights.
    fn rate_component(&self, mode: Mode, c: usize) -> Option<usize> {
        (c == 0 && (mode == PLUS || mode == MINUS)).then_some(1)
    }

    /// Impacts and overturning are surfaces $\varphi = \mathrm{const}$.
    fn event_component(&self, event: EventId) -> Option<usize> {
        matches!(
            event,
            IMPACT_PLUS | IMPACT_MINUS | OVERTURN_POS | OVERTURN_NEG
        )
        .then_some(0)
    }

    /// $S(\varphi, \psi, r, s) = -(\varphi, \psi, r, s)$, swapping the modes `+`/`-` and the
    /// events accordingly.
    fn symmetry(&self) -> Option<Z2Symmetry> {
        let mut matrix = vec![0.0; 16];
        for i in 0..4 {
            matrix[i + 4 * i] = -1.0;
        }
        Some(Z2Symmetry {
            matrix,
            modes: vec![MINUS, PLUS, REST],
            events: vec![
                IMPACT_MINUS,
                IMPACT_PLUS,
                OVERTURN_NEG,
                OVERTURN_POS,
                LIFT_OFF_MINUS,
                LIFT_OFF_PLUS,
            ],
        })
    }

    /// The forcing oscillator's multipliers: 1 (its phase, the flow direction) and
    /// $e^{-2T}$ (its amplitude, which relaxes at rate 2).
    fn trivial_multipliers(&self, _p: &[f64], period: f64) -> Vec<(f64, f64)> {
        vec![(1.0, 0.0), ((-2.0 * period).exp(), 0.0)]
    }

    fn zeno_transition(
        &self,
        _mode: Mode,
        _event: EventId,
        x: &[f64],
        p: &[f64],
        out: &mut [f64],
    ) -> Option<Mode> {
        out.copy_from_slice(x);
        out[0] = 0.0;
        out[1] = 0.0;
        Some(rest_or_lift_off(p[1], p[0], p[3], x[2]))
    }
}

impl HybridJacobians for RockingBlock {
    fn vector_field_jacobian(
        &self,
        mode: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        jacobian(mode, x, p, pivot(mode, x[0], p[3]), dx, dp);
    }

    #[inline]
    fn vector_field_with_jacobian(
        &self,
        mode: Mode,
        x: &[f64],
        p: &[f64],
        f: &mut [f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        // One sine and cosine of the pivot angle for both.
        let trig = pivot(mode, x[0], p[3]);
        field(mode, x, p, trig, f);
        jacobian(mode, x, p, trig, dx, dp);
    }

    fn event_gradient(
        &self,
        event: EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.fill(0.0);
        let (omega, alpha, theta_b) = (p[0], p[1], p[3]);
        let lift = event == LIFT_OFF_PLUS || event == LIFT_OFF_MINUS;
        // The clamped phase (see `forcing_phase`) is flat beyond |r| = 1.
        let inside = x[2].abs() <= 1.0;
        if lift {
            dx[2] = if inside {
                alpha * omega * omega * theta_b.tan()
            } else {
                0.0
            };
        } else {
            dx[0] = 1.0;
        }
        if let Some(dp) = dp {
            dp.fill(0.0);
            if lift {
                let (r, t) = (forcing_phase(x[2]), theta_b.tan());
                dp[0] = 2.0 * alpha * omega * r * t;
                dp[1] = omega * omega * r * t;
                dp[3] = alpha * omega * omega * r * (1.0 + t * t);
            }
        }
    }

    fn reset_jacobian(
        &self,
        event: EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.fill(0.0);
        for i in 0..4 {
            dx[i + 4 * i] = 1.0;
        }
        let impact = event == IMPACT_PLUS || event == IMPACT_MINUS;
        if impact {
            dx[1 + 4] = restitution(p[3]);
        }
        if let Some(dp) = dp {
            dp.fill(0.0);
            if impact {
                dp[1 + 4 * 3] = restitution_derivative(p[3]) * x[1];
            }
        }
    }
}

/// The parameter continued.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Free {
    /// The forcing frequency.
    Omega,
    /// The forcing amplitude.
    Alpha,
}

impl Free {
    /// The parameter handle.
    #[must_use]
    pub fn id(self) -> ParamId {
        match self {
            Free::Omega => OMEGA,
            Free::Alpha => ALPHA,
        }
    }

    /// The parameter of a handle, if it is one that is continued.
    #[must_use]
    pub fn of(id: ParamId) -> Option<Free> {
        [Free::Omega, Free::Alpha]
            .into_iter()
            .find(|f| f.id() == id)
    }

    /// The name in JSON output.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Free::Omega => "omega",
            Free::Alpha => "alpha",
        }
    }

    /// The study's range: omega in `[0.5, 4]`, alpha in `[0.01, 1.06]`.
    #[must_use]
    pub fn range(self) -> (f64, f64) {
        match self {
            Free::Omega => (0.5, 4.0),
            Free::Alpha => (0.01, 1.06),
        }
    }
}
