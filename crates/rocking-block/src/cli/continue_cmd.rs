//! `continue`: one-parameter continuation from the command line, and restarts.

use super::{ContinueArgs, DirectionArg, KindArg, MethodArg, RecipeArgs, read_err, stdout_err};
use crate::continuation::{AMP, Free, Recipe, default_method, study_run};
use crate::error::{Error, Result};
use crate::figures::branches::study_labels;
use crate::model::Parameters;
use crate::orbits::{OrbitKind, orbit};
use crate::provenance::Provenance;
use crate::report::branch_json;
use hycont_continuation::{OrbitBranch, OrbitMethod, RunDirection};
use hycont_core::orbit::PeriodicOrbit;
use std::io::Write;

pub(super) fn run_continue(
    args: &ContinueArgs,
    invocation: &Provenance,
    out: &mut dyn Write,
) -> Result<()> {
    args.start.refuse_with_restart(args.restart.is_some())?;
    let inputs: Vec<&std::path::Path> = args.restart.iter().map(|p| p.as_path()).collect();
    crate::output::check_outputs(&inputs, &output_flags(&args.out, &args.svg, &args.png))?;
    let saved = (args.restart.as_deref()).map(read_saved_run).transpose()?;
    let free = free_of(args, saved.as_ref())?;
    let (branch, dimensional) = continue_branch(args, free, saved)?;
    let record = invocation
        .clone()
        .with_parameters(Parameters::from_vec(&branch.template.params))
        .with_dimensional(dimensional);
    if let Some(path) = &args.out {
        write_saved(path, &branch, &record)?;
    }
    if args.svg.is_some() || args.png.is_some() {
        let labels = study_labels(std::slice::from_ref(&branch), free, &[]);
        let params = Parameters::from_vec(&branch.template.params);
        crate::output::write_picture(args.svg.as_deref(), args.png.as_deref(), |p| {
            crate::plot::branches_svg(
                p,
                &format!("continuation in {}", free.name()),
                std::slice::from_ref(&branch.branch),
                free,
                &labels,
                params.static_boundary(),
                None,
            )
        })?;
    }
    if args.json {
        let value = record.insert_into(branch_json(&branch, free));
        let text = serde_json::to_string_pretty(&value).expect("branch serialises");
        writeln!(out, "{text}").map_err(stdout_err)?;
        Ok(())
    } else {
        summary(&branch, free, args.recipe.mesh_tol, out)
    }
}

/// The outputs `--out`, `--svg` and `--png` that are given, with their flags.
pub(super) fn output_flags<'a>(
    out: &'a Option<std::path::PathBuf>,
    svg: &'a Option<std::path::PathBuf>,
    png: &'a Option<std::path::PathBuf>,
) -> Vec<(&'static str, &'a std::path::Path)> {
    [("out", out), ("svg", svg), ("png", png)]
        .into_iter()
        .filter_map(|(flag, p)| p.as_deref().map(|p| (flag, p)))
        .collect()
}

impl RecipeArgs {
    /// The recipe asked for (validated).
    ///
    /// # Errors
    /// `--ntst`/`--ncol` without collocation; an invalid setting.
    pub(super) fn recipe(&self) -> Result<Recipe> {
        let method = match self.method {
            MethodArg::Shooting if self.ntst.is_some() || self.ncol.is_some() => {
                return Err(Error::InvalidArgument {
                    name: "ntst/ncol",
                    value: format!("{:?}/{:?}", self.ntst, self.ncol),
                    reason: "set the collocation mesh with --method collocation",
                });
            }
            MethodArg::Shooting => default_method(),
            MethodArg::Collocation => {
                let d = hycont_core::orbit::CollocationSettings::default();
                OrbitMethod::Collocation(hycont_core::orbit::CollocationSettings {
                    ntst: self.ntst.unwrap_or(d.ntst),
                    ncol: self.ncol.unwrap_or(d.ncol),
                    ..d
                })
            }
        };
        // A first step given must lie in the window; the default follows the window given.
        if let Some(h0) = self.h0
            && !(h0 >= self.h_min && h0 <= self.h_max)
        {
            return Err(Error::InvalidArgument {
                name: "h0",
                value: hycont_core::error::num(h0),
                reason: "must be in [--h-min, --h-max]",
            });
        }
        let h0 = self
            .h0
            .unwrap_or_else(|| Recipe::default().h0.max(self.h_min).min(self.h_max));
        let recipe = Recipe {
            method,
            h0,
            h_min: self.h_min,
            h_max: self.h_max,
            max_points: self.max_points,
            tol: self.tol,
            adapt_every: self.adapt_every,
            mesh_tol: self.mesh_tol,
        };
        recipe.validate()?;
        Ok(recipe)
    }
}

