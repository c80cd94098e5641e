//! Derivatives by central differences: [`FiniteDifferences`] gives any system its Jacobians, and
//! [`check_derivatives`] compares a system's supplied derivatives (and its structural hints)
//! against them; [`check_derivatives_against`] compares them with another system's (e.g. an
//! automatically differentiated twin's).

use super::{
    EventAction, EventId, EventSpec, HybridJacobians, HybridSystem, Mode, ParamId, Z2Symmetry,
};
use serde::{Deserialize, Serialize};

/// Relative step for central differences: $\epsilon^{1/3}$, scaled by $\max(1, |v|)$.
fn fd_step(v: f64) -> f64 {
    f64::EPSILON.cbrt() * v.abs().max(1.0)
}

/// Central-difference Jacobian of `func: R^m -> R^r` at `v`, column-major into `out` ($r \times m$).
fn central_difference(
    v: &[f64],
    rows: usize,
    out: &mut [f64],
    mut func: impl FnMut(&[f64], &mut [f64]),
) {
    let mut w = v.to_vec();
    let mut plus = vec![0.0; rows];
    let mut minus = vec![0.0; rows];
    for j in 0..v.len() {
        let h = fd_step(v[j]);
        w[j] = v[j] + h;
        let hp = w[j] - v[j];
        func(&w, &mut plus);
        w[j] = v[j] - h;
        let hm = v[j] - w[j];
        func(&w, &mut minus);
        w[j] = v[j];
        for i in 0..rows {
            out[i + j * rows] = (plus[i] - minus[i]) / (hp + hm);
        }
    }
}

/// Gives any [`HybridSystem`] derivatives by central differences.
///
/// Accuracy is about $\epsilon^{2/3} \approx 4 \cdot 10^{-11}$ relative for smooth functions, which
/// is enough for Newton's method and for checking analytic Jacobians, but analytic Jacobians are
/// faster and exact; supply them for production models.
///
/// ```
/// use hycont_core::{FiniteDifferences, HybridJacobians, HybridSystem, Mode, EventId, EventSpec,
///                   Direction, EventAction};
/// struct Decay;
/// impl HybridSystem for Decay {
///     fn state_dim(&self) -> usize { 1 }
///     fn parameter_names(&self) -> &[&'static str] { &["k"] }
///     fn mode_count(&self) -> usize { 1 }
///     fn mode_name(&self, _: Mode) -> &'static str { "only" }
///     fn events(&self, _: Mode) -> &[EventId] { &[] }
///     fn event_spec(&self, _: EventId) -> EventSpec { unreachable!() }
///     fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], out: &mut [f64]) { out[0] = -p[0] * x[0]; }
///     fn event(&self, _: EventId, _: &[f64], _: &[f64]) -> f64 { unreachable!() }
/// }
/// let fd = FiniteDifferences::new(Decay);
/// let (mut dx, mut dp) = ([0.0], [0.0]);
/// fd.vector_field_jacobian(Mode(0), &[2.0], &[3.0], &mut dx, Some(&mut dp));
/// assert!((dx[0] + 3.0).abs() < 1e-8 && (dp[0] + 2.0).abs() < 1e-8);
/// ```
#[derive(Debug, Clone)]
pub struct FiniteDifferences<S> {
    inner: S,
}

impl<S: HybridSystem> FiniteDifferences<S> {
    /// Wraps a system.
    #[must_use]
    pub fn new(inner: S) -> Self {
        Self { inner }
    }

    /// The wrapped system.
    #[must_use]
    pub fn inner(&self) -> &S {
        &self.inner
    }
}

