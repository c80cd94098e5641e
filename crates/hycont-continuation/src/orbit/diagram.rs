//! Whole bifurcation diagrams in one call (BifurcationKit's `bifurcationdiagram`, for hybrid
//! orbits): from a start, the branch through it both ways, then at every branch point and
//! period doubling up to a depth the branch switched on there, both ways, recursively; special
//! points met on two branches and branches reached twice are followed once. The result is a
//! tree of saved branches with where each came from, serialisable and extendable
//! ([`OrbitRun::extend_diagram`]).

use super::run::{OrbitRun, RunDirection};
use super::saved::OrbitBranch;
use crate::branch::{BranchPoint, SpecialKind, SpecialPoint};
use crate::error::{Error, Result};
use hycont_core::HybridJacobians;
use hycont_core::orbit::PeriodicOrbit;
use serde::{Deserialize, Serialize};

/// A branch of a [`Diagram`]: its index in [`Diagram::branches`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct DiagramBranchId(pub usize);

/// Settings of [`OrbitRun::diagram`] (validated when a diagram is computed).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DiagramSettings {
    /// Levels of switching (default 2): the start's branch is at depth 0, a branch switched on
    /// at a point of a depth-`d` branch at depth `d + 1`; points on branches at `depth` are not
    /// switched at (their records say [`SwitchOutcome::DepthLimit`]).
    pub depth: usize,
    /// The kinds of special points switched at (default BP, PD, GR and DB: at a grazing or a
    /// domain boundary the diagram goes on with the signature beyond it,
    /// [`OrbitRun::switch_at`]; only these switch).
    pub kinds: Vec<SpecialKind>,
    /// Most branches in the diagram (default 256: a safety cap, the depth bounds a diagram;
    /// families switched at grazings branch again); further switches are recorded as
    /// [`SwitchOutcome::BranchLimit`].
    pub max_branches: usize,
    /// Relative tolerance (default `1e-6`) within which two special points of one kind are the
    /// same point: every parameter and every monitor within it of the other's (relative to
    /// `1 + |value|`). Monitors that a symmetry leaves invariant make a point and its mirror
    /// image the same point, so a symmetric pair is followed once.
    pub same_point_tol: f64,
}

impl Default for DiagramSettings {
    fn default() -> Self {
        Self {
            depth: 2,
            kinds: vec![
                SpecialKind::BranchPoint,
                SpecialKind::PeriodDoubling,
                SpecialKind::Grazing,
                SpecialKind::DOMAIN_BOUNDARY,
            ],
            max_branches: 256,
            same_point_tol: 1e-6,
        }
    }
}

impl DiagramSettings {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] naming the bad setting.
    pub fn validate(&self) -> Result<()> {
        if let Some(k) = self.kinds.iter().find(|k| !switchable(k)) {
            return Err(Error::InvalidSetting {
                name: "kinds",
                value: self.kinds.iter().position(|x| x == k).unwrap_or(0) as f64,
                reason: "branches are switched at BP, PD, GR and DB points only",
            });
        }
        if self.max_branches == 0 {
            return Err(Error::InvalidSetting {
                name: "max_branches",
                value: 0.0,
                reason: "must be >= 1",
            });
        }
        if !(self.same_point_tol > 0.0 && self.same_point_tol < 1.0) {
            return Err(Error::InvalidSetting {
                name: "same_point_tol",
                value: self.same_point_tol,
                reason: "must be in (0, 1)",
            });
        }
        Ok(())
    }
}

/// Whether a diagram switches at special points of `kind`: BP, PD, GR and DB
/// ([`SpecialKind::DOMAIN_BOUNDARY`]).
pub(super) fn switchable(kind: &SpecialKind) -> bool {
    matches!(
        kind,
        SpecialKind::BranchPoint | SpecialKind::PeriodDoubling | SpecialKind::Grazing
    ) || *kind == SpecialKind::DOMAIN_BOUNDARY
}

/// What became of a special point switched at (or not).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum SwitchOutcome {
    /// Switched: the branch it produced.
    Followed(DiagramBranchId),
    /// The point the branch itself was switched on at (its parent's point).
    Origin,
    /// The same point as a special point of another branch (a branch point is where two
    /// branches meet: the other is in the diagram) or one already switched at.
    Known {
        /// The branch of the other point.
        branch: DiagramBranchId,
        /// Its label there.
        label: usize,
    },
    /// The switch produced a branch already in the diagram (reached from another point).
    Duplicate(DiagramBranchId),
    /// Not switched: the branch is at the depth limit.
    DepthLimit,
    /// Not switched: the diagram has `max_branches` branches.
    BranchLimit,
    /// The switch failed; why.
    Failed(String),
}

