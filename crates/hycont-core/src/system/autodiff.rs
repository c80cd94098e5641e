//! Exact derivatives without hand coding: a hybrid system written once, generic over its scalar
//! ([`HybridModel`]), and [`AutoDiff`], which makes it a [`HybridSystem`] with
//! [`HybridJacobians`] from forward-mode dual numbers (`num_dual`): every Jacobian (vector
//! field, event gradient, reset) exact to rounding, in one evaluation of the model on dual
//! numbers carrying all $n$ (or $n + n_p$) directions at once; Jacobian-matrix products in one
//! evaluation on duals seeded with the matrix.

use super::{EventId, EventSpec, HybridJacobians, HybridSystem, Mode, Tangents, Z2Symmetry};
use nalgebra::SVector;
use num_dual::Derivative;
use num_dual::{Dual64, DualNum, DualSVec64, HyperDual64};

/// The scalar a [`HybridModel`] is written in: `f64`, or a dual number over it. Write the
/// model's functions with the operators and the methods of [`num_dual::DualNum`](https://docs.rs/num-dual/0.15/num_dual/trait.DualNum.html) (`sin`, `exp`,
/// `powi`, ...); constants enter as `T::from(c)` or through arithmetic with `f64` on the
/// right (`x * 2.0 + 1.0`, `x / 3.0`): `f64` cannot stand left of a generic scalar (`2.0 * x`
/// does not compile for a generic `T`; Rust has no `f64: Mul<T>` to name), so write
/// `T::from(2.0) * x` or `x * 2.0`.
///
/// Dual numbers differentiate the operations as written: where a function is not
/// differentiable the derivative they give is not finite, even where the value is (`sqrt` at
/// 0: `sqrt(x * x)` has the derivative `0 / 0` = NaN at `x = 0`; `abs` at 0 gives one side's).
/// Write such points out of the model (`x.abs()` rather than `sqrt(x * x)`), or keep the flow
/// away from them: a non-finite derivative met by a simulation with sensitivities, a shooting
/// or a collocation solve is an error naming the function and the entry
/// ([`crate::Error::NonFiniteDerivative`]), not a silent NaN.
pub trait Scalar: DualNum<Primitive = f64> + Copy {}

impl<T: DualNum<Primitive = f64> + Copy> Scalar for T {}

