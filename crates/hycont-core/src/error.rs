//! The error type of `hycont-core`.

use crate::system::Mode;

/// Everything that can go wrong in `hycont-core`.
///
/// Every variant names the offending value so that the message alone tells the user what to fix.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A slice had the wrong length.
    #[error("{what} has length {found}, expected {expected}")]
    DimensionMismatch {
        /// What was measured (e.g. "initial state").
        what: &'static str,
        /// The length the system requires.
        expected: usize,
        /// The length that was passed.
        found: usize,
    },
    /// An input contained NaN or an infinity.
    #[error("{what}[{index}] = {} is not finite", num(*value))]
    NonFinite {
        /// What was checked (e.g. "initial state", "parameters").
        what: &'static str,
        /// Index of the first non-finite entry.
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// A setting is out of its valid range.
    #[error("invalid setting {name} = {}: {reason}", num(*value))]
    InvalidSetting {
        /// Name of the setting.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// Why it was rejected (e.g. "must be > 0").
        reason: &'static str,
    },
    /// A model parameter is out of its valid range.
    #[error("parameter {name} = {} is out of range: {reason}", num(*value))]
    ParameterOutOfRange {
        /// Name of the parameter.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// The valid range, in words.
        reason: &'static str,
    },
    /// The integration interval is empty or reversed.
    #[error("end time {} is before start time {}", num(*t_end), num(*t0))]
    InvalidTimeSpan {
        /// Start time.
        t0: f64,
        /// Requested end time.
        t_end: f64,
    },
    /// A solved orbit leaves its modes' domains (see [`crate::orbit::check_admissible`]).
    #[error(
        "inadmissible orbit: segment {segment}{}, {violation:?} at t = {t} (value {value})",
        event.map(|e| format!(", event {e}")).unwrap_or_default()
    )]
    Inadmissible {
        /// The segment.
        segment: usize,
        /// The event whose surface is involved (`None` for a duration).
        event: Option<crate::system::EventId>,
        /// What is wrong.
        violation: crate::orbit::Violation,
        /// Time from the segment's start.
        t: f64,
        /// The violated condition's value (negative).
        value: f64,
    },
    /// A handle or index does not name anything that exists (a monitor of a problem, a
    /// segment of an orbit, ...).
    #[error("{what} {index} does not exist (there are {count})")]
    IndexOutOfRange {
        /// What the index names (e.g. "monitor").
        what: &'static str,
        /// The index given.
        index: usize,
        /// How many there are.
        count: usize,
    },
    /// A mode handle does not belong to the system.
    #[error("mode {mode} does not exist (the system has {count} modes)")]
    InvalidMode {
        /// The offending mode.
        mode: Mode,
        /// Number of modes of the system.
        count: usize,
    },
    /// The vector field returned a non-finite value during integration.
    #[error(
        "vector field of mode {mode} returned {value} in component {index} at t = {t} (state {state:?})"
    )]
    NonFiniteVectorField {
        /// Time of the failing evaluation.
        t: f64,
        /// Mode being integrated.
        mode: Mode,
        /// Component that was not finite.
        index: usize,
        /// The value returned.
        value: f64,
        /// The state at which the vector field was evaluated.
        state: Vec<f64>,
    },
    /// An event function returned a non-finite value during integration: its crossings
    /// cannot be found there (a NaN is never crossed, so a trajectory would pass through the
    /// event's surface unseen).
    #[error(
        "event {event} of mode {mode} returned {value} at t = {t} (state {state:?}): an event function must be finite wherever the flow goes"
    )]
    NonFiniteEvent {
        /// The event.
        event: crate::system::EventId,
        /// The mode being integrated.
        mode: Mode,
        /// Time of the evaluation.
        t: f64,
        /// The value returned.
        value: f64,
        /// The state at which it was evaluated.
        state: Vec<f64>,
    },
    /// A reset returned a non-finite state.
    #[error(
        "the reset of event {event} returned {value} in component {index} from state {state:?} (NaN: also a component it did not write, e.g. of a target mode with more states)"
    )]
    NonFiniteReset {
        /// The event.
        event: crate::system::EventId,
        /// The component that was not finite.
        index: usize,
        /// The value returned.
        value: f64,
        /// The state before the jump.
        state: Vec<f64>,
    },
    /// A derivative the system returned (an entry of the Jacobian of a vector field, an event
    /// function or a reset) is not finite. Automatic differentiation gives NaN derivatives at
    /// points where a function is not differentiable (e.g. `sqrt` at 0, `abs` at 0 gives a
    /// one-sided choice), where the system itself may be finite.
    #[error(
        "the derivative of the {of} is {value} at row {row}, column {column} ({columns}) at state {state:?}; derivatives must be finite where the flow goes (dual numbers give NaN where a function is not differentiable, e.g. sqrt at 0)"
    )]
    NonFiniteDerivative {
        /// Whose derivative: e.g. `vector field of mode 0`, `reset of event 1`.
        of: String,
        /// The row (component of the function).
        row: usize,
        /// The column (state component, or parameter after them).
        column: usize,
        /// What the columns are: `state`, `parameter` or, in the variational equations,
        /// `sensitivity`.
        columns: &'static str,
        /// The value returned.
        value: f64,
        /// The state at which it was evaluated.
        state: Vec<f64>,
    },
    /// The step size fell below what floating point can resolve.
    #[error("step size {} underflowed at t = {} in mode {mode}", num(*h), num(*t))]
    StepSizeUnderflow {
        /// Time at which it happened.
        t: f64,
        /// The step size that was too small.
        h: f64,
        /// Mode being integrated.
        mode: Mode,
    },
    /// A simulation's jumps (Zeno transitions included) repeat without time advancing: the
    /// system's resets or Zeno transitions lead straight back into the same jumps
    /// ([`crate::simulate::MAX_JUMPS_AT_ONE_INSTANT`] at one instant).
    #[error(
        "the simulation stalls at t = {t}: {jumps} jumps without time advancing (the last by {event} from mode {mode}); the system's resets or Zeno transitions lead straight back into the same jumps"
    )]
    Stalled {
        /// The instant.
        t: f64,
        /// The jumps counted there.
        jumps: usize,
        /// The last jump's event.
        event: crate::system::EventId,
        /// The mode it left.
        mode: Mode,
    },
    /// A periodic-orbit signature is inconsistent with the system or the data.
    #[error("invalid orbit signature at segment {segment}: {reason}")]
    InvalidSignature {
        /// The offending segment.
        segment: usize,
        /// What is wrong.
        reason: String,
    },
    /// A trajectory does not (yet) repeat, so no periodic orbit can be read off it.
    #[error("not periodic: {reason}")]
    NotPeriodic {
        /// Why.
        reason: String,
    },
    /// Newton's method did not converge.
    #[error("Newton's method failed: {reason}")]
    NewtonFailed {
        /// Why, with the number of iterations done.
        reason: String,
        /// What kind of failure it is.
        failure: crate::problem::NewtonFailure,
        /// The iterations done (those recorded; may be empty when the solver keeps none).
        history: Vec<crate::problem::NewtonIteration>,
    },
    /// A linear system could not be solved.
    #[error("singular linear system: {reason}")]
    SingularMatrix {
        /// What failed.
        reason: String,
    },
    /// A measure of an orbit is ill-defined for the system or the orbit (a component, segment or
    /// event that does not exist, a duplicate name).
    #[error("invalid measure: {reason}")]
    InvalidMeasure {
        /// What is wrong, naming the bad value.
        reason: String,
    },
    /// A system's $\mathbb{Z}_2$ symmetry is not one ([`crate::Z2Symmetry::validate`],
    /// [`crate::Z2Symmetry::check_at`]).
    #[error("invalid symmetry: {reason}")]
    InvalidSymmetry {
        /// What is wrong, naming the bad entry or map.
        reason: String,
    },
    /// A system does not fit what it is used with (e.g. a reference system of another layout
    /// in [`crate::check_derivatives_against`], or a state space of no dimension).
    #[error("invalid system: {reason}")]
    InvalidSystem {
        /// What does not fit.
        reason: String,
    },
    /// An event transition was requested by the system that it cannot carry out.
    #[error("event transition at t = {t} from mode {mode} is invalid: {reason}")]
    InvalidTransition {
        /// Time of the event.
        t: f64,
        /// Mode before the event.
        mode: Mode,
        /// Explanation.
        reason: String,
    },
}

