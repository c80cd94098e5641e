//! Two-parameter continuation of codimension-one points of hybrid periodic orbits: folds (SN),
//! period doublings (PD), symmetry-breaking branch points (BP), and events on monitors such as
//! boundary touch (SB) and grazing (GR).
//!
//! Each curve is the orbit's shooting problem with both parameters released and one defining
//! scalar equation added:
//! - PD: $\prod (1 + \lambda_i) = 0$ over the non-trivial Floquet multipliers;
//! - SN and BP of a $\mathbb{Z}_2$-symmetric orbit: on its half-orbit problem, with $\mu_i$ the
//!   non-trivial multipliers of the half map $S \circ \phi_{T/2}$, $\prod(\mu_i - 1) = 0$ (fold)
//!   and $\prod(1 + \mu_i) = 0$ (symmetry-breaking branch point); the full-period map has a
//!   multiplier $+1$ at both, the half map tells them apart;
//! - SN of a general orbit: $\prod(\lambda_i - 1) = 0$;
//! - events: a monitor of the orbit held at its level (SB), a signed grazing margin held at zero
//!   (GR: an interior dip of a flight touches the impact surface), or a segment's duration held
//!   at zero (GR: the segment has collapsed).
//!
//! The defining function's gradient is computed by central differences (the multipliers'
//! derivatives would need second derivatives of the flow); the problems are small, so the cost
//! is moderate.

use crate::branch::SpecialKind;
use crate::error::{Error, Result};
use crate::orbit::{Measures, OrbitContinuation, OrbitMethod};
use hycont_core::orbit::{Floquet, PeriodicOrbit, ShootingSettings, monodromy_by_shooting, unpack};
use hycont_core::problem::ZeroFunction;
use hycont_core::{HybridJacobians, ParamId};

/// The defining condition of a two-parameter curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Condition {
    /// A non-trivial multiplier of the full-period map at $-1$.
    PeriodDoubling,
    /// A non-trivial multiplier of the full-period map at $+1$.
    Fold,
    /// (Half orbit.) A non-trivial half-map multiplier at $+1$: a fold of symmetric orbits.
    SymmetricFold,
    /// (Half orbit.) A non-trivial half-map multiplier at $-1$: a symmetry-breaking branch point.
    SymmetryBreaking,
    /// Monitor `index` of the orbit's measures held at `level`.
    Monitor {
        /// Index into the [`Measures`] values.
        index: usize,
        /// The level.
        level: f64,
    },
    /// Measure `index` of the orbit's measures, a signed grazing margin (e.g. the depth of a
    /// flight's interior dip above its impact surface), held at zero: a grazing curve.
    Grazing {
        /// Index into the [`Measures`] values.
        index: usize,
    },
    /// The duration of segment `segment` held at zero.
    Collapse {
        /// The segment.
        segment: usize,
    },
}

impl Condition {
    /// The special-point kind whose curve this is.
    #[must_use]
    pub fn kind(self) -> SpecialKind {
        match self {
            Condition::PeriodDoubling => SpecialKind::PeriodDoubling,
            Condition::Fold | Condition::SymmetricFold => SpecialKind::Fold,
            Condition::SymmetryBreaking => SpecialKind::BranchPoint,
            Condition::Monitor { .. } => SpecialKind::BoundaryTouch,
            Condition::Grazing { .. } | Condition::Collapse { .. } => SpecialKind::Grazing,
        }
    }
}

fn product(f: &Floquet, shift: f64) -> f64 {
    crate::shifted_product(&f.multipliers, &f.trivial, shift)
}

/// The defining equation as a part of the shooting problem: one equation over all the shooting
/// unknowns, gradient by central differences.
struct DefiningEquation<'a, S: ?Sized> {
    system: &'a S,
    like: PeriodicOrbit,
    condition: Condition,
    settings: ShootingSettings,
    measures: Measures<'a>,
    n_unknowns: usize,
}