impl SwitchOutcome {
    /// Whether a later call with other settings may switch there ([`OrbitRun::extend_diagram`]).
    #[must_use]
    pub fn pending(&self) -> bool {
        matches!(self, Self::DepthLimit | Self::BranchLimit)
    }
}

/// One special point of a diagram's branch of a kind switched at, and its outcome.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SwitchRecord {
    /// The branch the point is on.
    pub branch: DiagramBranchId,
    /// Its label there.
    pub label: usize,
    /// Its kind.
    pub kind: SpecialKind,
    /// The continued parameter there.
    pub parameter: f64,
    /// What became of it.
    pub outcome: SwitchOutcome,
}

/// A branch of a diagram with where it came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DiagramBranch {
    /// The branch.
    pub branch: OrbitBranch,
    /// The branch and label it was switched on at (`None` for the start's branch).
    pub origin: Option<(DiagramBranchId, usize)>,
    /// Switching levels from the start's branch.
    pub depth: usize,
}

/// A bifurcation diagram: branches as a tree ([`DiagramBranch::origin`]) and every special
/// point switched at with its outcome, in the order they were met.
///
/// Saved as JSON ([`Diagram::to_json`]): `{"branches": [{"branch": <OrbitBranch>, "origin":
/// [parent, label] | null, "depth": d}, ...], "switches": [{"branch": b, "label": l, "kind":
/// "BP" | "PD", "parameter": p, "outcome": <SwitchOutcome>}, ...]}`, branches referred to by
/// their index. A [`SwitchOutcome`] is written as `{"followed": b}`, `"origin"`,
/// `{"known": {"branch": b, "label": l}}`, `{"duplicate": b}`, `"depth_limit"`,
/// `"branch_limit"` or `{"failed": "why"}`. A diagram read back is checked before it is used
/// ([`OrbitRun::check_diagram`], which [`OrbitRun::extend_diagram`] calls): an edited one is
/// refused, not extended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Diagram {
    /// The branches; the start's is first.
    pub branches: Vec<DiagramBranch>,
    /// The special points of the kinds switched at, with their outcomes.
    pub switches: Vec<SwitchRecord>,
}

impl Diagram {
    /// The branch with handle `id`.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for a handle of another diagram.
    pub fn get(&self, id: DiagramBranchId) -> Result<&DiagramBranch> {
        self.branches.get(id.0).ok_or(Error::InvalidSetting {
            name: "diagram branch",
            value: id.0 as f64,
            reason: "the diagram has no such branch",
        })
    }

    /// The branches switched on at points of branch `id`.
    pub fn children(&self, id: DiagramBranchId) -> impl Iterator<Item = DiagramBranchId> + '_ {
        (0..self.branches.len())
            .filter(move |&i| self.branches[i].origin.is_some_and(|(p, _)| p == id))
            .map(DiagramBranchId)
    }

    /// Every special point of every branch, with its branch.
    pub fn special_points(&self) -> impl Iterator<Item = (DiagramBranchId, &SpecialPoint)> + '_ {
        self.branches.iter().enumerate().flat_map(|(i, b)| {
            b.branch
                .branch
                .special_points
                .iter()
                .map(move |s| (DiagramBranchId(i), s))
        })
    }

    /// JSON text.
    ///
    /// # Errors
    /// Never for finite data (serde_json refuses NaN).
    pub fn to_json(&self) -> std::result::Result<String, serde_json::Error> {
        serde_json::to_string(self)
    }

    /// A diagram from JSON text (its branches are checked against the system when it is
    /// extended).
    ///
    /// # Errors
    /// If the text is not a serialised diagram.
    pub fn from_json(text: &str) -> std::result::Result<Self, serde_json::Error> {
        serde_json::from_str(text)
    }
}

