//! How well a located event is determined: the rate of its event function at the crossing and
//! estimates of the errors of the crossing time and of that rate.
//!
//! # Near-tangential crossings are ill-conditioned
//! The integrated state carries an error $\delta x$ of the order of the tolerances,
//! $\delta x_i \approx \mathrm{atol} + \mathrm{rtol}\,|x_i|$, so the event function is known
//! to $\delta h \approx \sum_i |h(x + \delta x_i e_i) - h(x)|$. Near a crossing
//! $h(t) \approx \dot h\,(t - t_e) + \tfrac12 \ddot h\,(t - t_e)^2$, hence
//! $$\delta t \approx \frac{\delta h}{|\dot h|} \quad\text{(at most } \sqrt{2\delta h / |\ddot h|}
//! \text{, the tangential limit)}, \qquad \delta\dot h \approx |\ddot h|\,\delta t
//! \approx \frac{|\ddot h|\,\delta h}{|\dot h|}.$$
//! The relative error of the approach rate grows like $1/\dot h^2$: an impact with approach
//! velocity $10^{-7}$ and unit acceleration, located with the default tolerances
//! ($\delta h \approx 10^{-10}$), has a rate known only to about $10^{-3}$, which is no rate at
//! all. This is the conditioning of the problem, not a defect of the root finder (which
//! locates the zero of the computed $h$ to $10^{-13}$). To tighten it, lower `rtol` and `atol`
//! ([`crate::SimulationSettings::rtol`]): the errors scale with them, down to rounding
//! ($\delta h \gtrsim 10^{-16} |x|$, so rates below about $10^{-8}$ are never resolved).
//! A velocity component of the state at the crossing (e.g. an impact velocity) has the same
//! error as the rate of an event on the matching position, $h = x_c - d$.

use super::Dop853;
use crate::system::{EventId, HybridSystem};
use serde::{Deserialize, Serialize};

/// The conditioning of a located event crossing (see the module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct EventConditioning {
    /// The rate $\dot h_e$ of the event function along the trajectory at the crossing (before
    /// the jump), from the integrator's dense output.
    pub rate: f64,
    /// Estimated error of the crossing time: $\delta h / |\dot h|$, at most
    /// $\sqrt{2\delta h/|\ddot h|}$, plus the root finder's tolerance.
    pub t_error: f64,
    /// Estimated error of `rate` (and of a velocity whose position the event watches):
    /// $|\ddot h|\,\delta t$ plus the tolerance's share of the rate.
    pub rate_error: f64,
}

impl EventConditioning {
    /// Whether the rate is known to within `fraction` of itself (e.g. `0.01`): a crossing is
    /// resolved when it is, ill-conditioned (near tangential) when not.
    #[must_use]
    pub fn rate_resolved(&self, fraction: f64) -> bool {
        self.rate_error <= fraction * self.rate.abs()
    }
}

/// The conditioning of `event`'s crossing at `te`, state `y` (its first `n` components), within
/// the accepted step `(t, t_new)` whose dense output `stepper` has prepared; `x` is scratch
/// space of `n` values.
#[allow(clippy::too_many_arguments)]
pub(super) fn conditioning<S: HybridSystem + ?Sized>(
    system: &S,
    event: EventId,
    p: &[f64],
    stepper: &Dop853,
    (t, t_new): (f64, f64),
    (te, y): (f64, &[f64]),
    (rtol, atol, event_tolerance): (f64, f64, f64),
    x: &mut [f64],
) -> EventConditioning {
    let n = x.len();
    let h0 = system.event(event, &y[..n], p);
    // The event function along the dense output at two more times in the step.
    let span = t_new - t;
    let ds = 1e-3 * span;
    let d1 = if te - t >= ds { ds } else { -2.0 * ds };
    let d2 = if t_new - te >= ds { ds } else { -2.0 * ds };
    let mut h_at = |time: f64| {
        for (i, v) in x.iter_mut().enumerate() {
            *v = stepper.dense_component(i, time);
        }
        system.event(event, x, p)
    };
    let (ha, hb) = (h_at(te - d1), h_at(te + d2));
    // The quadratic through the three values: h = h0 + g s + c s^2 / 2.
    let curvature = 2.0 * ((hb - h0) / d2 - (h0 - ha) / d1) / (d1 + d2);
    let rate = (h0 - ha) / d1 + curvature * d1 / 2.0;
    // The event function's uncertainty from the state's.
    let mut dh = 0.0;
    x.copy_from_slice(&y[..n]);
    for i in 0..n {
        let d = atol + rtol * y[i].abs();
        x[i] = y[i] + d;
        dh += (system.event(event, x, p) - h0).abs();
        x[i] = y[i];
    }
    let root = event_tolerance * te.abs().max(1.0);
    let linear = if rate == 0.0 {
        f64::INFINITY
    } else {
        dh / rate.abs()
    };
    let tangential = if curvature == 0.0 {
        f64::INFINITY
    } else {
        (2.0 * dh / curvature.abs()).sqrt()
    };
    let t_error = linear.min(tangential) + root;
    let rate_error = curvature.abs() * t_error + rtol * rate.abs();
    if !(span > 0.0 && t_error.is_finite() && rate_error.is_finite()) {
        return EventConditioning {
            rate,
            t_error: f64::INFINITY,
            rate_error: f64::INFINITY,
        };
    }
    EventConditioning {
        rate,
        t_error,
        rate_error,
    }
}
