//! Results: branches of points with their special points, serialisable and restartable.

use crate::error::{Error, Result};
use crate::quantity::{Label, MeasureId, Quantity};
use hycont_core::ParamId;
use serde::{Deserialize, Serialize};

/// The kind of a special point, with its label (AUTO's and COCO's two-letter labels, or a
/// user's [`Label`]). Serialised as the label text.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SpecialKind {
    /// Fold (saddle-node, limit point): `SN`.
    Fold,
    /// Branch point (e.g. symmetry breaking): `BP`.
    BranchPoint,
    /// Period doubling: `PD`.
    PeriodDoubling,
    /// Torus (Neimark-Sacker): `TR`.
    Torus,
    /// On a fold curve, a cusp: the fold curve's projection onto the parameter plane turns back
    /// (both parameters stationary along the curve): `CP`.
    Cusp,
    /// On a fold curve, a second multiplier at $+1$ (1:1 resonance): `R1`.
    Resonance1,
    /// On a fold or period-doubling curve, a multiplier at $+1$ and another at $-1$ (fold-flip):
    /// `LPPD`.
    FoldFlip,
    /// On a period-doubling curve, a second multiplier at $-1$ (1:2 resonance): `R2`.
    Resonance2,
    /// On a fold curve, a complex pair on the unit circle (fold-Neimark-Sacker): `LPNS`.
    FoldTorus,
    /// On a period-doubling curve, a complex pair on the unit circle (flip-Neimark-Sacker):
    /// `PDNS`.
    FlipTorus,
    /// Boundary touch (a measure reaches a boundary level, e.g. an amplitude at a static
    /// boundary): `SB`.
    BoundaryTouch,
    /// Grazing (a trajectory touches an event surface tangentially): `GR`.
    Grazing,
    /// End point of the branch (a bound): `EP`.
    EndPoint,
    /// A user point: a parameter or measure at a value asked for: `UZ`.
    UserPoint,
    /// A user event with its own label.
    Custom(Label),
}

impl SpecialKind {
    /// The points where an orbit reaches a domain boundary of its signature (`DB`: a segment
    /// collapses, or ends on another event's surface), which the run's admissibility events
    /// locate ([`crate::OrbitRun::admissibility`]); [`crate::OrbitRun::switch_at`] and
    /// diagrams switch signature there as at [`SpecialKind::Grazing`].
    pub const DOMAIN_BOUNDARY: SpecialKind = SpecialKind::Custom(crate::Label::DB);

    /// The label (`SN`, `BP`, ..., or the user's).
    #[must_use]
    pub fn label(&self) -> &str {
        match self {
            SpecialKind::Fold => "SN",
            SpecialKind::BranchPoint => "BP",
            SpecialKind::PeriodDoubling => "PD",
            SpecialKind::Torus => "TR",
            SpecialKind::Cusp => "CP",
            SpecialKind::Resonance1 => "R1",
            SpecialKind::FoldFlip => "LPPD",
            SpecialKind::Resonance2 => "R2",
            SpecialKind::FoldTorus => "LPNS",
            SpecialKind::FlipTorus => "PDNS",
            SpecialKind::BoundaryTouch => "SB",
            SpecialKind::Grazing => "GR",
            SpecialKind::EndPoint => "EP",
            SpecialKind::UserPoint => "UZ",
            SpecialKind::Custom(l) => l.as_str(),
        }
    }

    /// The kind with this label.
    ///
    /// # Errors
    /// [`Error::InvalidLabel`] if it is neither built in nor a valid user label.
    pub fn from_label(text: &str) -> Result<Self> {
        Ok(match text {
            "SN" => SpecialKind::Fold,
            "BP" => SpecialKind::BranchPoint,
            "PD" => SpecialKind::PeriodDoubling,
            "TR" => SpecialKind::Torus,
            "CP" => SpecialKind::Cusp,
            "R1" => SpecialKind::Resonance1,
            "LPPD" => SpecialKind::FoldFlip,
            "R2" => SpecialKind::Resonance2,
            "LPNS" => SpecialKind::FoldTorus,
            "PDNS" => SpecialKind::FlipTorus,
            "SB" => SpecialKind::BoundaryTouch,
            "GR" => SpecialKind::Grazing,
            "EP" => SpecialKind::EndPoint,
            "UZ" => SpecialKind::UserPoint,
            other => SpecialKind::Custom(Label::new(other)?),
        })
    }
}