impl<'a, S: HybridJacobians + ?Sized> OrbitRun<'a, S> {
    /// The bifurcation diagram from `start`: the branch through it both ways (named `name`),
    /// then, up to `settings.depth` levels, at every located special point of the kinds in
    /// `settings.kinds` the branch switched on there ([`OrbitRun::switch_at`]; both ways at a
    /// branch point, one way at a period doubling, whose two ways are the same doubled family
    /// one traversal apart; named after its parent and the point, e.g. `sym>BP7>PD12`), with
    /// this run's settings, bounds,
    /// measures and events. Breadth first, in the order of the points along each branch. A
    /// point that is the same as a special point of another branch (within
    /// `settings.same_point_tol`) is not switched at again, and a switched branch that runs on
    /// an existing one is dropped ([`SwitchOutcome`]). A failed switch is recorded and the
    /// diagram goes on; the observer hears every branch as it is finished
    /// ([`crate::Observer::branch`]).
    ///
    /// ```
    /// # use hycont_core::{EventId, EventSpec, HybridJacobians, HybridSystem, Mode, ParamId, Z2Symmetry};
    /// # use hycont_core::orbit::{PeriodicOrbit, SegmentEnd, SegmentSpec, Signature};
    /// use hycont_continuation::{DiagramSettings, OrbitRun, SpecialKind, SwitchOutcome};
    /// # /// x' = y + x (1 - x^2 - y^2), y' = -x + y (1 - x^2 - y^2), z' = z (mu - z^2):
    /// # /// the unit circle at height z with z (mu - z^2) = 0, symmetric under -I.
    /// # struct Pitchfork;
    /// # impl HybridSystem for Pitchfork {
    /// #     fn state_dim(&self) -> usize { 3 }
    /// #     fn parameter_names(&self) -> &[&'static str] { &["mu"] }
    /// #     fn mode_count(&self) -> usize { 1 }
    /// #     fn mode_name(&self, _: Mode) -> &'static str { "m" }
    /// #     fn events(&self, _: Mode) -> &[EventId] { &[] }
    /// #     fn event_spec(&self, _: EventId) -> EventSpec { unreachable!() }
    /// #     fn vector_field(&self, _: Mode, x: &[f64], p: &[f64], f: &mut [f64]) {
    /// #         let r = 1.0 - x[0] * x[0] - x[1] * x[1];
    /// #         f[0] = x[1] + x[0] * r; f[1] = -x[0] + x[1] * r; f[2] = x[2] * (p[0] - x[2] * x[2]);
    /// #     }
    /// #     fn event(&self, _: EventId, _: &[f64], _: &[f64]) -> f64 { 0.0 }
    /// #     fn symmetry(&self) -> Option<Z2Symmetry> {
    /// #         Some(Z2Symmetry { matrix: vec![-1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0],
    /// #                           modes: vec![Mode(0)], events: vec![] })
    /// #     }
    /// # }
    /// # impl HybridJacobians for Pitchfork {
    /// #     fn vector_field_jacobian(&self, _: Mode, x: &[f64], p: &[f64], dx: &mut [f64], dp: Option<&mut [f64]>) {
    /// #         let r = 1.0 - x[0] * x[0] - x[1] * x[1];
    /// #         dx.fill(0.0);
    /// #         dx[0] = r - 2.0 * x[0] * x[0]; dx[1] = -1.0 - 2.0 * x[0] * x[1];
    /// #         dx[3] = 1.0 - 2.0 * x[0] * x[1]; dx[4] = r - 2.0 * x[1] * x[1];
    /// #         dx[8] = p[0] - 3.0 * x[2] * x[2];
    /// #         if let Some(dp) = dp { dp.fill(0.0); dp[2] = x[2]; }
    /// #     }
    /// #     fn event_gradient(&self, _: EventId, _: &[f64], _: &[f64], _: &mut [f64], _: Option<&mut [f64]>) {}
    /// # }
    /// # let half = SegmentSpec { mode: Mode(0), end: SegmentEnd::Interior { component: 1, value: 0.0 } };
    /// # let sig = Signature::new(&Pitchfork, vec![half, half]).unwrap();
    /// // The symmetric orbit (z = 0) at mu = -0.3, two half turns.
    /// let start = PeriodicOrbit::new(&Pitchfork, sig, vec![vec![1.0, 0.0, 0.0], vec![-1.0, 0.0, 0.0]],
    ///                                vec![std::f64::consts::PI; 2], vec![-0.3]).unwrap();
    /// let mut run = OrbitRun::new(&Pitchfork, ParamId(0)).unwrap();
    /// run.bounds(-0.5, 0.5);
    /// let d = run.diagram("symmetric", &start, &DiagramSettings::default()).unwrap();
    /// // The symmetry breaks at mu = 0; the orbits born there (z^2 = mu) are the second branch.
    /// assert_eq!(d.branches.len(), 2);
    /// let bp = &d.switches[0];
    /// assert_eq!(bp.kind, SpecialKind::BranchPoint);
    /// assert!(bp.parameter.abs() < 1e-8);
    /// assert!(matches!(bp.outcome, SwitchOutcome::Followed(_)));
    /// let broken = &d.branches[1].branch;
    /// let far = broken.branch.points.last().unwrap();
    /// let z = broken.orbit_of(far).unwrap().starts[0][2];
    /// assert!((z * z - far[ParamId(0)]).abs() < 1e-8);
    /// ```
    ///
    /// # Errors
    /// Invalid settings; as [`OrbitRun::run`] for the start's branch.
    pub fn diagram(
        &mut self,
        name: &str,
        start: &PeriodicOrbit,
        settings: &DiagramSettings,
    ) -> Result<Diagram> {
        settings.validate()?;
        let root = self.run(name, start, RunDirection::Both)?;
        self.diagram_from(root, settings)
    }