/// A number for a message: as Rust prints it where that is short, in exponent notation where it
/// is not (`1e308`, not 309 digits; `1e-10`, not `0.0000000001`).
///
/// ```
/// use hycont_core::error::num;
/// assert_eq!(num(2.0), "2");
/// assert_eq!(num(1.3), "1.3");
/// assert_eq!(num(1e308), "1e308");
/// assert_eq!(num(-1e-10), "-1e-10");
/// assert_eq!(num(f64::NAN), "NaN");
/// ```
#[must_use]
pub fn num(v: f64) -> String {
    let a = v.abs();
    if !v.is_finite() {
        format!("{v:?}")
    } else if v == 0.0 || (1e-5..1e16).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Shorthand for `Result<T, hycont_core::Error>`.
pub type Result<T> = std::result::Result<T, Error>;

/// Returns an error naming the first non-finite entry of `values`.
///
/// # Errors
/// [`Error::NonFinite`] with the entry's index and value.
///
/// ```
/// use hycont_core::error::check_finite;
/// assert!(check_finite("state", &[1.0, 2.0]).is_ok());
/// assert!(check_finite("state", &[1.0, f64::NAN]).is_err());
/// ```
pub fn check_finite(what: &'static str, values: &[f64]) -> Result<()> {
    if all_finite(values) {
        return Ok(());
    }
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(Error::NonFinite {
            what,
            index,
            value: values[index],
        }),
        None => Ok(()),
    }
}

