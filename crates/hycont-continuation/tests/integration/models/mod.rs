//! Continuation problems with exactly known answers, for `closed_form.rs` (a module, not a
//! test target, so that other test files can share it): a dense zero function of given
//! residuals ([`Dense`]) inside a [`Test`] continuation problem whose analysis gives the
//! multipliers of a map, and the models with their closed forms.
#![allow(dead_code)] // each test file uses part of it

use hycont_continuation::observe::Silent;
use hycont_continuation::{
    ContinuationProblem, ContinuationSettings, MonitorEvent, PointInfo, continue_branch,
};
use hycont_core::problem::{Activity, Problem, UnknownMonitor, ZeroFunction};

pub type Residual = fn(&[f64], &mut [f64], Option<&mut [f64]>);

/// A zero function of all unknowns given by a function pointer (dense pattern).
pub struct Dense {
    pub unknowns: usize,
    pub equations: usize,
    pub f: Residual,
}

impl ZeroFunction for Dense {
    fn unknowns(&self) -> usize {
        self.unknowns
    }
    fn equations(&self) -> usize {
        self.equations
    }
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        (0..self.equations)
            .flat_map(|r| (0..self.unknowns).map(move |c| (r, c)))
            .collect()
    }
    fn evaluate(
        &mut self,
        u: &[f64],
        r: &mut [f64],
        j: Option<&mut [f64]>,
    ) -> hycont_core::Result<()> {
        (self.f)(u, r, j);
        Ok(())
    }
}

/// A test problem: unknowns `u[..dim]` (state), `u[dim]` the parameter; `analyse` computes the
/// multipliers of a map from the state.
pub struct Test {
    pub problem: Problem<'static>,
    pub dim: usize,
    pub multipliers: fn(&[f64]) -> Vec<(f64, f64)>,
    pub events: Vec<MonitorEvent>,
    pub fail_above: f64,
    pub weights: Option<Vec<f64>>,
    pub bp_factor: Option<fn(&[f64]) -> f64>,
    /// `end_among`'s choice among coinciding terminal events (default: the trait's, 0).
    pub end_choice: Option<fn(&[MonitorEvent]) -> usize>,
    /// What `end_among` was asked: the parameter at the point and the events' kinds.
    pub asked: Vec<(f64, Vec<hycont_continuation::SpecialKind>)>,
}

impl Test {
    pub fn new(dim: usize, f: Residual, multipliers: fn(&[f64]) -> Vec<(f64, f64)>) -> Self {
        let mut problem = Problem::new(dim + 1);
        problem
            .add_part(
                Box::new(Dense {
                    unknowns: dim + 1,
                    equations: dim,
                    f,
                }),
                (0..=dim).collect(),
            )
            .unwrap();
        problem
            .add_monitor(
                "p",
                Box::new(UnknownMonitor),
                vec![dim],
                Activity::Active(0.0),
            )
            .unwrap();
        Self {
            problem,
            dim,
            multipliers,
            events: Vec::new(),
            fail_above: f64::INFINITY,
            weights: None,
            bp_factor: None,
            end_choice: None,
            asked: Vec::new(),
        }
    }
    /// u0 = (state, parameter, active monitor value = parameter).
    pub fn start(&self, state: &[f64], p: f64) -> Vec<f64> {
        let mut u = state.to_vec();
        u.push(p);
        u.push(p);
        u
    }
}