impl<S: HybridJacobians + ?Sized> DefiningEquation<'_, S> {
    fn value(&mut self, u: &[f64]) -> hycont_core::Result<f64> {
        let orbit = unpack(&self.like, u);
        Ok(match self.condition {
            Condition::PeriodDoubling => product(
                &monodromy_by_shooting(self.system, &orbit, self.settings)?,
                1.0,
            ),
            Condition::Fold => product(
                &monodromy_by_shooting(self.system, &orbit, self.settings)?,
                -1.0,
            ),
            Condition::SymmetricFold | Condition::SymmetryBreaking => {
                let sym =
                    self.system
                        .symmetry()
                        .ok_or_else(|| hycont_core::Error::InvalidSignature {
                            segment: 0,
                            reason: "no symmetry".into(),
                        })?;
                let m = monodromy_by_shooting(self.system, &orbit, self.settings)?.monodromy;
                let n = self.system.state_dim();
                let mut half = vec![0.0; n * n];
                for j in 0..n {
                    for i in 0..n {
                        half[i + j * n] =
                            (0..n).map(|l| sym.matrix[i + l * n] * m[l + j * n]).sum();
                    }
                }
                let f = Floquet::from_monodromy(self.system, &orbit.params, orbit.period(), half)?;
                let shift = if self.condition == Condition::SymmetricFold {
                    -1.0
                } else {
                    1.0
                };
                product(&f, shift)
            }
            Condition::Monitor { index, level } => (self.measures.compute)(&orbit)[index] - level,
            Condition::Grazing { index } => (self.measures.compute)(&orbit)[index],
            Condition::Collapse { segment } => orbit.durations[segment],
        })
    }
}

impl<S: HybridJacobians + ?Sized> ZeroFunction for DefiningEquation<'_, S> {
    fn unknowns(&self) -> usize {
        self.n_unknowns
    }
    fn equations(&self) -> usize {
        1
    }
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        (0..self.n_unknowns).map(|c| (0, c)).collect()
    }
    fn evaluate(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) -> hycont_core::Result<()> {
        residual[0] = self.value(u)?;
        if let Some(jac) = jacobian {
            if let Condition::Collapse { segment } = self.condition {
                jac.fill(0.0);
                jac[self.like.segment_count() * self.like.starts[0].len() + segment] = 1.0;
                return Ok(());
            }
            // Forward differences (step ~ sqrt(eps) relative): the gradient only steers Newton
            // and the tangent, the equation itself is evaluated exactly.
            let f0 = residual[0];
            let mut w = u.to_vec();
            for c in 0..self.n_unknowns {
                let h = 1e-7 * u[c].abs().max(1e-1);
                w[c] = u[c] + h;
                let fp = self.value(&w)?;
                w[c] = u[c];
                jac[c] = (fp - f0) / h;
            }
        }
        Ok(())
    }
}

/// A two-parameter curve problem: the orbit's shooting problem with `first` and `second`
/// released and the defining equation of `condition` added; continued in `first` (the second
/// parameter is reported among the monitors, after `period`, `min_duration` and the measures).
pub struct Codim2<'a, S: ?Sized> {
    /// The underlying orbit continuation (with both parameters active).
    pub inner: OrbitContinuation<'a, S>,
    /// The condition.
    pub condition: Condition,
    second: ParamId,
}

