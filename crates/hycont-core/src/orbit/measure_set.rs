//! [`MeasureSet`]: named measures of an orbit evaluated together, one scan for all.

use super::measure::Measure;
use super::scan::{OrbitScan, ScanNeeds, scan, scan_simulator, scan_with};
use super::{Closure, PeriodicOrbit, Touch};
use crate::error::{Error, Result, check_finite};
use crate::simulate::{SimulationSettings, Simulator};
use crate::system::HybridJacobians;
use std::sync::Mutex;

/// Named measures evaluated together: one scan of the orbit serves all of them.
///
/// On a half orbit ([`Closure::Symmetric`]) the values are those of the full orbit: the half
/// orbit is measured directly when every measure is [invariant](Measure::invariant_under)
/// under the system's symmetry, and unfolded otherwise.
pub struct MeasureSet<'a, S: ?Sized> {
    names: Vec<String>,
    measures: Vec<Box<dyn Measure<S> + 'a>>,
    settings: SimulationSettings,
    /// The scans' simulator, kept for its work space (a scan that finds it in use, e.g. from
    /// a measure that evaluates measures, makes its own).
    scanner: Mutex<Option<Simulator>>,
}

impl<S: ?Sized> std::fmt::Debug for MeasureSet<'_, S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeasureSet")
            .field("names", &self.names)
            .finish_non_exhaustive()
    }
}

impl<S: ?Sized> Default for MeasureSet<'_, S> {
    fn default() -> Self {
        Self::new()
    }
}

impl<'a, S: ?Sized> MeasureSet<'a, S> {
    /// An empty set; scans integrate at `rtol = 1e-10`, `atol = 1e-12`.
    #[must_use]
    pub fn new() -> Self {
        Self {
            names: Vec::new(),
            measures: Vec::new(),
            settings: SimulationSettings::default().rtol(1e-10).atol(1e-12),
            scanner: Mutex::new(None),
        }
    }

    /// Sets the integration settings of the scans.
    #[must_use]
    pub fn with_settings(mut self, settings: SimulationSettings) -> Self {
        self.settings = settings;
        self.scanner = Mutex::new(None);
        self
    }

    /// Adds a measure; returns its index in the values of [`MeasureSet::evaluate`].
    ///
    /// # Errors
    /// [`Error::InvalidMeasure`] if the name is empty or already taken.
    pub fn add(&mut self, name: &str, measure: impl Measure<S> + 'a) -> Result<usize> {
        if name.is_empty() || self.names.iter().any(|n| n == name) {
            return Err(Error::InvalidMeasure {
                reason: format!("measure name {name:?} is empty or already used"),
            });
        }
        self.names.push(name.to_string());
        self.measures.push(Box::new(measure));
        Ok(self.names.len() - 1)
    }

    /// The names, in order.
    #[must_use]
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Number of measures.
    #[must_use]
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Whether the set is empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }
}

