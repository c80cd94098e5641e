//! The rocking block written once for any scalar ([`RockingBlockModel`], a
//! [`HybridModel`]): with [`hycont_core::AutoDiff`] a system with exact Jacobians by automatic
//! differentiation, beside [`RockingBlock`]'s hand-coded ones (equal to rounding:
//! `tests/integration/autodiff.rs`). Events, modes, symmetry, Zeno transitions and hints are
//! [`RockingBlock`]'s.

use crate::model::{
    IMPACT_MINUS, IMPACT_PLUS, LIFT_OFF_MARGIN, LIFT_OFF_PLUS, MINUS, OVERTURN_NEG, OVERTURN_POS,
    PLUS, RockingBlock,
};
use hycont_core::{EventId, EventSpec, HybridModel, HybridSystem, Mode, Scalar, Z2Symmetry};
use std::f64::consts::FRAC_PI_2;

/// The rocking block's equations (the study's eqs. (6)-(12), see [`crate::model`]) for any
/// [`Scalar`].
///
/// ```
/// use hycont_core::{AutoDiff, HybridJacobians};
/// use rocking_block::model_ad::RockingBlockModel;
/// use rocking_block::{PLUS, RockingBlock};
/// let (x, p) = ([0.2, -0.3, 0.6, 0.8], [1.3, 0.66, 0.00022, 0.8795]);
/// let (mut ad, mut hand) = ([0.0; 16], [0.0; 16]);
/// AutoDiff::new(RockingBlockModel).vector_field_jacobian(PLUS, &x, &p, &mut ad, None);
/// RockingBlock.vector_field_jacobian(PLUS, &x, &p, &mut hand, None);
/// for (a, h) in ad.iter().zip(&hand) {
///     assert!((a - h).abs() <= 1e-15 * (1.0 + h.abs()));
/// }
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RockingBlockModel;

/// The forcing's phase $r$ on its limit cycle, clamped to $[-1, 1]$ (as the hand-coded model).
fn forcing_phase<T: Scalar>(r: T) -> T {
    if r > 1.0 {
        T::from(1.0)
    } else if r < -1.0 {
        T::from(-1.0)
    } else {
        r
    }
}

impl HybridModel for RockingBlockModel {
    fn state_dim(&self) -> usize {
        RockingBlock.state_dim()
    }
    fn parameter_names(&self) -> &[&'static str] {
        RockingBlock.parameter_names()
    }
    fn mode_count(&self) -> usize {
        RockingBlock.mode_count()
    }
    fn mode_name(&self, mode: Mode) -> &'static str {
        RockingBlock.mode_name(mode)
    }
    fn events(&self, mode: Mode) -> &[EventId] {
        RockingBlock.events(mode)
    }
    fn event_spec(&self, event: EventId) -> EventSpec {
        RockingBlock.event_spec(event)
    }

    fn vector_field<T: Scalar>(&self, mode: Mode, x: &[T], p: &[T], out: &mut [T]) {
        let (phi, psi, r, s) = (x[0], x[1], x[2], x[3]);
        let (omega, alpha, xi, theta_b) = (p[0], p[1], p[2], p[3]);
        let rho2 = r * r + s * s;
        out[2] = r + omega * s - r * rho2;
        out[3] = s - omega * r - s * rho2;
        let sign = match mode {
            PLUS => 1.0,
            MINUS => -1.0,
            _ => {
                out[0] = T::from(0.0);
                out[1] = T::from(0.0);
                return;
            }
        };
        // psi' = 3/4 (a sin(tb + sign phi) - sign cos(tb + sign phi) - xi psi)
        let (sn, cs) = (theta_b + phi * sign).sin_cos();
        let a = alpha * omega * omega * r;
        out[0] = psi;
        out[1] = (a * sn - cs * sign - xi * psi) * 0.75;
    }

    fn event<T: Scalar>(&self, event: EventId, x: &[T], p: &[T]) -> T {
        let lift = |c: f64| p[1] * p[0] * p[0] * forcing_phase(x[2]) * p[3].tan() + c;
        match event {
            IMPACT_PLUS | IMPACT_MINUS => x[0],
            OVERTURN_POS => x[0] - FRAC_PI_2,
            OVERTURN_NEG => x[0] + FRAC_PI_2,
            LIFT_OFF_PLUS => lift(-(1.0 + LIFT_OFF_MARGIN)),
            _ => lift(1.0 + LIFT_OFF_MARGIN),
        }
    }

    fn reset<T: Scalar>(&self, event: EventId, x: &[T], p: &[T], out: &mut [T]) {
        out.copy_from_slice(x);
        if event == IMPACT_PLUS || event == IMPACT_MINUS {
            let c = (T::from(FRAC_PI_2) - p[3]).sin();
            out[1] = (T::from(1.0) - c * c * 1.5) * x[1];
        }
    }

    fn symmetry(&self) -> Option<Z2Symmetry> {
        RockingBlock.symmetry()
    }
    fn trivial_multipliers(&self, p: &[f64], period: f64) -> Vec<(f64, f64)> {
        RockingBlock.trivial_multipliers(p, period)
    }
    fn rate_component(&self, mode: Mode, c: usize) -> Option<usize> {
        RockingBlock.rate_component(mode, c)
    }
    fn event_component(&self, event: EventId) -> Option<usize> {
        RockingBlock.event_component(event)
    }
    fn zeno_transition(
        &self,
        mode: Mode,
        event: EventId,
        x: &[f64],
        p: &[f64],
        out: &mut [f64],
    ) -> Option<Mode> {
        RockingBlock.zeno_transition(mode, event, x, p, out)
    }
}
