//! Touches: single grazing and boundary conditions of one segment as smooth functions of the
//! orbit, with exact gradients, so that a two-parameter curve can hold one at zero.
//!
//! An admissibility margin ([`super::AdmissibilityMargin`], [`super::GrazingMargin`]) is the
//! smallest of many conditions. It vanishes at a grazing, but it is not smooth where two
//! conditions meet, e.g. where an interior turning point of an event function merges with a
//! segment's end: held at zero along a curve, it makes the corrector crawl. A [`Touch`] is
//! the one condition that attains the margin at a grazing, smooth on its own:
//! - [`Touch::Turn`]: the value $\sigma h_e$ at a **turning point** of the event function along
//!   the segment's flow, the critical point $t^*$ of $h_e(x(t))$ (a minimum of $\sigma h_e$,
//!   $\sigma = \pm 1$ the sign before a crossing). Holding it is COCO's split of the segment at
//!   the velocity-zero point with that point on the surface, with the split time eliminated:
//!   $t^*$ solves $\dot h_e(x(t^*)) = 0$ (located on the integrator's dense output), so the
//!   value is a smooth function of the segment's start, duration and parameters wherever
//!   $\ddot h_e(t^*) \ne 0$, also where $t^*$ reaches or passes the segment's end; by the
//!   envelope theorem its gradient is $\sigma \nabla h_e^\top \Phi(t^*)$ (start) and
//!   $\sigma(\nabla h_e^\top \Phi_p(t^*) + \partial_p h_e)$ (parameters), from the
//!   variational equations;
//! - [`Touch::Approach`]: the approach rate $-\sigma \nabla h_e \cdot f$ at the segment's end,
//!   before its jump (zero at a tangential impact). Its gradient needs
//!   $\nabla(\nabla h_e \cdot f) = J_f^\top \nabla h_e + H_e f$, whose Hessian term is a central
//!   difference of $\nabla h_e$ along $f$ (exactly zero for event functions affine in the
//!   state, as impact surfaces are);
//! - [`Touch::End`]: $\sigma h_e$ at the segment's end (zero where a segment ends on another
//!   event's surface, or where an interior split point sits on it): exact to the orbit's
//!   unknowns at an interior end (the next segment's start), integrated otherwise.
//!
//! Values at integrated points carry the integrator's error (`rtol = 1e-12`); collocation
//! orbits are integrated from their segment starts, so a curve held by a touch holds it for
//! the flow through the collocation orbit's segment starts.

use super::PeriodicOrbit;
use super::admissibility::rate;
use super::flow::SegmentFlow;
use super::signature::{Closure, SegmentEnd};
use super::turning::turning_time;
use crate::error::{Error, Result};
use crate::simulate::{Sensitivities, SimulationSettings, Simulator};
use crate::system::{EventId, HybridJacobians, HybridSystem, Mode};
use serde::{Deserialize, Serialize};

/// One grazing or boundary condition of one segment (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Touch {
    /// $\sigma h_e$ at the turning point of $h_e$ along segment `segment`'s flow nearest the
    /// time `fraction` $T_k$ from the segment's start (a minimum of $\sigma h_e$; it may lie
    /// past the segment's end).
    Turn {
        /// The segment.
        segment: usize,
        /// The event whose surface is touched.
        event: EventId,
        /// Where to look for the turning point, as a fraction of the segment's duration (so
        /// that it follows the segment as its duration changes).
        fraction: f64,
    },
    /// The approach rate $-\sigma \nabla h_e \cdot f$ at the end of segment `segment`.
    Approach {
        /// The segment.
        segment: usize,
        /// Its end event.
        event: EventId,
    },
    /// $\sigma h_e$ at the end of segment `segment` (before its jump).
    End {
        /// The segment.
        segment: usize,
        /// The event.
        event: EventId,
    },
}

