//! The test models shared by the diagram tests: a Hopf circle times a pitchfork loop,
//! $x_1' = x_2 + x_1(a - |x|^2)$, $x_2' = -x_1 + x_2(a - |x|^2)$, $y' = y(g(\mu) - y^2)$ with
//! $g(\mu) = \mu(c - \mu)$, symmetric under $S = -I$ (`diagram.rs` derives its orbits and
//! branch points).
#![allow(dead_code)] // each test file uses part of it

/// Edits of saved files, shared by the tests of saved atlases and diagrams.
pub mod edits;
/// The sphere's atlas model, shared by the atlas tests.
pub mod sphere;

use hycont_continuation::OrbitRun;
use hycont_core::orbit::{PeriodicOrbit, SegmentEnd, SegmentSpec, Signature};
use hycont_core::{EventId, EventSpec, HybridJacobians, HybridSystem, Mode, ParamId, Z2Symmetry};
use std::f64::consts::PI;

pub const MU: ParamId = ParamId(1);
pub const C: f64 = 1.0;

pub struct HopfLoop;

impl HybridSystem for HopfLoop {
    fn state_dim(&self) -> usize {
        3
    }
    fn parameter_names(&self) -> &[&'static str] {
        &["a", "mu", "c"]
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
        f[2] = x[2] * (p[1] * (p[2] - p[1]) - x[2] * x[2]);
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

impl HybridJacobians for HopfLoop {
    fn vector_field_jacobian(
        &self,
        _: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        let r = p[0] - x[0] * x[0] - x[1] * x[1];
        let g = p[1] * (p[2] - p[1]);
        dx.fill(0.0);
        dx[0] = r - 2.0 * x[0] * x[0];
        dx[1] = -1.0 - 2.0 * x[0] * x[1];
        dx[3] = 1.0 - 2.0 * x[0] * x[1];
        dx[4] = r - 2.0 * x[1] * x[1];
        dx[8] = g - 3.0 * x[2] * x[2];
        if let Some(dp) = dp {
            // Column-major 3 x 3: columns a, mu, c.
            dp.fill(0.0);
            dp[0] = x[0];
            dp[1] = x[1];
            dp[5] = x[2] * (p[2] - 2.0 * p[1]);
            dp[8] = x[2] * p[1];
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
/// crossings of x2 = 0 (the second half the image of the first: a symmetric orbit is
/// recognised as one).
pub fn circle(mu: f64, y: f64) -> PeriodicOrbit {
    let half = SegmentSpec {
        mode: Mode(0),
        end: SegmentEnd::Interior {
            component: 1,
            value: 0.0,
        },
    };
    let sig = Signature::new(&HopfLoop, vec![half, half]).unwrap();
    PeriodicOrbit::new(
        &HopfLoop,
        sig,
        vec![vec![1.0, 0.0, y], vec![-1.0, 0.0, y]],
        vec![PI, PI],
        vec![1.0, mu, C],
    )
    .unwrap()
}

pub fn run<'a>() -> OrbitRun<'a, HopfLoop> {
    let mut run = OrbitRun::new(&HopfLoop, MU).unwrap();
    run.bounds(-0.5, 1.5);
    run
}