/// Whether every entry is finite, without a branch per entry: $\sum_i 0 \cdot v_i$ (in four
/// independent lanes) is zero exactly when no $v_i$ is infinite or NaN ($0 \cdot \infty$ is
/// NaN). A check on every Jacobian block of a collocation evaluation, and on the states a
/// diagonal symmetry maps.
#[inline]
pub(crate) fn all_finite(values: &[f64]) -> bool {
    let mut lanes = [0.0_f64; 4];
    let chunks = values.chunks_exact(4);
    let tail = chunks.remainder();
    for chunk in chunks {
        for (l, x) in lanes.iter_mut().zip(chunk) {
            *l += x * 0.0;
        }
    }
    for x in tail {
        lanes[0] += x * 0.0;
    }
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) == 0.0
}

/// Returns an error if `values` does not have length `expected`.
///
/// # Errors
/// [`Error::DimensionMismatch`] naming both lengths.
///
/// ```
/// use hycont_core::error::check_len;
/// assert!(check_len("state", &[1.0, 2.0], 2).is_ok());
/// assert!(check_len("state", &[1.0], 2).is_err());
/// ```
pub fn check_len(what: &'static str, values: &[f64], expected: usize) -> Result<()> {
    if values.len() == expected {
        Ok(())
    } else {
        Err(Error::DimensionMismatch {
            what,
            expected,
            found: values.len(),
        })
    }
}

/// The first non-finite entry of the column-major matrix `m` of `rows` rows, as
/// [`Error::NonFiniteDerivative`] of `of()` at `state`: its columns are `columns` numbered
/// from `first_column` (e.g. the parameters after the state's).
///
/// # Errors
/// That error, if an entry is not finite.
#[inline(always)]
pub(crate) fn finite_derivative(
    m: &[f64],
    rows: usize,
    columns: (&'static str, usize),
    of: impl FnOnce() -> String,
    state: &[f64],
) -> Result<()> {
    // The check inline (every collocation point of every Jacobian), the error out of line.
    if all_finite(m) {
        return Ok(());
    }
    non_finite_derivative(m, rows, columns, of, state)
}

/// [`finite_derivative`]'s error.
#[cold]
#[inline(never)]
fn non_finite_derivative(
    m: &[f64],
    rows: usize,
    (columns, first_column): (&'static str, usize),
    of: impl FnOnce() -> String,
    state: &[f64],
) -> Result<()> {
    match m.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(k) => Err(Error::NonFiniteDerivative {
            of: of(),
            row: k % rows.max(1),
            column: first_column + k / rows.max(1),
            columns,
            value: m[k],
            state: state.to_vec(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::all_finite;

    /// Finite values of every size (the largest, subnormals, signed zeros) pass; one NaN or
    /// infinity anywhere (in the lanes and the tail, for every length up to 9) is found.
    #[test]
    fn all_finite_finds_any_non_finite_entry() {
        let finite = [
            f64::MAX,
            -f64::MAX,
            5e-324,
            -0.0,
            0.0,
            1.0,
            -3.5,
            f64::MIN_POSITIVE,
            1e300,
        ];
        for len in 0..=finite.len() {
            assert!(all_finite(&finite[..len]));
            for at in 0..len {
                for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                    let mut v = finite[..len].to_vec();
                    v[at] = bad;
                    assert!(!all_finite(&v), "{bad} at {at} of {len}");
                }
            }
        }
    }
}
