//! The defining equation of an event curve: a measure of the orbit held at a level (e.g. an
//! amplitude at a boundary), one touch held at zero (a grazing or boundary condition,
//! [`hycont_core::orbit::Touch`]), or a segment's duration held at zero.

use crate::orbit::SharedMeasures;
use hycont_core::orbit::{Discretisation, PeriodicOrbit, Touch};
use hycont_core::problem::ZeroFunction;
use hycont_core::{HybridJacobians, Result};

/// What is held.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Held {
    /// Measure `index` of the measure set at `level`.
    Measure { index: usize, level: f64 },
    /// The duration of a segment at zero (its unknown, exactly).
    Duration { column: usize },
    /// A touch at zero (its exact gradient); a turning point is looked for where it was found
    /// last.
    Touch(Touch),
}

/// One equation over the problem's base unknowns. A measure depends on the orbit (segment
/// starts, durations, parameters) only, so its gradient lives in those columns (shooting: all
/// unknowns; collocation: the first node of each segment and the rest): exact where the measure
/// provides it ([`hycont_core::orbit::Measure::gradient`]), else by forward differences.
pub(crate) struct MeasuredCondition<'a, S: ?Sized> {
    pub(crate) system: &'a S,
    pub(crate) like: PeriodicOrbit,
    pub(crate) disc: Discretisation,
    pub(crate) measures: SharedMeasures<'a, S>,
    pub(crate) held: Held,
    pub(crate) unknowns: usize,
    pub(crate) columns: Vec<usize>,
}

impl<S: HybridJacobians + ?Sized> MeasuredCondition<'_, S> {
    fn value(&mut self, u: &[f64]) -> Result<f64> {
        Ok(self.value_and_gradient(u)?.0)
    }

    /// The value and, where the measure knows it exactly, its gradient over
    /// [`MeasuredCondition::columns`] (the orbit's coordinates, in the same order).
    fn value_and_gradient(&mut self, u: &[f64]) -> Result<(f64, Option<Vec<f64>>)> {
        match self.held {
            Held::Touch(touch) => {
                let orbit = self.disc.unpack(&self.like, u);
                let v = touch.evaluate(self.system, &orbit)?;
                self.held = Held::Touch(touch.near(v.fraction));
                Ok((
                    v.value,
                    Some(v.gradient).filter(|g| g.len() == self.columns.len()),
                ))
            }
            Held::Measure { index, level } => {
                let orbit = self.disc.unpack(&self.like, u);
                let (v, g) = self
                    .measures
                    .evaluate_with_gradient(self.system, &orbit, index)?;
                Ok((v - level, g.filter(|g| g.len() == self.columns.len())))
            }
            Held::Duration { column } => Ok((u[column], None)),
        }
    }
}

impl<S: HybridJacobians + ?Sized> ZeroFunction for MeasuredCondition<'_, S> {
    fn unknowns(&self) -> usize {
        self.unknowns
    }
    fn equations(&self) -> usize {
        1
    }
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        match self.held {
            Held::Measure { .. } | Held::Touch(_) => self.columns.iter().map(|&c| (0, c)).collect(),
            Held::Duration { column } => vec![(0, column)],
        }
    }
    fn evaluate(
        &mut self,
        u: &[f64],
        residual: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) -> Result<()> {
        let (value, gradient) = self.value_and_gradient(u)?;
        residual[0] = value;
        let Some(jac) = jacobian else {
            return Ok(());
        };
        if let Held::Duration { .. } = self.held {
            jac[0] = 1.0;
            return Ok(());
        }
        if let Some(g) = gradient {
            jac.copy_from_slice(&g);
            return Ok(());
        }
        // Forward differences (step ~ sqrt(eps) relative): the gradient only steers Newton and
        // the tangent; the equation itself is evaluated exactly.
        let mut w = u.to_vec();
        let columns = self.columns.clone();
        for (slot, &c) in columns.iter().enumerate() {
            let h = 1e-7 * u[c].abs().max(1e-1);
            w[c] = u[c] + h;
            let fp = self.value(&w)?;
            w[c] = u[c];
            jac[slot] = (fp - residual[0]) / h;
        }
        Ok(())
    }
}
