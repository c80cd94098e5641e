//! `simulate`, `orbit` and `classify`.

use super::{ClassifyArgs, MethodArg, OrbitArgs, SimulateArgs, read_err, stdout_err};
use crate::error::{Error, Result};
use crate::plot;
use crate::provenance::Provenance;
use crate::simulation::{SimulationRequest, simulate};
use hycont_core::HybridSystem;
use std::io::Write;

/// A one-point result with its provenance: the invocation, the parameters and the dimensional
/// inputs they came from.
fn stamp(
    invocation: &Provenance,
    params: crate::model::Parameters,
    dims: Option<crate::block::DimensionalInputs>,
    value: serde_json::Value,
) -> serde_json::Value {
    invocation
        .clone()
        .with_parameters(params)
        .with_dimensional(dims)
        .insert_into(value)
}

pub(super) fn run_orbit(
    args: &OrbitArgs,
    invocation: &Provenance,
    out: &mut dyn Write,
) -> Result<()> {
    use crate::orbits::orbit;
    let (params, dims) = super::block_args::resolve(&args.block, &args.forcing)?;
    crate::simulation::check_start(args.phi0, args.psi0, args.beta)?;
    let settings = hycont_core::orbit::CollocationSettings {
        ntst: args.ntst,
        ncol: args.ncol,
        adapt: 1,
    };
    settings.validate()?;
    let (kind, name) = (args.kind.kind(), args.kind.name());
    let mut found = orbit(&params, kind, Some((args.phi0, args.psi0, args.beta)))?;
    if args.method == MethodArg::Collocation {
        found = found.by_collocation(settings)?;
    }
    let report = found.report(name)?;
    if args.json {
        let value = serde_json::to_value(&report).expect("report serialises");
        let value = stamp(invocation, params, dims, value);
        let text = serde_json::to_string_pretty(&value).expect("report serialises");
        writeln!(out, "{text}").map_err(stdout_err)?;
    } else {
        writeln!(
            out,
            "{name} orbit at omega = {}, alpha = {} ({:?}): period {:.10}, amp {:.10}, {}",
            params.omega,
            params.alpha,
            args.method,
            report.period,
            report.amp,
            if report.stable { "stable" } else { "unstable" }
        )
        .map_err(stdout_err)?;
        for s in &report.segments {
            writeln!(
                out,
                "  flight {}: {:.10} from {:?}",
                s.mode, s.duration, s.start
            )
            .map_err(stdout_err)?;
        }
        for (m, t) in report.multipliers.iter().zip(&report.trivial) {
            writeln!(
                out,
                "  multiplier {:+.10e} {:+.10e}i{}",
                m[0],
                m[1],
                if *t { " (trivial)" } else { "" }
            )
            .map_err(stdout_err)?;
        }
    }
    Ok(())
}

pub(super) fn run_classify(
    args: &ClassifyArgs,
    invocation: &Provenance,
    out: &mut dyn Write,
) -> Result<()> {
    use crate::classes::{ClassifierSettings, classify};
    let settings = ClassifierSettings::default();
    if let (Some(input), Some(output)) = (&args.input, &args.output) {
        return classify_file(args, input, output, out);
    }
    let (params, dims) = super::block_args::resolve(&args.block, &args.forcing)?;
    let c = classify(&params, args.beta, args.phi0, args.psi0, &settings)?;
    if args.json {
        let v = serde_json::json!({
            "omega": params.omega, "alpha": params.alpha, "xi": params.xi, "theta_b": params.theta_b,
            "dimensional": dims,
            "beta": args.beta,
            "phi0": args.phi0, "psi0": args.psi0,
            "class": c.class.name(), "decision": c.decision, "periods": c.periods,
            "with_rest": c.with_rest,
        });
        let v = stamp(invocation, params, dims, v);
        writeln!(
            out,
            "{}",
            serde_json::to_string_pretty(&v).expect("serialises")
        )
        .map_err(stdout_err)?;
    } else {
        writeln!(
            out,
            "{} ({:?} after {} periods{})",
            c.class.name(),
            c.decision,
            c.periods,
            if c.with_rest {
                ", with rest phases"
            } else {
                ""
            }
        )
        .map_err(stdout_err)?;
    }
    Ok(())
}