/// A hybrid system written once for any [`Scalar`]: what [`HybridSystem`] asks for, with the
/// vector fields, event functions and resets generic. [`AutoDiff`] turns it into a
/// [`HybridSystem`] with exact [`HybridJacobians`].
///
/// ```
/// use hycont_core::{AutoDiff, Direction, EventAction, EventId, EventSpec, HybridJacobians,
///                   HybridModel, Mode, Scalar};
/// /// A pendulum swinging against a wall at theta = 0: theta'' = -sin(theta) - c theta'.
/// struct Pendulum;
/// impl HybridModel for Pendulum {
///     fn state_dim(&self) -> usize { 2 }
///     fn parameter_names(&self) -> &[&'static str] { &["c", "e"] }
///     fn mode_count(&self) -> usize { 1 }
///     fn mode_name(&self, _: Mode) -> &'static str { "swing" }
///     fn events(&self, _: Mode) -> &[EventId] { &[EventId(0)] }
///     fn event_spec(&self, _: EventId) -> EventSpec {
///         EventSpec { name: "wall", direction: Direction::Falling,
///                     action: EventAction::Jump { to: Mode(0) } }
///     }
///     fn vector_field<T: Scalar>(&self, _: Mode, x: &[T], p: &[T], out: &mut [T]) {
///         out[0] = x[1];
///         out[1] = -x[0].sin() - p[0] * x[1];
///     }
///     fn event<T: Scalar>(&self, _: EventId, x: &[T], _: &[T]) -> T { x[0] }
///     fn reset<T: Scalar>(&self, _: EventId, x: &[T], p: &[T], out: &mut [T]) {
///         out[0] = x[0];
///         out[1] = -p[1] * x[1];
///     }
/// }
/// let sys = AutoDiff::new(Pendulum);
/// let (x, p) = ([0.3, -0.5], [0.1, 0.8]);
/// let (mut dx, mut dp) = ([0.0; 4], [0.0; 4]);
/// sys.vector_field_jacobian(Mode(0), &x, &p, &mut dx, Some(&mut dp));
/// assert_eq!(dx, [0.0, -0.3f64.cos(), 1.0, -0.1]); // column-major
/// assert_eq!(dp, [0.0, 0.5, 0.0, 0.0]);
/// ```
pub trait HybridModel {
    /// Dimension $n$ of the continuous state (the largest mode's, where they differ).
    fn state_dim(&self) -> usize;
    /// Dimension of the state in `mode` ([`HybridSystem::mode_dim`]; default: `state_dim()`).
    fn mode_dim(&self, mode: Mode) -> usize {
        let _ = mode;
        self.state_dim()
    }
    /// Names of the parameters, in the order of the parameter vector.
    fn parameter_names(&self) -> &[&'static str];
    /// Number of modes.
    fn mode_count(&self) -> usize;
    /// A short name of a mode.
    fn mode_name(&self, mode: Mode) -> &'static str;
    /// The events monitored while in `mode`.
    fn events(&self, mode: Mode) -> &[EventId];
    /// Direction, action and name of an event.
    fn event_spec(&self, event: EventId) -> EventSpec;
    /// Writes $f_m(x, p)$ into `out`.
    fn vector_field<T: Scalar>(&self, mode: Mode, x: &[T], p: &[T], out: &mut [T]);
    /// The event function $h_e(x, p)$.
    fn event<T: Scalar>(&self, event: EventId, x: &[T], p: &[T]) -> T;
    /// Writes the reset $g_e(x, p)$ into `out` (of the dimension of the mode the event leads
    /// to, [`HybridSystem::reset`]; default: the identity on the components both states have).
    fn reset<T: Scalar>(&self, event: EventId, x: &[T], p: &[T], out: &mut [T]) {
        let _ = (event, p);
        let k = x.len().min(out.len());
        out[..k].copy_from_slice(&x[..k]);
    }
    /// As [`HybridSystem::symmetry`].
    fn symmetry(&self) -> Option<Z2Symmetry> {
        None
    }
    /// As [`HybridSystem::trivial_multipliers`].
    fn trivial_multipliers(&self, p: &[f64], period: f64) -> Vec<(f64, f64)> {
        let _ = (p, period);
        vec![(1.0, 0.0)]
    }
    /// As [`HybridSystem::rate_component`].
    fn rate_component(&self, mode: Mode, c: usize) -> Option<usize> {
        let _ = (mode, c);
        None
    }
    /// As [`HybridSystem::event_component`].
    fn event_component(&self, event: EventId) -> Option<usize> {
        let _ = event;
        None
    }
    /// As [`HybridSystem::zeno_transition`].
    fn zeno_transition(
        &self,
        mode: Mode,
        event: EventId,
        x: &[f64],
        p: &[f64],
        out: &mut [f64],
    ) -> Option<Mode> {
        let _ = (mode, event, x, p, out);
        None
    }
}

/// A [`HybridModel`] as a [`HybridSystem`] with exact [`HybridJacobians`] by forward-mode
/// automatic differentiation: each Jacobian (with or without the parameter columns) from one
/// evaluation on dual numbers with one direction per variable (up to [`AutoDiff::MAX_VARIABLES`]
/// variables; beyond, one evaluation per variable). The derivatives along many directions that
/// the variational equations integrate ([`HybridJacobians::vector_field_with_tangents`]) come
/// from one evaluation on duals seeded with the directions (up to
/// [`AutoDiff::MAX_VARIABLES`] of them), without forming the Jacobians: as wide as the
/// sensitivities carried, not as the state and all parameters.
#[derive(Debug, Clone, Copy, Default)]
pub struct AutoDiff<M> {
    model: M,
}

impl<M> AutoDiff<M> {
    /// The most variables (state, and parameters where their columns are asked for)
    /// differentiated in one evaluation.
    pub const MAX_VARIABLES: usize = 16;

    /// Wraps `model`.
    pub fn new(model: M) -> Self {
        Self { model }
    }

    /// The model.
    pub fn inner(&self) -> &M {
        &self.model
    }
}

/// A variation (a direction) of the state and the parameters, for [`AutoDiff`]'s second derivatives.
#[derive(Debug, Clone, Copy)]
pub struct Variation<'a> {
    /// The state's part ($n$ values).
    pub x: &'a [f64],
    /// The parameters' part ($n_p$ values; empty for none).
    pub p: &'a [f64],
}

