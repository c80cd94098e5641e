//! Fig. 5: the stroboscopic brute-force diagram in alpha, swept up and down, with the study's
//! special points and the period-doubling cascade by continuation marked.

use super::{FigureFiles, write_json};
use crate::error::Result;
use crate::model::{ALPHA, RockingBlock, initial_mode, initial_state};
use crate::output::OutDir;
use crate::plot;
use crate::provenance::Provenance;
use hycont_core::{SimulationSettings, StopReason};
use hycont_sample::sweep::{Sweep, SweepPoint, brute_force};
use serde_json::{Value, json};

/// Switching levels of the continuation marked on the figure: the symmetric branch, the
/// asymmetric one, then the doubled branches of periods 2 to 16; their period doublings PD1
/// (on the asymmetric branch) to PD5 (on the period-16 branch) accumulate where the
/// brute-force diagram turns chaotic.
const CASCADE_DEPTH: usize = 5;

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
/// Stops when `progress` is asked to (an interrupt): the sweeps between values, the
/// continuation between points, and then writes nothing.
///
/// # Errors
/// Numerical or I/O failures; [`crate::error::Error::Interrupted`] when stopped.
pub fn figure5(
    out: &OutDir,
    provenance: &Provenance,
    progress: &hycont_sample::basin::Progress,
) -> Result<FigureFiles> {
    let params = provenance.block.at(1.3, 0.66);
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
        || {
            brute_force(
                &RockingBlock,
                mode,
                &x0,
                &params.to_vec(),
                &up,
                &settings,
                progress,
            )
        },
        || {
            brute_force(
                &RockingBlock,
                mode,
                &x0,
                &params.to_vec(),
                &down,
                &settings,
                progress,
            )
        },
    );
    let (a, b) = (a?, b?);
    super::stopped(progress, 5)?;
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
    // The special points on the line omega = 1.3 by continuation, in one diagram from the
    // Fig. 2 orbit: BP3 on the symmetric branch, then the period-doubling cascade PD1, PD2, ...
    // followed on the doubled branches (they must sit where the brute-force cascade splits).
    let start = crate::continuation::study_start(&provenance.block)?;
    let cont = crate::continuation::study_diagram(
        "symmetric",
        crate::continuation::Free::Alpha,
        crate::continuation::Free::Alpha.range(),
        &provenance.recipe(),
        &start,
        &hycont_continuation::DiagramSettings {
            depth: CASCADE_DEPTH,
            ..Default::default()
        },
        &mut hycont_continuation::observe::StopFlag(&progress.stop),
    )?;
    super::stopped(progress, 5)?;
    let bp3 = cont.branches[0]
        .branch
        .special(hycont_continuation::SpecialKind::BranchPoint)
        .next()
        .map(|s| s.point[ALPHA]);
    let cascade = cont.cascades().into_iter().next();
    let doublings = cascade.as_ref().map_or(&[][..], |c| &c.doublings[..]);
    let names: Vec<String> = (1..=doublings.len()).map(|k| format!("PD{k}")).collect();
    let markers: Vec<(&str, f64)> = bp3
        .map(|a| ("BP3", a))
        .into_iter()
        .chain(
            names
                .iter()
                .map(String::as_str)
                .zip(doublings.iter().copied()),
        )
        .collect();
    let json = json!({
        "figure": 5,
        "parameters": {"omega": params.omega, "alpha": params.alpha, "xi": params.xi, "theta_b": params.theta_b},
        "transient_periods": 300,
        "recorded_periods": 100,
        "initial": {"phi0": 0.01, "psi0": 0.0, "beta": std::f64::consts::FRAC_PI_2},
        "diagram": diagram(&a),
        "diagram_down": diagram(&b),
        "continuation": {
            "BP3": bp3,
            "period_doublings": doublings,
            "intervals": cascade.as_ref().map(|c| c.intervals()),
            "ratios": cascade.as_ref().map(|c| c.ratios()),
        },
    });
    let json_path = out.join("fig5.json");
    write_json(&json_path, &provenance.insert_into(json))?;
    let overturned = |p: &SweepPoint| outcome(p).starts_with("overturn");
    let title = format!(
        "Fig. 5: brute-force diagram, omega = 1.3 (psi at t = 2 pi k / omega){}",
        provenance.block.note()
    );
    let pictures = out.picture("fig5", |p| {
        plot::brute_force_svg(p, &title, &a, &b, &markers, &overturned)
    })?;
    Ok(FigureFiles {
        figure: 5,
        files: [vec![json_path], pictures].concat(),
    })
}
