//! The test functions whose zeros are an atlas's edges, and their values at a chart.

use super::Edge;
use super::settings::AtlasSettings;
use crate::branch::SpecialKind;
use crate::error::{Error, Result};
use crate::quantity::Quantity;
use crate::{ContinuationProblem, PointInfo};

/// One test function.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Test {
    /// `on - level` (`sign` +1, a lower bound) or `level - on` (`sign` -1, an upper bound).
    Bound { on: Quantity, level: f64, sign: f64 },
    /// A terminal event: `on - level`.
    Event {
        kind: SpecialKind,
        on: Quantity,
        level: f64,
    },
    /// $\det [J; e_{p_1}^\top; e_{p_2}^\top]$, scaled by the first chart's magnitude.
    Fold,
    /// A half orbit's symmetry-breaking factor.
    BranchPoint,
    /// $\prod (1 + \lambda)$ over the non-trivial multipliers.
    PeriodDoubling,
    /// The torus product over pairs.
    Torus,
}

impl Test {
    /// The edge a zero of this test is.
    pub(super) fn edge(self) -> Edge {
        match self {
            Test::Bound { on, level, .. } => Edge::Bound { on, level },
            Test::Event { kind, .. } => Edge::Special { kind },
            Test::Fold => Edge::Special {
                kind: SpecialKind::Fold,
            },
            Test::BranchPoint => Edge::Special {
                kind: SpecialKind::BranchPoint,
            },
            Test::PeriodDoubling => Edge::Special {
                kind: SpecialKind::PeriodDoubling,
            },
            Test::Torus => Edge::Special {
                kind: SpecialKind::Torus,
            },
        }
    }
}

/// The tests of `settings` and the problem's terminal events, checked against its
/// parameters and monitors.
pub(super) fn tests<'a, P: ContinuationProblem<'a> + ?Sized>(
    p: &P,
    settings: &AtlasSettings,
) -> Result<Vec<Test>> {
    let (np, monitors) = (p.parameter_names().len(), p.monitor_names());
    let nm = monitors.len();
    let check = |q: Quantity| {
        let (index, count) = match q {
            Quantity::Parameter(id) => (id.index(), np),
            Quantity::Measure(m) => (m.index(), nm),
        };
        if index >= count {
            return Err(Error::NoSuchQuantity { quantity: q, count });
        }
        // A measure handle of another run names another measure at that index here.
        match q {
            Quantity::Measure(m) if !m.fits_key(crate::quantity::name_key(&monitors[index])) => {
                Err(Error::ForeignHandle {
                    quantity: q,
                    reason: format!("the measure at that index here is {}", monitors[index]),
                })
            }
            _ => Ok(()),
        }
    };
    let mut out = Vec::new();
    for b in &settings.bounds {
        check(b.on)?;
        out.push(Test::Bound {
            on: b.on,
            level: b.min,
            sign: 1.0,
        });
        out.push(Test::Bound {
            on: b.on,
            level: b.max,
            sign: -1.0,
        });
    }
    for ev in p.monitor_events().into_iter().filter(|e| e.terminal) {
        check(ev.on)?;
        out.push(Test::Event {
            kind: ev.kind,
            on: ev.on,
            level: ev.level,
        });
    }
    let e = settings.edges;
    for (on, test) in [
        (e.fold, Test::Fold),
        (e.branch_point, Test::BranchPoint),
        (e.period_doubling, Test::PeriodDoubling),
        (e.torus, Test::Torus),
    ] {
        if on {
            out.push(test);
        }
    }
    Ok(out)
}

fn value_of(q: Quantity, info: &PointInfo) -> f64 {
    match q {
        Quantity::Parameter(id) => info.params[id.index()],
        Quantity::Measure(m) => info.monitors[m.index()],
    }
}

/// The raw values of `tests` at a point with analysis `info` and fold determinant `det`
/// (sign, log-magnitude; scaled by `det_ref`).
pub(super) fn values(tests: &[Test], info: &PointInfo, det: (f64, f64), det_ref: f64) -> Vec<f64> {
    tests
        .iter()
        .map(|t| match *t {
            Test::Bound { on, level, sign } => sign * (value_of(on, info) - level),
            Test::Event { on, level, .. } => value_of(on, info) - level,
            Test::Fold => det.0 * (det.1 - det_ref).clamp(-700.0, 700.0).exp(),
            Test::BranchPoint => info.branch_point_factor.unwrap_or(1.0),
            Test::PeriodDoubling => crate::palc::pd_test(info),
            Test::Torus => crate::palc::tr_test(info),
        })
        .collect()
}
