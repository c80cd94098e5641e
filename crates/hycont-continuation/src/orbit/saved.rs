//! A branch of hybrid periodic orbits with everything needed to read its points as orbits, to
//! restart from them, switch branches at them and continue curves from them: serialisable (a
//! saved run).

use super::run::RunDirection;
use crate::branch::{Branch, BranchPoint, SpecialKind, SpecialPoint};
use crate::codim2::CurveCondition;
use crate::error::{Error, Result};
use hycont_core::orbit::{Discretisation, PeriodicOrbit};
use hycont_core::{HybridSystem, ParamId};
use serde::{Deserialize, Serialize};

/// A branch of orbits (or a two-parameter curve) with its layout: points' unknowns are those
/// of `discretisation` for orbits like `template` (always the full orbits, also for branches
/// continued on half orbits), followed by the active parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OrbitBranch {
    /// The branch.
    pub branch: Branch,
    /// The continued parameter.
    pub free: ParamId,
    /// The second parameter of a two-parameter curve.
    #[serde(default)]
    pub second: Option<ParamId>,
    /// The defining condition of a two-parameter curve (what [`crate::OrbitRun::curve_from`]
    /// continues it with); `None` for a branch, and for curves saved before it was recorded.
    #[serde(default)]
    pub condition: Option<CurveCondition>,
    /// An orbit with the branch's signature (the first point's, as started).
    pub template: PeriodicOrbit,
    /// The discretisation the run started on (of every point with
    /// [`BranchPoint::discretisation`] 0).
    pub discretisation: Discretisation,
    /// The discretisations the run adapted to along the way, in order: a point with
    /// [`BranchPoint::discretisation`] `r > 0` is on `rediscretised[r - 1]` (collocation
    /// meshes of the same degree and segments; refined ones have more intervals, and their
    /// points more unknowns).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rediscretised: Vec<Discretisation>,
}

impl OrbitBranch {
    /// The number of unknowns of a point on `disc`.
    fn unknowns(&self, disc: &Discretisation) -> usize {
        let base = disc.segment_values(&self.template)
            + self.template.segment_count()
            + self.template.params.len();
        base + 1 + usize::from(self.second.is_some())
    }

    /// Checks the branch against `system` (e.g. after reading it from a file): the template
    /// fits the system, the discretisation fits the template, and every point has the right
    /// number of unknowns.
    ///
    /// # Errors
    /// [`Error::Core`] or [`Error::InvalidSetting`] naming what does not fit.
    pub fn validate<S: HybridSystem + ?Sized>(&self, system: &S) -> Result<()> {
        self.template.validate(system)?;
        crate::orbit::check_parameter(system, self.free)?;
        if let Some(p) = self.second {
            crate::orbit::check_parameter(system, p)?;
        }
        for d in &self.rediscretised {
            let same_layout = match (&self.discretisation, d) {
                (
                    Discretisation::Collocation { meshes: a, ncol: p },
                    Discretisation::Collocation { meshes: b, ncol: q },
                ) => p == q && a.len() == b.len(),
                _ => false,
            };
            if !same_layout {
                return Err(Error::InvalidSetting {
                    name: "rediscretised",
                    value: self.rediscretised.len() as f64,
                    reason: "adapted discretisations are collocation meshes of the first one's degree and segments",
                });
            }
        }
        for disc in std::iter::once(&self.discretisation).chain(&self.rediscretised) {
            Self::validate_meshes(disc, self.template.segment_count())?;
        }
        let points = self
            .branch
            .points
            .iter()
            .chain(self.branch.special_points.iter().map(|s| &s.point));
        for p in points {
            let n = self.discretisation_of(p).map(|d| self.unknowns(d));
            if n.is_err()
                || n.is_ok_and(|n| p.u.len() != n || p.tangent.len() != n)
                || p.u.iter().any(|v| !v.is_finite())
            {
                return Err(Error::InvalidSetting {
                    name: "point unknowns",
                    value: p.label as f64,
                    reason: "a point's unknowns, tangent or discretisation do not fit the branch's layout",
                });
            }
        }
        Ok(())
    }