impl<S: HybridSystem> HybridSystem for FiniteDifferences<S> {
    fn state_dim(&self) -> usize {
        self.inner.state_dim()
    }
    fn mode_dim(&self, mode: Mode) -> usize {
        self.inner.mode_dim(mode)
    }
    fn parameter_names(&self) -> &[&'static str] {
        self.inner.parameter_names()
    }
    fn parameter_count(&self) -> usize {
        self.inner.parameter_count()
    }
    fn parameter_id(&self, name: &str) -> Option<ParamId> {
        self.inner.parameter_id(name)
    }
    fn mode_count(&self) -> usize {
        self.inner.mode_count()
    }
    fn mode_name(&self, mode: Mode) -> &'static str {
        self.inner.mode_name(mode)
    }
    fn events(&self, mode: Mode) -> &[EventId] {
        self.inner.events(mode)
    }
    fn event_spec(&self, event: EventId) -> EventSpec {
        self.inner.event_spec(event)
    }
    fn vector_field(&self, mode: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        self.inner.vector_field(mode, x, p, out);
    }
    fn event(&self, event: EventId, x: &[f64], p: &[f64]) -> f64 {
        self.inner.event(event, x, p)
    }
    fn reset(&self, event: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        self.inner.reset(event, x, p, out);
    }
    fn zeno_transition(
        &self,
        mode: Mode,
        event: EventId,
        x: &[f64],
        p: &[f64],
        out: &mut [f64],
    ) -> Option<Mode> {
        self.inner.zeno_transition(mode, event, x, p, out)
    }
    fn symmetry(&self) -> Option<Z2Symmetry> {
        self.inner.symmetry()
    }
    fn rate_component(&self, mode: Mode, c: usize) -> Option<usize> {
        self.inner.rate_component(mode, c)
    }
    fn event_component(&self, event: EventId) -> Option<usize> {
        self.inner.event_component(event)
    }
    fn trivial_multipliers(&self, p: &[f64], period: f64) -> Vec<(f64, f64)> {
        self.inner.trivial_multipliers(p, period)
    }
}

impl<S: HybridSystem> HybridJacobians for FiniteDifferences<S> {
    fn vector_field_jacobian(
        &self,
        mode: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        let n = x.len();
        central_difference(x, n, dx, |w, out| {
            self.inner.vector_field(mode, w, p, out);
        });
        if let Some(dp) = dp {
            central_difference(p, n, dp, |w, out| {
                self.inner.vector_field(mode, x, w, out);
            });
        }
    }

    fn event_gradient(
        &self,
        event: EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        central_difference(x, 1, dx, |w, out| out[0] = self.inner.event(event, w, p));
        if let Some(dp) = dp {
            central_difference(p, 1, dp, |w, out| out[0] = self.inner.event(event, x, w));
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
        let m = super::reset_dim(self, event, x.len());
        central_difference(x, m, dx, |w, out| self.inner.reset(event, w, p, out));
        if let Some(dp) = dp {
            central_difference(p, m, dp, |w, out| self.inner.reset(event, x, w, out));
        }
    }
}

/// Which derivative an entry of a [`DerivativeCheck`] refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum DerivativeKind {
    /// $\partial f_m / \partial x$.
    VectorFieldState,
    /// $\partial f_m / \partial p$.
    VectorFieldParams,
    /// $\partial h_e / \partial x$ of the given event.
    EventState(EventId),
    /// $\partial h_e / \partial p$ of the given event.
    EventParams(EventId),
    /// $\partial g_e / \partial x$ of the given event.
    ResetState(EventId),
    /// $\partial g_e / \partial p$ of the given event.
    ResetParams(EventId),
    /// The hint [`HybridSystem::rate_component`]: $f_c$ (supplied) against $x_j$ (numeric), one
    /// entry per hinted component.
    RateComponent,
    /// The hint [`HybridSystem::event_component`] of the given event: the unit vector $e_c$
    /// (supplied) against the event function's central-difference gradient.
    EventComponent(EventId),
    /// [`HybridJacobians::vector_field_with_jacobian`] against the separate methods: $f$, then
    /// $\partial f / \partial x$, then $\partial f / \partial p$, one column of `n` rows each
    /// (`numeric` holds the separate methods' values; they must agree to round-off).
    VectorFieldWithJacobian,
}

/// The worst disagreement between a supplied derivative and central differences.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DerivativeMismatch {
    /// Which derivative.
    pub kind: DerivativeKind,
    /// Row of the entry.
    pub row: usize,
    /// Column of the entry.
    pub col: usize,
    /// The supplied value.
    pub supplied: f64,
    /// The reference value: central differences ([`check_derivatives`]) or the reference
    /// system's ([`check_derivatives_against`]).
    pub numeric: f64,
    /// `|supplied - numeric| / (1 + |numeric|)`.
    pub error: f64,
}

