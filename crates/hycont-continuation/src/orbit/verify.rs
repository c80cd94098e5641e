//! Re-checking the points of a saved branch: each is an orbit of the system (its orbit
//! equations hold) and, where asked, a physical one (admissible).

use super::problem::OrbitContinuation;
use super::run::OrbitRun;
use super::saved::OrbitBranch;
use crate::ContinuationProblem;
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

impl<S: HybridJacobians + ?Sized> OrbitRun<'_, S> {
    /// Re-checks a saved one-parameter branch (e.g. read from a file) before this run uses
    /// it: written for this system (its parameter names) and continued in this run's
    /// parameter with this run's measures (monitor names); every point an orbit
    /// ([`OrbitBranch::check_points`], admissible when the run's admissibility is on), whose
    /// parameters are those of its unknowns and whose monitors, multipliers and stability are
    /// what this run's analysis gives at its unknowns again (to [`crate::ANALYSIS_TOL`] relative),
    /// and whose tangent is in the null space of the Jacobian there ($|J t|$ at most
    /// [`crate::ANALYSIS_TOL`] of $\max_i \sum_j |J_{ij} t_j|$; a branch point's, the tangent of the
    /// chart before it, at most a tenth); points labelled in order along the branch, special
    /// points after them.
    ///
    /// # Errors
    /// [`Error::InvalidSaved`] naming what does not fit; [`Error::InvalidPoint`] naming the
    /// first point that is not what it says.
    pub fn check_saved(&self, saved: &OrbitBranch) -> Result<()> {
        let what = "branch";
        let invalid = |reason: String| Error::InvalidSaved { what, reason };
        saved.validate(self.system)?;
        let b = &saved.branch;
        if saved.second.is_some() || saved.condition.is_some() {
            return Err(invalid(format!(
                "{} is a two-parameter curve, not a branch",
                b.name
            )));
        }
        if saved.free != self.free {
            return Err(invalid(format!(
                "{} was continued in parameter {}, this run continues {}",
                b.name,
                saved.free.index(),
                self.free.index()
            )));
        }
        let names: Vec<String> = self
            .system
            .parameter_names()
            .iter()
            .map(|n| (*n).to_string())
            .collect();
        if b.parameter_names != names || b.parameter_index != self.free.index() {
            return Err(invalid(format!(
                "{} names the parameters {:?} (continued: {}), the system {names:?}",
                b.name, b.parameter_names, b.parameter_index
            )));
        }
        check_labels(b).map_err(|r| invalid(format!("{}: {r}", b.name)))?;
        let monitors = self.monitor_names_of(saved)?;
        if b.monitor_names != monitors {
            return Err(invalid(format!(
                "{} records the measures {:?}, this run {monitors:?}",
                b.name, b.monitor_names
            )));
        }
        saved.check_points(self.system, self.admissibility_on())?;
        self.check_analyses(saved)
    }

    /// The monitor names of a run of this one on `saved`'s layout.
    fn monitor_names_of(&self, saved: &OrbitBranch) -> Result<Vec<String>> {
        let cp = OrbitContinuation::on_discretisation(
            self.system,
            saved.template.clone(),
            saved.discretisation.clone(),
            self.free,
            self.measures.clone(),
            self.events.clone(),
        )?;
        Ok(cp.monitor_names())
    }
}

/// Points labelled `1..=n` in order, special points `n + 1..` after them (as a run labels
/// them, [`crate::Branch::relabel`]).
fn check_labels(b: &crate::Branch) -> std::result::Result<(), String> {
    let n = b.points.len();
    if n == 0 {
        return Err("the branch has no points".into());
    }
    let labels = b
        .points
        .iter()
        .chain(b.special_points.iter().map(|s| &s.point))
        .map(|p| p.label);
    match labels.enumerate().find(|(i, l)| *l != i + 1) {
        Some((i, l)) => Err(format!(
            "its labels are not in order (label {l} at position {})",
            i + 1
        )),
        None => Ok(()),
    }
}