impl std::fmt::Display for SpecialKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.label())
    }
}

impl Serialize for SpecialKind {
    fn serialize<Z: serde::Serializer>(&self, s: Z) -> std::result::Result<Z::Ok, Z::Error> {
        s.serialize_str(self.label())
    }
}

impl<'de> Deserialize<'de> for SpecialKind {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let text = String::deserialize(d)?;
        SpecialKind::from_label(&text).map_err(serde::de::Error::custom)
    }
}

pub use hycont_core::orbit::NEUTRAL_BAND;

/// One point of a branch.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BranchPoint {
    /// Label, unique within the branch (points and special points share the numbering).
    pub label: usize,
    /// The unknowns (for restarts).
    pub u: Vec<f64>,
    /// The unit tangent (for restarts).
    pub tangent: Vec<f64>,
    /// All parameters.
    pub params: Vec<f64>,
    /// The problem's monitors (names in [`Branch::monitor_names`]).
    pub monitors: Vec<f64>,
    /// Floquet (or other) multipliers `(re, im)`.
    pub multipliers: Vec<(f64, f64)>,
    /// Which multipliers are trivial.
    pub trivial: Vec<bool>,
    /// Number of non-trivial multipliers outside the unit circle by more than
    /// [`NEUTRAL_BAND`] (relative).
    pub unstable: usize,
    /// Corrector iterations.
    pub newton_iterations: usize,
    /// Arclength step that reached this point.
    pub step: f64,
    /// The estimated discretisation error (see [`crate::PointInfo::discretisation_error`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub discretisation_error: Option<f64>,
    /// The revision of the problem's discretisation `u` and `tangent` are on (0 unless the run
    /// re-discretised, [`crate::ContinuationProblem::rediscretise`]).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub discretisation: usize,
    /// The keys of the branch's measure names, against which measure handles are checked
    /// (restored from [`Branch::monitor_names`] when a branch is read; empty: unchecked).
    #[serde(skip)]
    pub(crate) measure_keys: MeasureKeys,
}

/// The keys of a branch's measure names ([`crate::MeasureId`]), shared by its points: derived
/// data, not serialised and not compared.
#[derive(Debug, Clone, Default)]
pub(crate) struct MeasureKeys(std::sync::Arc<[u64]>);

impl PartialEq for MeasureKeys {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl MeasureKeys {
    pub(crate) fn of(names: &[String]) -> Self {
        Self(names.iter().map(|n| crate::quantity::name_key(n)).collect())
    }
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
fn is_zero(v: &usize) -> bool {
    *v == 0
}

impl BranchPoint {
    /// The point with unknowns `u`, tangent `tangent` and the analysis `info`.
    #[must_use]
    pub fn from_info(
        info: &crate::PointInfo,
        u: Vec<f64>,
        tangent: Vec<f64>,
        newton_iterations: usize,
        step: f64,
    ) -> Self {
        let unstable = info
            .multipliers
            .iter()
            .zip(&info.trivial)
            .filter(|((re, im), t)| !**t && re.hypot(*im) > 1.0 + NEUTRAL_BAND)
            .count();
        BranchPoint {
            label: 0,
            u,
            tangent,
            params: info.params.clone(),
            monitors: info.monitors.clone(),
            multipliers: info.multipliers.clone(),
            trivial: info.trivial.clone(),
            unstable,
            newton_iterations,
            step,
            discretisation_error: info.discretisation_error,
            discretisation: 0,
            measure_keys: MeasureKeys::default(),
        }
    }

    /// Whether the point is stable: no non-trivial multiplier outside the unit circle (beyond
    /// the [`NEUTRAL_BAND`]; a located fold, branch point, period doubling or torus point has the
    /// stability of its other multipliers).
    #[must_use]
    pub fn stable(&self) -> bool {
        self.unstable == 0
    }

    /// The value of a parameter or measure at this point, if the branch has it (`None` also
    /// for a measure handle of another run, whose measure at that index has another name).
    #[must_use]
    pub fn get(&self, q: impl Into<Quantity>) -> Option<f64> {
        self.value(q).ok()
    }