    /// [`OrbitRun::diagram`] from a branch already computed (e.g. a restarted one).
    ///
    /// # Errors
    /// Invalid settings; a branch that does not fit the system.
    pub fn diagram_from(
        &mut self,
        root: OrbitBranch,
        settings: &DiagramSettings,
    ) -> Result<Diagram> {
        settings.validate()?;
        self.check_saved(&root)?;
        self.observer.branch(&root.branch);
        let mut diagram = Diagram {
            branches: vec![DiagramBranch {
                branch: root,
                origin: None,
                depth: 0,
            }],
            switches: Vec::new(),
        };
        self.explore(&mut diagram, settings)?;
        Ok(diagram)
    }

    /// Extends a diagram (e.g. one read from a file) with other settings: points left at the
    /// depth or branch limit are switched at where the new settings allow, and the new
    /// branches' points in turn. The diagram is checked first ([`OrbitRun::check_diagram`]:
    /// its tree, and every point of every branch an orbit of this run whose analysis is what
    /// it says), so that a diagram edited or written by another system or run is refused,
    /// not extended from points where no orbit is.
    ///
    /// # Errors
    /// Invalid settings; a diagram that does not pass [`OrbitRun::check_diagram`].
    pub fn extend_diagram(
        &mut self,
        diagram: &mut Diagram,
        settings: &DiagramSettings,
    ) -> Result<()> {
        settings.validate()?;
        self.check_diagram(diagram)?;
        diagram.switches.retain(|r| !r.outcome.pending());
        self.explore(diagram, settings)
    }

    /// Breadth first over the branches: each point of a switched kind without a final outcome
    /// gets one.
    fn explore(&mut self, d: &mut Diagram, settings: &DiagramSettings) -> Result<()> {
        let mut i = 0;
        while i < d.branches.len() {
            let id = DiagramBranchId(i);
            let points: Vec<SpecialPoint> = d.branches[i]
                .branch
                .branch
                .special_points
                .iter()
                .filter(|s| s.located && settings.kinds.contains(&s.kind))
                .cloned()
                .collect();
            for s in points {
                if d.switches
                    .iter()
                    .any(|r| r.branch == id && r.label == s.point.label)
                {
                    continue;
                }
                // Asked to stop: the points left have no record yet (an extension switches
                // there).
                if self.observer.stop() {
                    return Ok(());
                }
                let outcome = self.outcome(d, id, &s, settings);
                d.switches.push(SwitchRecord {
                    branch: id,
                    label: s.point.label,
                    kind: s.kind,
                    parameter: d.branches[i].branch.branch.parameter_of(&s.point),
                    outcome,
                });
            }
            i += 1;
        }
        Ok(())
    }

    /// What becomes of special point `s` of branch `id`: the checks in order, then the switch.
    fn outcome(
        &mut self,
        d: &mut Diagram,
        id: DiagramBranchId,
        s: &SpecialPoint,
        settings: &DiagramSettings,
    ) -> SwitchOutcome {
        let tol = settings.same_point_tol;
        let here = &d.branches[id.0];
        if let Some((parent, label)) = here.origin
            && let Some(parent) = d.branches.get(parent.0)
            && let Ok(p) = parent.branch.special_at(label)
            && same_point(&p.point, &s.point, tol)
        {
            return SwitchOutcome::Origin;
        }
        if let Some((branch, label)) = known(d, id, s, tol) {
            return SwitchOutcome::Known { branch, label };
        }
        if here.depth >= settings.depth {
            return SwitchOutcome::DepthLimit;
        }
        if d.branches.len() >= settings.max_branches {
            return SwitchOutcome::BranchLimit;
        }
        let parent = &here.branch;
        let name = format!("{}>{}{}", parent.branch.name, s.kind.label(), s.point.label);
        let depth = here.depth + 1;
        // Both ways from a branch point (the two halves may differ); one way from a period
        // doubling (the two ways along the flip direction are the same doubled family, one
        // traversal apart) and from a grazing (the way the new signature is physical).
        let direction = if s.kind == SpecialKind::BranchPoint {
            RunDirection::Both
        } else {
            RunDirection::Up
        };
        let child = match self.switch_at(&name, parent, s.point.label, direction) {
            Ok(c) => c,
            Err(e) => return SwitchOutcome::Failed(e.to_string()),
        };
        if let Some(j) = (0..d.branches.len()).find(|&j| runs_on(&child, &d.branches[j].branch)) {
            return SwitchOutcome::Duplicate(DiagramBranchId(j));
        }
        self.observer.branch(&child.branch);
        d.branches.push(DiagramBranch {
            branch: child,
            origin: Some((id, s.point.label)),
            depth,
        });
        SwitchOutcome::Followed(DiagramBranchId(d.branches.len() - 1))
    }
}

