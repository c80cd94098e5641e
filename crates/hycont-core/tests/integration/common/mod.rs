//! Test models, each paired with its closed-form reference solution.
#![allow(dead_code)]

pub mod shuttle;

use hycont_core::{
    Direction, EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode,
};

/// Bouncing ball: height y, velocity v; y'' = -g; impact at y = 0 (falling) with v -> -e v.
/// Parameters (g, e). Mode 0 flight, mode 1 rest (Zeno target).
///
/// Reference: from (0, v0), flight k (k = 0, 1, ...) lasts 2 v0 e^k / g, so the impacts are at
/// t_k = (2 v0 / g) (1 - e^(k+1)) / (1 - e) and accumulate at 2 v0 / (g (1 - e)).
pub struct Ball {
    pub zeno_rest: bool,
}

impl HybridSystem for Ball {
    fn state_dim(&self) -> usize {
        2
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["g", "e"]
    }
    fn mode_count(&self) -> usize {
        2
    }
    fn mode_name(&self, m: Mode) -> &'static str {
        ["flight", "rest"][m.0]
    }
    fn events(&self, m: Mode) -> &[EventId] {
        if m.0 == 0 { &[EventId(0)] } else { &[] }
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "impact",
            direction: Direction::Falling,
            action: EventAction::Jump { to: Mode(0) },
        }
    }
    fn vector_field(&self, m: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        if m.0 == 0 {
            out[0] = x[1];
            out[1] = -p[0];
        } else {
            out.fill(0.0);
        }
    }
    fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 {
        x[0]
    }
    fn reset(&self, _: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        out[0] = x[0];
        out[1] = -p[1] * x[1];
    }
    fn zeno_transition(
        &self,
        _: Mode,
        _: EventId,
        _: &[f64],
        _: &[f64],
        out: &mut [f64],
    ) -> Option<Mode> {
        if self.zeno_rest {
            out.fill(0.0);
            Some(Mode(1))
        } else {
            None
        }
    }
}

/// Impact oscillator: x'' = -k x for x > 0 with a wall at x = 0 (impact when x falls through 0,
/// v -> -e v). Parameters (k, e). Optional terminal event at x = cap (rising).
///
/// Reference: from (0, v0 > 0), x(t) = (v0 e^j / w) sin(w (t - t_j)) on flight j with w = sqrt(k),
/// so impacts are exactly at t_j = (j + 1) pi / w and the pre-impact velocity of impact j is
/// -v0 e^j.
pub struct ImpactOscillator {
    pub cap: Option<f64>,
}

const IO_EVENTS_CAP: [EventId; 2] = [EventId(0), EventId(1)];

impl HybridSystem for ImpactOscillator {
    fn state_dim(&self) -> usize {
        2
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["k", "e"]
    }
    fn mode_count(&self) -> usize {
        1
    }
    fn mode_name(&self, _: Mode) -> &'static str {
        "free"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        if self.cap.is_some() {
            &IO_EVENTS_CAP
        } else {
            &IO_EVENTS_CAP[..1]
        }
    }
    fn event_spec(&self, e: EventId) -> EventSpec {
        if e.0 == 0 {
            EventSpec {
                name: "wall",
                direction: Direction::Falling,
                action: EventAction::Jump { to: Mode(0) },
            }
        } else {
            EventSpec {
                name: "cap",
                direction: Direction::Rising,
                action: EventAction::Terminal,
            }
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        out[0] = x[1];
        out[1] = -p[0] * x[0];
    }
    fn event(&self, e: EventId, x: &[f64], _: &[f64]) -> f64 {
        if e.0 == 0 {
            x[0]
        } else {
            x[0] - self.cap.unwrap_or(f64::INFINITY)
        }
    }
    fn reset(&self, _: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        out[0] = x[0];
        out[1] = -p[1] * x[1];
    }
}