/// Result of [`check_derivatives`]: the largest scaled error over all checked entries.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DerivativeCheck {
    /// The worst entry per derivative kind checked.
    pub worst: Vec<DerivativeMismatch>,
}

impl DerivativeCheck {
    /// The largest scaled error $|a - d| / (1 + |d|)$ over all checked entries.
    #[must_use]
    pub fn max_error(&self) -> f64 {
        self.worst.iter().map(|m| m.error).fold(0.0, f64::max)
    }
}

fn compare(
    kind: DerivativeKind,
    rows: usize,
    supplied: &[f64],
    numeric: &[f64],
) -> DerivativeMismatch {
    let mut worst = DerivativeMismatch {
        kind,
        row: 0,
        col: 0,
        supplied: supplied.first().copied().unwrap_or(0.0),
        numeric: numeric.first().copied().unwrap_or(0.0),
        error: 0.0,
    };
    for (k, (&a, &d)) in supplied.iter().zip(numeric).enumerate() {
        let error = (a - d).abs() / (1.0 + d.abs());
        if error > worst.error || error.is_nan() {
            worst = DerivativeMismatch {
                kind,
                row: k % rows,
                col: k / rows,
                supplied: a,
                numeric: d,
                error: if error.is_nan() { f64::INFINITY } else { error },
            };
        }
    }
    worst
}

/// Compares a system's supplied derivatives in `mode` at `(x, p)` against central differences
/// (vector field, and event gradients and reset Jacobians of every event of the mode).
///
/// Central differences have a truncation error of order $h^2 \|f'''\|$ with
/// $h = \epsilon^{1/3} \max(1, |v|)$, so agreement to about `1e-7` (scaled) is expected for
/// well-scaled smooth functions.
///
/// # Errors
/// [`crate::Error::InvalidMode`] for a mode the system does not have,
/// [`crate::Error::DimensionMismatch`] for `x` or `p` of the wrong length.
pub fn check_derivatives<S: HybridJacobians + ?Sized>(
    system: &S,
    mode: Mode,
    x: &[f64],
    p: &[f64],
) -> crate::Result<DerivativeCheck> {
    check_point(system, mode, x, p)?;
    let n = system.mode_dim(mode);
    let np = system.parameter_count();
    let mut worst = Vec::new();
    let mut ax = vec![0.0; n * n];
    let mut ap = vec![0.0; n * np];
    let mut nx = vec![0.0; n * n];
    let mut npm = vec![0.0; n * np];

    system.vector_field_jacobian(mode, x, p, &mut ax, Some(&mut ap));
    central_difference(x, n, &mut nx, |w, out| system.vector_field(mode, w, p, out));
    central_difference(p, n, &mut npm, |w, out| {
        system.vector_field(mode, x, w, out);
    });
    worst.push(compare(DerivativeKind::VectorFieldState, n, &ax, &nx));
    worst.push(compare(DerivativeKind::VectorFieldParams, n, &ap, &npm));

    // The combined evaluation must agree with the separate ones.
    let mut separate = vec![0.0; n];
    system.vector_field(mode, x, p, &mut separate);
    separate.extend_from_slice(&ax);
    separate.extend_from_slice(&ap);
    let mut combined = vec![0.0; n * (1 + n + np)];
    {
        let (f, rest) = combined.split_at_mut(n);
        let (cx, cp) = rest.split_at_mut(n * n);
        system.vector_field_with_jacobian(mode, x, p, f, cx, Some(cp));
    }
    worst.push(compare(
        DerivativeKind::VectorFieldWithJacobian,
        n,
        &combined,
        &separate,
    ));

    // Structural hints: f_c = x_j exactly.
    let hinted: Vec<(usize, usize)> = (0..n)
        .filter_map(|c| system.rate_component(mode, c).map(|j| (c, j)))
        .collect();
    if !hinted.is_empty() {
        let mut f = vec![0.0; n];
        system.vector_field(mode, x, p, &mut f);
        let supplied: Vec<f64> = hinted.iter().map(|&(c, _)| f[c]).collect();
        let numeric: Vec<f64> = hinted
            .iter()
            .map(|&(_, j)| x.get(j).copied().unwrap_or(f64::NAN))
            .collect();
        worst.push(compare(
            DerivativeKind::RateComponent,
            1,
            &supplied,
            &numeric,
        ));
    }

    for &e in system.events(mode) {
        if let Some(c) = system.event_component(e) {
            let mut unit = vec![0.0; n];
            if let Some(u) = unit.get_mut(c) {
                *u = 1.0;
            }
            let mut ngx = vec![0.0; n];
            central_difference(x, 1, &mut ngx, |w, out| out[0] = system.event(e, w, p));
            if c >= n {
                unit[0] = f64::NAN;
            }
            worst.push(compare(DerivativeKind::EventComponent(e), 1, &unit, &ngx));
        }
        let mut gx = vec![0.0; n];
        let mut gp = vec![0.0; np];
        let mut ngx = vec![0.0; n];
        let mut ngp = vec![0.0; np];
        system.event_gradient(e, x, p, &mut gx, Some(&mut gp));
        central_difference(x, 1, &mut ngx, |w, out| out[0] = system.event(e, w, p));
        central_difference(p, 1, &mut ngp, |w, out| out[0] = system.event(e, x, w));
        worst.push(compare(DerivativeKind::EventState(e), 1, &gx, &ngx));
        worst.push(compare(DerivativeKind::EventParams(e), 1, &gp, &ngp));

        if let EventAction::Jump { .. } = system.event_spec(e).action {
            // n_+ x n (the reset may change the state's dimension).
            let m = super::reset_dim(system, e, n);
            let (mut ax, mut ap) = (vec![0.0; m * n], vec![0.0; m * np]);
            let (mut nx, mut npm) = (vec![0.0; m * n], vec![0.0; m * np]);
            system.reset_jacobian(e, x, p, &mut ax, Some(&mut ap));
            central_difference(x, m, &mut nx, |w, out| system.reset(e, w, p, out));
            central_difference(p, m, &mut npm, |w, out| system.reset(e, x, w, out));
            worst.push(compare(DerivativeKind::ResetState(e), m, &ax, &nx));
            worst.push(compare(DerivativeKind::ResetParams(e), m, &ap, &npm));
        }
    }
    Ok(DerivativeCheck { worst })
}