/// A touch's value on an orbit, with its exact gradient.
#[derive(Debug, Clone, PartialEq)]
pub struct TouchValue {
    /// The value (zero at the touch).
    pub value: f64,
    /// The gradient with respect to the orbit's coordinates: the segment starts, the
    /// durations, the parameters (the order of [`super::pack`]).
    pub gradient: Vec<f64>,
    /// The turning point's time from the segment's start, as a fraction of its duration
    /// ([`Touch::Turn`]; 1 for the others).
    pub fraction: f64,
}

/// Integration tolerances of touches.
fn settings() -> SimulationSettings {
    SimulationSettings::default().rtol(1e-12).atol(1e-13)
}

impl Touch {
    /// The segment.
    #[must_use]
    pub fn segment(&self) -> usize {
        match *self {
            Touch::Turn { segment, .. }
            | Touch::Approach { segment, .. }
            | Touch::End { segment, .. } => segment,
        }
    }

    /// The event.
    #[must_use]
    pub fn event(&self) -> EventId {
        match *self {
            Touch::Turn { event, .. }
            | Touch::Approach { event, .. }
            | Touch::End { event, .. } => event,
        }
    }

    /// The touch of a turning point of `event` found at time `t` of segment `segment` of
    /// `orbit` (e.g. a scan's critical point):
    /// - at a segment's end where that segment's own jump on `event` happens (at its start,
    ///   the end of the segment before; after the last segment of a half orbit, through the
    ///   symmetry): a tangential impact, [`Touch::Approach`] of that segment (there the turning
    ///   point's value is quadratic in the distance to the grazing, the approach rate linear);
    /// - at the start of a segment that follows an interior split in the same mode (a scan
    ///   counts a boundary point to the segment it starts): [`Touch::Turn`] at the end of the
    ///   segment before, so that its search window covers both sides of the split;
    /// - else [`Touch::Turn`] near `t`.
    #[must_use]
    pub fn at_turn<S: HybridSystem + ?Sized>(
        system: &S,
        orbit: &PeriodicOrbit,
        segment: usize,
        event: EventId,
        t: f64,
    ) -> Self {
        let segs = orbit.signature.segments();
        let kk = segs.len();
        let duration = |k: usize| orbit.durations.get(k).map_or(1.0, |d| d.abs().max(1e-300));
        if segment >= kk {
            return Touch::Turn {
                segment,
                event,
                fraction: 0.0,
            };
        }
        let band = 1e-6 * duration(segment);
        let before = (segment + kk - 1) % kk;
        // The event that ends the segment before, as seen from this segment's side.
        let wraps_symmetric = segment == 0 && orbit.signature.closure() == Closure::Symmetric;
        let seen = |e: EventId| match (wraps_symmetric, system.symmetry()) {
            (true, Some(sym)) => sym.events.get(e.0).copied(),
            (true, None) => None,
            (false, _) => Some(e),
        };
        if t.abs() <= band {
            match segs[before].end {
                SegmentEnd::Event(e) if seen(e) == Some(event) => {
                    return Touch::Approach {
                        segment: before,
                        event: e,
                    };
                }
                SegmentEnd::Interior { .. }
                    if !wraps_symmetric && segs[before].mode == segs[segment].mode =>
                {
                    return Touch::Turn {
                        segment: before,
                        event,
                        fraction: 1.0,
                    };
                }
                _ => {}
            }
        }
        if (t - orbit.durations[segment]).abs() <= band
            && segs[segment].end == SegmentEnd::Event(event)
        {
            return Touch::Approach { segment, event };
        }
        Touch::Turn {
            segment,
            event,
            fraction: t / duration(segment),
        }
    }

    /// The same touch looking for its turning point near `fraction` of its segment's
    /// duration (other touches unchanged): e.g. where it was found last.
    #[must_use]
    pub fn near(self, fraction: f64) -> Self {
        match self {
            Touch::Turn { segment, event, .. } => Touch::Turn {
                segment,
                event,
                fraction,
            },
            other => other,
        }
    }

