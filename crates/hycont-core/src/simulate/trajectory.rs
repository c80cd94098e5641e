//! What a simulation returns.

use crate::system::{EventId, Mode};
use serde::{Deserialize, Serialize};

/// Why a simulation ended.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum StopReason {
    /// The requested end time was reached.
    EndReached,
    /// A terminal event was crossed (e.g. the block overturned).
    TerminalEvent {
        /// The event.
        event: EventId,
        /// Its time.
        t: f64,
    },
    /// Jumps accumulated and the system defines no Zeno transition for them.
    ZenoAccumulation {
        /// The accumulating event (the last one).
        event: EventId,
        /// Time of the last jump before stopping.
        t: f64,
    },
    /// The step limit of the settings was reached.
    StepLimit {
        /// Time reached.
        t: f64,
    },
}

/// A time series of states with their modes, stored flat (one allocation per series, not per
/// point). States have [`TimeSeries::dim`] components, except where a run crossed into modes
/// of other dimensions ([`crate::HybridSystem::mode_dim`]): each point's state then has its
/// mode's ([`TimeSeries::state`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TimeSeries {
    dim: usize,
    /// Times.
    pub t: Vec<f64>,
    /// Mode at each time.
    pub mode: Vec<Mode>,
    /// States, `dim` values per time (where all have `dim`; else each its own, see `ends`).
    pub x: Vec<f64>,
    /// Where each point's state ends in `x`, once a state of another length than `dim` was
    /// pushed (empty while all have `dim`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    ends: Vec<usize>,
}

impl TimeSeries {
    /// An empty series of states of dimension `dim`.
    #[must_use]
    pub fn new(dim: usize) -> Self {
        Self {
            dim,
            ..Self::default()
        }
    }

    /// Appends a point (the first `dim` components of `x`).
    pub fn push(&mut self, t: f64, mode: Mode, x: &[f64]) {
        self.push_state(t, mode, &x[..self.dim]);
    }

    /// Appends a point with the whole state `x`, of any length (a mode of another dimension).
    pub fn push_state(&mut self, t: f64, mode: Mode, x: &[f64]) {
        if self.ends.is_empty() && x.len() != self.dim {
            self.ends = (1..=self.t.len()).map(|i| i * self.dim).collect();
        }
        self.t.push(t);
        self.mode.push(mode);
        self.x.extend_from_slice(x);
        if !self.ends.is_empty() {
            self.ends.push(self.x.len());
        }
    }

    /// Number of points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether there are no points.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// State dimension (of every point, unless the run crossed into modes of other
    /// dimensions: [`TimeSeries::uniform`]).
    #[must_use]
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Whether every point's state has [`TimeSeries::dim`] components.
    #[must_use]
    pub fn uniform(&self) -> bool {
        self.ends.is_empty()
    }

    /// State of point `i`.
    ///
    /// # Panics
    /// If `i >= len()`.
    #[must_use]
    pub fn state(&self, i: usize) -> &[f64] {
        if self.ends.is_empty() {
            &self.x[i * self.dim..(i + 1) * self.dim]
        } else {
            let start = if i == 0 { 0 } else { self.ends[i - 1] };
            &self.x[start..self.ends[i]]
        }
    }

    /// Iterates over `(t, mode, state)`.
    pub fn iter(&self) -> impl Iterator<Item = (f64, Mode, &[f64])> + '_ {
        (0..self.len()).map(|i| (self.t[i], self.mode[i], self.state(i)))
    }
}

/// One crossing of an event.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EventRecord {
    /// Time of the crossing.
    pub t: f64,
    /// The event.
    pub event: EventId,
    /// Mode before.
    pub mode_before: Mode,
    /// Mode after (`None` for a terminal event).
    pub mode_after: Option<Mode>,
    /// State just before (on the event surface, to the event tolerance).
    pub state_before: Vec<f64>,
    /// State just after the reset (equal to `state_before` for a terminal event).
    pub state_after: Vec<f64>,
    /// How well the crossing is determined: the event function's rate there and the
    /// estimated errors of the time and the rate (large near a tangential crossing; see
    /// [`super::EventConditioning`]).
    #[serde(default)]
    pub conditioning: super::EventConditioning,
}