impl<M: HybridModel> AutoDiff<M> {
    /// The second derivative of the vector field of `mode` at `(x, p)` along the directions
    /// `a` and `b` of the state and the parameters,
    /// $B(a, b) = \sum_{j,k} \frac{\partial^2 f}{\partial z_j \partial z_k} a_j b_k$ with
    /// $z = (x, p)$ (the bilinear form of normal-form coefficients, e.g. a fold's
    /// $\tfrac12 \langle w, B(q, q) \rangle$), into `out` ($n$ values), exactly, from one
    /// evaluation on hyper-dual numbers.
    ///
    /// ```
    /// # use hycont_core::{AutoDiff, Variation, HybridModel, Scalar, Mode, EventId, EventSpec};
    /// # struct M;
    /// # impl HybridModel for M {
    /// #     fn state_dim(&self) -> usize { 2 }
    /// #     fn parameter_names(&self) -> &[&'static str] { &["c"] }
    /// #     fn mode_count(&self) -> usize { 1 }
    /// #     fn mode_name(&self, _: Mode) -> &'static str { "m" }
    /// #     fn events(&self, _: Mode) -> &[EventId] { &[] }
    /// #     fn event_spec(&self, _: EventId) -> EventSpec { unreachable!() }
    /// #     fn event<T: Scalar>(&self, _: EventId, x: &[T], _: &[T]) -> T { x[0] }
    /// // f = (c x0^2 x1, sin x0)
    /// fn vector_field<T: Scalar>(&self, _: Mode, x: &[T], p: &[T], out: &mut [T]) {
    ///     out[0] = p[0] * x[0] * x[0] * x[1];
    ///     out[1] = x[0].sin();
    /// }
    /// # }
    /// let m = AutoDiff::new(M);
    /// let (x, p) = ([0.5, 2.0], [3.0]);
    /// let a = Variation { x: &[1.0, 0.0], p: &[] };
    /// let b = Variation { x: &[0.0, 1.0], p: &[] };
    /// let mut out = [0.0; 2];
    /// m.vector_field_second_derivative(Mode(0), &x, &p, a, b, &mut out).unwrap();
    /// // d^2 f0 / dx0 dx1 = 2 c x0 = 3, d^2 f1 / dx0 dx1 = 0
    /// assert_eq!(out, [3.0, 0.0]);
    /// ```
    ///
    /// # Errors
    /// [`crate::Error::InvalidMode`] for a mode the model does not have;
    /// [`crate::Error::DimensionMismatch`] naming a slice of the wrong length (`x`, `out` and
    /// the variations' state parts have the state's $n$ values, `p` the parameters', the
    /// variations' parameter parts as many or none).
    pub fn vector_field_second_derivative(
        &self,
        mode: Mode,
        x: &[f64],
        p: &[f64],
        a: Variation<'_>,
        b: Variation<'_>,
        out: &mut [f64],
    ) -> crate::Result<()> {
        if mode.0 >= self.model.mode_count() {
            return Err(crate::Error::InvalidMode {
                mode,
                count: self.model.mode_count(),
            });
        }
        self.check_second(x, p, (a, b), out.len(), self.model.state_dim())?;
        second(&self.model, Function::Field(mode), x, p, a, b, out);
        Ok(())
    }

    /// The second derivative of an event function along `a` and `b` (one value), as
    /// [`AutoDiff::vector_field_second_derivative`].
    ///
    /// # Errors
    /// [`crate::Error::IndexOutOfRange`] for an event the model does not have; as
    /// [`AutoDiff::vector_field_second_derivative`] for slices of the wrong length.
    pub fn event_second_derivative(
        &self,
        event: EventId,
        x: &[f64],
        p: &[f64],
        a: Variation<'_>,
        b: Variation<'_>,
    ) -> crate::Result<f64> {
        self.check_event(event)?;
        self.check_second(x, p, (a, b), 1, 1)?;
        let mut out = [0.0];
        second(&self.model, Function::Event(event), x, p, a, b, &mut out);
        Ok(out[0])
    }

    /// The second derivative of a reset along `a` and `b` ($n$ values), as
    /// [`AutoDiff::vector_field_second_derivative`].
    ///
    /// # Errors
    /// As [`AutoDiff::event_second_derivative`].
    pub fn reset_second_derivative(
        &self,
        event: EventId,
        x: &[f64],
        p: &[f64],
        a: Variation<'_>,
        b: Variation<'_>,
        out: &mut [f64],
    ) -> crate::Result<()> {
        self.check_event(event)?;
        self.check_second(x, p, (a, b), out.len(), self.model.state_dim())?;
        second(&self.model, Function::Reset(event), x, p, a, b, out);
        Ok(())
    }

