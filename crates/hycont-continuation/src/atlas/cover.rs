//! Growing an atlas: the first chart, new charts at uncovered vertices, neighbours, and
//! boundary charts on the edges.

use super::functions::{Test, tests, values};
use super::polygon::{HalfPlane, circumscribed, clip, outside_vertex};
use super::solver::{Basis, Solver, wdot};
use super::{Atlas, AtlasChart, AtlasEnd, AtlasSettings, AtlasStatistics, EdgeCut};
use crate::branch::BranchPoint;
use crate::error::{Error, Result};
use crate::observe::Observer;
use crate::{ContinuationProblem, PointInfo};

/// Sides of a fresh chart's polygon.
const SIDES: usize = 8;
/// A vertex counts as uncovered when it lies this far (relative) outside the chart's disc.
const SLACK: f64 = 1e-6;

/// An edge located closer than this fraction of the radius to a chart's centre cuts the
/// chart instead of making a boundary chart.
const EDGE_INSIDE: f64 = 0.1;
/// A new chart closer than this fraction of a radius to an existing chart is a duplicate
/// (e.g. an edge point located again at a corner of two edges): rejected.
const DUPLICATE: f64 = 0.05;
/// Edge cuts of one chart beyond which it is given up (the edges do not close it).
pub(super) const MAX_CUTS: usize = 4;

/// What growing from a chart gave.
enum Outcome {
    /// A new chart: its candidate, radius, and edge cut and edge for a boundary chart.
    Chart(Box<Candidate>, f64, Option<(EdgeCut, super::Edge)>),
    /// A cut of the chart by an edge through its disc.
    Cut(EdgeCut),
    /// A rejected chart: the radius shrinks.
    Reject,
}

/// A corrected solution with everything a chart needs.
#[derive(Debug, Clone)]
pub(super) struct Candidate {
    pub(super) u: Vec<f64>,
    pub(super) basis: Basis,
    pub(super) info: PointInfo,
    /// Oriented test values.
    pub(super) values: Vec<f64>,
    pub(super) iterations: usize,
}

pub(super) struct Grower<'s, 'p, 'a, P: ContinuationProblem<'a> + ?Sized> {
    pub(super) solver: Solver<'p, 'a, P>,
    pub(super) tests: Vec<Test>,
    pub(super) atlas: &'s mut Atlas,
    det_ref: f64,
}

/// Covers the two-dimensional solution manifold of `p` (two more unknowns than equations)
/// through `u0` (an approximate solution), whose free parameters are the unknowns `params`,
/// with charts (see [the module docs](super)).
///
/// # Errors
/// Invalid settings, a problem that is not two-dimensional, no solution near `u0`, a start
/// outside the bounds or refused by [`ContinuationProblem::check_start`], or a tangent plane
/// that is not two-dimensional at the start.
pub fn cover<'a, P: ContinuationProblem<'a> + ?Sized>(
    p: &mut P,
    name: &str,
    u0: &[f64],
    params: [usize; 2],
    settings: &AtlasSettings,
    observer: &mut dyn Observer,
) -> Result<Atlas> {
    settings.validate()?;
    let tests = tests(p, settings)?;
    let mut atlas = Atlas {
        name: name.to_string(),
        parameter_names: p.parameter_names(),
        monitor_names: p.monitor_names(),
        unknown_params: params,
        charts: Vec::new(),
        settings: settings.clone(),
        orientation: vec![1.0; tests.len()],
        fold_scale: 0.0,
        end: AtlasEnd::ChartLimit,
        stats: AtlasStatistics::default(),
    };
    let mut solver = Solver::new(p, params, settings.newton)?;
    if u0.len() != solver.n || u0.iter().any(|x| !x.is_finite()) {
        return Err(Error::InvalidSetting {
            name: "atlas start",
            value: u0.len() as f64,
            reason: "needs one finite value per unknown",
        });
    }
    let basis = solver.parameter_basis();
    let (u, iterations) = solver.project(u0, &basis)?;
    solver.p.check_start(&u)?;
    let mut grower = Grower {
        solver,
        tests,
        atlas: &mut atlas,
        det_ref: 0.0,
    };
    let first = grower.evaluate(u, iterations)?;
    grower.orient(first)?;
    observer.chart(&grower.atlas.charts[0], 1);
    grower.grow(observer);
    Ok(atlas)
}