    /// The value of a parameter or measure at this point.
    ///
    /// # Errors
    /// [`Error::NoSuchQuantity`] for a parameter or measure the branch does not have;
    /// [`Error::ForeignHandle`] for a measure handle of another run (its measure at that
    /// index has another name).
    pub fn value(&self, q: impl Into<Quantity>) -> Result<f64> {
        let q = q.into();
        let (values, index) = match q {
            Quantity::Parameter(p) => (&self.params, p.index()),
            Quantity::Measure(m) => {
                let key = self.measure_keys.0.get(m.index()).copied().unwrap_or(0);
                if !m.fits_key(key) {
                    return Err(Error::ForeignHandle {
                        quantity: q,
                        reason: "the branch's measure at that index has another name (a handle of another run?)".into(),
                    });
                }
                (&self.monitors, m.index())
            }
        };
        values.get(index).copied().ok_or(Error::NoSuchQuantity {
            quantity: q,
            count: values.len(),
        })
    }
}

/// `point[p]`: the value of parameter `p` (panics if the branch has no such parameter; see
/// [`BranchPoint::value`] for an error instead).
impl std::ops::Index<ParamId> for BranchPoint {
    type Output = f64;
    fn index(&self, p: ParamId) -> &f64 {
        &self.params[p.index()]
    }
}

/// `point[m]`: the value of measure `m`. Panics if the branch has no such measure or `m` is a
/// handle of another run (its measure at that index has another name): never another
/// measure's value; [`BranchPoint::value`] gives the error instead.
impl std::ops::Index<MeasureId> for BranchPoint {
    type Output = f64;
    fn index(&self, m: MeasureId) -> &f64 {
        match self.value(m) {
            Ok(_) => &self.monitors[m.index()],
            Err(e) => panic!("point {}: {e}", self.label),
        }
    }
}

/// A located (or bracketed) special point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpecialPoint {
    /// What it is.
    pub kind: SpecialKind,
    /// The point itself.
    pub point: BranchPoint,
    /// Continuation-parameter values of the two branch points bracketing it.
    pub bracket: (f64, f64),
    /// Whether it was located to the tolerance (otherwise `point` is the best estimate).
    pub located: bool,
    /// Final arclength uncertainty of the location.
    pub accuracy: f64,
    /// For events, user points and end points: the quantity that reached its level.
    #[serde(default)]
    pub on: Option<Quantity>,
    /// For events, user points and end points: the level it reached.
    #[serde(default)]
    pub level: Option<f64>,
    /// For SN, BP, PD and TR points of problems with multipliers: the non-trivial multiplier
    /// `(re, im)` at the kind's critical value ($+1$, $+1$, $-1$, the unit circle). A located
    /// point is reported only when this lies within
    /// [`crate::ContinuationSettings::critical_tolerance`] of that value.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub critical: Option<(f64, f64)>,
}

/// Why a branch ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum EndReason {
    /// A bound was reached (an EP special point is on it).
    Bound,
    /// The point limit was reached.
    MaxPoints,
    /// The corrector failed with the smallest step; the reason.
    CorrectorFailed(String),
    /// A special point that ends admissible orbits (e.g. grazing) was reached.
    Inadmissible(SpecialKind),
    /// The branch closed on itself (returned to its start).
    Closed,
    /// A special point of a kind in [`crate::ContinuationSettings::stop_at`] was reached.
    Reached(SpecialKind),
    /// The observer asked the run to stop ([`crate::Observer::stop`], e.g. on an interrupt).
    Stopped,
}

/// A branch: its points, special points, and how it ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(from = "BranchData")]
pub struct Branch {
    /// A name (e.g. `symmetric`).
    pub name: String,
    /// Name of the continuation parameter.
    pub parameter: String,
    /// Index of the continuation parameter in [`BranchPoint::params`].
    pub parameter_index: usize,
    /// Names of all parameters.
    pub parameter_names: Vec<String>,
    /// Names of the monitors.
    pub monitor_names: Vec<String>,
    /// The points, in continuation order.
    pub points: Vec<BranchPoint>,
    /// The special points, in continuation order.
    pub special_points: Vec<SpecialPoint>,
    /// How it ended.
    pub end: EndReason,
    /// The work it took.
    #[serde(default)]
    pub statistics: RunStatistics,
}

