//! Re-checking the points of a saved branch: each is an orbit of the system (its orbit
//! equations hold) and, where asked, a physical one (admissible).

use super::saved::OrbitBranch;
use crate::codim2::CurveCondition;
use crate::error::{Error, Result};
use hycont_core::HybridJacobians;
use hycont_core::orbit::check_admissible_collapsed;

/// The largest residual of the orbit equations a point may have, relative to
/// $1 + \max_i |u_i|$: far above what the corrector leaves (its steps end below $10^{-10}$),
/// far below any orbit that does not close.
pub const POINT_RESIDUAL_TOL: f64 = 1e-6;

impl OrbitBranch {
    /// Re-checks every point of the branch (regular and special) against `system`: the
    /// layout fits ([`OrbitBranch::validate`]), the point's unknowns solve the orbit equations
    /// of its discretisation (largest residual at most [`POINT_RESIDUAL_TOL`] times
    /// $1 + \max |u|$), and, with `admissible`, its orbit is admissible
    /// ([`hycont_core::orbit::check_admissible`]; on a curve held by a collapsed segment, that
    /// segment's zero duration is allowed). A branch of an [`crate::OrbitRun`] with its
    /// admissibility on passes with `admissible`; one run with it off may not.
    ///
    /// # Errors
    /// As [`OrbitBranch::validate`]; [`Error::InvalidPoint`] naming the first point that fails
    /// and why.
    pub fn check_points<S: HybridJacobians + ?Sized>(
        &self,
        system: &S,
        admissible: bool,
    ) -> Result<()> {
        self.validate(system)?;
        let collapsed: Vec<usize> = match self.condition {
            Some(CurveCondition::Collapse { segment }) => {
                // On a half-orbit curve the segment's image has collapsed as well.
                let half = self.template.segment_count() / 2;
                vec![segment, segment + half]
            }
            _ => Vec::new(),
        };
        let bad = |label: usize, reason: String| Error::InvalidPoint {
            label,
            branch: self.branch.name.clone(),
            reason,
        };
        let points = self
            .branch
            .points
            .iter()
            .chain(self.branch.special_points.iter().map(|s| &s.point));
        // The equations of each discretisation revision, built once.
        let mut equations: Vec<Option<Box<dyn hycont_core::orbit::OrbitEquations + '_>>> =
            (0..=self.rediscretised.len()).map(|_| None).collect();
        for p in points {
            let disc = self.discretisation_of(p)?;
            let eq = match &mut equations[p.discretisation] {
                Some(eq) => eq,
                slot => slot.insert(disc.equations(system, &self.template, None)?),
            };
            let base = eq.unknowns();
            let mut residual = vec![0.0; eq.equations()];
            eq.evaluate(&p.u[..base], &mut residual, None)?;
            let scale = 1.0 + p.u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let (row, worst) = residual.iter().enumerate().fold((0, 0.0f64), |m, (i, r)| {
                if r.abs() > m.1 { (i, r.abs()) } else { m }
            });
            if !(worst <= POINT_RESIDUAL_TOL * scale) {
                return Err(bad(
                    p.label,
                    format!("its orbit equations do not hold (residual {worst:e} in row {row})"),
                ));
            }
            if admissible {
                let orbit = disc.unpack(&self.template, &p.u);
                if let Err(e) = check_admissible_collapsed(system, &orbit, &collapsed) {
                    return Err(bad(p.label, format!("its orbit is not admissible: {e}")));
                }
            }
        }
        Ok(())
    }
}