impl ContinuationProblem<'static> for Test {
    fn problem(&mut self) -> &mut Problem<'static> {
        &mut self.problem
    }
    fn parameter_index(&self) -> usize {
        self.dim
    }
    fn parameter_position(&self) -> usize {
        0
    }
    fn parameter_name(&self) -> String {
        "p".into()
    }
    fn parameter_names(&self) -> Vec<String> {
        vec!["p".into()]
    }
    fn monitor_names(&self) -> Vec<String> {
        vec!["x".into()]
    }
    fn analyse(&mut self, u: &[f64]) -> hycont_core::Result<PointInfo> {
        if u[self.dim] > self.fail_above {
            return Err(hycont_core::Error::NotPeriodic {
                reason: "deliberate failure".into(),
            });
        }
        let m = (self.multipliers)(u);
        Ok(PointInfo {
            params: vec![u[self.dim]],
            monitors: vec![u[0]],
            trivial: vec![false; m.len()],
            multipliers: m,
            branch_point_factor: self.bp_factor.map(|f| f(u)),
            discretisation_error: None,
        })
    }
    fn monitor_events(&self) -> Vec<MonitorEvent> {
        self.events.clone()
    }
    fn end_among(&mut self, u: &[f64], located: &[MonitorEvent]) -> usize {
        self.asked
            .push((u[self.dim], located.iter().map(|e| e.kind).collect()));
        self.end_choice.map_or(0, |choose| choose(located))
    }
    fn unknown_weights(&self) -> Option<Vec<f64>> {
        self.weights.clone()
    }
}

pub fn no_multipliers(_: &[f64]) -> Vec<(f64, f64)> {
    Vec::new()
}

pub fn parabola(u: &[f64], r: &mut [f64], j: Option<&mut [f64]>) {
    r[0] = u[0] * u[0] - u[1];
    if let Some(j) = j {
        j[0] = 2.0 * u[0];
        j[1] = -1.0;
    }
}

pub fn pitchfork(u: &[f64], r: &mut [f64], j: Option<&mut [f64]>) {
    r[0] = u[0].powi(3) - u[1] * u[0];
    if let Some(j) = j {
        j[0] = 3.0 * u[0] * u[0] - u[1];
        j[1] = -u[0];
    }
}

/// Fixed points of the logistic map x -> r x (1 - x): x = 1 - 1/r, multiplier 2 - r.
pub fn logistic(u: &[f64], res: &mut [f64], j: Option<&mut [f64]>) {
    let (x, r) = (u[0], u[1]);
    res[0] = r * x * (1.0 - x) - x;
    if let Some(j) = j {
        j[0] = r * (1.0 - 2.0 * x) - 1.0;
        j[1] = x * (1.0 - x);
    }
}

pub fn logistic_multiplier(u: &[f64]) -> Vec<(f64, f64)> {
    vec![(u[1] * (1.0 - 2.0 * u[0]), 0.0)]
}

/// Fixed points of the delayed logistic map (x, y) -> (y, r y (1 - x)): x = y = 1 - 1/r; the
/// Jacobian [[0, 1], [-r y, r (1 - x)]] has determinant r - 1: a torus point at r = 2.
pub fn delayed_logistic(u: &[f64], res: &mut [f64], j: Option<&mut [f64]>) {
    let (x, y, r) = (u[0], u[1], u[2]);
    res[0] = y - x;
    res[1] = r * y * (1.0 - x) - y;
    if let Some(j) = j {
        // Row-major over the dense pattern: d/dx, d/dy, d/dr for each equation.
        j.copy_from_slice(&[-1.0, 1.0, 0.0, -r * y, r * (1.0 - x) - 1.0, y * (1.0 - x)]);
    }
}

pub fn delayed_logistic_multipliers(u: &[f64]) -> Vec<(f64, f64)> {
    let (x, y, r) = (u[0], u[1], u[2]);
    let a = [0.0, -r * y, 1.0, r * (1.0 - x)];
    hycont_core::linalg::eigenvalues(2, &a).unwrap()
}

/// The branch x^2 = l from (x, l) = (1, 1), continued towards decreasing l.
pub fn parabola_down(t: &mut Test, s: &ContinuationSettings) -> hycont_continuation::Branch {
    let u0 = t.start(&[1.0], 1.0);
    continue_branch(t, "parabola", &u0, -1.0, s, &mut Silent).unwrap()
}

pub fn settings() -> ContinuationSettings {
    ContinuationSettings::default().steps(0.01, 1e-8, 0.05)
}