    /// Checks the touch against `system` and `orbit`: the segment exists, its mode monitors the
    /// event, the event has a direction (and ends the segment, for [`Touch::Approach`]).
    ///
    /// # Errors
    /// [`Error::InvalidMeasure`] naming what does not fit.
    pub fn validate<S: HybridSystem + ?Sized>(
        &self,
        system: &S,
        orbit: &PeriodicOrbit,
    ) -> Result<()> {
        let (k, e) = (self.segment(), self.event());
        let bad = |reason: String| Err(Error::InvalidMeasure { reason });
        let Some(seg) = orbit.signature.segments().get(k) else {
            return bad(format!(
                "touch of segment {k}: the orbit has {} segments",
                orbit.segment_count()
            ));
        };
        if !system.events(seg.mode).contains(&e) {
            return bad(format!("touch of {e}: not monitored in segment {k}'s mode"));
        }
        if system.event_spec(e).direction.sign_before().is_none() {
            return bad(format!("touch of {e}: the event has no crossing direction"));
        }
        if matches!(self, Touch::Approach { .. }) && seg.end != SegmentEnd::Event(e) {
            return bad(format!("approach to {e}: segment {k} does not end with it"));
        }
        if let Touch::Turn { fraction, .. } = self
            && !fraction.is_finite()
        {
            return bad(format!(
                "touch of {e}: the fraction {fraction} is not finite"
            ));
        }
        Ok(())
    }

    /// The touch's value on `orbit` with its exact gradient.
    ///
    /// # Errors
    /// As [`Touch::validate`]; [`Error::InvalidMeasure`] when the segment's flow has no turning
    /// point towards the surface near the time asked for; integration failures.
    pub fn evaluate<S: HybridJacobians + ?Sized>(
        &self,
        system: &S,
        orbit: &PeriodicOrbit,
    ) -> Result<TouchValue> {
        self.validate(system, orbit)?;
        let (k, e) = (self.segment(), self.event());
        let sigma = system.event_spec(e).direction.sign_before().unwrap_or(1.0);
        let duration = orbit.durations[k];
        match *self {
            Touch::Turn { fraction, .. } => {
                let t_star = turning_time(system, orbit, k, e, sigma, fraction * duration)?;
                let at = Flowed::new(system, orbit, k, t_star)?;
                let (value, gradient) = at.event_value(system, orbit, e, sigma, false);
                Ok(TouchValue {
                    value,
                    gradient,
                    fraction: if duration == 0.0 {
                        0.0
                    } else {
                        t_star / duration
                    },
                })
            }
            Touch::End { .. } => {
                let (value, gradient) = match interior_end(system, orbit, k) {
                    Some(end) => end.event_value(system, orbit, e, sigma),
                    None => Flowed::new(system, orbit, k, duration)?
                        .event_value(system, orbit, e, sigma, true),
                };
                Ok(TouchValue {
                    value,
                    gradient,
                    fraction: 1.0,
                })
            }
            Touch::Approach { .. } => {
                let at = Flowed::new(system, orbit, k, duration)?;
                let (value, gradient) = at.approach(system, orbit, e, sigma);
                Ok(TouchValue {
                    value,
                    gradient,
                    fraction: 1.0,
                })
            }
        }
    }
}

/// The number of coordinates of `orbit` and the index of its first parameter.
fn layout(orbit: &PeriodicOrbit) -> (usize, usize) {
    let p0 = orbit.start_offset(orbit.segment_count()) + orbit.segment_count();
    (p0 + orbit.params.len(), p0)
}

/// The state reached by segment `k`'s flow at time `t` from its start, with its sensitivities
/// to the start ($\Phi$) and the parameters ($\Phi_p$).
struct Flowed {
    k: usize,
    mode: Mode,
    x: Vec<f64>,
    phi: Vec<f64>,
    phi_p: Vec<f64>,
}