/// The parameter to continue in: `--free`, or else the saved run's.
fn free_of(args: &ContinueArgs, saved: Option<&OrbitBranch>) -> Result<Free> {
    match (args.free, saved, &args.restart) {
        (Some(f), ..) => Ok(Free::from(f)),
        (None, Some(saved), Some(path)) => Free::of(saved.free).ok_or_else(|| Error::InvalidFile {
            path: path.clone(),
            reason: "the saved run continues neither omega nor alpha: give --free".into(),
        }),
        _ => Err(Error::InvalidArgument {
            name: "free",
            value: String::new(),
            reason: "name the parameter to continue in (omega or alpha)",
        }),
    }
}

/// The run `continue` asks for: from a saved run's labelled point, or from a fresh start of
/// the block and forcing given (with its dimensional inputs, if any).
fn continue_branch(
    args: &ContinueArgs,
    free: Free,
    saved: Option<OrbitBranch>,
) -> Result<(OrbitBranch, Option<crate::block::DimensionalInputs>)> {
    let window = super::window(free, args.min, args.max)?;
    let recipe = args.recipe.recipe()?;
    let direction = RunDirection::from(args.direction);
    if let (Some(path), Some(label), Some(saved)) = (&args.restart, args.label, saved) {
        saved.point(label).map_err(|e| Error::InvalidFile {
            path: path.clone(),
            reason: e.to_string(),
        })?;
        let params = Parameters::from_vec(&saved.template.params);
        let mut run = study_run(free, &params, window, recipe.method)?;
        recipe.apply(&mut run);
        if args.switch {
            return Ok((run.switch_at("switched", &saved, label, direction)?, None));
        }
        // Restarting both ways: keep going the way the saved run went.
        let way = (args.direction != DirectionArg::Both).then_some(direction);
        return Ok((run.restart("branch", &saved, label, way)?, None));
    }
    let (start, dimensional) = args.start.orbit()?;
    let params = Parameters::from_vec(&start.params);
    let mut run = study_run(free, &params, window, recipe.method)?;
    recipe.apply(&mut run);
    let branch = run.run("branch", &start, direction)?;
    Ok((branch, dimensional))
}

impl KindArg {
    /// The orbit asked for.
    pub(super) fn kind(self) -> OrbitKind {
        match self {
            KindArg::Symmetric => OrbitKind::Symmetric,
            KindArg::AsymmetricPos => OrbitKind::AsymmetricPos,
            KindArg::AsymmetricNeg => OrbitKind::AsymmetricNeg,
            KindArg::Simulate => OrbitKind::Simulate,
        }
    }

    /// Its name on the command line.
    pub(super) fn name(self) -> &'static str {
        match self {
            KindArg::Symmetric => "symmetric",
            KindArg::AsymmetricPos => "asymmetric-pos",
            KindArg::AsymmetricNeg => "asymmetric-neg",
            KindArg::Simulate => "simulate",
        }
    }
}

impl super::StartArgs {
    /// Refuses block or dimensional forcing options given with a restart (which keeps the
    /// saved run's).
    pub(super) fn refuse_with_restart(&self, restart: bool) -> Result<()> {
        if restart && (self.block.given() || self.forcing.dimensional_given()) {
            return Err(Error::InvalidArgument {
                name: "block options",
                value: "given with --restart".into(),
                reason: "a restart continues the saved run's block and forcing; give them for fresh starts only",
            });
        }
        Ok(())
    }

    /// The start orbit of the block and forcing given (and their dimensional inputs, if any).
    pub(super) fn orbit(&self) -> Result<(PeriodicOrbit, Option<crate::block::DimensionalInputs>)> {
        let (params, dimensional) = super::block_args::resolve(&self.block, &self.forcing)?;
        crate::simulation::check_start(self.phi0, self.psi0, self.beta)?;
        let ics = Some((self.phi0, self.psi0, self.beta));
        let found = orbit(&params, self.kind.kind(), ics)?;
        Ok((found.solution.orbit, dimensional))
    }
}