    /// An event of some mode of the model.
    fn check_event(&self, event: EventId) -> crate::Result<()> {
        let m = &self.model;
        let known = (0..m.mode_count()).any(|k| m.events(Mode(k)).contains(&event));
        if known {
            Ok(())
        } else {
            Err(crate::Error::IndexOutOfRange {
                what: "event",
                index: event.0,
                count: (0..m.mode_count())
                    .flat_map(|k| m.events(Mode(k)).iter().map(|e| e.0 + 1))
                    .max()
                    .unwrap_or(0),
            })
        }
    }

    /// The lengths of a second derivative's point, variations and output (`rows` of `out`,
    /// `expected` of them).
    fn check_second(
        &self,
        x: &[f64],
        p: &[f64],
        (a, b): (Variation<'_>, Variation<'_>),
        rows: usize,
        expected: usize,
    ) -> crate::Result<()> {
        use crate::error::check_len;
        let (n, np) = (self.model.state_dim(), self.model.parameter_names().len());
        check_len("state", x, n)?;
        check_len("parameters", p, np)?;
        for (what, v) in [("variation a", a), ("variation b", b)] {
            check_len(what, v.x, n)?;
            if !v.p.is_empty() {
                check_len(what, v.p, np)?;
            }
        }
        if rows == expected {
            Ok(())
        } else {
            Err(crate::Error::DimensionMismatch {
                what: "second derivative output",
                expected,
                found: rows,
            })
        }
    }
}

/// $B(a, b)$ of `f` at `(x, p)` by one evaluation on [`HyperDual64`] numbers
/// ($z + a\,\varepsilon_1 + b\,\varepsilon_2$: the $\varepsilon_1\varepsilon_2$ part).
fn second<M: HybridModel + ?Sized>(
    m: &M,
    f: Function,
    x: &[f64],
    p: &[f64],
    a: Variation<'_>,
    b: Variation<'_>,
    out: &mut [f64],
) {
    let part = |d: &[f64], k: usize| d.get(k).copied().unwrap_or(0.0);
    let xd: Vec<HyperDual64> = (0..x.len())
        .map(|k| HyperDual64::new(x[k], part(a.x, k), part(b.x, k), 0.0))
        .collect();
    let pd: Vec<HyperDual64> = (0..p.len())
        .map(|k| HyperDual64::new(p[k], part(a.p, k), part(b.p, k), 0.0))
        .collect();
    let mut yd = vec![HyperDual64::from_re(0.0); out.len()];
    f.eval(m, &xd, &pd, &mut yd);
    for (o, y) in out.iter_mut().zip(&yd) {
        *o = y.eps1eps2;
    }
}

/// What a Jacobian is of.
#[derive(Debug, Clone, Copy)]
enum Function {
    Field(Mode),
    Event(EventId),
    Reset(EventId),
}

impl Function {
    fn eval<M: HybridModel + ?Sized, T: Scalar>(self, m: &M, x: &[T], p: &[T], out: &mut [T]) {
        match self {
            Function::Field(mode) => m.vector_field(mode, x, p, out),
            Function::Event(e) => out[0] = m.event(e, x, p),
            Function::Reset(e) => m.reset(e, x, p, out),
        }
    }
}

/// Where the value and the Jacobians go: `rows` outputs, `dx` column-major
/// $\mathrm{rows} \times n$, `dp` $\mathrm{rows} \times n_p$ when asked for.
struct Outputs<'a> {
    rows: usize,
    value: Option<&'a mut [f64]>,
    dx: &'a mut [f64],
    dp: Option<&'a mut [f64]>,
}

impl<'a> Outputs<'a> {
    /// `rows` outputs into `dx` and `dp` (and the value into `value`).
    fn new(
        rows: usize,
        value: Option<&'a mut [f64]>,
        dx: &'a mut [f64],
        dp: Option<&'a mut [f64]>,
    ) -> Self {
        Self {
            rows,
            value,
            dx,
            dp,
        }
    }
}