impl Flowed {
    fn new<S: HybridJacobians + ?Sized>(
        system: &S,
        orbit: &PeriodicOrbit,
        k: usize,
        t: f64,
    ) -> Result<Self> {
        let mode = orbit.signature.segments()[k].mode;
        let flow = if t >= 0.0 {
            SegmentFlow::plain(system, mode)
        } else {
            SegmentFlow::backward(system, mode)
        };
        let mut sim = Simulator::new(settings())?;
        let traj = sim.run_with_sensitivities(
            &flow,
            Mode(0),
            0.0,
            &orbit.starts[k],
            &orbit.params,
            t.abs(),
            Sensitivities::StateAndParameters,
        )?;
        let sens = traj.sensitivities.ok_or_else(|| Error::InvalidMeasure {
            reason: "touch: the flow's sensitivities were not integrated".into(),
        })?;
        Ok(Self {
            k,
            mode,
            x: traj.state_final,
            phi: sens.state,
            phi_p: sens.params.unwrap_or_default(),
        })
    }

    /// The gradient over the orbit's coordinates of a function of the flowed state with
    /// gradient `gx` (state) and direct parameter derivative `gp`; `with_duration` when the
    /// state is the segment's end (it moves with the duration along $f$).
    fn chain<S: HybridJacobians + ?Sized>(
        &self,
        system: &S,
        orbit: &PeriodicOrbit,
        (gx, gp): (&[f64], &[f64]),
        with_duration: bool,
    ) -> Vec<f64> {
        let n = self.x.len();
        let (len, p0) = layout(orbit);
        let mut g = vec![0.0; len];
        for j in 0..n {
            g[orbit.start_offset(self.k) + j] = (0..n).map(|i| gx[i] * self.phi[i + j * n]).sum();
        }
        for (q, d) in gp.iter().enumerate() {
            let through = if self.phi_p.is_empty() {
                0.0
            } else {
                (0..n).map(|i| gx[i] * self.phi_p[i + q * n]).sum()
            };
            g[p0 + q] = d + through;
        }
        if with_duration {
            let mut f = vec![0.0; n];
            system.vector_field(self.mode, &self.x, &orbit.params, &mut f);
            g[orbit.start_offset(orbit.segment_count()) + self.k] = dot(gx, &f);
        }
        g
    }

    /// $\sigma h_e$ at the flowed state and its gradient.
    fn event_value<S: HybridJacobians + ?Sized>(
        &self,
        system: &S,
        orbit: &PeriodicOrbit,
        e: EventId,
        sigma: f64,
        with_duration: bool,
    ) -> (f64, Vec<f64>) {
        let p = &orbit.params;
        let (mut gx, mut gp) = (vec![0.0; self.x.len()], vec![0.0; p.len()]);
        system.event_gradient(e, &self.x, p, &mut gx, Some(&mut gp));
        scale(&mut gx, sigma);
        scale(&mut gp, sigma);
        let value = sigma * system.event(e, &self.x, p);
        (value, self.chain(system, orbit, (&gx, &gp), with_duration))
    }

    /// The approach rate $-\sigma \nabla h_e \cdot f$ at the flowed state and its gradient.
    fn approach<S: HybridJacobians + ?Sized>(
        &self,
        system: &S,
        orbit: &PeriodicOrbit,
        e: EventId,
        sigma: f64,
    ) -> (f64, Vec<f64>) {
        let (gx, gp) = rate_gradient(system, self.mode, e, &self.x, &orbit.params);
        let value = -sigma * rate(system, self.mode, e, &self.x, &orbit.params);
        let gx: Vec<f64> = gx.iter().map(|v| -sigma * v).collect();
        let gp: Vec<f64> = gp.iter().map(|v| -sigma * v).collect();
        (value, self.chain(system, orbit, (&gx, &gp), true))
    }
}

/// The end of segment `k` when it is an interior point: the next segment's start (or $S x_0$
/// after the last segment of a half orbit), exact to the orbit's unknowns.
struct InteriorEnd {
    /// The coordinates' index of the state's first component.
    at: usize,
    /// $S$ (column-major) when the end is the image of the first start.
    through: Option<Vec<f64>>,
    x: Vec<f64>,
}

