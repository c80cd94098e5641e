//! The command line's arguments (clap).

pub use super::block_args::{BlockArgs, ForcingArgs};
use crate::continuation::Recipe;
use crate::output::Format;
use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// Reproduces the rocking-block study: simulations now; orbits, continuation and figures as
/// they land.
#[derive(Debug, Parser)]
#[command(name = "rocking-block", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate the block from an initial condition (event-driven, DOP853).
    Simulate(SimulateArgs),
    /// Compute a periodic orbit (Newton on a multi-segment boundary-value problem) with its
    /// Floquet multipliers.
    Orbit(OrbitArgs),
    /// Reproduce a figure of the study: writes DIR/figN.json and DIR/figN.svg.
    Figure(FigureArgs),
    /// Continue a periodic orbit in omega or alpha (pseudo-arclength), detecting and locating
    /// SN, BP, PD, TR, SB and GR; or restart from a labelled point of a saved run.
    Continue(ContinueArgs),
    /// Continue a two-parameter curve (SN, PD, BP, SB or GR) from a labelled special point of a
    /// run saved by `continue --out`, or a saved curve further from one of its points.
    Curve(CurveArgs),
    /// A whole bifurcation diagram in one call: the branch through a start both ways, then at
    /// every BP and PD (to --depth levels) the branch switched on there, branches reached twice
    /// kept once; prints each branch's special points, the switches and the period-doubling
    /// cascades (their intervals and ratios).
    Diagram(super::DiagramArgs),
    /// Classify trials (the study's solution classes): one trial with --json, or a CSV batch
    /// (columns omega, alpha, beta, phi0, psi0) with --input/--output.
    Classify(ClassifyArgs),
    /// Merge shard files of a sampling figure (written with `figure N --shard I/N`) and write
    /// the figure.
    Merge(MergeArgs),
    /// Basin stability for your ranges: each of omega, alpha, beta, phi0, psi0 fixed or
    /// uniform (LO:HI), binned on up to two (--bin NAME:BINS); writes DIR/basin.json,
    /// basin.csv (counts per cell with 95 % Wilson intervals) and basin.svg.
    Basin(super::BasinArgs),
}

/// Arguments of `rocking-block classify`.
#[derive(Debug, Args)]
pub struct ClassifyArgs {
    /// The forcing (single trial).
    #[command(flatten)]
    pub forcing: ForcingArgs,
    /// Forcing phase (single trial).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub beta: f64,
    /// Initial angle (single trial).
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true)]
    pub phi0: f64,
    /// Initial angular velocity (single trial).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub psi0: f64,
    /// The block (every trial).
    #[command(flatten)]
    pub block: BlockArgs,
    /// CSV file of trials (header omega,alpha,beta,phi0,psi0).
    #[arg(long, requires = "output")]
    pub input: Option<PathBuf>,
    /// CSV file to write (the input columns plus class, decision, periods, with_rest).
    #[arg(long, requires = "input")]
    pub output: Option<PathBuf>,
    /// Print the single trial's classification as JSON.
    #[arg(long)]
    pub json: bool,
}

/// The continuation parameter on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FreeArg {
    /// Forcing frequency.
    Omega,
    /// Forcing amplitude.
    Alpha,
}

/// Directions on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum DirectionArg {
    /// Both ways from the start, joined.
    Both,
    /// Increasing parameter.
    Up,
    /// Decreasing parameter.
    Down,
}