/// A branch as stored: read into a [`Branch`], its points' measure handles are tied to its
/// measure names again.
#[derive(Deserialize)]
struct BranchData {
    name: String,
    parameter: String,
    parameter_index: usize,
    parameter_names: Vec<String>,
    monitor_names: Vec<String>,
    points: Vec<BranchPoint>,
    special_points: Vec<SpecialPoint>,
    end: EndReason,
    #[serde(default)]
    statistics: RunStatistics,
}

impl From<BranchData> for Branch {
    fn from(d: BranchData) -> Self {
        let mut b = Branch {
            name: d.name,
            parameter: d.parameter,
            parameter_index: d.parameter_index,
            parameter_names: d.parameter_names,
            monitor_names: d.monitor_names,
            points: d.points,
            special_points: d.special_points,
            end: d.end,
            statistics: d.statistics,
        };
        b.attach_measure_keys();
        b
    }
}

/// The work a continuation run did: evaluations of the problem, split into stepping along the
/// branch and locating special points.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunStatistics {
    /// Jacobian evaluations (each with a residual and a sparse LU factorisation) while stepping.
    pub jacobians: usize,
    /// Residual-only evaluations (chord iterations) while stepping.
    pub residuals: usize,
    /// Jacobian evaluations while locating special points.
    pub location_jacobians: usize,
    /// Residual-only evaluations while locating special points.
    pub location_residuals: usize,
    /// Analyses of solutions (multipliers and monitors).
    pub analyses: usize,
    /// Steps retried with half the step size (corrector failure or too large an angle).
    pub rejected_steps: usize,
    /// Located sign changes of SN, BP, PD or TR test functions not reported because no
    /// multiplier was at the critical value (e.g. a multiplier through infinity at grazing).
    #[serde(default)]
    pub discarded_tests: usize,
    /// Times the discretisation was adapted along the run
    /// ([`crate::ContinuationProblem::rediscretise`]).
    #[serde(default)]
    pub rediscretisations: usize,
}

impl std::ops::Add for RunStatistics {
    type Output = RunStatistics;
    fn add(self, o: RunStatistics) -> RunStatistics {
        RunStatistics {
            jacobians: self.jacobians + o.jacobians,
            residuals: self.residuals + o.residuals,
            location_jacobians: self.location_jacobians + o.location_jacobians,
            location_residuals: self.location_residuals + o.location_residuals,
            analyses: self.analyses + o.analyses,
            rejected_steps: self.rejected_steps + o.rejected_steps,
            discarded_tests: self.discarded_tests + o.discarded_tests,
            rediscretisations: self.rediscretisations + o.rediscretisations,
        }
    }
}

impl Branch {
    /// Ties every point's measure handles to [`Branch::monitor_names`] (see
    /// [`crate::MeasureId`]): a handle of another run, whose measure at that index has another
    /// name, is then not read.
    pub fn attach_measure_keys(&mut self) {
        let keys = MeasureKeys::of(&self.monitor_names);
        for p in self
            .points
            .iter_mut()
            .chain(self.special_points.iter_mut().map(|s| &mut s.point))
        {
            p.measure_keys = keys.clone();
        }
    }

    /// The point (regular or special) with the given label.
    ///
    /// # Errors
    /// [`Error::NoSuchLabel`].
    pub fn point(&self, label: usize) -> Result<&BranchPoint> {
        self.points
            .iter()
            .chain(self.special_points.iter().map(|s| &s.point))
            .find(|p| p.label == label)
            .ok_or_else(|| Error::NoSuchLabel {
                label,
                branch: self.name.clone(),
            })
    }

