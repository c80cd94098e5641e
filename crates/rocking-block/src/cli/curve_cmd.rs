//! `curve`: two-parameter continuation from a labelled special point of a saved run.

use super::continue_cmd::read_saved_run;
use super::{CurveArgs, stdout_err};
use crate::continuation::{AMP, Curve, Free, default_method, study_run};
use crate::error::{Error, Result};
use crate::model::Parameters;
use crate::provenance::Provenance;
use hycont_continuation::{CurveSpec, RunDirection};
use std::io::Write;

pub(super) fn run_curve(
    args: &CurveArgs,
    invocation: &Provenance,
    out: &mut dyn Write,
) -> Result<()> {
    crate::output::check_outputs(
        &[args.restart.as_path()],
        &super::continue_cmd::output_flags(&args.out, &args.svg, &args.png),
    )?;
    let saved = read_saved_run(&args.restart)?;
    let free = Free::of(saved.free).ok_or_else(|| Error::InvalidFile {
        path: args.restart.clone(),
        reason: "the saved run continues neither omega nor alpha".into(),
    })?;
    let second = Free::from(args.second);
    if second == free {
        return Err(Error::InvalidArgument {
            name: "second",
            value: second.name().into(),
            reason: "the second parameter must differ from the saved run's",
        });
    }
    let (min, max) = super::window(second, args.min, args.max)?;
    // A saved curve continues from any of its points; a branch from a special point.
    let kind = match saved.condition {
        Some(condition) => condition.kind(),
        None => saved.special_at(args.label)?.kind,
    };
    let params = Parameters::from_vec(&saved.template.params);
    let mut run = study_run(free, &params, free.range(), default_method())?;
    let direction = RunDirection::from(args.direction);
    let spec = CurveSpec::new(second.id())
        .bounds(min, max)
        .direction(direction)
        .user_points(Free::Omega.id(), args.uz_omega.iter().copied())
        .user_points(Free::Alpha.id(), args.uz_alpha.iter().copied());
    let branch = if saved.second.is_some() {
        run.curve_from(kind.label(), &saved, args.label, &spec)?
    } else {
        run.curve_at(kind.label(), &saved, args.label, &spec)?
    };
    let record = invocation.clone().with_parameters(params);
    if let Some(path) = &args.out {
        super::continue_cmd::write_saved(path, &branch, &record)?;
    }
    let curve = Curve { kind, branch };
    let title = format!(
        "{} curve from label {} of {}",
        kind.label(),
        args.label,
        args.restart.display()
    );
    crate::output::write_picture(args.svg.as_deref(), args.png.as_deref(), |p| {
        crate::plot::curve_svg(p, &title, &curve, &params)
    })?;
    report(&curve, (free, second), args.json.then_some(&record), out)
}

/// Prints the curve: the study's JSON with both parameters named, or a summary.
fn report(
    curve: &Curve,
    (free, second): (Free, Free),
    json: Option<&Provenance>,
    out: &mut dyn Write,
) -> Result<()> {
    let b = &curve.branch.branch;
    if let Some(provenance) = json {
        let mut v = crate::report::branch_json(&curve.branch, free);
        v["free"] = serde_json::json!([free.name(), second.name()]);
        v["kind"] = serde_json::json!(curve.kind.label());
        let text =
            serde_json::to_string_pretty(&provenance.insert_into(v)).expect("curve serialises");
        return writeln!(out, "{text}").map_err(stdout_err);
    }
    writeln!(
        out,
        "{} curve: {} points, ended: {:?}",
        curve.kind.label(),
        b.points.len(),
        b.end
    )
    .map_err(stdout_err)?;
    for s in &b.special_points {
        writeln!(
            out,
            "  {} label {} omega = {:.10} alpha = {:.10} amp {:.8}{}",
            s.kind.label(),
            s.point.label,
            s.point[Free::Omega.id()],
            s.point[Free::Alpha.id()],
            s.point[AMP],
            if s.located { "" } else { " (not located)" }
        )
        .map_err(stdout_err)?;
    }
    Ok(())
}