/// Arguments of `rocking-block continue`.
#[derive(Debug, Args)]
pub struct ContinueArgs {
    /// The parameter to continue in (with --restart: the saved run's unless given).
    #[arg(long, value_enum, required_unless_present = "restart")]
    pub free: Option<FreeArg>,
    /// The start: block, forcing, which orbit.
    #[command(flatten)]
    pub start: StartArgs,
    /// Smallest parameter value (default: 0.5 for omega, 0.01 for alpha).
    #[arg(long, allow_hyphen_values = true)]
    pub min: Option<f64>,
    /// Largest parameter value (default: 4.0 for omega, 1.06 for alpha).
    #[arg(long, allow_hyphen_values = true)]
    pub max: Option<f64>,
    /// Direction.
    #[arg(long, value_enum, default_value_t = DirectionArg::Both)]
    pub direction: DirectionArg,
    /// Discretisation, steps, point count, tolerance and mesh (a collocation run restarted by
    /// collocation keeps its mesh).
    #[command(flatten)]
    pub recipe: RecipeArgs,
    /// Restart from this saved run (a file written by --out).
    #[arg(long, requires = "label")]
    pub restart: Option<PathBuf>,
    /// Label of the point of the saved run to restart from.
    #[arg(long, requires = "restart", allow_hyphen_values = true)]
    pub label: Option<usize>,
    /// Switch branches at the labelled point (a BP, PD, GR or DB of the saved run) instead of
    /// continuing through it: at a GR, the family with the grazing's extra impacts, the way
    /// it is physical.
    #[arg(long, requires = "label")]
    pub switch: bool,
    /// Write the run (branch with unknowns, for restarts) to this JSON file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Draw the branch to this SVG file.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Draw the branch to this PNG file (rendered with a bundled font; with --svg, the same picture).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Print the branch (study format) as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// How branches are continued (the study's [`Recipe`] by default): `continue`, and the branch
/// figures of `figure`.
#[derive(Debug, Clone, Args)]
pub struct RecipeArgs {
    /// Discretisation.
    #[arg(long, value_enum, default_value_t = MethodArg::Shooting)]
    pub method: MethodArg,
    /// First arclength step (default 0.02, or the nearest of --h-min and --h-max where they
    /// exclude it).
    #[arg(long, allow_hyphen_values = true)]
    pub h0: Option<f64>,
    /// Smallest arclength step before the run gives up.
    #[arg(long = "h-min", default_value_t = Recipe::default().h_min, allow_hyphen_values = true)]
    pub h_min: f64,
    /// Largest arclength step (smaller: denser branches).
    #[arg(long = "h-max", default_value_t = Recipe::default().h_max, allow_hyphen_values = true)]
    pub h_max: f64,
    /// Largest number of points of a run (each way).
    #[arg(
        long = "max-points",
        default_value_t = Recipe::default().max_points,
        allow_hyphen_values = true
    )]
    pub max_points: usize,
    /// Collocation: mesh intervals per segment (--method collocation; a restart by collocation
    /// keeps the saved mesh).
    #[arg(long, allow_hyphen_values = true)]
    pub ntst: Option<usize>,
    /// Collocation: collocation points per interval, 1 to 7 (--method collocation).
    #[arg(long, allow_hyphen_values = true)]
    pub ncol: Option<usize>,
    /// Newton tolerance of the corrector: the step relative to 1 + |u| (the residual must
    /// also be below 1e-10).
    #[arg(long, default_value_t = Recipe::default().tol, allow_hyphen_values = true)]
    pub tol: f64,
    /// Collocation: re-adapt the mesh (same size, equidistributing the error) every N points;
    /// 0: only when the error estimate exceeds --mesh-tol.
    #[arg(
        long = "adapt-every",
        default_value_t = Recipe::default().adapt_every,
        allow_hyphen_values = true
    )]
    pub adapt_every: usize,
    /// Collocation: re-adapt the mesh at points whose error estimate (largest interior error of
    /// the polynomials, in the units of the state) exceeds this.
    #[arg(long = "mesh-tol", default_value_t = Recipe::default().mesh_tol, allow_hyphen_values = true)]
    pub mesh_tol: f64,
}

/// A fresh start of a continuation (`continue`, `diagram`): the block, the forcing and which
/// orbit; a restart keeps the saved run's block and forcing.
#[derive(Debug, Args)]
pub struct StartArgs {
    /// The forcing at the start (the continued parameter's start value and the other's fixed
    /// value).
    #[command(flatten)]
    pub forcing: ForcingArgs,
    /// The block (fresh starts; a restart keeps the saved run's block).
    #[command(flatten)]
    pub block: BlockArgs,
    /// Start: which orbit.
    #[arg(long, value_enum, default_value_t = KindArg::Symmetric)]
    pub kind: KindArg,
    /// Initial angle for --kind simulate.
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true)]
    pub phi0: f64,
    /// Initial angular velocity for --kind simulate.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub psi0: f64,
    /// Forcing phase for --kind simulate.
    #[arg(long, default_value_t = std::f64::consts::FRAC_PI_2, allow_hyphen_values = true)]
    pub beta: f64,
}

/// Orbit kinds on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum KindArg {
    /// The symmetric period-1 orbit.
    Symmetric,
    /// The asymmetric period-1 orbit leaning to phi > 0.
    AsymmetricPos,
    /// The asymmetric period-1 orbit leaning to phi < 0.
    AsymmetricNeg,
    /// The orbit a simulation settles on (from --phi0, --psi0, --beta).
    Simulate,
}

/// Discretisations on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MethodArg {
    /// Orthogonal collocation.
    Collocation,
    /// Multiple shooting.
    Shooting,
}

