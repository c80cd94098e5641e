//! The error type of `hycont-continuation`.

/// What can go wrong before a branch starts. (A failure in the middle of a branch does not
/// error: the branch so far is returned with an [`crate::EndReason`].)
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// An error of the numerical core (evaluation, linear algebra, Newton at the start point).
    #[error(transparent)]
    Core(#[from] hycont_core::Error),
    /// A setting is out of range.
    #[error("invalid continuation setting {name} = {}: {reason}", hycont_core::error::num(*value))]
    InvalidSetting {
        /// Name of the setting.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// What is allowed.
        reason: &'static str,
    },
    /// The problem does not have exactly one more unknown than equations.
    #[error(
        "a continuation problem needs one more unknown than equations (has {unknowns} unknowns, {equations} equations)"
    )]
    NotOneDimensional {
        /// Unknowns.
        unknowns: usize,
        /// Equations.
        equations: usize,
    },
    /// The start of a run lies outside the bounds of the continued parameter (a run would
    /// otherwise return points outside the window asked for).
    #[error("the start {parameter} = {} lies outside the bounds [{}, {}]", hycont_core::error::num(*value), hycont_core::error::num(*min), hycont_core::error::num(*max))]
    StartOutsideBounds {
        /// The continued parameter's name.
        parameter: String,
        /// Its value at the start.
        value: f64,
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
    },
    /// The corrected start of a run (a fresh start, a restart, the first point of a switched
    /// branch or of a curve) is not a physical orbit: one of its segments leaves its mode's
    /// domain ([`hycont_core::orbit::check_admissible`]). A branch from it would hold no
    /// physical orbit until it crossed back, so the run is refused.
    #[error(
        "the start is not a physical orbit: segment {segment}{}: {violation} (value {value} at t = {t} into the segment); start from an admissible orbit, or turn admissibility off to continue it anyway",
        event.map(|e| format!(" ({e})")).unwrap_or_default()
    )]
    InadmissibleStart {
        /// The segment.
        segment: usize,
        /// The event whose surface is involved (`None` for a duration).
        event: Option<hycont_core::EventId>,
        /// What is wrong.
        violation: hycont_core::orbit::Violation,
        /// Time from the segment's start.
        t: f64,
        /// The violated condition's value (negative).
        value: f64,
    },
    /// A point of a branch fails a re-check ([`crate::OrbitBranch::check_points`]).
    #[error("point {label} of branch {branch} is not an orbit it should be: {reason}")]
    InvalidPoint {
        /// The point's label.
        label: usize,
        /// The branch's name.
        branch: String,
        /// What fails.
        reason: String,
    },
    /// A saved result (a diagram, an atlas, a branch) read back does not fit the run or
    /// system given, or is not consistent in itself: it was edited, or written by another
    /// system or run.
    #[error("the saved {what} does not fit: {reason}")]
    InvalidSaved {
        /// What was read (e.g. `diagram`, `atlas`).
        what: &'static str,
        /// What does not fit.
        reason: String,
    },
    /// A label does not exist in the branch.
    #[error("no point labelled {label} in branch {branch}")]
    NoSuchLabel {
        /// The label asked for.
        label: usize,
        /// The branch's name.
        branch: String,
    },
    /// A label names a regular point where a special point is needed (a switch, a curve).
    #[error(
        "point {label} of branch {branch} is a regular point, not a special point ({specials})"
    )]
    NotASpecialPoint {
        /// The label asked for.
        label: usize,
        /// The branch's name.
        branch: String,
        /// The branch's special points, labelled.
        specials: String,
    },
    /// A branch has no special point of the kind asked for.
    #[error("branch {branch} has no {kind} point")]
    NoSuchSpecialPoint {
        /// The kind's label (e.g. `PD`).
        kind: String,
        /// The branch's name.
        branch: String,
    },
    /// A label for a user event is not valid.
    #[error("invalid label {label:?}: {reason}")]
    InvalidLabel {
        /// The text given.
        label: String,
        /// What is wrong.
        reason: &'static str,
    },
    /// A parameter or measure that the problem does not have.
    #[error("{quantity} does not exist (there are {count})")]
    NoSuchQuantity {
        /// The handle given.
        quantity: crate::Quantity,
        /// How many parameters or measures there are.
        count: usize,
    },
    /// A measure handle of another run: the measure at its index has another name here.
    #[error("{quantity} is not a measure of this run or branch: {reason}")]
    ForeignHandle {
        /// The handle given.
        quantity: crate::Quantity,
        /// What is there instead.
        reason: String,
    },
    /// A special point at which the asked operation is not defined.
    #[error("cannot {operation} at label {label} of branch {branch}: it is {kind} ({reason})")]
    WrongSpecialPoint {
        /// What was asked (e.g. "switch branches").
        operation: &'static str,
        /// The label.
        label: usize,
        /// The branch.
        branch: String,
        /// The kind of point there.
        kind: String,
        /// Why it does not apply.
        reason: &'static str,
    },
    /// Branch switching could not find a second direction.
    #[error("branch switching failed: {reason}")]
    SwitchFailed {
        /// Why.
        reason: String,
    },
}

/// Shorthand for `Result<T, hycont_continuation::Error>`.
pub type Result<T> = std::result::Result<T, Error>;