impl<S: HybridJacobians + ?Sized> MeasureSet<'_, S> {
    /// The values of all measures on `orbit` (a full orbit or a half orbit).
    ///
    /// # Errors
    /// A measure that fails, or a failing scan.
    pub fn evaluate(&self, system: &S, orbit: &PeriodicOrbit) -> Result<Vec<f64>> {
        self.evaluate_indices(system, orbit, 0..self.measures.len())
    }

    /// The value of measure `index` alone (only its own needs are scanned).
    ///
    /// # Errors
    /// As [`MeasureSet::evaluate`]; an index out of range.
    pub fn evaluate_one(&self, system: &S, orbit: &PeriodicOrbit, index: usize) -> Result<f64> {
        if index >= self.measures.len() {
            return Err(Error::InvalidMeasure {
                reason: format!("measure {index} does not exist ({} measures)", self.len()),
            });
        }
        Ok(self.evaluate_indices(system, orbit, index..=index)?[0])
    }

    /// The value of measure `index` and its exact gradient with respect to the orbit's
    /// coordinates ([`Measure::gradient`]); no gradient for a half orbit that had to be
    /// unfolded.
    ///
    /// # Errors
    /// As [`MeasureSet::evaluate_one`], and [`Error::InvalidMeasure`] for a gradient of the wrong
    /// length ([`Error::NonFinite`] for one with NaN or infinities).
    pub fn evaluate_with_gradient(
        &self,
        system: &S,
        orbit: &PeriodicOrbit,
        index: usize,
    ) -> Result<(f64, Option<Vec<f64>>)> {
        let Some((m, scanned)) = self.scanned_as_given(system, orbit, index)? else {
            return Ok((self.evaluate_one(system, orbit, index)?, None));
        };
        let value = m.value(system, orbit, &scanned)?;
        let gradient = m.gradient(system, orbit, &scanned);
        if let Some(g) = &gradient {
            let expected = orbit.starts.iter().map(Vec::len).sum::<usize>()
                + orbit.durations.len()
                + orbit.params.len();
            if g.len() != expected {
                return Err(Error::InvalidMeasure {
                    reason: format!(
                        "the gradient of measure {:?} has {} entries, the orbit has {expected} coordinates",
                        self.names[index],
                        g.len()
                    ),
                });
            }
            check_finite("measure gradient", g)?;
        }
        Ok((value, gradient))
    }

    /// Where measure `index` is attained on `orbit`, as one smooth condition
    /// ([`Measure::touch`]); `None` for a measure that is not a margin, and on a half orbit
    /// that had to be unfolded to be measured.
    ///
    /// # Errors
    /// As [`MeasureSet::evaluate_one`].
    pub fn touch(&self, system: &S, orbit: &PeriodicOrbit, index: usize) -> Result<Option<Touch>> {
        Ok(self
            .scanned_as_given(system, orbit, index)?
            .and_then(|(m, scanned)| m.touch(system, orbit, &scanned)))
    }

    /// Measure `index` and the scan of `orbit` it needs, where it is measured on the orbit as
    /// given (`None`: a half orbit it must see unfolded).
    fn scanned_as_given(
        &self,
        system: &S,
        orbit: &PeriodicOrbit,
        index: usize,
    ) -> Result<Option<(&dyn Measure<S>, OrbitScan)>> {
        let Some(m) = self.measures.get(index) else {
            return Err(Error::InvalidMeasure {
                reason: format!("measure {index} does not exist ({} measures)", self.len()),
            });
        };
        let unfold = orbit.signature.closure() == Closure::Symmetric
            && system
                .symmetry()
                .is_some_and(|sym| !m.invariant_under(system, &sym));
        if unfold {
            return Ok(None);
        }
        let needs = m.needs();
        let scanned = if needs.is_empty() {
            OrbitScan::default()
        } else {
            self.scan(system, orbit, &needs)?
        };
        Ok(Some((m.as_ref(), scanned)))
    }

    /// [`scan`] at the set's settings, with the kept simulator where it is free.
    fn scan(&self, system: &S, orbit: &PeriodicOrbit, needs: &ScanNeeds) -> Result<OrbitScan>
    where
        S: HybridJacobians,
    {
        if let Ok(mut kept) = self.scanner.try_lock() {
            if kept.is_none() {
                *kept = Some(scan_simulator(&self.settings)?);
            }
            if let Some(sim) = kept.as_mut() {
                return scan_with(sim, system, orbit, needs);
            }
        }
        scan(system, orbit, needs, &self.settings)
    }

    fn evaluate_indices(
        &self,
        system: &S,
        orbit: &PeriodicOrbit,
        indices: impl Iterator<Item = usize> + Clone,
    ) -> Result<Vec<f64>> {
        let unfolded;
        let orbit = match (orbit.signature.closure(), system.symmetry()) {
            (Closure::Symmetric, Some(sym))
                if !indices
                    .clone()
                    .all(|i| self.measures[i].invariant_under(system, &sym)) =>
            {
                unfolded = orbit.unfold_symmetric(system)?;
                &unfolded
            }
            _ => orbit,
        };
        let mut needs = ScanNeeds::default();
        for i in indices.clone() {
            needs.merge(&self.measures[i].needs());
        }
        let scanned = if needs.is_empty() {
            OrbitScan::default()
        } else {
            self.scan(system, orbit, &needs)?
        };
        indices
            .map(|i| self.measures[i].value(system, orbit, &scanned))
            .collect()
    }
}