/// Arguments of `rocking-block curve`.
#[derive(Debug, Args)]
pub struct CurveArgs {
    /// The saved run (a file written by `continue --out`), or a curve written by `curve --out`
    /// to continue further.
    #[arg(long)]
    pub restart: PathBuf,
    /// Label of the special point (SN, PD, BP, SB or GR) of the saved run to start from; of any
    /// point of a saved curve.
    #[arg(long, allow_hyphen_values = true)]
    pub label: usize,
    /// The second parameter (the other is the saved run's).
    #[arg(long, value_enum)]
    pub second: FreeArg,
    /// Smallest value of the second parameter (default: the study's range, 0.5 for omega, 0 for
    /// alpha).
    #[arg(long, allow_hyphen_values = true)]
    pub min: Option<f64>,
    /// Largest value of the second parameter (default: 4 for omega, 1.06 for alpha).
    #[arg(long, allow_hyphen_values = true)]
    pub max: Option<f64>,
    /// Which way(s) from the special point.
    #[arg(long, value_enum, default_value_t = DirectionArg::Both)]
    pub direction: DirectionArg,
    /// User points (UZ): where the curve crosses omega = X (repeatable).
    #[arg(long = "uz-omega", allow_hyphen_values = true)]
    pub uz_omega: Vec<f64>,
    /// User points (UZ): where the curve crosses alpha = Y (repeatable).
    #[arg(long = "uz-alpha", allow_hyphen_values = true)]
    pub uz_alpha: Vec<f64>,
    /// Write the curve (both parameters at every point, with unknowns) to this JSON file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Draw the curve in the (omega, alpha) plane to this SVG file.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Draw the curve to this PNG file (rendered with a bundled font; with --svg, the same picture).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Print the curve (study format, both parameters per point) as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `rocking-block orbit`.
#[derive(Debug, Args)]
pub struct OrbitArgs {
    /// The forcing.
    #[command(flatten)]
    pub forcing: ForcingArgs,
    /// The block.
    #[command(flatten)]
    pub block: BlockArgs,
    /// Which orbit.
    #[arg(long, value_enum, default_value_t = KindArg::Symmetric)]
    pub kind: KindArg,
    /// Discretisation of the boundary-value problem.
    #[arg(long, value_enum, default_value_t = MethodArg::Collocation)]
    pub method: MethodArg,
    /// Collocation: mesh intervals per segment.
    #[arg(long, default_value_t = 20, allow_hyphen_values = true)]
    pub ntst: usize,
    /// Collocation: points per interval.
    #[arg(long, default_value_t = 4, allow_hyphen_values = true)]
    pub ncol: usize,
    /// Initial angle for --kind simulate.
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true)]
    pub phi0: f64,
    /// Initial angular velocity for --kind simulate.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub psi0: f64,
    /// Forcing phase for --kind simulate.
    #[arg(long, default_value_t = std::f64::consts::FRAC_PI_2, allow_hyphen_values = true)]
    pub beta: f64,
    /// Print the orbit as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `rocking-block figure`.
#[derive(Debug, Args)]
pub struct FigureArgs {
    /// Figure number (2 to 10), `atlas` (the symmetric orbits over (omega, alpha)) or `all`
    /// (optional with --resume).
    #[arg(required_unless_present = "resume")]
    pub which: Option<String>,
    /// Output directory.
    #[arg(long, default_value = "results")]
    pub out: PathBuf,
    /// Sampling figures: trials per basin (default: Fig. 10 100,000, enough for the study's
    /// trends; the study: 20,000 per omega for Fig. 7, 1,000,000 per beta for Fig. 9,
    /// 2,000,000 for Fig. 10). For Figs. 7 and 9, a fixed number of trials per omega or beta
    /// instead of the default cell by cell (see --halfwidth).
    #[arg(long, allow_hyphen_values = true)]
    pub trials: Option<u64>,
    /// Figs. 7 and 9: trials drawn cell by cell (uniform inside each cell of the grid: Fig. 7
    /// (phi0, psi0), Fig. 9 (omega, alpha)) until every class's 95 % Wilson half-width in
    /// every cell is at most this, or the cell has --max-per-cell trials [default without
    /// --trials: 0.1].
    #[arg(long, conflicts_with = "trials", allow_hyphen_values = true)]
    pub halfwidth: Option<f64>,
    /// Figs. 7 and 9 sampled cell by cell: most trials per cell (and panel).
    #[arg(long, default_value_t = 4096, allow_hyphen_values = true)]
    pub max_per_cell: u64,
    /// Sampling figures: seed (results are identical for a seed whatever the threads).
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    pub seed: u64,
    /// Worker threads (default: all cores).
    #[arg(long, allow_hyphen_values = true)]
    pub threads: Option<usize>,
    /// Sampling figures 7, 9, 10: run only shard I of N (0-based, `I/N`) of the trials and write
    /// DIR/figN.shard-I-of-N.json, for `rocking-block merge` (cluster array jobs).
    #[arg(long)]
    pub shard: Option<String>,
    /// Complete an interrupted sampling run or shard from its `*.partial.json` file (written on
    /// Ctrl-C, SIGTERM or by an incomplete merge): runs the missing trials only (the file
    /// fixes the trials, seed and shard: they cannot be given with it).
    #[arg(long, conflicts_with_all = ["trials", "seed", "shard"])]
    pub resume: Option<PathBuf>,
    /// Sampling figures: stop once this many trials of the run are counted (those of a resumed
    /// file included; whole chunks of 256 per thread), as an interrupt would: the counts go to
    /// the partial file, to be completed with --resume (e.g. to fit a run into a time slot).
    /// Under mpirun each rank counts its own trials (and the resumed file's).
    #[arg(long, allow_hyphen_values = true)]
    pub stop_after: Option<u64>,
    /// An interrupted run also replaces figN.json and figN.svg by the figure of the trials
    /// counted so far (otherwise only the partial file is written).
    #[arg(long)]
    pub force: bool,
    /// Picture format: figN.svg, figN.png (rendered with a bundled font) or both.
    #[arg(long, value_enum, default_value_t = Format::Svg)]
    pub format: Format,
    /// Print the files written as JSON (`{"files": [...]}`).
    #[arg(long)]
    pub json: bool,
    /// The block (the figures of the study for another block; a resumed run keeps its block).
    #[command(flatten)]
    pub block: BlockArgs,
    /// How the branches of Figs. 3, 4 and 5 are continued (Fig. 6 and the sampling figures
    /// keep the study's recipe).
    #[command(flatten)]
    pub recipe: RecipeArgs,
}