fn interior_end<S: HybridSystem + ?Sized>(
    system: &S,
    orbit: &PeriodicOrbit,
    k: usize,
) -> Option<InteriorEnd> {
    let segs = orbit.signature.segments();
    if !matches!(segs[k].end, SegmentEnd::Interior { .. }) {
        return None;
    }
    let n = system.mode_dim(segs[0].mode);
    let next = (k + 1) % segs.len();
    let wrap_symmetric = k + 1 == segs.len() && orbit.signature.closure() == Closure::Symmetric;
    if wrap_symmetric {
        let sym = system.symmetry()?;
        let mut x = vec![0.0; n];
        sym.apply(&orbit.starts[0], &mut x);
        return Some(InteriorEnd {
            at: 0,
            through: Some(sym.block(n)),
            x,
        });
    }
    Some(InteriorEnd {
        at: orbit.start_offset(next),
        through: None,
        x: orbit.starts[next].clone(),
    })
}

impl InteriorEnd {
    fn event_value<S: HybridJacobians + ?Sized>(
        &self,
        system: &S,
        orbit: &PeriodicOrbit,
        e: EventId,
        sigma: f64,
    ) -> (f64, Vec<f64>) {
        let (n, p) = (self.x.len(), &orbit.params);
        let (mut gx, mut gp) = (vec![0.0; n], vec![0.0; p.len()]);
        system.event_gradient(e, &self.x, p, &mut gx, Some(&mut gp));
        let (len, p0) = layout(orbit);
        let mut g = vec![0.0; len];
        for j in 0..n {
            g[self.at + j] = sigma
                * match &self.through {
                    Some(sm) => (0..n).map(|i| gx[i] * sm[i + j * n]).sum(),
                    None => gx[j],
                };
        }
        for (q, d) in gp.iter().enumerate() {
            g[p0 + q] = sigma * d;
        }
        (sigma * system.event(e, &self.x, p), g)
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn scale(v: &mut [f64], s: f64) {
    for x in v.iter_mut() {
        *x *= s;
    }
}

/// The gradient of $\dot h_e = \nabla h_e \cdot f_m$ in the state and the parameters:
/// $J_f^\top \nabla h_e + H_e f$ and $f_p^\top \nabla h_e + (\partial_x \partial_p h_e) f$, the
/// second-derivative terms as central differences of $\nabla h_e$ and $\partial_p h_e$ along
/// $f$ (step $\epsilon^{1/3}$ relative; exact for event functions affine in the state).
fn rate_gradient<S: HybridJacobians + ?Sized>(
    system: &S,
    m: Mode,
    e: EventId,
    x: &[f64],
    p: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let (n, np) = (x.len(), p.len());
    let (mut g, mut gp) = (vec![0.0; n], vec![0.0; np]);
    system.event_gradient(e, x, p, &mut g, Some(&mut gp));
    let (mut f, mut jx, mut jp) = (vec![0.0; n], vec![0.0; n * n], vec![0.0; n * np]);
    system.vector_field_with_jacobian(m, x, p, &mut f, &mut jx, Some(&mut jp));
    let mut gx: Vec<f64> = (0..n).map(|j| dot(&g, &jx[j * n..(j + 1) * n])).collect();
    let mut gpx: Vec<f64> = (0..np).map(|q| dot(&g, &jp[q * n..(q + 1) * n])).collect();
    // Second derivatives along f.
    let fnorm = f.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    if fnorm > 0.0 {
        let xnorm = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let h = f64::EPSILON.cbrt() * (1.0 + xnorm) / fnorm;
        let (mut gplus, mut gminus) = (vec![0.0; n], vec![0.0; n]);
        let (mut pplus, mut pminus) = (vec![0.0; np], vec![0.0; np]);
        let shifted = |s: f64| -> Vec<f64> { x.iter().zip(&f).map(|(a, b)| a + s * b).collect() };
        system.event_gradient(e, &shifted(h), p, &mut gplus, Some(&mut pplus));
        system.event_gradient(e, &shifted(-h), p, &mut gminus, Some(&mut pminus));
        for j in 0..n {
            gx[j] += (gplus[j] - gminus[j]) / (2.0 * h);
        }
        for q in 0..np {
            gpx[q] += (pplus[q] - pminus[q]) / (2.0 * h);
        }
    }
    (gx, gpx)
}
