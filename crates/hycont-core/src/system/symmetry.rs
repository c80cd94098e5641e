//! $\mathbb{Z}_2$ symmetries of hybrid systems, and the checks that they are one.

use super::{Direction, EventAction, EventId, HybridSystem, Mode};
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// A linear $\mathbb{Z}_2$ symmetry of a hybrid system: a matrix $S$ with $S^2 = I$, an
/// involution $\sigma$ of the modes and one of the events, such that the system commutes with
/// them:
/// $$S f_m(x) = f_{\sigma(m)}(S x), \qquad h_{\sigma(e)}(S x) = \pm h_e(x), \qquad
/// S g_e(x) = g_{\sigma(e)}(S x),$$
/// with $+$ where $e$ and $\sigma(e)$ cross in the same direction and $-$ where in opposite
/// ones; $e$ monitored in $m$ means $\sigma(e)$ monitored in $\sigma(m)$, and a jump of $e$ to
/// mode $m'$ means a jump of $\sigma(e)$ to $\sigma(m')$.
///
/// The map must be **linear** in the state. A harmonically forced system whose forcing phase is
/// a wrapped angle $\theta$ has the symmetry $\theta \mapsto \theta + \pi$, which is not: carry
/// the phase as an oscillator pair $(r, s) = (\sin\theta, \cos\theta)$ (a limit cycle of
/// $\dot r = r + \omega s - r(r^2+s^2)$, $\dot s = s - \omega r - s(r^2+s^2)$), which the symmetry
/// maps to $(-r, -s)$ (`examples/symmetric_branch/model.rs`).
///
/// The library checks a system's symmetry before using it: its structure
/// ([`Z2Symmetry::validate`]) wherever a half orbit's signature is built, and its commuting with
/// the system at the states it starts from ([`Z2Symmetry::check_at`]) in
/// [`crate::orbit::find_symmetric_orbit`], the half-orbit solves and continuation.
///
/// ```
/// use hycont_core::{Mode, EventId, Z2Symmetry};
/// // x -> -x in two dimensions, one mode, two events swapped.
/// let sym = Z2Symmetry {
///     matrix: vec![-1.0, 0.0, 0.0, -1.0],
///     modes: vec![Mode(0)],
///     events: vec![EventId(1), EventId(0)],
/// };
/// let mut y = [0.0; 2];
/// sym.apply(&[1.0, 2.0], &mut y);
/// assert_eq!(y, [-1.0, -2.0]);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Z2Symmetry {
    /// $S$, column-major $n \times n$.
    pub matrix: Vec<f64>,
    /// $\sigma$: the image of each mode (one entry per mode).
    pub modes: Vec<Mode>,
    /// The image of each event (one entry per event, up to the largest event a mode monitors).
    pub events: Vec<EventId>,
}

/// Relative tolerance of the symmetry checks.
const TOL: f64 = 1e-8;

fn invalid(reason: String) -> Error {
    Error::InvalidSymmetry { reason }
}

