//! Sample-based figures: Fig. 5 (brute-force diagram) and Fig. 7 (basins of attraction).

use super::{FigureFiles, write_json};
use crate::classes::{Class, RockingClassifier, base_class};
use crate::error::{Error, Result};
use crate::model::{ALPHA, Parameters, RockingBlock, initial_mode, initial_state};
use crate::plot;
use hycont_core::{HybridSystem, SimulationSettings, StopReason};
use hycont_sample::basin::{Axis, Classifier, Counts, Distribution, Progress, Study, run};
use hycont_sample::sweep::{Sweep, SweepPoint, brute_force};
use serde_json::{Value, json};
use std::path::Path;

/// Options of the sampling figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleOptions {
    /// Trials per basin (Fig. 7: per omega).
    pub trials: u64,
    /// Seed.
    pub seed: u64,
}

fn sample_err(e: hycont_sample::Error) -> Error {
    Error::InvalidArgument {
        name: "study",
        value: e.to_string(),
        reason: "invalid sampling study",
    }
}

fn outcome(p: &SweepPoint) -> &'static str {
    match p.stop {
        StopReason::TerminalEvent { event, .. } if event == crate::OVERTURN_POS => "overturn_pos",
        StopReason::TerminalEvent { .. } => "overturn_neg",
        _ if p.modes.iter().all(|m| *m == crate::REST) => "rest",
        _ => "running",
    }
}

/// Fig. 5: stroboscopic brute-force diagram in alpha at omega = 1.3 (the study's 300 transient
/// and 100 recorded periods per value, 301 values in [0.5, 0.8], continuing from the last
/// state), swept up and down (hysteresis), from phi0 = 0.01, psi0 = 0, beta = pi/2.
///
/// # Errors
/// Numerical or I/O failures.
pub fn figure5(out: &Path) -> Result<FigureFiles> {
    let params = Parameters::new(1.3, 0.66);
    let values: Vec<f64> = (0..=300)
        .map(|i| 0.5 + 0.3 * f64::from(i) / 300.0)
        .collect();
    let x0 = initial_state(0.01, 0.0, std::f64::consts::FRAC_PI_2);
    let mode = initial_mode(&x0, &params);
    let settings = SimulationSettings::default().rtol(1e-10).atol(1e-12);
    let sweep_of = |vals: Vec<f64>| Sweep {
        values: vals,
        parameter: ALPHA.index(),
        period: params.forcing_period(),
        transient: 300,
        recorded: 100,
    };
    let up = sweep_of(values.clone());
    let down = sweep_of(values.iter().rev().copied().collect());
    let (a, b) = rayon::join(
        || brute_force(&RockingBlock, mode, &x0, &params.to_vec(), &up, &settings),
        || brute_force(&RockingBlock, mode, &x0, &params.to_vec(), &down, &settings),
    );
    let (a, b) = (a?, b?);
    let diagram = |pts: &[SweepPoint]| -> Vec<Value> {
        pts.iter()
            .map(|p| {
                json!({
                    "alpha": p.value,
                    "phi": p.samples.iter().map(|s| s[0]).collect::<Vec<_>>(),
                    "psi": p.samples.iter().map(|s| s[1]).collect::<Vec<_>>(),
                    "outcome": outcome(p),
                })
            })
            .collect()
    };
    let json = json!({
        "figure": 5,
        "parameters": {"omega": params.omega, "alpha": params.alpha, "xi": params.xi, "theta_b": params.theta_b},
        "transient_periods": 300,
        "recorded_periods": 100,
        "initial": {"phi0": 0.01, "psi0": 0.0, "beta": std::f64::consts::FRAC_PI_2},
        "diagram": diagram(&a),
        "diagram_down": diagram(&b),
    });
    let json_path = out.join("fig5.json");
    write_json(&json_path, &json)?;
    let svg_path = out.join("fig5.svg");
    plot::brute_force_svg(&svg_path, &a, &b)?;
    Ok(FigureFiles {
        figure: 5,
        files: vec![json_path, svg_path],
    })
}

/// The omega values of Fig. 7.
pub const FIG7_OMEGAS: [f64; 6] = [1.0, 1.16, 1.5, 2.0, 3.0, 4.0];

/// Raster bins per axis of Fig. 7's basins.
pub const RASTER: usize = 40;

/// The basin study of Fig. 7 at one omega.
#[must_use]
pub fn fig7_study(omega: f64, seed: u64) -> Study {
    let b = Parameters::default().static_boundary();
    Study {
        names: ["omega", "alpha", "beta", "phi0", "psi0"]
            .iter()
            .map(ToString::to_string)
            .collect(),
        variables: vec![
            Distribution::Fixed(omega),
            Distribution::Fixed(0.66),
            Distribution::Fixed(0.0),
            Distribution::Uniform { lo: -b, hi: b },
            Distribution::Uniform { lo: -1.0, hi: 1.0 },
        ],
        axes: vec![
            Axis {
                variable: 3,
                lo: -b,
                hi: b,
                bins: RASTER,
            },
            Axis {
                variable: 4,
                lo: -1.0,
                hi: 1.0,
                bins: RASTER,
            },
        ],
        seed,
    }
}