/// Grows a saved `atlas` of the problem `p` further, up to `max_charts` charts in all (e.g.
/// after [`AtlasEnd::ChartLimit`]). The atlas is checked first: the problem's (its names and
/// tests), consistent in itself, every chart a solution with its tangent plane, analysis and
/// test values there (to [`crate::ANALYSIS_TOL`]; `atlas/check.rs`), so that an atlas edited
/// or written by another problem is refused, not grown from charts off the solutions.
///
/// # Errors
/// A problem that does not fit the atlas (another number of unknowns or test functions);
/// [`Error::InvalidSaved`] for an atlas that does not pass the checks.
pub fn extend<'a, P: ContinuationProblem<'a> + ?Sized>(
    p: &mut P,
    atlas: &mut Atlas,
    max_charts: usize,
    observer: &mut dyn Observer,
) -> Result<()> {
    atlas.settings.max_charts = max_charts;
    let mut grower = Grower::of_saved(p, atlas)?;
    grower.check_saved()?;
    grower.grow(observer);
    Ok(())
}

/// Checks a saved `atlas` against the problem `p` as [`extend`] does before it grows it.
///
/// # Errors
/// As [`extend`].
pub fn check<'a, P: ContinuationProblem<'a> + ?Sized>(p: &mut P, atlas: &Atlas) -> Result<()> {
    let mut copy = atlas.clone();
    Grower::of_saved(p, &mut copy)?.check_saved()
}

impl<'s, 'p, 'a, P: ContinuationProblem<'a> + ?Sized> Grower<'s, 'p, 'a, P> {
    /// The grower of a saved atlas of `p`, once its layout fits the problem.
    fn of_saved(p: &'p mut P, atlas: &'s mut Atlas) -> Result<Self> {
        atlas.settings.validate()?;
        let tests = tests(p, &atlas.settings)?;
        let solver = Solver::new(p, atlas.unknown_params, atlas.settings.newton)?;
        let fits = atlas.orientation.len() == tests.len()
            && atlas.charts.iter().all(|c| c.point.u.len() == solver.n);
        if !fits || atlas.charts.is_empty() {
            return Err(Error::InvalidSetting {
                name: "atlas",
                value: atlas.charts.len() as f64,
                reason: "does not fit the problem (unknowns or test functions differ)",
            });
        }
        let det_ref = atlas.fold_scale;
        Ok(Grower {
            solver,
            tests,
            atlas,
            det_ref,
        })
    }
}