/// Whether two points are the same within relative `tol`: the same number of parameters and
/// monitors, each within `tol (1 + |value|)`.
fn same_point(a: &BranchPoint, b: &BranchPoint, tol: f64) -> bool {
    let close = |x: &[f64], y: &[f64]| {
        x.len() == y.len()
            && x.iter()
                .zip(y)
                .all(|(u, v)| (u - v).abs() <= tol * (1.0 + u.abs().max(v.abs())))
    };
    close(&a.params, &b.params) && close(&a.monitors, &b.monitors)
}

/// A special point of the same kind that is the same as `s` (of branch `id`): on another
/// branch (for a branch point, that branch is the other one through it), or on the same
/// branch and already switched at.
fn known(
    d: &Diagram,
    id: DiagramBranchId,
    s: &SpecialPoint,
    tol: f64,
) -> Option<(DiagramBranchId, usize)> {
    d.special_points()
        .filter(|(b, o)| {
            o.kind == s.kind && o.located && !(*b == id && o.point.label == s.point.label)
        })
        .filter(|(b, o)| {
            *b != id
                || d.switches
                    .iter()
                    .any(|r| r.branch == id && r.label == o.point.label && !r.outcome.pending())
        })
        .find(|(_, o)| same_point(&o.point, &s.point, tol))
        .map(|(b, o)| (b, o.point.label))
}

/// Whether `child` runs on `other`: the same parameter and segments, and its points a quarter,
/// half and three quarters along lie on `other`'s polyline in (parameters, monitors, segment
/// start states, durations) within a tenth of the nearest chord (a chord of a curve with
/// curvature $\kappa$ and length $h$ deviates from it by $\kappa h^2/8$, well below $h/10$
/// for the steps continuation takes).
fn runs_on(child: &OrbitBranch, other: &OrbitBranch) -> bool {
    let pts = &child.branch.points;
    if child.free != other.free
        || child.second.is_some()
        || other.second.is_some()
        || child.template.segment_count() != other.template.segment_count()
        || pts.len() < 4
        || other.branch.points.len() < 2
    {
        return false;
    }
    let Some(line) = other
        .branch
        .points
        .iter()
        .map(|q| coordinates(other, q))
        .collect::<Option<Vec<_>>>()
    else {
        return false;
    };
    [pts.len() / 4, pts.len() / 2, 3 * pts.len() / 4]
        .iter()
        .all(|&k| coordinates(child, &pts[k]).is_some_and(|x| on_polyline(&x, &line)))
}

/// A point's parameters, monitors, segment start states and durations.
fn coordinates(branch: &OrbitBranch, q: &BranchPoint) -> Option<Vec<f64>> {
    let orbit = branch.orbit_of(q).ok()?;
    let mut x: Vec<f64> = q.params.iter().chain(&q.monitors).copied().collect();
    x.extend(orbit.starts.iter().flatten());
    x.extend(&orbit.durations);
    Some(x)
}

/// Whether `x` lies within a tenth of a chord of the polyline through `line`.
fn on_polyline(x: &[f64], line: &[Vec<f64>]) -> bool {
    line.windows(2).any(|w| {
        let (a, b) = (&w[0], &w[1]);
        if a.len() != x.len() || b.len() != x.len() {
            return false;
        }
        let ab: Vec<f64> = a.iter().zip(b).map(|(u, v)| v - u).collect();
        let len2: f64 = ab.iter().map(|v| v * v).sum();
        let along: f64 = x
            .iter()
            .zip(a)
            .zip(&ab)
            .map(|((xi, ai), d)| (xi - ai) * d)
            .sum();
        let t = if len2 > 0.0 {
            (along / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let dist2: f64 = x
            .iter()
            .zip(a)
            .zip(&ab)
            .map(|((xi, ai), d)| (xi - ai - t * d).powi(2))
            .sum();
        dist2 <= 0.01 * len2.max(f64::MIN_POSITIVE)
    })
}