    /// The special point with the given label.
    ///
    /// # Errors
    /// [`Error::NoSuchLabel`] if no special point has it (a regular point does not count).
    pub fn special_at(&self, label: usize) -> Result<&SpecialPoint> {
        if let Some(s) = self.special_points.iter().find(|s| s.point.label == label) {
            return Ok(s);
        }
        let specials: Vec<String> = self
            .special_points
            .iter()
            .map(|s| format!("{} ({})", s.point.label, s.kind))
            .collect();
        let specials = if specials.is_empty() {
            "it has none".to_string()
        } else {
            format!("its special points are {}", specials.join(", "))
        };
        if self.points.iter().any(|p| p.label == label) {
            Err(Error::NotASpecialPoint {
                label,
                branch: self.name.clone(),
                specials,
            })
        } else {
            Err(Error::NoSuchLabel {
                label,
                branch: self.name.clone(),
            })
        }
    }

    /// The special points of one kind.
    pub fn special(&self, kind: SpecialKind) -> impl Iterator<Item = &SpecialPoint> {
        self.special_points.iter().filter(move |s| s.kind == kind)
    }

    /// The first special point of one kind along the branch.
    ///
    /// # Errors
    /// [`Error::NoSuchSpecialPoint`] naming the kind and the branch.
    pub fn first(&self, kind: SpecialKind) -> Result<&SpecialPoint> {
        self.special(kind)
            .next()
            .ok_or_else(|| Error::NoSuchSpecialPoint {
                kind: kind.label().to_string(),
                branch: self.name.clone(),
            })
    }

    /// The located special point the run ended on (a bound, an inadmissible orbit, a
    /// [`crate::ContinuationSettings::stop_at`] kind), which the regular points stop short of.
    #[must_use]
    pub fn end_point(&self) -> Option<&BranchPoint> {
        let ended_on_special = matches!(
            self.end,
            EndReason::Bound | EndReason::Inadmissible(_) | EndReason::Reached(_)
        );
        self.special_points
            .last()
            .filter(|s| ended_on_special && s.located)
            .map(|s| &s.point)
    }

    /// Appends the located special point the run ended on ([`Branch::end_point`]) to the
    /// points, so that they reach it (plots draw the points), and relabels.
    pub fn close_end(&mut self) {
        if let Some(p) = self.end_point().cloned() {
            self.points.push(p);
        }
        self.relabel();
    }

    /// One branch from a backward and a forward run from the same start: the backward run
    /// reversed, then the forward one (the shared start once), with the end points the runs
    /// ended on at both ends ([`Branch::end_point`]), labelled afresh; the work of both.
    #[must_use]
    pub fn joined(name: &str, backward: Branch, forward: Branch) -> Branch {
        let mut points: Vec<BranchPoint> = backward.end_point().cloned().into_iter().collect();
        let fwd_end = forward.end_point().cloned();
        points.extend(backward.points.into_iter().rev());
        points.extend(forward.points.into_iter().skip(1));
        points.extend(fwd_end);
        let mut specials = backward.special_points;
        specials.reverse();
        specials.extend(forward.special_points);
        let mut out = Branch {
            name: name.to_string(),
            points,
            special_points: specials,
            end: forward.end,
            statistics: backward.statistics + forward.statistics,
            ..forward
        };
        out.relabel();
        out
    }

    /// Numbers the points `1..` in order, then the special points after them.
    pub fn relabel(&mut self) {
        for (i, p) in self.points.iter_mut().enumerate() {
            p.label = i + 1;
        }
        let base = self.points.len();
        for (i, s) in self.special_points.iter_mut().enumerate() {
            s.point.label = base + i + 1;
        }
    }

    /// Whether the run ended where it should (a bound, a stop point, admissibility, a closed
    /// curve, the point limit) rather than by a corrector failure.
    #[must_use]
    pub fn ended_cleanly(&self) -> bool {
        !matches!(self.end, EndReason::CorrectorFailed(_))
    }

    /// The continuation parameter of a point.
    #[must_use]
    pub fn parameter_of(&self, p: &BranchPoint) -> f64 {
        p.params[self.parameter_index]
    }

    /// JSON text of the branch.
    ///
    /// # Errors
    /// Never for finite data (serde_json refuses NaN).
    pub fn to_json(&self) -> std::result::Result<String, serde_json::Error> {
        serde_json::to_string(self)
    }

    /// A branch from JSON text.
    ///
    /// # Errors
    /// If the text is not a serialised branch.
    pub fn from_json(text: &str) -> std::result::Result<Self, serde_json::Error> {
        serde_json::from_str(text)
    }
}