/// The value and Jacobians of `f` in one evaluation on `N`-direction duals (`N` at least the
/// state's dimension, plus the parameters' when their columns are asked for; `rows`, `n` and
/// `n_p` at most [`AutoDiff::MAX_VARIABLES`]).
fn jacobian_n<M: HybridModel + ?Sized, const N: usize>(
    m: &M,
    f: Function,
    x: &[f64],
    p: &[f64],
    out: Outputs<'_>,
) {
    const MAX: usize = 16;
    let (n, np) = (x.len(), p.len());
    let with_p = out.dp.is_some();
    let zero = DualSVec64::<N>::from_re(0.0);
    let (mut xd, mut pd, mut yd) = ([zero; MAX], [zero; MAX], [zero; MAX]);
    for (i, v) in x.iter().enumerate() {
        xd[i] = DualSVec64::from_re(*v).derivative(i);
    }
    for (j, v) in p.iter().enumerate() {
        pd[j] = DualSVec64::from_re(*v);
        if with_p {
            pd[j] = pd[j].derivative(n + j);
        }
    }
    f.eval(m, &xd[..n], &pd[..np], &mut yd[..out.rows]);
    let rows = out.rows;
    if let Some(value) = out.value {
        for (v, y) in value.iter_mut().zip(&yd[..rows]) {
            *v = y.re;
        }
    }
    let mut dp = out.dp;
    for (r, y) in yd[..rows].iter().enumerate() {
        let eps = y.eps.0.as_ref();
        let d = |k: usize| eps.map_or(0.0, |e| e[k]);
        for c in 0..n {
            out.dx[r + c * rows] = d(c);
        }
        if let Some(dp) = dp.as_deref_mut() {
            for j in 0..np {
                dp[r + j * rows] = d(n + j);
            }
        }
    }
}

/// The value and Jacobians of `f` one variable at a time (any number of variables).
fn jacobian_scalar<M: HybridModel + ?Sized>(
    m: &M,
    f: Function,
    x: &[f64],
    p: &[f64],
    out: Outputs<'_>,
) {
    let (n, np, rows) = (x.len(), p.len(), out.rows);
    let mut xd: Vec<Dual64> = x.iter().map(|v| Dual64::from_re(*v)).collect();
    let mut pd: Vec<Dual64> = p.iter().map(|v| Dual64::from_re(*v)).collect();
    let mut yd = vec![Dual64::from_re(0.0); rows];
    let vars = if out.dp.is_some() { n + np } else { n };
    let mut dp = out.dp;
    for k in 0..vars.max(1) {
        if k < n {
            xd[k] = xd[k].derivative();
        } else if k < vars {
            pd[k - n] = pd[k - n].derivative();
        }
        f.eval(m, &xd, &pd, &mut yd);
        for (r, y) in yd.iter().enumerate() {
            let d = y.eps;
            if k < n {
                out.dx[r + k * rows] = d;
            } else if let Some(dp) = dp.as_deref_mut() {
                dp[r + (k - n) * rows] = d;
            }
        }
        if k < n {
            xd[k] = Dual64::from_re(x[k]);
        } else if k < vars {
            pd[k - n] = Dual64::from_re(p[k - n]);
        }
    }
    if let Some(value) = out.value {
        for (v, y) in value.iter_mut().zip(&yd) {
            *v = y.re;
        }
    }
}

/// Dispatches to [`jacobian_n`] with the smallest supported `N` for the variables, or to
/// [`jacobian_scalar`].
fn jacobian<M: HybridModel + ?Sized>(m: &M, f: Function, x: &[f64], p: &[f64], out: Outputs<'_>) {
    let vars = x.len() + if out.dp.is_some() { p.len() } else { 0 };
    let fits = out.rows <= 16 && x.len() <= 16 && p.len() <= 16;
    macro_rules! by_size {
        ($($k:literal)*) => {
            match vars {
                $( $k if fits => jacobian_n::<M, $k>(m, f, x, p, out), )*
                _ => jacobian_scalar(m, f, x, p, out),
            }
        };
    }
    by_size!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16);
}

/// The vector field and its derivatives along `t`'s `N` directions in one evaluation on
/// `N`-direction duals seeded with the directions (a parameter a direction moves gets that
/// direction's unit component); the Jacobians are never formed.
fn tangents_n<M: HybridModel + ?Sized, const N: usize>(
    m: &M,
    mode: Mode,
    (x, p): (&[f64], &[f64]),
    f: &mut [f64],
    t: Tangents<'_>,
) {
    const MAX: usize = 16;
    let Tangents {
        x: dirs,
        params,
        out,
        ..
    } = t;
    let n = x.len();
    let zero = DualSVec64::<N>::from_re(0.0);
    let (mut xd, mut pd, mut yd) = ([zero; MAX], [zero; MAX], [zero; MAX]);
    for (i, v) in x.iter().enumerate() {
        let seed = SVector::<f64, N>::from_fn(|j, _| dirs[i + j * n]);
        xd[i] = DualSVec64::new(*v, Derivative::some(seed));
    }
    for (j, v) in p.iter().enumerate() {
        pd[j] = DualSVec64::from_re(*v);
    }
    let first = N - params.len();
    for (k, &q) in params.iter().enumerate() {
        pd[q.index()] += zero.derivative(first + k);
    }
    m.vector_field(mode, &xd[..n], &pd[..p.len()], &mut yd[..n]);
    for (i, y) in yd[..n].iter().enumerate() {
        f[i] = y.re;
        let eps = y.eps.0.as_ref();
        for j in 0..N {
            out[i + j * n] = eps.map_or(0.0, |e| e[j]);
        }
    }
}