impl HybridJacobians for ImpactOscillator {
    fn vector_field_jacobian(
        &self,
        _: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.copy_from_slice(&[0.0, -p[0], 1.0, 0.0]);
        if let Some(dp) = dp {
            dp.copy_from_slice(&[0.0, -x[0], 0.0, 0.0]);
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
    fn reset_jacobian(
        &self,
        _: EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.copy_from_slice(&[1.0, 0.0, 0.0, -p[1]]);
        if let Some(dp) = dp {
            dp.copy_from_slice(&[0.0, 0.0, 0.0, -x[1]]);
        }
    }
}

/// Relaxation oscillator: x' = a - x, y' = -2 y; event x = 1.5 (rising) with reset
/// (x, y) -> (x / 3, y + 1). Parameter a > 1.5.
///
/// Reference: the periodic orbit starts at x = 0.5 and lasts T = ln((a - 0.5) / (a - 1.5));
/// y(0) = 1 / (1 - e^{-2T}); Floquet multipliers 1 (flow direction) and e^{-2T}.
pub struct Relaxation;

impl Relaxation {
    pub fn period(a: f64) -> f64 {
        ((a - 0.5) / (a - 1.5)).ln()
    }
    pub fn y0(a: f64) -> f64 {
        1.0 / (1.0 - (-2.0 * Self::period(a)).exp())
    }
    /// The state at time `t` of the orbit: $x = a - (a - 0.5)e^{-t}$, $y = y_0 e^{-2t}$.
    pub fn state(a: f64, t: f64) -> [f64; 2] {
        [a - (a - 0.5) * (-t).exp(), Self::y0(a) * (-2.0 * t).exp()]
    }
    /// The orbit's signature: one charging segment ended by firing.
    pub fn signature() -> hycont_core::orbit::Signature {
        use hycont_core::orbit::{SegmentEnd, SegmentSpec, Signature};
        Signature::new(
            &Relaxation,
            vec![SegmentSpec {
                mode: Mode(0),
                end: SegmentEnd::Event(EventId(0)),
            }],
        )
        .unwrap()
    }
    /// An orbit of one charging segment from `start` lasting `duration`, at parameter `a`.
    pub fn orbit(start: [f64; 2], duration: f64, a: f64) -> hycont_core::orbit::PeriodicOrbit {
        hycont_core::orbit::PeriodicOrbit::new(
            &Relaxation,
            Self::signature(),
            vec![start.to_vec()],
            vec![duration],
            vec![a],
        )
        .unwrap()
    }
    /// The true largest error of collocation unknowns `u` (on `disc`, orbits like `like`) at
    /// parameter `a`: the polynomial, read on a fine mesh through the transfer (which evaluates
    /// it at the new nodes), against [`Relaxation::state`].
    pub fn collocation_error(
        disc: &hycont_core::orbit::Discretisation,
        like: &hycont_core::orbit::PeriodicOrbit,
        u: &[f64],
        a: f64,
    ) -> f64 {
        use hycont_core::orbit::{Discretisation, Mesh, collocation_unpack};
        let Discretisation::Collocation { ncol, .. } = disc else {
            panic!("a collocation discretisation")
        };
        let fine_mesh: Mesh = (0..=2000).map(|j| f64::from(j) / 2000.0).collect();
        let fine = Discretisation::Collocation {
            meshes: vec![fine_mesh.clone()],
            ncol: *ncol,
        };
        let v = disc.transfer(&fine, like, u).unwrap();
        let (nodes, _) = collocation_unpack(like, &[fine_mesh], *ncol, &v);
        let count = nodes[0].len() / 2;
        (0..count)
            .map(|k| {
                let t = Self::period(a) * k as f64 / (count - 1) as f64;
                let [x, y] = Self::state(a, t);
                (nodes[0][2 * k] - x)
                    .abs()
                    .max((nodes[0][2 * k + 1] - y).abs())
            })
            .fold(0.0, f64::max)
    }
}

impl HybridSystem for Relaxation {
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
        "charge"
    }
    fn events(&self, _: Mode) -> &[EventId] {
        &[EventId(0)]
    }
    fn event_spec(&self, _: EventId) -> EventSpec {
        EventSpec {
            name: "fire",
            direction: Direction::Rising,
            action: EventAction::Jump { to: Mode(0) },
        }
    }
    fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        out[0] = p[0] - x[0];
        out[1] = -2.0 * x[1];
    }
    fn event(&self, _: EventId, x: &[f64], _: &[f64]) -> f64 {
        x[0] - 1.5
    }
    fn reset(&self, _: EventId, x: &[f64], _: &[f64], out: &mut [f64]) {
        out[0] = x[0] / 3.0;
        out[1] = x[1] + 1.0;
    }
    fn trivial_multipliers(&self, _: &[f64], _: f64) -> Vec<(f64, f64)> {
        vec![(1.0, 0.0)]
    }
}

impl HybridJacobians for Relaxation {
    fn vector_field_jacobian(
        &self,
        _: Mode,
        _: &[f64],
        _: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.copy_from_slice(&[-1.0, 0.0, 0.0, -2.0]);
        if let Some(dp) = dp {
            dp.copy_from_slice(&[1.0, 0.0]);
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
    fn reset_jacobian(
        &self,
        _: EventId,
        _: &[f64],
        _: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        dx.copy_from_slice(&[1.0 / 3.0, 0.0, 0.0, 1.0]);
        if let Some(dp) = dp {
            dp.fill(0.0);
        }
    }
}

/// A small deterministic generator (xorshift64*), so that the tests are reproducible.
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next() * n as f64) as usize).min(n - 1)
    }
    pub fn shuffle(&mut self, n: usize) -> Vec<usize> {
        let mut p: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            p.swap(i, self.below(i + 1));
        }
        p
    }
}
