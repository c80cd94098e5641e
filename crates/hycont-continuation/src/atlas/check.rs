//! Re-checking a saved atlas before it grows further ([`super::extend`]): the atlas is the
//! problem's (its parameter and monitor names, its tests), its charts are consistent in
//! themselves (radii within the settings, neighbours symmetric and complete, parents earlier,
//! edges and cuts of its tests), and every chart is what it says: a solution of the problem
//! with its tangent plane, analysis and test values there.

use super::cover::Grower;
use super::functions::values;
use super::solver::wdot;
use crate::ContinuationProblem;
use crate::error::{Error, Result};
use crate::recheck::{ANALYSIS_TOL, check_multipliers_within, close, same_values};

impl<'a, P: ContinuationProblem<'a> + ?Sized> Grower<'_, '_, 'a, P> {
    /// Checks the saved atlas against the problem (see the module docs). The work is not
    /// counted in the atlas's statistics.
    pub(super) fn check_saved(&mut self) -> Result<()> {
        let (corrections, factorisations) = (self.solver.corrections, self.solver.factorisations);
        self.check_layout().map_err(invalid)?;
        for i in 0..self.atlas.charts.len() {
            self.check_chart(i)
                .map_err(|reason| invalid(format!("chart {i}: {reason}")))?;
        }
        self.solver.corrections = corrections;
        self.solver.factorisations = factorisations;
        Ok(())
    }

    /// Names, orientation, radii, parents, neighbours, edges and cuts.
    fn check_layout(&self) -> std::result::Result<(), String> {
        let a = &*self.atlas;
        let p = &*self.solver.p;
        if a.parameter_names != p.parameter_names() || a.monitor_names != p.monitor_names() {
            return Err(format!(
                "it names the parameters {:?} and monitors {:?}, the problem {:?} and {:?}",
                a.parameter_names,
                a.monitor_names,
                p.parameter_names(),
                p.monitor_names()
            ));
        }
        if a.orientation.iter().any(|o| o.abs() != 1.0) || !a.fold_scale.is_finite() {
            return Err("its test orientations are not +-1, or its fold scale not finite".into());
        }
        let s = &a.settings;
        let edges: Vec<super::Edge> = self.tests.iter().map(|t| t.edge()).collect();
        let n = a.charts.len();
        for (i, c) in a.charts.iter().enumerate() {
            let at = |r: String| format!("chart {i}: {r}");
            if !(c.radius >= s.min_radius && c.radius <= s.max_radius) {
                return Err(at(format!(
                    "radius {} outside the settings' [{}, {}]",
                    c.radius, s.min_radius, s.max_radius
                )));
            }
            if (i == 0) != c.parent.is_none() || c.parent.is_some_and(|k| k >= i) {
                return Err(at(format!("parent {:?} is not an earlier chart", c.parent)));
            }
            if !radius_fits(c.radius, c.point.step, c.parent.is_none(), s) {
                return Err(at(format!(
                    "radius {} is not one it could have grown to from its parent's {}",
                    c.radius, c.point.step
                )));
            }
            let mut sorted = c.neighbours.clone();
            sorted.sort_unstable();
            sorted.dedup();
            let symmetric = c
                .neighbours
                .iter()
                .all(|&k| k < n && k != i && a.charts[k].neighbours.contains(&i));
            if sorted.len() != c.neighbours.len() || !symmetric {
                return Err(at(format!(
                    "neighbours {:?} are not mutual charts",
                    c.neighbours
                )));
            }
            // A chart is given up when its radius would fall below the smallest, or when
            // more edges than MAX_CUTS cut it.
            let too_small = 0.5 * c.radius < s.min_radius;
            let too_cut = c.cuts.len() > super::cover::MAX_CUTS;
            if c.gave_up != (too_cut || (c.gave_up && too_small)) {
                return Err(at(format!(
                    "it says it was{} given up, with radius {} and {} cuts",
                    if c.gave_up { "" } else { " not" },
                    c.radius,
                    c.cuts.len()
                )));
            }
            // A boundary chart is made with the cut of its edge, first.
            let first_cut = c.cuts.first().and_then(|h| edges.get(h.test));
            if c.edge
                .is_some_and(|e| !edges.contains(&e) || first_cut != Some(&e))
            {
                return Err(at(format!(
                    "edge {:?} is none of the atlas's, or not its first cut's",
                    c.edge
                )));
            }
            let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
            if c.cuts.iter().any(|h| {
                !(finite(&h.line.normal)
                    && h.line.offset.is_finite()
                    && h.test < self.tests.len()
                    && h.radius > 0.0
                    && h.radius.is_finite())
            }) || c.tests.len() != self.tests.len()
                || c.tests.iter().any(|v| !(*v >= 0.0))
            {
                return Err(at(
                    "its cuts are not lines, or its tests are not one non-negative value per test"
                        .into(),
                ));
            }
        }
        self.check_neighbourhood()
    }

    /// Charts whose discs meet are neighbours (a chart's disc only shrinks after it is
    /// connected, so discs that meet now met then).
    fn check_neighbourhood(&self) -> std::result::Result<(), String> {
        let (a, w, params) = (&*self.atlas, &self.solver.w, self.solver.params);
        for (i, ci) in a.charts.iter().enumerate() {
            if ci.point.u.len() != self.solver.n || ci.point.u.iter().any(|x| !x.is_finite()) {
                return Err(format!("chart {i}'s unknowns do not fit the problem"));
            }
            for (k, ck) in a.charts.iter().enumerate().take(i) {
                let reach = (ci.radius + ck.radius) * (1.0 - 1e-9);
                let dp: f64 = params
                    .iter()
                    .map(|&n| w[n] * (ci.point.u[n] - ck.point.u[n]).powi(2))
                    .sum();
                if dp.sqrt() >= reach || ci.neighbours.contains(&k) {
                    continue;
                }
                let d: Vec<f64> = ci
                    .point
                    .u
                    .iter()
                    .zip(&ck.point.u)
                    .map(|(x, y)| x - y)
                    .collect();
                if wdot(w, &d, &d).sqrt() < reach {
                    return Err(format!("charts {k} and {i} overlap but are not neighbours"));
                }
            }
        }
        Ok(())
    }

    /// Chart `i` is a solution (the corrector from it stays there), with its tangent plane,
    /// analysis and oriented test values.
    fn check_chart(&mut self, i: usize) -> std::result::Result<(), String> {
        let c = &self.atlas.charts[i];
        let saved = [c.point.tangent.clone(), c.tangent2.clone()];
        let w = &self.solver.w;
        let gram = [
            wdot(w, &saved[0], &saved[0]) - 1.0,
            wdot(w, &saved[1], &saved[1]) - 1.0,
            wdot(w, &saved[0], &saved[1]),
        ];
        if gram.iter().any(|g| !(g.abs() <= ANALYSIS_TOL)) {
            return Err("its tangent vectors are not orthonormal".into());
        }
        let u = c.point.u.clone();
        let residual = (self.solver.factor_at(&u, &saved)).map_err(|e| e.to_string())?;
        let scale = 1.0 + u.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if !(residual <= crate::POINT_RESIDUAL_TOL * scale) {
            return Err(format!(
                "it is not a solution of the problem (residual {residual:e})"
            ));
        }
        let plane = self.solver.tangent_plane().map_err(|e| e.to_string())?;
        let cosine = self.plane_cosine(i, &plane);
        if !(cosine >= 1.0 - ANALYSIS_TOL) {
            return Err(format!(
                "its tangent plane is not the solutions' there (cosine {cosine})"
            ));
        }
        let info = self.solver.analyse(&u).map_err(|e| e.to_string())?;
        let det = if self.tests.contains(&super::functions::Test::Fold) {
            self.solver.fold_determinant().map_err(|e| e.to_string())?
        } else {
            (1.0, 0.0)
        };
        let c = &self.atlas.charts[i];
        let p = &c.point;
        if !same_values(&p.params, &info.params, 1e-12)
            || !same_values(&p.monitors, &info.monitors, ANALYSIS_TOL)
        {
            return Err(format!(
                "its parameters {:?} and monitors {:?} are not its solution's {:?}, {:?}",
                p.params, p.monitors, info.params, info.monitors
            ));
        }
        check_multipliers_within(p, &info, || {
            self.solver.p.analyse_afresh(&u).map_err(|e| e.to_string())
        })?;
        let tests = values(&self.tests, &info, det, self.atlas.fold_scale);
        let agree = tests
            .iter()
            .zip(&self.atlas.orientation)
            .zip(&c.tests)
            .all(|((v, o), saved)| close(v * o, *saved, ANALYSIS_TOL));
        if !agree {
            return Err(format!(
                "its test values {:?} are not its solution's",
                c.tests
            ));
        }
        self.check_cuts(i)
    }
}