impl<'a, S: HybridJacobians + ?Sized> Codim2<'a, S> {
    /// The curve problem through `orbit` (a point of the curve, e.g. a located special point's
    /// orbit; for [`Condition::SymmetricFold`] and [`Condition::SymmetryBreaking`] the half
    /// orbit of a symmetric one), and the starting unknowns.
    ///
    /// `measures` are recorded along the curve; `condition_measures` evaluate
    /// [`Condition::Monitor`] (usually the same functions).
    ///
    /// # Errors
    /// If the problem cannot be built or solved at the start.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        system: &'a S,
        orbit: &PeriodicOrbit,
        settings: ShootingSettings,
        first: ParamId,
        second: ParamId,
        condition: Condition,
        measures: Measures<'a>,
        condition_measures: Measures<'a>,
    ) -> Result<(Self, Vec<f64>)> {
        let (mut inner, mut u0) = OrbitContinuation::new(
            system,
            orbit,
            &OrbitMethod::Shooting(settings),
            first,
            measures,
            Vec::new(),
        )?;
        let name = system.parameter_names()[second.index()];
        let problem = inner.problem_mut();
        let id = problem
            .monitor_id(name)
            .ok_or_else(|| Error::SwitchFailed {
                reason: format!("no monitor for parameter {name}"),
            })?;
        problem.set_activity(
            id,
            hycont_core::problem::Activity::Active(orbit.params[second.index()]),
        );
        let base = problem.base_unknowns();
        let part = DefiningEquation {
            system,
            like: orbit.clone(),
            condition,
            settings,
            measures: condition_measures,
            n_unknowns: base,
        };
        problem.add_part(Box::new(part), (0..base).collect())?;
        // Unknowns: base, then the active monitors' values in monitor order (the first
        // parameter's monitor precedes the second's when its index is lower).
        let (p1, p2) = (orbit.params[first.index()], orbit.params[second.index()]);
        u0.truncate(base);
        if first.index() < second.index() {
            u0.extend([p1, p2]);
        } else {
            u0.extend([p2, p1]);
        }
        inner.set_second_parameter(second, first.index() > second.index());
        if let Condition::Collapse { segment } = condition {
            inner.set_collapsed(segment);
        }
        Ok((
            Self {
                inner,
                condition,
                second,
            },
            u0,
        ))
    }
}

impl<'a, S: HybridJacobians + ?Sized> Codim2<'a, S> {
    /// The fold curve through a fold of a general orbit ($\prod(\lambda_i - 1) = 0$).
    ///
    /// # Errors
    /// As [`Codim2::new`].
    pub fn from_fold(
        system: &'a S,
        orbit: &PeriodicOrbit,
        settings: ShootingSettings,
        first: ParamId,
        second: ParamId,
        measures: Measures<'a>,
    ) -> Result<(Self, Vec<f64>)> {
        Self::new(
            system,
            orbit,
            settings,
            first,
            second,
            Condition::Fold,
            measures,
            Measures::default(),
        )
    }

    /// The fold curve through a fold of a symmetric orbit, on its half orbit
    /// (`orbit.half_of_symmetric(..)`).
    ///
    /// # Errors
    /// As [`Codim2::new`].
    pub fn from_symmetric_fold(
        system: &'a S,
        half_orbit: &PeriodicOrbit,
        settings: ShootingSettings,
        first: ParamId,
        second: ParamId,
        measures: Measures<'a>,
    ) -> Result<(Self, Vec<f64>)> {
        Self::new(
            system,
            half_orbit,
            settings,
            first,
            second,
            Condition::SymmetricFold,
            measures,
            Measures::default(),
        )
    }

    /// The period-doubling curve through a period doubling of `orbit`.
    ///
    /// # Errors
    /// As [`Codim2::new`].
    pub fn from_period_doubling(
        system: &'a S,
        orbit: &PeriodicOrbit,
        settings: ShootingSettings,
        first: ParamId,
        second: ParamId,
        measures: Measures<'a>,
    ) -> Result<(Self, Vec<f64>)> {
        Self::new(
            system,
            orbit,
            settings,
            first,
            second,
            Condition::PeriodDoubling,
            measures,
            Measures::default(),
        )
    }

