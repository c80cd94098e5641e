//! `diagram`: a whole bifurcation diagram in one call (every BP and PD switched at, to a
//! depth), its period-doubling cascades, and extensions of a saved diagram to a greater depth.

use super::continue_cmd::output_flags;
use super::{FreeArg, RecipeArgs, StartArgs, read_err, stdout_err};
use crate::continuation::{AMP, Free, study_diagram, study_run};
use crate::error::{Error, Result};
use crate::figures::branches::study_labels;
use crate::model::{Parameters, RockingBlock};
use crate::provenance::Provenance;
use crate::report::branch_json;
use clap::Args;
use hycont_continuation::observe::Observer;
use hycont_continuation::{
    Branch, Diagram, DiagramBranchId, DiagramSettings, Error as ContinuationError, SpecialKind,
    SwitchOutcome,
};
use serde_json::json;
use std::io::Write;
use std::path::PathBuf;

/// Feigenbaum's constant $\delta$, the limit of the ratios of successive doubling intervals.
const FEIGENBAUM_DELTA: f64 = 4.669_201_609_102_99;

/// Arguments of `rocking-block diagram`.
#[derive(Debug, Args)]
pub struct DiagramArgs {
    /// The parameter to continue in.
    #[arg(long, value_enum)]
    pub free: FreeArg,
    /// The start: block, forcing, which orbit (an extension keeps the saved diagram's block).
    #[command(flatten)]
    pub start: StartArgs,
    /// Smallest parameter value (default: 0.5 for omega, 0.01 for alpha).
    #[arg(long, allow_hyphen_values = true)]
    pub min: Option<f64>,
    /// Largest parameter value (default: 4.0 for omega, 1.06 for alpha).
    #[arg(long, allow_hyphen_values = true)]
    pub max: Option<f64>,
    /// Levels of switching: 0 is the start's branch alone; each level switches at the BP and
    /// PD points of the last (deeper in alpha: the period-doubling cascade).
    #[arg(long, default_value_t = 2, allow_hyphen_values = true)]
    pub depth: usize,
    /// Most branches.
    #[arg(long = "max-branches", default_value_t = DiagramSettings::default().max_branches, allow_hyphen_values = true)]
    pub max_branches: usize,
    /// Discretisation, steps, point count, tolerance and mesh of every branch.
    #[command(flatten)]
    pub recipe: RecipeArgs,
    /// Extend this saved diagram (a file written by --out) to --depth.
    #[arg(long)]
    pub restart: Option<PathBuf>,
    /// Write the diagram (its branches with unknowns, for extensions and restarts) to this
    /// JSON file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Draw the branches to this SVG file.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Draw the branches to this PNG file (with --svg, the same picture).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Print the diagram (study format: branches, switches, cascades) as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// A line on stderr per finished branch.
struct BranchLines;

impl Observer for BranchLines {
    fn branch(&mut self, branch: &Branch) {
        eprintln!(
            "branch {}: {} points, {} special points, ended: {:?}",
            branch.name,
            branch.points.len(),
            branch.special_points.len(),
            branch.end
        );
    }
}

/// A line on stderr every 250 charts of an atlas (`figure atlas`).
#[derive(Debug, Default)]
struct ChartLines;

impl Observer for ChartLines {
    fn chart(&mut self, _: &hycont_continuation::atlas::AtlasChart, count: usize) {
        if count.is_multiple_of(250) {
            eprintln!("atlas: {count} charts");
        }
    }
}

/// `figure atlas` for `block`, with a line on stderr every 250 charts; the files written.
pub(super) fn figure_atlas(
    dir: &crate::output::OutDir,
    invocation: &Provenance,
    block: crate::block::Block,
) -> Result<Vec<PathBuf>> {
    let record = invocation.clone().with_block(block);
    Ok(crate::figures::figure_atlas(dir, &record, &mut ChartLines)?.files)
}

pub(super) fn run_diagram(
    args: &DiagramArgs,
    invocation: &Provenance,
    out: &mut dyn Write,
) -> Result<()> {
    let free = Free::from(args.free);
    args.start.refuse_with_restart(args.restart.is_some())?;
    let inputs: Vec<&std::path::Path> = args.restart.iter().map(|p| p.as_path()).collect();
    crate::output::check_outputs(&inputs, &output_flags(&args.out, &args.svg, &args.png))?;
    let (diagram, dimensional) = compute(args, free)?;
    let params = Parameters::from_vec(&diagram.branches[0].branch.template.params);
    let record = invocation
        .clone()
        .with_parameters(params)
        .with_dimensional(dimensional);
    if let Some(path) = &args.out {
        let value = serde_json::to_value(&diagram).expect("a diagram of finite values serialises");
        let text = serde_json::to_string(&record.insert_into(value)).expect("serialises");
        crate::output::write_atomic(path, text)?;
    }
    if args.svg.is_some() || args.png.is_some() {
        let saved: Vec<_> = diagram.branches.iter().map(|b| b.branch.clone()).collect();
        let labels = study_labels(&saved, free, &[]);
        let plain: Vec<Branch> = saved.into_iter().map(|b| b.branch).collect();
        crate::output::write_picture(args.svg.as_deref(), args.png.as_deref(), |p| {
            crate::plot::branches_svg(
                p,
                &format!(
                    "bifurcation diagram in {} (depth {})",
                    free.name(),
                    args.depth
                ),
                &plain,
                free,
                &labels,
                params.static_boundary(),
                None,
            )
        })?;
    }
    if args.json {
        let value = record.insert_into(diagram_json(&diagram, free));
        let text = serde_json::to_string_pretty(&value).expect("diagram serialises");
        writeln!(out, "{text}").map_err(stdout_err)
    } else {
        summary(&diagram, free, out)
    }
}

/// The diagram asked for: a saved one extended, or a fresh one from the start given.
fn compute(
    args: &DiagramArgs,
    free: Free,
) -> Result<(Diagram, Option<crate::block::DimensionalInputs>)> {
    let window = super::window(free, args.min, args.max)?;
    let recipe = args.recipe.recipe()?;
    let settings = DiagramSettings {
        depth: args.depth,
        max_branches: args.max_branches,
        ..DiagramSettings::default()
    };
    settings.validate()?;
    if let Some(path) = &args.restart {
        let mut diagram = read_saved_diagram(path)?;
        let root = &diagram.branches[0].branch;
        if root.free != free.id() {
            return Err(Error::InvalidArgument {
                name: "free",
                value: free.name().into(),
                reason: "the saved diagram was continued in the other parameter",
            });
        }
        let mut run = study_run(
            free,
            &Parameters::from_vec(&root.template.params),
            window,
            recipe.method,
        )?;
        recipe.apply(&mut run);
        run.observer(Box::new(BranchLines));
        // The saved diagram is checked first: one that is not this run's, as it says, is bad
        // input.
        run.extend_diagram(&mut diagram, &settings)
            .map_err(|e| match e {
                ContinuationError::InvalidSaved { .. } | ContinuationError::InvalidPoint { .. } => {
                    Error::InvalidFile {
                        path: path.clone(),
                        reason: e.to_string(),
                    }
                }
                other => other.into(),
            })?;
        return Ok((diagram, None));
    }
    let (start, dimensional) = args.start.orbit()?;
    let name = args.start.kind.name();
    let mut lines = BranchLines;
    let diagram = study_diagram(name, free, window, &recipe, &start, &settings, &mut lines)?;
    Ok((diagram, dimensional))
}

/// A diagram saved by `diagram --out`, read and checked against the model.
///
/// # Errors
/// [`Error::Read`] if the file cannot be read, [`Error::InvalidFile`] if it is not such a
/// diagram.
fn read_saved_diagram(path: &std::path::Path) -> Result<Diagram> {
    let text = std::fs::read_to_string(path).map_err(read_err(path))?;
    let invalid = |reason: String| Error::InvalidFile {
        path: path.to_path_buf(),
        reason,
    };
    let diagram = Diagram::from_json(&text).map_err(|e| {
        invalid(if e.is_syntax() {
            format!("not JSON ({e})")
        } else {
            format!("not a diagram saved by `diagram --out` ({e})")
        })
    })?;
    if diagram.branches.is_empty() {
        return Err(invalid("the diagram has no branches".into()));
    }
    for b in &diagram.branches {
        b.branch
            .validate(&RockingBlock)
            .map_err(|e| invalid(format!("not a diagram of the rocking block: {e}")))?;
    }
    Ok(diagram)
}

/// What became of a switch, in words.
fn outcome_text(o: &SwitchOutcome) -> String {
    match o {
        SwitchOutcome::Followed(b) => format!("followed: branch {}", b.0),
        SwitchOutcome::Origin => "where the branch began".into(),
        SwitchOutcome::Known { branch, label } => {
            format!("known: label {label} of branch {}", branch.0)
        }
        SwitchOutcome::Duplicate(b) => format!("leads to branch {} again", b.0),
        SwitchOutcome::DepthLimit => "not followed (depth)".into(),
        SwitchOutcome::BranchLimit => "not followed (--max-branches)".into(),
        SwitchOutcome::Failed(why) => format!("switch failed: {why}"),
        _ => format!("{o:?}"),
    }
}

/// The diagram on stdout: each branch with its special points as `continue` prints them, the
/// switches, the cascades.
fn summary(d: &Diagram, free: Free, out: &mut dyn Write) -> Result<()> {
    let w = |out: &mut dyn Write, line: String| writeln!(out, "{line}").map_err(stdout_err);
    w(out, format!("{} branches", d.branches.len()))?;
    for (i, b) in d.branches.iter().enumerate() {
        let br = &b.branch.branch;
        let from = b.origin.map_or(String::new(), |(p, l)| {
            format!(" (from branch {} at label {l})", p.0)
        });
        w(
            out,
            format!(
                "branch {i} {}{from}: {} points, ended: {:?}",
                br.name,
                br.points.len(),
                br.end
            ),
        )?;
        for s in &br.special_points {
            w(
                out,
                format!(
                    "  {} label {} {} = {:.10} amp {:.8}{}",
                    s.kind.label(),
                    s.point.label,
                    free.name(),
                    s.point[free.id()],
                    s.point[AMP],
                    if s.located { "" } else { " (not located)" }
                ),
            )?;
        }
    }
    for r in &d.switches {
        w(
            out,
            format!(
                "switch {} label {} on branch {} {} = {:.10}: {}",
                r.kind.label(),
                r.label,
                r.branch.0,
                free.name(),
                r.parameter,
                outcome_text(&r.outcome)
            ),
        )?;
    }
    for c in d.cascades().iter().filter(|c| c.doublings.len() > 1) {
        let list = |v: &[f64], digits: usize| {
            v.iter()
                .map(|x| format!("{x:.digits$}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let chain: Vec<String> = c
            .branches
            .iter()
            .map(|b: &DiagramBranchId| b.0.to_string())
            .collect();
        w(
            out,
            format!(
                "period-doubling cascade over branches {}:",
                chain.join(" -> ")
            ),
        )?;
        w(
            out,
            format!("  PD {} = {}", free.name(), list(&c.doublings, 10)),
        )?;
        w(out, format!("  intervals {}", list(&c.intervals(), 10)))?;
        if !c.ratios().is_empty() {
            w(
                out,
                format!(
                    "  ratios {} (Feigenbaum's delta = {FEIGENBAUM_DELTA:.4})",
                    list(&c.ratios(), 4)
                ),
            )?;
        }
    }
    Ok(())
}

/// The diagram as JSON: its branches (study format) with their origins, the switches and the
/// cascades.
fn diagram_json(d: &Diagram, free: Free) -> serde_json::Value {
    let branches: Vec<_> = d
        .branches
        .iter()
        .map(|b| {
            let mut v = branch_json(&b.branch, free);
            v["depth"] = json!(b.depth);
            v["origin"] = json!(b.origin.map(|(p, l)| json!({"branch": p.0, "label": l})));
            v
        })
        .collect();
    let switches: Vec<_> = d
        .switches
        .iter()
        .map(|r| {
            json!({
                "branch": r.branch.0,
                "label": r.label,
                "kind": r.kind.label(),
                free.name(): r.parameter,
                "outcome": outcome_text(&r.outcome),
            })
        })
        .collect();
    let cascades: Vec<_> = d
        .cascades()
        .iter()
        .map(|c| {
            json!({
                "branches": c.branches.iter().map(|b| b.0).collect::<Vec<_>>(),
                "doublings": c.doublings,
                "intervals": c.intervals(),
                "ratios": c.ratios(),
            })
        })
        .collect();
    let kinds: Vec<&str> = [SpecialKind::BranchPoint, SpecialKind::PeriodDoubling]
        .iter()
        .map(SpecialKind::label)
        .collect();
    json!({
        "free": free.name(),
        "switched_at": kinds,
        "branches": branches,
        "switches": switches,
        "cascades": cascades,
    })
}
