//! Results in the study's JSON format: orbits (`orbit --json`, `fig2.json`) and branches
//! (`continue --json`, `fig3.json`, `fig4.json`).

use crate::continuation::{AMP, Free};
use crate::error::Result;
use crate::model::{ALPHA, IMPACT_MINUS, IMPACT_PLUS, OMEGA, RockingBlock};
use crate::orbits::RockingOrbit;
use hycont_continuation::{BranchPoint, MeasureId, OrbitBranch};
use hycont_core::HybridSystem;
use hycont_core::orbit::{Extremum, GrazingMargin, Measure};
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

/// One flight of an orbit in a report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SegmentReport {
    /// `"+"` or `"-"`.
    pub mode: String,
    /// Duration of the flight (impact to impact).
    pub duration: f64,
    /// State right after the impact that starts it.
    pub start: Vec<f64>,
}

/// An orbit in the study's JSON format (`orbits` entries of `fig2.json`, `orbit --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OrbitReport {
    /// Name (`symmetric`, `asymmetric-pos`, ...).
    pub name: String,
    /// Forcing frequency.
    pub omega: f64,
    /// Forcing amplitude.
    pub alpha: f64,
    /// $\max |\varphi|$ over the orbit (the exact extremum).
    pub amp: f64,
    /// Period.
    pub period: f64,
    /// Whether all non-trivial multipliers are inside the unit circle.
    pub stable: bool,
    /// All Floquet multipliers `[re, im]`.
    pub multipliers: Vec<[f64; 2]>,
    /// Which multipliers are trivial (the forcing oscillator's 1 and $e^{-2T}$).
    pub trivial: Vec<bool>,
    /// Whether the orbit is $\mathbb{Z}_2$-symmetric.
    pub symmetric: bool,
    /// Half-map multipliers of a symmetric orbit.
    pub half_multipliers: Option<Vec<[f64; 2]>>,
    /// Smallest $|\varphi|$ at an interior extremum turning back from the impact surface (a
    /// grazing measure: 0 at grazing), if the orbit has such an extremum.
    pub grazing: Option<f64>,
    /// Flights, impact to impact.
    pub segments: Vec<SegmentReport>,
    /// Newton iterations.
    pub newton_iterations: usize,
    /// Final residual.
    pub residual: f64,
}

impl RockingOrbit {
    /// The report of this orbit under `name`.
    ///
    /// # Errors
    /// If the orbit cannot be integrated for its measures (never for a solved orbit).
    pub fn report(&self, name: &str) -> Result<OrbitReport> {
        let orbit = &self.solution.orbit;
        let flights = orbit.without_interior_points(&RockingBlock)?;
        let fl = &self.solution.floquet;
        let margin =
            GrazingMargin::new([IMPACT_PLUS, IMPACT_MINUS]).evaluate(&RockingBlock, orbit)?;
        let pairs = |m: &[(f64, f64)]| m.iter().map(|&(a, b)| [a, b]).collect::<Vec<_>>();
        Ok(OrbitReport {
            name: name.to_string(),
            omega: orbit.params[OMEGA.index()],
            alpha: orbit.params[ALPHA.index()],
            amp: Extremum::max_abs(0).evaluate(&RockingBlock, orbit)?,
            period: orbit.period(),
            stable: fl.stable(),
            multipliers: pairs(&fl.multipliers),
            trivial: fl.trivial.clone(),
            symmetric: orbit.is_symmetric(&RockingBlock, 1e-6),
            half_multipliers: self.half_multipliers.as_deref().map(pairs),
            grazing: (margin < f64::MAX).then_some(margin.abs()),
            segments: flights
                .signature
                .segments()
                .iter()
                .zip(&flights.durations)
                .zip(&flights.starts)
                .map(|((s, d), x)| SegmentReport {
                    mode: RockingBlock.mode_name(s.mode).to_string(),
                    duration: *d,
                    start: x.clone(),
                })
                .collect(),
            newton_iterations: self.solution.newton.len(),
            residual: self.solution.residual,
        })
    }
}

fn multipliers_json(m: &[(f64, f64)]) -> Value {
    Value::Array(m.iter().map(|(a, b)| json!([a, b])).collect())
}

fn point_json(p: &BranchPoint) -> Value {
    json!({
        "label": p.label,
        "omega": p[OMEGA],
        "alpha": p[ALPHA],
        "amp": p[AMP],
        "period": p[MeasureId::PERIOD],
        "stable": p.stable(),
        "multipliers": multipliers_json(&p.multipliers),
    })
}

/// A branch in the study's JSON format (`name`, `free`, `points`, `special_points`), with the
/// end reason, labels, located-ness and brackets added.
#[must_use]
pub fn branch_json(b: &OrbitBranch, free: Free) -> Value {
    let points = b.branch.points.iter().map(|p| {
        let mut v = point_json(p);
        v["unstable"] = json!(p.unstable);
        v["trivial"] = json!(p.trivial);
        v["newton_iterations"] = json!(p.newton_iterations);
        if let Some(e) = p.discretisation_error {
            v["discretisation_error"] = json!(e);
        }
        v
    });
    let specials = b.branch.special_points.iter().map(|s| {
        let mut v = point_json(&s.point);
        v["kind"] = json!(s.kind.label());
        v["located"] = json!(s.located);
        v["accuracy"] = json!(s.accuracy);
        v["bracket"] = json!([s.bracket.0, s.bracket.1]);
        v
    });
    json!({
        "name": b.branch.name,
        "free": [free.name()],
        "end": format!("{:?}", b.branch.end),
        "points": points.collect::<Vec<_>>(),
        "special_points": specials.collect::<Vec<_>>(),
    })
}