/// A switch to another mode after jumps accumulated (Zeno behaviour).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ZenoRecord {
    /// Time of the last resolved jump, where the switch happened.
    pub t: f64,
    /// Predicted accumulation time of the jumps (geometric extrapolation).
    pub t_accumulation: f64,
    /// The accumulating event.
    pub event: EventId,
    /// Mode switched to.
    pub mode_after: Mode,
    /// State switched to.
    pub state_after: Vec<f64>,
}

/// Work and event counters of a simulation.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SimulationStats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected step attempts.
    pub rejected_steps: u64,
    /// Right-hand side evaluations (of the possibly augmented system).
    pub rhs_evaluations: u64,
    /// Steps whose dense output was built.
    pub dense_outputs: u64,
    /// Event crossings located.
    pub events: u64,
    /// Jumps applied.
    pub jumps: u64,
    /// Zeno transitions.
    pub zeno_transitions: u64,
}

/// Sensitivities at the final time, column-major.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SensitivityMatrices {
    /// State dimension $n$.
    pub n: usize,
    /// $\Phi = \partial x(t_f) / \partial x_0$, $n \times n$ (saltation matrices applied at every
    /// jump).
    pub state: Vec<f64>,
    /// $\partial x(t_f) / \partial p$, $n \times n_p$, if requested.
    pub params: Option<Vec<f64>>,
}

impl SensitivityMatrices {
    /// The sensitivities in a final augmented state $(x, \Phi, \partial x / \partial p)$ of
    /// a run that integrated `which` (the parameter columns integrated are stored in
    /// parameter order; the others are zero).
    pub(super) fn from_augmented(
        aug: &[f64],
        n: usize,
        np: usize,
        which: super::Sensitivities,
    ) -> Self {
        use super::Sensitivities as W;
        let state = aug[n..n + n * n].to_vec();
        let params = match which {
            W::StateAndParameters => Some(aug[n + n * n..n + n * n + n * np].to_vec()),
            W::StateAndSomeParameters(_) => {
                let mut out = vec![0.0; n * np];
                let mut col = n + n * n;
                for q in (0..np).filter(|&q| which.includes_parameter(q)) {
                    out[q * n..(q + 1) * n].copy_from_slice(&aug[col..col + n]);
                    col += n;
                }
                Some(out)
            }
            _ => None,
        };
        Self { n, state, params }
    }

    /// Entry $(i, j)$ of $\Phi$.
    #[must_use]
    pub fn state_entry(&self, i: usize, j: usize) -> f64 {
        self.state[i + j * self.n]
    }
}

/// The result of a simulation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Trajectory {
    /// Why it ended.
    pub stop: StopReason,
    /// Final time.
    pub t_final: f64,
    /// Final mode.
    pub mode_final: Mode,
    /// Final state.
    pub state_final: Vec<f64>,
    /// Samples at the prescribed times (empty if none were asked for).
    pub samples: TimeSeries,
    /// Every accepted step, with both sides of every jump (empty unless recorded).
    pub steps: TimeSeries,
    /// Every event crossing (empty unless recorded).
    pub events: Vec<EventRecord>,
    /// Zeno transitions.
    pub zeno: Vec<ZenoRecord>,
    /// Sensitivities at the final time, if requested and defined (a Zeno transition leaves them
    /// undefined: `None`).
    pub sensitivities: Option<SensitivityMatrices>,
    /// Counters.
    pub stats: SimulationStats,
    /// The step size the integrator proposed last (before any cut at `t_end`): where a
    /// following run continues this one, [`Simulator::resume`](crate::Simulator::resume)
    /// starts with it.
    #[serde(default)]
    pub next_step: f64,
}
