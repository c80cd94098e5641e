//! The orbits that break a $\mathbb{Z}_2$ symmetry, reached by continuation: from a symmetric
//! orbit to the branch point where its symmetry breaks, then along the asymmetric branch born
//! there to a parameter value. Unstable asymmetric orbits, which no simulation settles on, are
//! found this way.

use super::run::{OrbitRun, RunDirection};
use crate::branch::SpecialKind;
use crate::error::Result;
use hycont_core::HybridJacobians;
use hycont_core::orbit::PeriodicOrbit;

impl<S: HybridJacobians + ?Sized> OrbitRun<'_, S> {
    /// The pair of mirror-image orbits at `target` of the continued parameter that break the
    /// symmetry of `symmetric`'s orbits: the symmetric orbit is continued down, then up, to the
    /// first symmetry-breaking branch point; the asymmetric branch is switched on there
    /// ([`OrbitRun::switch_at`]) and continued to `target`, where it ends on a bound; the orbit
    /// there and its image under the symmetry are returned. `None` if no branch from a branch
    /// point of the symmetric branch reaches `target` (within the run's bounds, otherwise
    /// ignored here) with an orbit that is not symmetric.
    ///
    /// # Errors
    /// An invalid start or a system without a symmetry; a failing continuation of the symmetric
    /// orbit.
    pub fn symmetry_broken_at(
        &mut self,
        symmetric: &PeriodicOrbit,
        target: f64,
    ) -> Result<Option<(PeriodicOrbit, PeriodicOrbit)>> {
        let saved = self.settings.clone();
        let found = self.search_broken(symmetric, target);
        self.settings = saved;
        found
    }

    fn search_broken(
        &mut self,
        symmetric: &PeriodicOrbit,
        target: f64,
    ) -> Result<Option<(PeriodicOrbit, PeriodicOrbit)>> {
        let q = self.free;
        self.settings.stop_at.push(SpecialKind::BranchPoint);
        let (lo, hi) = self.settings.continuation_bounds();
        for dir in [RunDirection::Down, RunDirection::Up] {
            let b = self.run("symmetric", symmetric, dir)?;
            let Some(bp) = b.special(SpecialKind::BranchPoint).find(|s| s.located) else {
                continue;
            };
            let (label, at) = (bp.point.label, bp.point[q]);
            // Up to the target, where the branch ends on its bound (or back at a branch point).
            if target > at {
                self.bounds(lo, target);
            } else {
                self.bounds(target, hi);
            }
            let switched = self.switch_at("asymmetric", &b, label, RunDirection::Up);
            self.bounds(lo, hi);
            let Ok(asym) = switched else {
                continue;
            };
            let end = asym
                .branch
                .end_point()
                .filter(|p| (p[q] - target).abs() < 1e-9);
            let Some(end) = end else {
                continue;
            };
            let found = asym.orbit_of(end)?;
            if found.is_symmetric(self.system, self.symmetry_tol) {
                continue;
            }
            let mirror = found.symmetric_image(self.system)?;
            return Ok(Some((found, mirror)));
        }
        Ok(None)
    }
}