impl<'a, P: ContinuationProblem<'a> + ?Sized> Grower<'_, '_, 'a, P> {
    /// Chart `i`'s cuts made again from it, with their tests and radii.
    fn check_cuts(&mut self, i: usize) -> std::result::Result<(), String> {
        let own = self.own_candidate(i);
        for cut in self.atlas.charts[i].cuts.clone() {
            let again = self.cut(&own, cut.test, cut.radius);
            let same = again.is_some_and(|a| {
                let l = (a.line, cut.line);
                close(l.0.normal[0], l.1.normal[0], ANALYSIS_TOL)
                    && close(l.0.normal[1], l.1.normal[1], ANALYSIS_TOL)
                    && close(l.0.offset, l.1.offset, ANALYSIS_TOL)
            });
            if !same {
                return Err(format!(
                    "its cut {:?} is not the edge's line there ({again:?})",
                    cut.line
                ));
            }
        }
        Ok(())
    }
}

/// Whether a chart's radius is one the atlas gives: its radius when made (the settings' first
/// radius for the first chart; else its parent's radius then, `step`, grown by the settings'
/// factor up to the largest radius, or kept) halved a whole number of times.
fn radius_fits(radius: f64, step: f64, first: bool, s: &super::AtlasSettings) -> bool {
    let made: &[f64] = if first {
        &[s.radius]
    } else {
        &[step, (step * s.growth).min(s.max_radius)]
    };
    made.iter().any(|&r0| {
        let halvings = (r0 / radius).log2();
        halvings >= -1e-9 && (halvings - halvings.round()).abs() <= 1e-9
    })
}

fn invalid(reason: String) -> Error {
    Error::InvalidSaved {
        what: "atlas",
        reason,
    }
}