/// Compares a system's derivatives in `mode` at `(x, p)` against those of a `reference` system
/// with the same equations (vector field, event gradients and reset Jacobians of every event of
/// the mode; `numeric` of each [`DerivativeMismatch`] is the reference's value): hand-coded
/// Jacobians against an [`super::AutoDiff`] twin's agree to rounding, about `1e-15` scaled,
/// where [`check_derivatives`]'s central differences only resolve about `1e-7`.
///
/// # Errors
/// As [`check_derivatives`]; [`crate::Error::InvalidSystem`] for a reference of another
/// layout (states, parameters, modes, or the mode's events).
///
/// ```
/// use hycont_core::{AutoDiff, FiniteDifferences, HybridModel, Mode, EventId, EventSpec, Scalar,
///                   check_derivatives_against};
/// /// x' = -k x^3.
/// struct Cubic;
/// impl HybridModel for Cubic {
///     fn state_dim(&self) -> usize { 1 }
///     fn parameter_names(&self) -> &[&'static str] { &["k"] }
///     fn mode_count(&self) -> usize { 1 }
///     fn mode_name(&self, _: Mode) -> &'static str { "only" }
///     fn events(&self, _: Mode) -> &[EventId] { &[] }
///     fn event_spec(&self, _: EventId) -> EventSpec { unreachable!() }
///     fn vector_field<T: Scalar>(&self, _: Mode, x: &[T], p: &[T], f: &mut [T]) {
///         f[0] = -p[0] * x[0].powi(3);
///     }
///     fn event<T: Scalar>(&self, _: EventId, x: &[T], _: &[T]) -> T { x[0] }
/// }
/// let (exact, differences) = (AutoDiff::new(Cubic), FiniteDifferences::new(AutoDiff::new(Cubic)));
/// let check = check_derivatives_against(&differences, &exact, Mode(0), &[1.5], &[2.0]).unwrap();
/// assert!(check.max_error() > 0.0 && check.max_error() < 1e-8);
/// ```
pub fn check_derivatives_against<S, R>(
    system: &S,
    reference: &R,
    mode: Mode,
    x: &[f64],
    p: &[f64],
) -> crate::Result<DerivativeCheck>
where
    S: HybridJacobians + ?Sized,
    R: HybridJacobians + ?Sized,
{
    check_point(system, mode, x, p)?;
    let (a, b) = (
        (
            system.mode_dim(mode),
            system.parameter_count(),
            system.mode_count(),
        ),
        (
            reference.mode_dim(mode),
            reference.parameter_count(),
            reference.mode_count(),
        ),
    );
    if a != b || system.events(mode) != reference.events(mode) {
        return Err(crate::Error::InvalidSystem {
            reason: format!(
                "the reference has another layout: {} states, {} parameters, {} modes and events {:?} in mode {mode}, against {} states, {} parameters, {} modes and events {:?}",
                b.0,
                b.1,
                b.2,
                reference.events(mode),
                a.0,
                a.1,
                a.2,
                system.events(mode)
            ),
        });
    }
    let (n, np) = (system.mode_dim(mode), system.parameter_count());
    let mut worst = Vec::new();
    let (mut ax, mut ap) = (vec![0.0; n * n], vec![0.0; n * np]);
    let (mut rx, mut rp) = (vec![0.0; n * n], vec![0.0; n * np]);
    system.vector_field_jacobian(mode, x, p, &mut ax, Some(&mut ap));
    reference.vector_field_jacobian(mode, x, p, &mut rx, Some(&mut rp));
    worst.push(compare(DerivativeKind::VectorFieldState, n, &ax, &rx));
    worst.push(compare(DerivativeKind::VectorFieldParams, n, &ap, &rp));
    for &e in system.events(mode) {
        let (mut gx, mut gp) = (vec![0.0; n], vec![0.0; np]);
        let (mut hx, mut hp) = (vec![0.0; n], vec![0.0; np]);
        system.event_gradient(e, x, p, &mut gx, Some(&mut gp));
        reference.event_gradient(e, x, p, &mut hx, Some(&mut hp));
        worst.push(compare(DerivativeKind::EventState(e), 1, &gx, &hx));
        worst.push(compare(DerivativeKind::EventParams(e), 1, &gp, &hp));
        if let EventAction::Jump { .. } = system.event_spec(e).action {
            let m = super::reset_dim(system, e, n);
            if m != super::reset_dim(reference, e, n) {
                return Err(crate::Error::InvalidSystem {
                    reason: format!(
                        "the reference's {e} leads to a state of {} components, the system's to {m}",
                        super::reset_dim(reference, e, n)
                    ),
                });
            }
            let (mut ax, mut ap) = (vec![0.0; m * n], vec![0.0; m * np]);
            let (mut rx, mut rp) = (vec![0.0; m * n], vec![0.0; m * np]);
            system.reset_jacobian(e, x, p, &mut ax, Some(&mut ap));
            reference.reset_jacobian(e, x, p, &mut rx, Some(&mut rp));
            worst.push(compare(DerivativeKind::ResetState(e), m, &ax, &rx));
            worst.push(compare(DerivativeKind::ResetParams(e), m, &ap, &rp));
        }
    }
    Ok(DerivativeCheck { worst })
}

/// Checks a point of `system` in `mode`: the mode exists, `x` and `p` have the system's
/// lengths.
fn check_point<S: HybridSystem + ?Sized>(
    system: &S,
    mode: Mode,
    x: &[f64],
    p: &[f64],
) -> crate::Result<()> {
    if mode.0 >= system.mode_count() {
        return Err(crate::Error::InvalidMode {
            mode,
            count: system.mode_count(),
        });
    }
    if !super::uniform_dims(system) {
        super::check_mode_dims(system)?;
    }
    crate::error::check_len("state", x, system.mode_dim(mode))?;
    crate::error::check_len("parameters", p, system.parameter_count())
}