    /// Checks a collocation discretisation's meshes: one per segment, each increasing from 0
    /// to 1, and `ncol` in `1..=7`.
    fn validate_meshes(disc: &Discretisation, segments: usize) -> Result<()> {
        if let Discretisation::Collocation { meshes, ncol } = disc {
            let bad_mesh = |m: &Vec<f64>| {
                m.len() < 2
                    || m[0] != 0.0
                    || m.last() != Some(&1.0)
                    || m.windows(2).any(|w| !(w[1] > w[0]))
            };
            if meshes.len() != segments || meshes.iter().any(bad_mesh) || !(1..=7).contains(ncol) {
                return Err(Error::InvalidSetting {
                    name: "collocation mesh",
                    value: meshes.len() as f64,
                    reason: "one increasing mesh from 0 to 1 per segment, ncol in 1..=7",
                });
            }
        }
        Ok(())
    }

    /// The discretisation a point's unknowns are on (see [`BranchPoint::discretisation`]).
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for a revision the branch does not have.
    pub fn discretisation_of(&self, point: &BranchPoint) -> Result<&Discretisation> {
        match point.discretisation {
            0 => Ok(&self.discretisation),
            r => self.rediscretised.get(r - 1).ok_or(Error::InvalidSetting {
                name: "point discretisation",
                value: r as f64,
                reason: "the branch has no such discretisation revision",
            }),
        }
    }

    /// The point (regular or special) with the given label.
    ///
    /// # Errors
    /// [`Error::NoSuchLabel`].
    pub fn point(&self, label: usize) -> Result<&BranchPoint> {
        self.branch.point(label)
    }

    /// The special point with the given label.
    ///
    /// # Errors
    /// [`Error::NoSuchLabel`].
    pub fn special_at(&self, label: usize) -> Result<&SpecialPoint> {
        self.branch.special_at(label)
    }

    /// The special points of one kind.
    pub fn special(&self, kind: SpecialKind) -> impl Iterator<Item = &SpecialPoint> {
        self.branch.special(kind)
    }

    /// The first special point of one kind along the branch.
    ///
    /// # Errors
    /// [`Error::NoSuchSpecialPoint`] naming the kind and the branch.
    pub fn first(&self, kind: SpecialKind) -> Result<&SpecialPoint> {
        self.branch.first(kind)
    }

    /// The orbit at a point of this branch.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] if the point's unknowns do not fit the layout.
    pub fn orbit_of(&self, point: &BranchPoint) -> Result<PeriodicOrbit> {
        let disc = self.discretisation_of(point)?;
        if point.u.len() != self.unknowns(disc) {
            return Err(Error::InvalidSetting {
                name: "point unknowns",
                value: point.u.len() as f64,
                reason: "do not fit the branch's layout",
            });
        }
        Ok(disc.unpack(&self.template, &point.u))
    }

    /// The orbit at the point with the given label.
    ///
    /// # Errors
    /// [`Error::NoSuchLabel`]; as [`OrbitBranch::orbit_of`].
    pub fn orbit_at(&self, label: usize) -> Result<PeriodicOrbit> {
        self.orbit_of(self.point(label)?)
    }

    /// The way the run went at a point: up or down in the continued parameter (the sign of the
    /// tangent's component).
    ///
    /// # Errors
    /// [`Error::NoSuchLabel`].
    pub fn direction_at(&self, label: usize) -> Result<RunDirection> {
        let p = self.point(label)?;
        let i = self.discretisation_of(p)?.segment_values(&self.template)
            + self.template.segment_count()
            + self.free.index();
        Ok(match p.tangent.get(i) {
            Some(t) if *t < 0.0 => RunDirection::Down,
            _ => RunDirection::Up,
        })
    }

    /// JSON text.
    ///
    /// # Errors
    /// Never for finite data (serde_json refuses NaN).
    pub fn to_json(&self) -> std::result::Result<String, serde_json::Error> {
        serde_json::to_string(self)
    }

    /// A branch from JSON text (check it with [`OrbitBranch::validate`] before use).
    ///
    /// # Errors
    /// If the text is not a serialised orbit branch.
    pub fn from_json(text: &str) -> std::result::Result<Self, serde_json::Error> {
        serde_json::from_str(text)
    }
}