/// Arguments of `rocking-block merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Shard files written by `figure N --shard I/N` or `basin --shard I/N` (complete or
    /// `*.partial.json`).
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// Output directory for figN.json and figN.svg.
    #[arg(long, default_value = "results")]
    pub out: PathBuf,
    /// Picture format of the merged figure: SVG, PNG or both.
    #[arg(long, value_enum, default_value_t = Format::Svg)]
    pub format: Format,
    /// Print the files written as JSON (`{"files": [...]}`).
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `rocking-block simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// The forcing.
    #[command(flatten)]
    pub forcing: ForcingArgs,
    /// Initial angle phi0.
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true)]
    pub phi0: f64,
    /// Initial angular velocity psi0.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub psi0: f64,
    /// Forcing phase beta: (r0, s0) = (sin beta, cos beta).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub beta: f64,
    /// Forcing-oscillator state r0 (with --s0; overrides --beta).
    #[arg(long, requires = "s0", allow_hyphen_values = true)]
    pub r0: Option<f64>,
    /// Forcing-oscillator state s0 (with --r0; overrides --beta).
    #[arg(long, requires = "r0", allow_hyphen_values = true)]
    pub s0: Option<f64>,
    /// Duration in forcing periods 2 pi / omega.
    #[arg(long, default_value_t = 100.0, allow_hyphen_values = true)]
    pub periods: f64,
    /// The block.
    #[command(flatten)]
    pub block: BlockArgs,
    /// Relative tolerance of the integrator.
    #[arg(long, default_value_t = 1e-10, allow_hyphen_values = true)]
    pub rtol: f64,
    /// Absolute tolerance of the integrator.
    #[arg(long, default_value_t = 1e-12, allow_hyphen_values = true)]
    pub atol: f64,
    /// Dense samples per forcing period for --csv, --svg and max_abs_phi (default 200 when a
    /// file is asked for, else 0).
    #[arg(long, allow_hyphen_values = true)]
    pub points_per_period: Option<usize>,
    /// Print the result as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write the dense time series (t, mode, phi, psi, r, s) to this CSV file.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Draw the time series and phase portrait to this SVG file.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Draw the same picture to this PNG file (rendered with a bundled font; with --svg, the same picture).
    #[arg(long)]
    pub png: Option<PathBuf>,
}

impl From<FreeArg> for crate::continuation::Free {
    fn from(f: FreeArg) -> Self {
        match f {
            FreeArg::Omega => Self::Omega,
            FreeArg::Alpha => Self::Alpha,
        }
    }
}

impl From<DirectionArg> for hycont_continuation::RunDirection {
    fn from(d: DirectionArg) -> Self {
        match d {
            DirectionArg::Both => Self::Both,
            DirectionArg::Up => Self::Up,
            DirectionArg::Down => Self::Down,
        }
    }
}

/// `[min, max]` of a parameter: the given ends or the study's range.
///
/// # Errors
/// [`crate::Error::InvalidArgument`] unless `min < max`.
pub fn window(
    free: crate::continuation::Free,
    min: Option<f64>,
    max: Option<f64>,
) -> crate::Result<(f64, f64)> {
    let (lo, hi) = free.range();
    let (min, max) = (min.unwrap_or(lo), max.unwrap_or(hi));
    if min < max {
        Ok((min, max))
    } else {
        Err(crate::Error::InvalidArgument {
            name: "min/max",
            value: format!("{min}/{max}"),
            reason: "min must be below max",
        })
    }
}
