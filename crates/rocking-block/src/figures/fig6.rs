//! Fig. 6: two-parameter curves in the (omega, alpha) plane, stability regions, and test points
//! below the fold curve.

use super::{FigureFiles, write_json};
use crate::block::Block;
use crate::continuation::{Curve, study_curves};
use crate::error::Result;
use crate::output::OutDir;
use crate::plot;
use crate::provenance::Provenance;
use crate::simulation::{Outcome, SimulationRequest, simulate};
use hycont_continuation::SpecialKind;
use hycont_continuation::observe::Observer;
use serde_json::json;

/// The initial state of the study's test points: $(\varphi, \psi, r, s)$.
pub const TEST_STATE: [f64; 4] = [-0.2254, -0.1597, -0.7778, 0.6284];

/// Omega values of the six test points OV1-OV6 (spread along the fold curve); each is placed
/// 0.05 below the curve in alpha.
pub const TEST_OMEGAS: [f64; 6] = [0.8, 1.0, 1.4, 2.0, 2.8, 3.6];

/// A simulated test point.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TestPoint {
    /// OV1 ... OV6.
    pub label: String,
    /// Forcing frequency.
    pub omega: f64,
    /// Forcing amplitude (0.05 below the fold curve).
    pub alpha: f64,
    /// What happens from [`TEST_STATE`].
    pub outcome: Outcome,
    /// When the run ended (overturn time, or the end of the simulated window).
    pub t_end: f64,
    /// When chattering impacts accumulated and the block came to rest, if it did.
    pub rest_times: Vec<f64>,
    /// Whether a block at rest can lift off again ($\alpha\omega^2\tan\theta_b > 1$).
    pub lift_off_possible: bool,
}

/// Simulates the test points below the SN curve.
///
/// # Errors
/// If a simulation fails.
pub fn test_points(
    sn: &Curve,
    block: &Block,
) -> Result<(Vec<TestPoint>, Vec<hycont_core::Trajectory>)> {
    let mut points = Vec::new();
    let mut trajectories = Vec::new();
    for (i, &omega) in TEST_OMEGAS.iter().enumerate() {
        let Some(alpha_sn) = sn.alpha_at(omega) else {
            continue;
        };
        let params = block.at(omega, (alpha_sn - 0.05).max(0.01));
        let req = SimulationRequest {
            params,
            phi0: TEST_STATE[0],
            psi0: TEST_STATE[1],
            forcing_state: Some([TEST_STATE[2], TEST_STATE[3]]),
            periods: 30.0,
            points_per_period: 100,
            ..SimulationRequest::default()
        };
        let (report, traj) = simulate(&req)?;
        points.push(TestPoint {
            label: format!("OV{}", i + 1),
            omega,
            alpha: params.alpha,
            outcome: report.outcome,
            t_end: report.t_end,
            rest_times: report.rest_times,
            lift_off_possible: params.lift_off_possible(),
        });
        trajectories.push(traj);
    }
    Ok((points, trajectories))
}

/// A curve's JSON: its points and its user points (UZ) where it crosses alpha = 0.66 or
/// omega = 1.3, where it meets the special points of Figs. 3 and 4.
pub(crate) fn curve_json(c: &Curve) -> serde_json::Value {
    use crate::continuation::AMP;
    use crate::model::{ALPHA, OMEGA};
    let point = |p: &hycont_continuation::BranchPoint| {
        json!({"omega": p[OMEGA], "alpha": p[ALPHA], "amp": p[AMP],
               "period": p[hycont_continuation::MeasureId::PERIOD]})
    };
    let b = &c.branch.branch;
    json!({
        "kind": c.kind.label(),
        "end": format!("{:?}", b.end),
        "points": b.points.iter().map(point).collect::<Vec<_>>(),
        "special_points": b.special_points.iter().map(|s| {
            let mut v = point(&s.point);
            v["kind"] = json!(s.kind.label());
            v["located"] = json!(s.located);
            v
        }).collect::<Vec<_>>(),
    })
}

/// Writes `fig6.json` (`"curves": [{"kind", "points": [{"omega", "alpha", "amp"}]}]`, test
/// points), `fig6.svg` (the plane) and `fig6_tests.svg` (the test points' time series).
///
/// # Errors
/// Numerical or I/O failures.
pub fn figure6(
    out: &OutDir,
    provenance: &Provenance,
    observer: &mut dyn Observer,
) -> Result<FigureFiles> {
    let block = provenance.block;
    let params = block.at(1.3, 0.66);
    let curves = study_curves(&block, observer)?;
    super::stopped_by(observer, 6)?;
    // Another block may have no fold on the study's lines: then there are no test points.
    let (tests, trajectories) = match curves.iter().find(|c| c.kind == SpecialKind::Fold) {
        Some(sn) => test_points(sn, &block)?,
        None => (Vec::new(), Vec::new()),
    };
    let json = json!({
        "figure": 6,
        "parameters": {"omega": params.omega, "alpha": params.alpha, "xi": params.xi, "theta_b": params.theta_b},
        "curves": curves.iter().map(curve_json).collect::<Vec<_>>(),
        "test_points": tests,
        "test_state": TEST_STATE,
        "note": "The study says the test points overturn. Simulated from the given state they do what \
                 `outcome` says: where alpha omega^2 tan(theta_b) < 1 a block that comes to rest can \
                 never lift off again.",
    });
    let json_path = out.join("fig6.json");
    write_json(&json_path, &provenance.insert_into(json))?;
    let note = provenance.block.note();
    let title = format!("Fig. 6: two-parameter curves (omega, alpha){note}");
    let pictures = out.picture("fig6", |p| {
        plot::curves_svg(p, &title, &curves, &tests, &params)
    })?;
    let title =
        format!("Fig. 6: test points, phi(t) (blue: mode +, red: mode -, grey: at rest){note}");
    let tests = out.picture("fig6_tests", |p| {
        plot::test_points_svg(p, &title, &tests, &trajectories)
    })?;
    Ok(FigureFiles {
        figure: 6,
        files: [vec![json_path], pictures, tests].concat(),
    })
}

/// Points of a curve in the (omega, alpha) plane, for the figures.
impl Curve {
    /// `(omega, alpha)` of every point.
    #[must_use]
    pub fn points(&self) -> Vec<(f64, f64)> {
        let pts = &self.branch.branch.points;
        pts.iter()
            .map(|p| (p[crate::OMEGA], p[crate::ALPHA]))
            .collect()
    }

    /// alpha at `omega` by linear interpolation along the curve (the first crossing), if the
    /// curve reaches that omega.
    #[must_use]
    pub fn alpha_at(&self, omega: f64) -> Option<f64> {
        self.points().windows(2).find_map(|w| {
            let ((w0, a0), (w1, a1)) = (w[0], w[1]);
            let (lo, hi) = (w0.min(w1), w0.max(w1));
            (omega >= lo && omega <= hi && hi > lo)
                .then(|| a0 + (a1 - a0) * (omega - w0) / (w1 - w0))
        })
    }
}