/// `classify --input trials.csv --output classes.csv`: every trial of the file, in parallel,
/// one row each (a trial that fails is written as `error` with the reason).
fn classify_file(
    args: &ClassifyArgs,
    input: &std::path::Path,
    output: &std::path::Path,
    out: &mut dyn Write,
) -> Result<()> {
    use crate::classes::{ClassifierSettings, classify};
    use rayon::prelude::*;
    crate::output::check_outputs(&[input], &[("output", output)])?;
    let text = std::fs::read_to_string(input).map_err(read_err(input))?;
    let rows = crate::classes::parse_trials(&text).map_err(|reason| Error::InvalidFile {
        path: input.to_path_buf(),
        reason,
    })?;
    let block = args.block.block()?;
    let settings = ClassifierSettings::default();
    let results: Vec<String> = rows
        .par_iter()
        .map(
            |v| match classify(&block.at(v[0], v[1]), v[2], v[3], v[4], &settings) {
                Ok(c) => format!(
                    "{},{},{},{},{},{},{:?},{},{}",
                    v[0],
                    v[1],
                    v[2],
                    v[3],
                    v[4],
                    c.class.name(),
                    c.decision,
                    c.periods,
                    c.with_rest
                ),
                Err(e) => format!(
                    "{},{},{},{},{},error,\"{e}\",0,false",
                    v[0], v[1], v[2], v[3], v[4]
                ),
            },
        )
        .collect();
    let mut text = String::from("omega,alpha,beta,phi0,psi0,class,decision,periods,with_rest\n");
    for r in results {
        text.push_str(&r);
        text.push('\n');
    }
    crate::output::write_atomic(output, text)?;
    writeln!(
        out,
        "classified {} trials into {}",
        rows.len(),
        output.display()
    )
    .map_err(stdout_err)
}

pub(super) fn run_simulate(
    args: &SimulateArgs,
    invocation: &Provenance,
    out: &mut dyn Write,
) -> Result<()> {
    let (params, dims) = super::block_args::resolve(&args.block, &args.forcing)?;
    let wants_files = args.csv.is_some() || args.svg.is_some() || args.png.is_some();
    let req = SimulationRequest {
        params,
        phi0: args.phi0,
        psi0: args.psi0,
        beta: args.beta,
        forcing_state: args.r0.zip(args.s0).map(|(r, s)| [r, s]),
        periods: args.periods,
        rtol: args.rtol,
        atol: args.atol,
        points_per_period: args
            .points_per_period
            .unwrap_or(if wants_files { 200 } else { 0 }),
    };
    let outputs: Vec<(&'static str, &std::path::Path)> =
        [("csv", &args.csv), ("svg", &args.svg), ("png", &args.png)]
            .into_iter()
            .filter_map(|(flag, p)| p.as_deref().map(|p| (flag, p)))
            .collect();
    crate::output::check_outputs(&[], &outputs)?;
    let (report, traj) = simulate(&req)?;
    if let Some(path) = &args.csv {
        let mut text = String::from("t,mode,phi,psi,r,s\n");
        for (t, mode, x) in traj.samples.iter() {
            let name = crate::model::RockingBlock.mode_name(mode);
            text.push_str(&format!("{t},{name},{},{},{},{}\n", x[0], x[1], x[2], x[3]));
        }
        crate::output::write_atomic(path, text)?;
    }
    let title = format!(
        "rocking block: omega = {}, alpha = {}, phi0 = {}, psi0 = {}, beta = {} ({:?})",
        params.omega, params.alpha, args.phi0, args.psi0, args.beta, report.outcome
    );
    crate::output::write_picture(args.svg.as_deref(), args.png.as_deref(), |p| {
        plot::trajectory_svg(p, &title, &traj, &params)
    })?;
    if args.json {
        let mut value = serde_json::to_value(&report).expect("report serialises");
        value["outcome_description"] = report.outcome.describe().into();
        let value = stamp(invocation, params, dims, value);
        let text = serde_json::to_string_pretty(&value).expect("report serialises");
        writeln!(out, "{text}").map_err(stdout_err)?;
    } else {
        writeln!(
            out,
            "outcome: {:?} ({})\nt_end: {:.6}\nimpacts: {}\nfinal mode: {}\nfinal state: {:?}\n\
             rest times: {:?}\nsteps: {} (rejected {}), rhs evaluations: {}",
            report.outcome,
            report.outcome.describe(),
            report.t_end,
            report.impacts,
            report.final_mode,
            report.final_state,
            report.rest_times,
            report.stats.steps,
            report.stats.rejected_steps,
            report.stats.rhs_evaluations
        )
        .map_err(stdout_err)?;
    }
    Ok(())
}