/// The run's summary on stdout: points, end, mesh, special points.
fn summary(branch: &OrbitBranch, free: Free, mesh_tol: f64, out: &mut dyn Write) -> Result<()> {
    let b = &branch.branch;
    writeln!(out, "{} points, ended: {:?}", b.points.len(), b.end).map_err(stdout_err)?;
    if let Some(line) = mesh_summary(branch, mesh_tol) {
        writeln!(out, "{line}").map_err(stdout_err)?;
    }
    for (i, s) in b.special_points.iter().enumerate() {
        writeln!(
            out,
            "  {} label {} {} = {:.10} amp {:.8}{}{}",
            s.kind.label(),
            s.point.label,
            free.name(),
            s.point[free.id()],
            s.point[AMP],
            if s.located { "" } else { " (not located)" },
            mirror_note(&b.special_points, i, free.id())
        )
        .map_err(stdout_err)?;
    }
    Ok(())
}

/// For a special point that repeats an earlier one (the same kind, parameter and amplitude)
/// with a branch point between them, the note that names both: past a symmetry-breaking
/// branch point a branch of asymmetric orbits runs on to their mirror images, whose special
/// points are the same values again.
fn mirror_note(
    points: &[hycont_continuation::SpecialPoint],
    i: usize,
    free: hycont_core::ParamId,
) -> String {
    let s = &points[i];
    let same = |a: f64, b: f64| (a - b).abs() <= 1e-8 * a.abs().max(1.0);
    let param = s.point[free];
    for (j, e) in points[..i].iter().enumerate().rev() {
        let bp = (points[j + 1..i].iter())
            .find(|q| q.kind == hycont_continuation::SpecialKind::BranchPoint);
        if let Some(bp) = bp
            && e.kind == s.kind
            && same(e.point[free], param)
            && same(e.point[AMP], s.point[AMP])
        {
            return format!(
                " (as label {}: past BP label {} the branch runs on the mirror-image orbits)",
                e.point.label, bp.point.label
            );
        }
    }
    String::new()
}

/// A collocation run's mesh: how often it was adapted, its intervals per segment at the start
/// and at the most, and the largest error estimate along the branch, with a hint when that
/// stayed above the tolerance (by more than the growth over the step before a refinement);
/// `None` for shooting.
fn mesh_summary(branch: &OrbitBranch, tol: f64) -> Option<String> {
    let largest = branch
        .branch
        .points
        .iter()
        .filter_map(|p| p.discretisation_error)
        .reduce(f64::max)?;
    let intervals = |d: &hycont_core::orbit::Discretisation| match d {
        hycont_core::orbit::Discretisation::Collocation { meshes, .. } => {
            meshes.iter().map(|m| m.len() - 1).max().unwrap_or(0)
        }
        hycont_core::orbit::Discretisation::Shooting(_) => 0,
    };
    let most = branch
        .rediscretised
        .iter()
        .map(intervals)
        .max()
        .unwrap_or(0);
    let first = intervals(&branch.discretisation);
    let mut line = format!(
        "collocation mesh: {} adaptations along the run, {first} intervals per segment at the start, {} at the most; largest error estimate {largest:.2e}",
        branch.branch.statistics.rediscretisations,
        most.max(first)
    );
    if largest > 2.0 * tol {
        line += &format!(" (above --mesh-tol {tol:e}: raise --ntst or --ncol)");
    }
    Some(line)
}

/// Writes a run or curve for restarts, with its provenance (which restarts ignore).
///
/// # Errors
/// [`Error::Io`] naming the file.
pub(super) fn write_saved(
    path: &std::path::Path,
    branch: &hycont_continuation::OrbitBranch,
    provenance: &Provenance,
) -> Result<()> {
    let value = serde_json::to_value(branch).expect("a branch of finite values serialises");
    let text = serde_json::to_string(&provenance.insert_into(value)).expect("serialises");
    crate::output::write_atomic(path, text)
}

/// A run saved by `continue --out`, read and checked against the model.
///
/// # Errors
/// [`Error::Read`] if the file cannot be read, [`Error::InvalidFile`] if it is not such a run.
pub(super) fn read_saved_run(path: &std::path::Path) -> Result<hycont_continuation::OrbitBranch> {
    let text = std::fs::read_to_string(path).map_err(read_err(path))?;
    let invalid = |reason: String| Error::InvalidFile {
        path: path.to_path_buf(),
        reason,
    };
    let saved = hycont_continuation::OrbitBranch::from_json(&text).map_err(|e| {
        invalid(if e.is_syntax() {
            format!("not JSON ({e})")
        } else {
            format!("not a run saved by `continue --out` ({e})")
        })
    })?;
    saved
        .validate(&crate::model::RockingBlock)
        .map_err(|e| invalid(format!("not a run of the rocking block: {e}")))?;
    Ok(saved)
}