impl<'a, P: ContinuationProblem<'a> + ?Sized> Grower<'_, '_, 'a, P> {
    pub(super) fn basis(&self, i: usize) -> Basis {
        let c = &self.atlas.charts[i];
        [c.point.tangent.clone(), c.tangent2.clone()]
    }

    /// The candidate at a point [`Solver::project`] has just converged to (`None` if its
    /// analysis fails).
    pub(super) fn evaluate_at(&mut self, u: Vec<f64>, iterations: usize) -> Option<Candidate> {
        self.evaluate(u, iterations).ok()
    }

    /// The candidate at a point [`Solver::project`] has just converged to.
    fn evaluate(&mut self, u: Vec<f64>, iterations: usize) -> Result<Candidate> {
        let basis = self.solver.tangent_plane()?;
        let info = self.solver.analyse(&u)?;
        let det = if self.tests.contains(&Test::Fold) {
            self.solver.fold_determinant()?
        } else {
            (1.0, 0.0)
        };
        let raw = values(&self.tests, &info, det, self.det_ref);
        let values = raw
            .iter()
            .zip(&self.atlas.orientation)
            .map(|(v, o)| v * o)
            .collect();
        Ok(Candidate {
            u,
            basis,
            info,
            values,
            iterations,
        })
    }

    /// Orients the tests by the first chart (inside its bounds) and makes it the atlas's
    /// first chart.
    fn orient(&mut self, mut first: Candidate) -> Result<()> {
        let det = if self.tests.contains(&Test::Fold) {
            self.solver.fold_determinant()?
        } else {
            (1.0, 0.0)
        };
        self.det_ref = det.1;
        self.atlas.fold_scale = det.1;
        let raw = values(&self.tests, &first.info, det, self.det_ref);
        for (k, (t, v)) in self.tests.iter().zip(&raw).enumerate() {
            if let Test::Bound { .. } = t {
                if *v < 0.0 {
                    return Err(Error::InvalidSetting {
                        name: "atlas start",
                        value: *v,
                        reason: "lies outside the atlas's bounds (by this much)",
                    });
                }
            } else {
                self.atlas.orientation[k] = if *v < 0.0 { -1.0 } else { 1.0 };
            }
        }
        first.values = raw
            .iter()
            .zip(&self.atlas.orientation)
            .map(|(v, o)| v * o)
            .collect();
        let r = self.atlas.settings.radius;
        self.push(first, r, None, None, Vec::new());
        Ok(())
    }

    /// Grows until every chart is closed or the chart limit is reached.
    fn grow(&mut self, observer: &mut dyn Observer) {
        // The neighbours' centres and the polygons are derived: made afresh for the charts
        // there are (a saved atlas's included).
        let start = self.atlas.charts.len();
        for i in 0..start {
            let ks = self.atlas.charts[i].neighbours.clone();
            self.atlas.charts[i].centres = ks.iter().map(|&k| self.project_centre(i, k)).collect();
            self.rebuild(i);
        }
        loop {
            let Some(i) = self.atlas.charts.iter().position(|c| c.open) else {
                self.atlas.end = AtlasEnd::Covered;
                break;
            };
            if self.atlas.charts.len() >= self.atlas.settings.max_charts {
                self.atlas.end = AtlasEnd::ChartLimit;
                break;
            }
            if observer.stop() {
                self.atlas.end = AtlasEnd::Stopped;
                break;
            }
            let c = &self.atlas.charts[i];
            let Some(v) = outside_vertex(&c.polygon, c.radius, SLACK) else {
                self.atlas.charts[i].open = false;
                continue;
            };
            let (r, d) = (c.radius, v[0].hypot(v[1]));
            let s = [r * v[0] / d, r * v[1] / d];
            match self.attempt(i, s) {
                Outcome::Chart(cand, radius, edge) => {
                    let (cuts, edge) = edge.map_or((Vec::new(), None), |(c, e)| (vec![c], Some(e)));
                    let j = self.push(*cand, radius, Some(i), edge, cuts);
                    observer.chart(&self.atlas.charts[j], j + 1);
                }
                Outcome::Cut(cut) => {
                    let c = &mut self.atlas.charts[i];
                    c.cuts.push(cut);
                    if c.cuts.len() > MAX_CUTS {
                        c.gave_up = true;
                    }
                    self.rebuild(i);
                }
                Outcome::Reject => self.shrink(i),
            }
        }
        self.atlas.stats.corrections = self.solver.corrections;
        self.atlas.stats.factorisations = self.solver.factorisations;
        self.atlas.restore_keys();
    }

    /// The solution in the normal space of chart `i`'s tangent plane at $u_i + T_i s$.
    pub(super) fn solve_at(&mut self, i: usize, s: [f64; 2]) -> Option<(Candidate, f64)> {
        let basis = self.basis(i);
        let u_i = &self.atlas.charts[i].point.u;
        let pred: Vec<f64> = (0..u_i.len())
            .map(|n| u_i[n] + basis[0][n] * s[0] + basis[1][n] * s[1])
            .collect();
        let (u, it) = self.solver.project(&pred, &basis).ok()?;
        let cand = self.evaluate(u, it).ok()?;
        let diff: Vec<f64> = cand.u.iter().zip(&pred).map(|(a, b)| a - b).collect();
        let moved = wdot(&self.solver.w, &diff, &diff).sqrt();
        Some((cand, moved))
    }

    /// The cosine of the largest principal angle between chart `i`'s tangent plane and
    /// `basis`: the smaller singular value of $T_i^\top W T$.
    pub(super) fn plane_cosine(&self, i: usize, basis: &Basis) -> f64 {
        let ti = self.basis(i);
        let w = &self.solver.w;
        let m = |a: usize, b: usize| wdot(w, &ti[a], &basis[b]);
        let (a, b, c, d) = (m(0, 0), m(0, 1), m(1, 0), m(1, 1));
        // Eigenvalues of M^T M: (tr -+ sqrt(tr^2 - 4 det^2)) / 2.
        let tr = a * a + b * b + c * c + d * d;
        let det = a * d - b * c;
        let disc = (tr * tr - 4.0 * det * det).max(0.0).sqrt();
        (0.5 * (tr - disc)).max(0.0).sqrt()
    }

    /// A new chart from chart `i` toward `s` (|s| its radius), or a cut of chart `i` by an
    /// edge close to its centre, or a rejection.
    fn attempt(&mut self, i: usize, s: [f64; 2]) -> Outcome {
        let set = self.atlas.settings.clone();
        let r = self.atlas.charts[i].radius;
        let Some((cand, moved)) = self.solve_at(i, s) else {
            return Outcome::Reject;
        };
        let cosine = self.plane_cosine(i, &cand.basis);
        if moved > set.max_correction * r || cosine < set.max_angle.cos() {
            return Outcome::Reject;
        }
        if cand.values.iter().all(|&v| v >= 0.0) {
            if self.duplicate(&cand.u, r) {
                return Outcome::Reject;
            }
            let easy = cand.iterations <= 3
                && moved <= 0.25 * set.max_correction * r
                && cosine >= (0.5 * set.max_angle).cos();
            let radius = if easy {
                (r * set.growth).min(set.max_radius)
            } else {
                r
            };
            return Outcome::Chart(Box::new(cand), radius, None);
        }
        let Some((at, edge_point, k)) = self.edge_point(i, s, &cand) else {
            return Outcome::Reject;
        };
        self.atlas.stats.located += 1;
        if at < EDGE_INSIDE * r {
            // The edge crosses chart i's disc near its centre: a chart there would hardly
            // differ from chart i; the edge's line cuts chart i instead.
            let own = self.own_candidate(i);
            return match self.cut(&own, k, r) {
                Some(cut) => Outcome::Cut(cut),
                None => Outcome::Reject,
            };
        }
        if self.duplicate(&edge_point.u, r) {
            return Outcome::Reject;
        }
        match self.cut(&edge_point, k, r) {
            Some(cut) => Outcome::Chart(Box::new(edge_point), r, Some((cut, self.tests[k].edge()))),
            None => Outcome::Reject,
        }
    }

    /// Whether `u` lies within [`DUPLICATE`] radii (the smaller of `r` and the chart's) of an
    /// existing chart.
    fn duplicate(&self, u: &[f64], r: f64) -> bool {
        let w = &self.solver.w;
        self.atlas.charts.iter().any(|c| {
            let near = DUPLICATE * r.min(c.radius);
            let dp: f64 = (self.solver.params.iter())
                .map(|&n| w[n] * (u[n] - c.point.u[n]).powi(2))
                .sum();
            dp < near * near && {
                let d: f64 = (0..u.len())
                    .map(|n| w[n] * (u[n] - c.point.u[n]).powi(2))
                    .sum();
                d < near * near
            }
        })
    }

    /// Chart `i` as a candidate (to cut it by an edge).
    pub(super) fn own_candidate(&self, i: usize) -> Candidate {
        let c = &self.atlas.charts[i];
        Candidate {
            u: c.point.u.clone(),
            basis: self.basis(i),
            info: crate::PointInfo::default(),
            values: c.tests.clone(),
            iterations: 0,
        }
    }

    /// Appends a chart made from `cand` and connects it to its neighbours; its index.
    fn push(
        &mut self,
        cand: Candidate,
        radius: f64,
        parent: Option<usize>,
        edge: Option<super::Edge>,
        cuts: Vec<EdgeCut>,
    ) -> usize {
        let step = parent.map_or(0.0, |p| self.atlas.charts[p].radius);
        let [t0, t1] = cand.basis;
        let point = BranchPoint::from_info(&cand.info, cand.u, t0, cand.iterations, step);
        self.atlas.charts.push(AtlasChart {
            point,
            tangent2: t1,
            radius,
            polygon: Vec::new(),
            cuts,
            edge,
            neighbours: Vec::new(),
            centres: Vec::new(),
            parent,
            open: true,
            gave_up: false,
            tests: cand.values,
        });
        let j = self.atlas.charts.len() - 1;
        self.connect(j);
        j
    }

    /// Chart `k`'s centre in chart `i`'s tangent coordinates.
    fn project_centre(&self, i: usize, k: usize) -> [f64; 2] {
        let (ci, ck) = (&self.atlas.charts[i], &self.atlas.charts[k]);
        let d: Vec<f64> = ck
            .point
            .u
            .iter()
            .zip(&ci.point.u)
            .map(|(a, b)| a - b)
            .collect();
        let w = &self.solver.w;
        [wdot(w, &ci.point.tangent, &d), wdot(w, &ci.tangent2, &d)]
    }

    /// Finds chart `j`'s neighbours (discs that meet) and rebuilds both sides' polygons.
    fn connect(&mut self, j: usize) {
        let w = self.solver.w.clone();
        let params = self.solver.params;
        let rj = self.atlas.charts[j].radius;
        let mut found = Vec::new();
        for k in 0..j {
            let (cj, ck) = (&self.atlas.charts[j], &self.atlas.charts[k]);
            let reach = rj + ck.radius;
            // The parameters' part of the distance is a lower bound of the whole.
            let dp: f64 = params
                .iter()
                .map(|&n| w[n] * (cj.point.u[n] - ck.point.u[n]).powi(2))
                .sum();
            if dp.sqrt() >= reach {
                continue;
            }
            let d: Vec<f64> = cj
                .point
                .u
                .iter()
                .zip(&ck.point.u)
                .map(|(a, b)| a - b)
                .collect();
            if wdot(&w, &d, &d).sqrt() < reach {
                found.push(k);
            }
        }
        for &k in &found {
            // The new neighbour only cuts chart k's polygon further.
            let centre = self.project_centre(k, j);
            let c = &mut self.atlas.charts[k];
            c.neighbours.push(j);
            c.centres.push(centre);
            c.polygon = clip(&c.polygon, &HalfPlane::against(centre, c.radius, rj));
            c.open = c.open && outside_vertex(&c.polygon, c.radius, SLACK).is_some();
        }
        let centres = found.iter().map(|&k| self.project_centre(j, k)).collect();
        let c = &mut self.atlas.charts[j];
        c.neighbours = found;
        c.centres = centres;
        self.rebuild(j);
    }

    /// Recomputes chart `i`'s polygon from its radius, cuts and neighbours, and whether it
    /// is open.
    fn rebuild(&mut self, i: usize) {
        let c = &self.atlas.charts[i];
        let r = c.radius;
        let mut poly = circumscribed(r, SIDES);
        for cut in &c.cuts {
            poly = clip(&poly, &cut.line);
        }
        for (&k, &centre) in c.neighbours.iter().zip(&c.centres) {
            let rk = self.atlas.charts[k].radius;
            poly = clip(&poly, &HalfPlane::against(centre, r, rk));
        }
        let open = !c.gave_up && outside_vertex(&poly, r, SLACK).is_some();
        let c = &mut self.atlas.charts[i];
        c.polygon = poly;
        c.open = open;
    }

    /// Halves chart `i`'s radius after a rejected chart (gives the chart up below the
    /// smallest radius) and rebuilds it and its neighbours.
    fn shrink(&mut self, i: usize) {
        self.atlas.stats.rejected += 1;
        let min = self.atlas.settings.min_radius;
        let c = &mut self.atlas.charts[i];
        if 0.5 * c.radius < min {
            c.gave_up = true;
            c.open = false;
            return;
        }
        c.radius *= 0.5;
        let neighbours = c.neighbours.clone();
        self.rebuild(i);
        for k in neighbours {
            self.rebuild(k);
        }
    }
}