/// Fractions per study class (rest-phase variants folded in) with 95 % intervals over all cells,
/// and the fractions of rest-phase motions.
#[must_use]
pub fn fractions_json(counts: &Counts) -> (Value, Value, Value) {
    let total: u64 = (0..counts.counts.len()).map(|c| counts.trials(c)).sum();
    let mut per = vec![0u64; Class::ALL.len()];
    let mut rest = vec![0u64; Class::ALL.len()];
    for cell in &counts.counts {
        for (i, n) in cell.iter().enumerate() {
            let (c, with_rest) = base_class(i);
            per[c.index()] += n;
            if with_rest {
                rest[c.index()] += n;
            }
        }
    }
    let frac = |n: u64| {
        if total == 0 {
            0.0
        } else {
            n as f64 / total as f64
        }
    };
    // Wilson interval on the pooled counts.
    let wilson = |n: u64| {
        let nn = total as f64;
        if nn == 0.0 {
            return [0.0, 1.0];
        }
        let p = n as f64 / nn;
        let z: f64 = 1.959_963_984_540_054;
        let d = 1.0 + z * z / nn;
        let c = (p + z * z / (2.0 * nn)) / d;
        let h = z * (p * (1.0 - p) / nn + z * z / (4.0 * nn * nn)).sqrt() / d;
        [(c - h).max(0.0), (c + h).min(1.0)]
    };
    let mut fr = serde_json::Map::new();
    let mut ci = serde_json::Map::new();
    let mut wr = serde_json::Map::new();
    for c in Class::ALL {
        fr.insert(c.name().into(), json!(frac(per[c.index()])));
        ci.insert(c.name().into(), json!(wilson(per[c.index()])));
        if rest[c.index()] > 0 {
            wr.insert(c.name().into(), json!(frac(rest[c.index()])));
        }
    }
    (Value::Object(fr), Value::Object(ci), Value::Object(wr))
}

/// The dominant study class per raster cell (`null` for empty cells).
#[must_use]
pub fn raster(counts: &Counts) -> Vec<Vec<Option<&'static str>>> {
    (0..RASTER)
        .map(|i| {
            (0..RASTER)
                .map(|j| {
                    let cell = &counts.counts[i * RASTER + j];
                    let mut per = [0u64; 8];
                    for (k, n) in cell.iter().enumerate() {
                        per[base_class(k).0.index()] += n;
                    }
                    let (best, n) = per
                        .iter()
                        .enumerate()
                        .max_by_key(|(_, n)| **n)
                        .expect("8 classes");
                    (*n > 0).then(|| Class::ALL[best].name())
                })
                .collect()
        })
        .collect()
}

/// Fig. 7: basins at alpha = 0.66, beta = 0 for the omega values of [`FIG7_OMEGAS`], `trials`
/// each (the study: 20,000), phi0 uniform in the static boundary, psi0 in (-1, 1).
///
/// # Errors
/// Numerical or I/O failures.
pub fn figure7(out: &Path, options: SampleOptions, progress: &Progress) -> Result<FigureFiles> {
    let classifier = RockingClassifier::default();
    let mut basins = Vec::new();
    let mut rasters = Vec::new();
    for (k, &omega) in FIG7_OMEGAS.iter().enumerate() {
        let study = fig7_study(omega, options.seed.wrapping_add(k as u64));
        let counts = run(&study, &classifier, 0..options.trials, progress).map_err(sample_err)?;
        let (fractions, intervals, with_rest) = fractions_json(&counts);
        let trials: u64 = (0..counts.counts.len()).map(|c| counts.trials(c)).sum();
        let r = raster(&counts);
        basins.push(json!({
            "omega": omega,
            "alpha": 0.66,
            "beta": 0.0,
            "trials": trials,
            "seed": study.seed,
            "fractions": fractions,
            "intervals_95": intervals,
            "with_rest_phases": with_rest,
            "failures": counts.failures.iter().sum::<u64>(),
            "trial_ranges": counts.ranges,
            "raster": {"phi0": [study.axes[0].lo, study.axes[0].hi, RASTER], "psi0": [-1.0, 1.0, RASTER], "dominant": r},
        }));
        rasters.push((omega, r));
    }
    let _ = classifier.classes();
    let json = json!({
        "figure": 7,
        "parameters": {"alpha": 0.66, "beta": 0.0, "xi": Parameters::default().xi, "theta_b": Parameters::default().theta_b},
        "classifier": crate::classes::ClassifierSettings::default(),
        "basins": basins,
    });
    let json_path = out.join("fig7.json");
    write_json(&json_path, &json)?;
    let svg_path = out.join("fig7.svg");
    plot::basins_svg(&svg_path, &rasters, Parameters::default().static_boundary())?;
    let _ = RockingBlock.state_dim();
    Ok(FigureFiles {
        figure: 7,
        files: vec![json_path, svg_path],
    })
}