    /// The curve of symmetry-breaking branch points through one, on the half orbit of the
    /// symmetric orbit there.
    ///
    /// # Errors
    /// As [`Codim2::new`].
    pub fn from_branch_point(
        system: &'a S,
        half_orbit: &PeriodicOrbit,
        settings: ShootingSettings,
        first: ParamId,
        second: ParamId,
        measures: Measures<'a>,
    ) -> Result<(Self, Vec<f64>)> {
        Self::new(
            system,
            half_orbit,
            settings,
            first,
            second,
            Condition::SymmetryBreaking,
            measures,
            Measures::default(),
        )
    }

    /// The grazing curve through an orbit at which measure `index` of `condition_measures`, a
    /// signed grazing margin (zero where an interior dip of a flight touches its impact
    /// surface), vanishes.
    ///
    /// # Errors
    /// As [`Codim2::new`].
    #[allow(clippy::too_many_arguments)]
    pub fn from_grazing(
        system: &'a S,
        orbit: &PeriodicOrbit,
        settings: ShootingSettings,
        first: ParamId,
        second: ParamId,
        index: usize,
        measures: Measures<'a>,
        condition_measures: Measures<'a>,
    ) -> Result<(Self, Vec<f64>)> {
        Self::new(
            system,
            orbit,
            settings,
            first,
            second,
            Condition::Grazing { index },
            measures,
            condition_measures,
        )
    }

    /// The curve of an event through a point where it holds: measure `index` of
    /// `condition_measures` at `level` (e.g. boundary touch), or, with `index == None`, the
    /// shortest segment collapsed to zero duration (grazing).
    ///
    /// # Errors
    /// As [`Codim2::new`].
    #[allow(clippy::too_many_arguments)]
    pub fn from_event(
        system: &'a S,
        orbit: &PeriodicOrbit,
        settings: ShootingSettings,
        first: ParamId,
        second: ParamId,
        index: Option<usize>,
        level: f64,
        measures: Measures<'a>,
        condition_measures: Measures<'a>,
    ) -> Result<(Self, Vec<f64>)> {
        let condition = match index {
            Some(index) => Condition::Monitor { index, level },
            None => Condition::Collapse {
                segment: orbit
                    .durations
                    .iter()
                    .enumerate()
                    .min_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
                    .map_or(0, |(i, _)| i),
            },
        };
        Self::new(
            system,
            orbit,
            settings,
            first,
            second,
            condition,
            measures,
            condition_measures,
        )
    }
}

impl<'a, S: HybridJacobians + ?Sized> crate::ContinuationProblem<'a> for Codim2<'a, S> {
    fn problem(&mut self) -> &mut hycont_core::problem::Problem<'a> {
        self.inner.problem_mut()
    }
    fn parameter_index(&self) -> usize {
        self.inner.parameter_index()
    }
    fn parameter_position(&self) -> usize {
        self.inner.parameter_position()
    }
    fn parameter_name(&self) -> String {
        self.inner.parameter_name()
    }
    fn parameter_names(&self) -> Vec<String> {
        self.inner.parameter_names()
    }
    fn monitor_names(&self) -> Vec<String> {
        let mut names = self.inner.monitor_names();
        names.push(self.inner.parameter_names()[self.second.index()].clone());
        names
    }
    fn analyse(&mut self, u: &[f64]) -> hycont_core::Result<crate::PointInfo> {
        let mut info = self.inner.analyse(u)?;
        info.monitors.push(info.params[self.second.index()]);
        Ok(info)
    }
    fn monitor_events(&self) -> Vec<crate::MonitorEvent> {
        self.inner.monitor_events()
    }
}

/// Continuation settings suited to two-parameter curves: larger steps (the curves are smooth),
/// and only turning points and monitor events detected (the one-parameter test functions are
/// meaningless on a curve defined by one of them).
#[must_use]
pub fn curve_settings() -> crate::ContinuationSettings {
    crate::ContinuationSettings::default()
        .steps(0.02, 1e-8, 0.25)
        .detect(crate::Detect {
            fold: true,
            branch_point: false,
            period_doubling: false,
            torus: false,
            monitor_events: true,
        })
}