impl<M: HybridModel> HybridSystem for AutoDiff<M> {
    fn state_dim(&self) -> usize {
        self.model.state_dim()
    }
    fn mode_dim(&self, mode: Mode) -> usize {
        self.model.mode_dim(mode)
    }
    fn parameter_names(&self) -> &[&'static str] {
        self.model.parameter_names()
    }
    fn mode_count(&self) -> usize {
        self.model.mode_count()
    }
    fn mode_name(&self, mode: Mode) -> &'static str {
        self.model.mode_name(mode)
    }
    fn events(&self, mode: Mode) -> &[EventId] {
        self.model.events(mode)
    }
    fn event_spec(&self, event: EventId) -> EventSpec {
        self.model.event_spec(event)
    }
    fn vector_field(&self, mode: Mode, x: &[f64], p: &[f64], out: &mut [f64]) {
        self.model.vector_field(mode, x, p, out);
    }
    fn event(&self, event: EventId, x: &[f64], p: &[f64]) -> f64 {
        self.model.event(event, x, p)
    }
    fn reset(&self, event: EventId, x: &[f64], p: &[f64], out: &mut [f64]) {
        self.model.reset(event, x, p, out);
    }
    fn symmetry(&self) -> Option<Z2Symmetry> {
        self.model.symmetry()
    }
    fn trivial_multipliers(&self, p: &[f64], period: f64) -> Vec<(f64, f64)> {
        self.model.trivial_multipliers(p, period)
    }
    fn rate_component(&self, mode: Mode, c: usize) -> Option<usize> {
        self.model.rate_component(mode, c)
    }
    fn event_component(&self, event: EventId) -> Option<usize> {
        self.model.event_component(event)
    }
    fn zeno_transition(
        &self,
        mode: Mode,
        event: EventId,
        x: &[f64],
        p: &[f64],
        out: &mut [f64],
    ) -> Option<Mode> {
        self.model.zeno_transition(mode, event, x, p, out)
    }
}

impl<M: HybridModel> HybridJacobians for AutoDiff<M> {
    fn vector_field_jacobian(
        &self,
        mode: Mode,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        let out = Outputs::new(x.len(), None, dx, dp);
        jacobian(&self.model, Function::Field(mode), x, p, out);
    }

    fn vector_field_with_jacobian(
        &self,
        mode: Mode,
        x: &[f64],
        p: &[f64],
        f: &mut [f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        let out = Outputs::new(x.len(), Some(f), dx, dp);
        jacobian(&self.model, Function::Field(mode), x, p, out);
    }

    fn vector_field_with_tangents(
        &self,
        mode: Mode,
        x: &[f64],
        p: &[f64],
        f: &mut [f64],
        tangents: Tangents<'_>,
    ) {
        let k = tangents.count(x.len());
        let fits = x.len() <= 16
            && p.len() <= 16
            && tangents.params.len() <= k
            && tangents.params.iter().all(|q| q.index() < p.len());
        macro_rules! by_size {
            ($($k:literal)*) => {
                match k {
                    $( $k if fits => tangents_n::<M, $k>(&self.model, mode, (x, p), f, tangents), )*
                    _ => super::tangents::by_jacobians(self, mode, x, p, f, tangents),
                }
            };
        }
        by_size!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16);
    }

    fn event_gradient(
        &self,
        event: EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        let out = Outputs::new(1, None, dx, dp);
        jacobian(&self.model, Function::Event(event), x, p, out);
    }

    fn reset_jacobian(
        &self,
        event: EventId,
        x: &[f64],
        p: &[f64],
        dx: &mut [f64],
        dp: Option<&mut [f64]>,
    ) {
        // n_+ x n_- (the state after the jump may have another dimension).
        let rows = super::reset_dim(self, event, x.len());
        let out = Outputs::new(rows, None, dx, dp);
        jacobian(&self.model, Function::Reset(event), x, p, out);
    }
}