/// The number of events of `system`: one more than the largest event any mode monitors.
fn event_count<S: HybridSystem + ?Sized>(system: &S) -> usize {
    (0..system.mode_count())
        .flat_map(|m| system.events(Mode(m)).iter().map(|e| e.0 + 1))
        .max()
        .unwrap_or(0)
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

impl Z2Symmetry {
    /// Writes $S x$ into `out`; a state of a mode with fewer states than the system's largest
    /// (`x.len()` < $n$) is mapped by $S$'s leading `x.len()` x `x.len()` block (which
    /// [`Z2Symmetry::validate`] checks maps such states among themselves).
    pub fn apply(&self, x: &[f64], out: &mut [f64]) {
        let stride = self.matrix.len().isqrt().max(1);
        let n = x.len();
        // Column by column: each out[i] adds its terms in the order j = 0, 1, .. (as a row
        // sum from -0.0 would).
        out.fill(-0.0);
        for (col, &xj) in self.matrix.chunks_exact(stride).zip(x) {
            for (o, s) in out.iter_mut().zip(&col[..n.min(stride)]) {
                *o += s * xj;
            }
        }
    }

    /// $S$'s leading `n` x `n` block (column-major): the symmetry on the states of a mode of
    /// `n` states.
    #[must_use]
    pub fn block(&self, n: usize) -> Vec<f64> {
        self.block_ref(n).into_owned()
    }

    /// [`Z2Symmetry::block`], borrowed from $S$ where it is the whole matrix (the common case:
    /// a mode with the system's full state), built where it is not.
    pub(crate) fn block_ref(&self, n: usize) -> std::borrow::Cow<'_, [f64]> {
        let stride = self.matrix.len().isqrt();
        if n == stride && n * n == self.matrix.len() {
            return std::borrow::Cow::Borrowed(&self.matrix);
        }
        let mut out = Vec::with_capacity(n * n);
        for j in 0..n {
            out.extend((0..n).map(|i| self.matrix.get(i + j * stride).copied().unwrap_or(0.0)));
        }
        std::borrow::Cow::Owned(out)
    }

    /// Checks the symmetry's structure against `system`: $S$ is a finite $n \times n$ matrix
    /// with $S^2 = I$ (to $10^{-8}$ relative); the mode and event maps have an entry for each
    /// mode and event, name existing ones and are involutions; each mode's events map to events
    /// of the image mode, with the same action (jumps to the images of their targets).
    ///
    /// # Errors
    /// [`Error::InvalidSymmetry`] naming what is wrong.
    pub fn validate<S: HybridSystem + ?Sized>(&self, system: &S) -> Result<()> {
        self.validate_matrix(system.state_dim())?;
        let modes = system.mode_count();
        if self.modes.len() != modes {
            return Err(invalid(format!(
                "the mode map has {} entries; the system has {modes} modes",
                self.modes.len()
            )));
        }
        for (m, &image) in self.modes.iter().enumerate() {
            if image.0 >= modes || self.modes[image.0] != Mode(m) {
                return Err(invalid(format!(
                    "the mode map is not an involution: mode {m} maps to {image}, which maps to {}",
                    self.modes
                        .get(image.0)
                        .map_or("nothing".to_string(), ToString::to_string)
                )));
            }
        }
        let events = event_count(system);
        if self.events.len() < events {
            return Err(invalid(format!(
                "the event map has {} entries; the system's modes monitor {events} events",
                self.events.len()
            )));
        }
        for e in 0..events {
            let image = self.events[e];
            if image.0 >= events || self.events[image.0] != EventId(e) {
                return Err(invalid(format!(
                    "the event map is not an involution: event #{e} maps to {image}, which maps to {}",
                    self.events
                        .get(image.0)
                        .map_or("nothing".to_string(), ToString::to_string)
                )));
            }
        }
        for m in 0..modes {
            self.validate_mode_dims(system, Mode(m))?;
            self.validate_mode_events(system, Mode(m))?;
        }
        Ok(())
    }

    /// A mode and its image have states of one dimension $n_m$, which $S$ maps among
    /// themselves: no entry of $S$ couples the first $n_m$ components with the others.
    fn validate_mode_dims<S: HybridSystem + ?Sized>(&self, system: &S, m: Mode) -> Result<()> {
        let (n, nm) = (system.state_dim(), system.mode_dim(m));
        let image = self.modes[m.0];
        if system.mode_dim(image) != nm {
            return Err(invalid(format!(
                "mode {m} has {nm} states, its image {image} {}: a mode and its image share their dimension",
                system.mode_dim(image)
            )));
        }
        let couples = |i: usize, j: usize| (i < nm) != (j < nm) && self.matrix[i + j * n] != 0.0;
        if let Some((i, j)) = (0..n)
            .flat_map(|j| (0..n).map(move |i| (i, j)))
            .find(|&(i, j)| couples(i, j))
        {
            return Err(invalid(format!(
                "S couples component {j} with component {i} across mode {m}'s {nm} states: the states of a mode must map among themselves"
            )));
        }
        Ok(())
    }

    fn validate_matrix(&self, n: usize) -> Result<()> {
        if self.matrix.len() != n * n {
            return Err(invalid(format!(
                "the matrix has {} entries; a state of dimension {n} needs {} ({n} x {n}, column-major)",
                self.matrix.len(),
                n * n
            )));
        }
        if let Some(i) = self.matrix.iter().position(|v| !v.is_finite()) {
            return Err(invalid(format!(
                "matrix entry {i} is {} (not finite)",
                self.matrix[i]
            )));
        }
        let scale = 1.0 + max_abs(&self.matrix).powi(2);
        for i in 0..n {
            for j in 0..n {
                let sq: f64 = (0..n)
                    .map(|l| self.matrix[i + l * n] * self.matrix[l + j * n])
                    .sum();
                let id = if i == j { 1.0 } else { 0.0 };
                if (sq - id).abs() > TOL * scale {
                    return Err(invalid(format!(
                        "S^2 is not the identity: its entry ({i}, {j}) is {sq}"
                    )));
                }
            }
        }
        Ok(())
    }

    fn validate_mode_events<S: HybridSystem + ?Sized>(&self, system: &S, m: Mode) -> Result<()> {
        let image_mode = self.modes[m.0];
        for &e in system.events(m) {
            let image = self.events[e.0];
            if !system.events(image_mode).contains(&image) {
                return Err(invalid(format!(
                    "{e} is monitored in mode {m}, but its image {image} is not monitored in the image mode {image_mode}"
                )));
            }
            let (a, b) = (system.event_spec(e), system.event_spec(image));
            let consistent = match (a.action, b.action) {
                (EventAction::Terminal, EventAction::Terminal) => true,
                (EventAction::Jump { to }, EventAction::Jump { to: to_image }) => {
                    self.modes.get(to.0) == Some(&to_image)
                }
                _ => false,
            };
            if !consistent {
                return Err(invalid(format!(
                    "{e} ({:?}) and its image {image} ({:?}) do not act alike: a jump must lead to the image of its target",
                    a.action, b.action
                )));
            }
            if (a.direction == Direction::Either) != (b.direction == Direction::Either) {
                return Err(invalid(format!(
                    "{e} and its image {image} must both have a direction or both not"
                )));
            }
        }
        Ok(())
    }

    /// Checks that the system commutes with the symmetry at `states` of mode `mode` (e.g. an
    /// orbit's segment starts) with parameters `params`, to $10^{-8}$ relative: the vector
    /// field, every event the mode monitors (with the sign its direction implies) and the
    /// resets of its jumps. Also checks the structure ([`Z2Symmetry::validate`]).
    ///
    /// # Errors
    /// [`Error::InvalidSymmetry`] naming the first map that does not commute and where.
    pub fn check_at<S: HybridSystem + ?Sized>(
        &self,
        system: &S,
        mode: Mode,
        states: &[&[f64]],
        params: &[f64],
    ) -> Result<()> {
        self.validate(system)?;
        if mode.0 >= system.mode_count() {
            return Err(Error::InvalidMode {
                mode,
                count: system.mode_count(),
            });
        }
        let n = system.mode_dim(mode);
        let image_mode = self.modes[mode.0];
        let big = system.state_dim();
        let (mut sx, mut a, mut b, mut c) =
            (vec![0.0; n], vec![0.0; big], vec![0.0; big], vec![0.0; big]);
        for x in states {
            crate::error::check_len("state", x, n)?;
            self.apply(x, &mut sx);
            let scale = 1.0 + max_abs(x);
            // S f_m(x) = f_sigma(m)(S x).
            system.vector_field(mode, x, params, &mut a[..n]);
            self.apply(&a[..n], &mut b[..n]);
            system.vector_field(image_mode, &sx, params, &mut c[..n]);
            let fscale = scale + max_abs(&b[..n]);
            if let Some(i) = (0..n).find(|&i| (b[i] - c[i]).abs() > TOL * fscale) {
                return Err(invalid(format!(
                    "the vector field does not commute with S at {x:?} in mode {mode}: component {i} of S f is {}, of f(S x) {}",
                    b[i], c[i]
                )));
            }
            for &e in system.events(mode) {
                self.check_event_at(system, e, x, &sx, params)?;
                if let EventAction::Jump { .. } = system.event_spec(e).action {
                    // Into the target's dimension.
                    let m = super::reset_dim(system, e, n);
                    let (a, b, c) = (&mut a[..m], &mut b[..m], &mut c[..m]);
                    system.reset(e, x, params, a);
                    self.apply(a, b);
                    system.reset(self.events[e.0], &sx, params, c);
                    let gscale = scale + max_abs(b);
                    if let Some(i) = (0..m).find(|&i| (b[i] - c[i]).abs() > TOL * gscale) {
                        return Err(invalid(format!(
                            "the reset of {e} does not commute with S at {x:?}: component {i} of S g is {}, of g(S x) {}",
                            b[i], c[i]
                        )));
                    }
                }
            }
        }
        Ok(())
    }

    /// $h_{\sigma(e)}(S x) = \pm h_e(x)$ with the sign the directions imply.
    fn check_event_at<S: HybridSystem + ?Sized>(
        &self,
        system: &S,
        e: EventId,
        x: &[f64],
        sx: &[f64],
        params: &[f64],
    ) -> Result<()> {
        let image = self.events[e.0];
        let (h, hs) = (system.event(e, x, params), system.event(image, sx, params));
        let (da, db) = (
            system.event_spec(e).direction,
            system.event_spec(image).direction,
        );
        let tol = TOL * (1.0 + max_abs(x) + h.abs());
        // Before a crossing, sign_before(e) h_e(x) > 0 and sign_before(image) h_image(S x) > 0.
        let ok = match (da.sign_before(), db.sign_before()) {
            (Some(a), Some(b)) => (hs - a * b * h).abs() <= tol,
            _ => (hs - h).abs() <= tol || (hs + h).abs() <= tol,
        };
        if ok {
            return Ok(());
        }
        Err(invalid(format!(
            "{e} does not map to its image {image} at {x:?}: h_e(x) = {h}, h_image(S x) = {hs} (directions {da:?} and {db:?})"
        )))
    }
}

/// The system's symmetry, checked ([`Z2Symmetry::validate`]).
///
/// # Errors
/// [`Error::InvalidSymmetry`] if the system has none or it is not valid.
pub fn checked_symmetry<S: HybridSystem + ?Sized>(system: &S) -> Result<Z2Symmetry> {
    let sym = system
        .symmetry()
        .ok_or_else(|| invalid("the system has no symmetry".to_string()))?;
    sym.validate(system)?;
    Ok(sym)
}
