//! The `rocking-block` command line.

use crate::error::{Error, Result};
use crate::model::{DEFAULT_THETA_B, DEFAULT_XI, Parameters};
use crate::plot;
use crate::simulation::{SimulationRequest, simulate};
use clap::{Args, Parser, Subcommand};
use hycont_core::HybridSystem;
use std::io::Write;
use std::path::{Path, PathBuf};

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
    /// Classify trials (the study's solution classes): one trial with --json, or a CSV batch
    /// (columns omega, alpha, beta, phi0, psi0) with --input/--output.
    Classify(ClassifyArgs),
    /// Merge shard files of a sampling figure (written with `figure N --shard I/N`) and write
    /// the figure.
    Merge(MergeArgs),
}

/// Arguments of `rocking-block classify`.
#[derive(Debug, Args)]
pub struct ClassifyArgs {
    /// Forcing frequency (single trial).
    #[arg(long, default_value_t = 1.3, allow_negative_numbers = true)]
    pub omega: f64,
    /// Forcing amplitude (single trial).
    #[arg(long, default_value_t = 0.66, allow_negative_numbers = true)]
    pub alpha: f64,
    /// Forcing phase (single trial).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub beta: f64,
    /// Initial angle (single trial).
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub phi0: f64,
    /// Initial angular velocity (single trial).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub psi0: f64,
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
    /// The parameter to continue in.
    #[arg(long, value_enum)]
    pub free: FreeArg,
    /// Start: forcing frequency.
    #[arg(long, default_value_t = 1.3, allow_negative_numbers = true)]
    pub omega: f64,
    /// Start: forcing amplitude.
    #[arg(long, default_value_t = 0.66, allow_negative_numbers = true)]
    pub alpha: f64,
    /// Start: which orbit.
    #[arg(long, value_enum, default_value_t = KindArg::Symmetric)]
    pub kind: KindArg,
    /// Initial angle for --kind simulate.
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub phi0: f64,
    /// Initial angular velocity for --kind simulate.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub psi0: f64,
    /// Forcing phase for --kind simulate.
    #[arg(long, default_value_t = std::f64::consts::FRAC_PI_2, allow_negative_numbers = true)]
    pub beta: f64,
    /// Smallest parameter value (default: 0.5 for omega, 0.01 for alpha).
    #[arg(long, allow_negative_numbers = true)]
    pub min: Option<f64>,
    /// Largest parameter value (default: 4.0 for omega, 1.06 for alpha).
    #[arg(long, allow_negative_numbers = true)]
    pub max: Option<f64>,
    /// Direction.
    #[arg(long, value_enum, default_value_t = DirectionArg::Both)]
    pub direction: DirectionArg,
    /// Discretisation (a collocation run restarted by collocation keeps its mesh).
    #[arg(long, value_enum, default_value_t = MethodArg::Shooting)]
    pub method: MethodArg,
    /// Restart from this saved run (a file written by --out).
    #[arg(long, requires = "label")]
    pub restart: Option<PathBuf>,
    /// Label of the point of the saved run to restart from.
    #[arg(long, requires = "restart")]
    pub label: Option<usize>,
    /// Write the run (branch with unknowns, for restarts) to this JSON file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Draw the branch to this SVG file.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Print the branch (study format) as JSON on stdout.
    #[arg(long)]
    pub json: bool,
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

/// Arguments of `rocking-block orbit`.
#[derive(Debug, Args)]
pub struct OrbitArgs {
    /// Forcing frequency omega (> 0).
    #[arg(long, default_value_t = 1.3, allow_negative_numbers = true)]
    pub omega: f64,
    /// Forcing amplitude alpha (>= 0).
    #[arg(long, default_value_t = 0.66, allow_negative_numbers = true)]
    pub alpha: f64,
    /// Which orbit.
    #[arg(long, value_enum, default_value_t = KindArg::Symmetric)]
    pub kind: KindArg,
    /// Discretisation of the boundary-value problem.
    #[arg(long, value_enum, default_value_t = MethodArg::Collocation)]
    pub method: MethodArg,
    /// Collocation: mesh intervals per segment.
    #[arg(long, default_value_t = 20)]
    pub ntst: usize,
    /// Collocation: points per interval.
    #[arg(long, default_value_t = 4)]
    pub ncol: usize,
    /// Initial angle for --kind simulate.
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub phi0: f64,
    /// Initial angular velocity for --kind simulate.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub psi0: f64,
    /// Forcing phase for --kind simulate.
    #[arg(long, default_value_t = std::f64::consts::FRAC_PI_2, allow_negative_numbers = true)]
    pub beta: f64,
    /// Print the orbit as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `rocking-block figure`.
#[derive(Debug, Args)]
pub struct FigureArgs {
    /// Figure number (2 to 10) or `all`.
    pub which: String,
    /// Output directory.
    #[arg(long, default_value = "results")]
    pub out: PathBuf,
    /// Sampling figures: trials per basin (the study: 20,000 for Fig. 7).
    #[arg(long, default_value_t = 2000)]
    pub trials: u64,
    /// Sampling figures: seed (results are identical for a seed whatever the threads).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Sampling figures 7, 9, 10: run only shard I of N (0-based, `I/N`) of the trials and write
    /// DIR/figN.shard-I-of-N.json, for `rocking-block merge` (cluster array jobs).
    #[arg(long)]
    pub shard: Option<String>,
    /// Print the files written as JSON (`{"files": [...]}`).
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `rocking-block merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Shard files written by `figure N --shard I/N`.
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// Output directory for figN.json and figN.svg.
    #[arg(long, default_value = "results")]
    pub out: PathBuf,
    /// Print the files written as JSON (`{"files": [...]}`).
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `rocking-block simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// Forcing frequency omega (> 0).
    #[arg(long, default_value_t = 1.3, allow_negative_numbers = true)]
    pub omega: f64,
    /// Forcing amplitude alpha (>= 0; the study's range is (0, 1.06]).
    #[arg(long, default_value_t = 0.66, allow_negative_numbers = true)]
    pub alpha: f64,
    /// Initial angle phi0.
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub phi0: f64,
    /// Initial angular velocity psi0.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub psi0: f64,
    /// Forcing phase beta: (r0, s0) = (sin beta, cos beta).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub beta: f64,
    /// Forcing-oscillator state r0 (with --s0; overrides --beta).
    #[arg(long, requires = "s0", allow_negative_numbers = true)]
    pub r0: Option<f64>,
    /// Forcing-oscillator state s0 (with --r0; overrides --beta).
    #[arg(long, requires = "r0", allow_negative_numbers = true)]
    pub s0: Option<f64>,
    /// Duration in forcing periods 2 pi / omega.
    #[arg(long, default_value_t = 100.0)]
    pub periods: f64,
    /// Damping xi (>= 0).
    #[arg(long, default_value_t = DEFAULT_XI)]
    pub xi: f64,
    /// Slenderness angle theta_b (rad).
    #[arg(long = "theta-b", default_value_t = DEFAULT_THETA_B)]
    pub theta_b: f64,
    /// Relative tolerance of the integrator.
    #[arg(long, default_value_t = 1e-10)]
    pub rtol: f64,
    /// Absolute tolerance of the integrator.
    #[arg(long, default_value_t = 1e-12)]
    pub atol: f64,
    /// Dense samples per forcing period for --csv, --svg and max_abs_phi (default 200 when a
    /// file is asked for, else 0).
    #[arg(long)]
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
}

/// Creates the parent directory of an output file, if needed.
fn ensure_parent(path: &Path) -> Result<()> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => {
            std::fs::create_dir_all(dir).map_err(io_err(dir))
        }
        _ => Ok(()),
    }
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |source| Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Runs a parsed command line, writing results to `out`.
///
/// # Errors
/// Invalid arguments, numerical failures, or files that cannot be written.
pub fn run(cli: Cli, out: &mut dyn Write) -> Result<()> {
    match cli.command {
        Command::Simulate(args) => run_simulate(&args, out),
        Command::Orbit(args) => run_orbit(&args, out),
        Command::Figure(args) => run_figure(&args, out),
        Command::Continue(args) => run_continue(&args, out),
        Command::Classify(args) => run_classify(&args, out),
        Command::Merge(args) => run_merge(&args, out),
    }
}

/// A shard of a sampling figure on disk.
#[derive(Debug, serde::Serialize, serde::Deserialize)]
struct ShardFile {
    figure: u32,
    trials: u64,
    seed: u64,
    shard: (u64, u64),
    counts: Vec<hycont_sample::basin::Counts>,
}

fn parse_shard(text: &str) -> Result<(u64, u64)> {
    let bad = || Error::InvalidArgument {
        name: "shard",
        value: text.to_string(),
        reason: "expected I/N with 0 <= I < N",
    };
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    let (i, n): (u64, u64) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 || i >= n {
        return Err(bad());
    }
    Ok((i, n))
}

fn run_merge(args: &MergeArgs, out: &mut dyn Write) -> Result<()> {
    let mut merged: Option<ShardFile> = None;
    for path in &args.shards {
        let text = std::fs::read_to_string(path).map_err(io_err(path))?;
        let shard: ShardFile = serde_json::from_str(&text).map_err(|_| Error::InvalidArgument {
            name: "shard",
            value: path.display().to_string(),
            reason: "not a shard file written by `figure N --shard I/N`",
        })?;
        match merged.as_mut() {
            None => merged = Some(shard),
            Some(m) => {
                if (m.figure, m.trials, m.seed) != (shard.figure, shard.trials, shard.seed)
                    || m.counts.len() != shard.counts.len()
                {
                    return Err(Error::InvalidArgument {
                        name: "shard",
                        value: path.display().to_string(),
                        reason: "belongs to another figure, trial count or seed",
                    });
                }
                for (a, b) in m.counts.iter_mut().zip(&shard.counts) {
                    a.merge(b).map_err(|e| Error::InvalidArgument {
                        name: "shard",
                        value: format!("{}: {e}", path.display()),
                        reason: "overlaps a shard merged before",
                    })?;
                }
            }
        }
    }
    let m = merged.expect("clap requires at least one shard");
    let complete: u64 = m.counts[0].ranges.iter().map(|(a, b)| b - a).sum();
    if complete != m.trials {
        eprintln!(
            "rocking-block: the shards hold {complete} of {} trials; writing what they hold",
            m.trials
        );
    }
    std::fs::create_dir_all(&args.out).map_err(io_err(&args.out))?;
    let options = crate::figures::sampling::SampleOptions {
        trials: m.trials,
        seed: m.seed,
    };
    let files = crate::figures::sampling::render(m.figure, &args.out, options, &m.counts)?;
    print_written(out, &files.files, args.json)
}

fn run_continue(args: &ContinueArgs, out: &mut dyn Write) -> Result<()> {
    use crate::continuation::{AMP, Free, default_method, study_run};
    use crate::figures::branches::study_labels;
    use crate::orbits::{OrbitKind, orbit};
    use crate::report::branch_json;
    use hycont_continuation::{OrbitBranch, OrbitMethod, RunDirection};
    let free = match args.free {
        FreeArg::Omega => Free::Omega,
        FreeArg::Alpha => Free::Alpha,
    };
    let (lo, hi) = free.range();
    let (min, max) = (args.min.unwrap_or(lo), args.max.unwrap_or(hi));
    if !(min < max) {
        return Err(Error::InvalidArgument {
            name: "min/max",
            value: format!("{min}/{max}"),
            reason: "min must be below max",
        });
    }
    let method = match args.method {
        MethodArg::Shooting => default_method(),
        MethodArg::Collocation => {
            OrbitMethod::Collocation(hycont_core::orbit::CollocationSettings::default())
        }
    };
    let direction = match args.direction {
        DirectionArg::Both => RunDirection::Both,
        DirectionArg::Up => RunDirection::Up,
        DirectionArg::Down => RunDirection::Down,
    };
    let branch = if let (Some(path), Some(label)) = (&args.restart, args.label) {
        let text = std::fs::read_to_string(path).map_err(io_err(path))?;
        let saved = OrbitBranch::from_json(&text).map_err(|e| Error::InvalidArgument {
            name: "restart",
            value: path.display().to_string(),
            reason: if e.is_syntax() {
                "not JSON"
            } else {
                "not a run saved by `continue --out`"
            },
        })?;
        let params = Parameters::from_vec(&saved.template.params);
        let mut run = study_run(free, &params, (min, max), method)?;
        // Restarting both ways: keep going the way the saved run went.
        let way = (args.direction != DirectionArg::Both).then_some(direction);
        run.restart("branch", &saved, label, way)?
    } else {
        let params = Parameters::new(args.omega, args.alpha);
        params.validate()?;
        crate::simulation::check_start(args.phi0, args.psi0, args.beta)?;
        let kind = match args.kind {
            KindArg::Symmetric => OrbitKind::Symmetric,
            KindArg::AsymmetricPos => OrbitKind::AsymmetricPos,
            KindArg::AsymmetricNeg => OrbitKind::AsymmetricNeg,
            KindArg::Simulate => OrbitKind::Simulate,
        };
        let start = orbit(&params, kind, Some((args.phi0, args.psi0, args.beta)))?;
        let mut run = study_run(free, &params, (min, max), method)?;
        run.run("branch", &start.solution.orbit, direction)?
    };
    let stdout_err = |source| Error::Io {
        path: PathBuf::from("<stdout>"),
        source,
    };
    if let Some(path) = &args.out {
        ensure_parent(path)?;
        let text = branch
            .to_json()
            .expect("a branch of finite values serialises");
        std::fs::write(path, text).map_err(io_err(path))?;
    }
    if let Some(path) = &args.svg {
        ensure_parent(path)?;
        let labels = study_labels(std::slice::from_ref(&branch), free, &[]);
        let params = Parameters::from_vec(&branch.template.params);
        crate::plot::branches_svg(
            path,
            &format!("continuation in {}", free.name()),
            std::slice::from_ref(&branch.branch),
            free,
            &labels,
            params.static_boundary(),
        )?;
    }
    if args.json {
        let text =
            serde_json::to_string_pretty(&branch_json(&branch, free)).expect("branch serialises");
        writeln!(out, "{text}").map_err(stdout_err)?;
    } else {
        let b = &branch.branch;
        writeln!(out, "{} points, ended: {:?}", b.points.len(), b.end).map_err(stdout_err)?;
        for s in &b.special_points {
            writeln!(
                out,
                "  {} label {} {} = {:.10} amp {:.8}{}",
                s.kind.label(),
                s.point.label,
                free.name(),
                s.point[free.id()],
                s.point[AMP],
                if s.located { "" } else { " (not located)" }
            )
            .map_err(stdout_err)?;
        }
    }
    Ok(())
}

fn run_orbit(args: &OrbitArgs, out: &mut dyn Write) -> Result<()> {
    use crate::orbits::{OrbitKind, orbit};
    let params = Parameters::new(args.omega, args.alpha);
    params.validate()?;
    crate::simulation::check_start(args.phi0, args.psi0, args.beta)?;
    let settings = hycont_core::orbit::CollocationSettings {
        ntst: args.ntst,
        ncol: args.ncol,
        adapt: 1,
    };
    settings.validate()?;
    let (kind, name) = match args.kind {
        KindArg::Symmetric => (OrbitKind::Symmetric, "symmetric"),
        KindArg::AsymmetricPos => (OrbitKind::AsymmetricPos, "asymmetric-pos"),
        KindArg::AsymmetricNeg => (OrbitKind::AsymmetricNeg, "asymmetric-neg"),
        KindArg::Simulate => (OrbitKind::Simulate, "simulate"),
    };
    let mut found = orbit(&params, kind, Some((args.phi0, args.psi0, args.beta)))?;
    if args.method == MethodArg::Collocation {
        found = found.by_collocation(settings)?;
    }
    let report = found.report(name)?;
    let stdout_err = |source| Error::Io {
        path: PathBuf::from("<stdout>"),
        source,
    };
    if args.json {
        let text = serde_json::to_string_pretty(&report).expect("report serialises");
        writeln!(out, "{text}").map_err(stdout_err)?;
    } else {
        writeln!(
            out,
            "{name} orbit at omega = {}, alpha = {} ({:?}): period {:.10}, amp {:.10}, {}",
            args.omega,
            args.alpha,
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

fn run_figure(args: &FigureArgs, out: &mut dyn Write) -> Result<()> {
    use hycont_sample::basin::Progress;
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, Ordering};
    let which: Vec<u32> = if args.which == "all" {
        crate::figures::AVAILABLE.to_vec()
    } else {
        vec![args.which.parse().map_err(|_| Error::InvalidArgument {
            name: "figure",
            value: args.which.clone(),
            reason: "expected a figure number (2 to 10) or `all`",
        })?]
    };
    if args.trials == 0 {
        return Err(Error::InvalidArgument {
            name: "trials",
            value: "0".into(),
            reason: "must be at least 1",
        });
    }
    if let Some(n) = args.threads {
        if n == 0 {
            return Err(Error::InvalidArgument {
                name: "threads",
                value: "0".into(),
                reason: "must be at least 1",
            });
        }
        // Only the first call configures the global pool; results do not depend on it.
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global();
    }
    let options = crate::figures::sampling::SampleOptions {
        trials: args.trials,
        seed: args.seed,
    };
    let progress = Arc::new(Progress::default());
    if let Some(shard) = &args.shard {
        let (i, n) = parse_shard(shard)?;
        let [fig] = which.as_slice() else {
            return Err(Error::InvalidArgument {
                name: "shard",
                value: args.which.clone(),
                reason: "shard one sampling figure (7, 9 or 10) at a time",
            });
        };
        let range = hycont_sample::basin::shard_range(args.trials, i, n).map_err(|e| {
            Error::InvalidArgument {
                name: "shard",
                value: e.to_string(),
                reason: "invalid shard",
            }
        })?;
        let counts = crate::figures::sampling::counts_for(*fig, options, range, &progress)?;
        std::fs::create_dir_all(&args.out).map_err(io_err(&args.out))?;
        let path = args.out.join(format!("fig{fig}.shard-{i}-of-{n}.json"));
        let file = ShardFile {
            figure: *fig,
            trials: args.trials,
            seed: args.seed,
            shard: (i, n),
            counts,
        };
        std::fs::write(&path, serde_json::to_string(&file).expect("serialises"))
            .map_err(io_err(&path))?;
        return print_written(out, &[path], args.json);
    }
    // Ctrl-C stops sampling studies early; what was counted is written, with its trial ranges.
    {
        let p = Arc::clone(&progress);
        let _ = ctrlc::set_handler(move || p.stop.store(true, Ordering::Relaxed));
    }
    let mut written: Vec<PathBuf> = Vec::new();
    for n in which {
        let total = match n {
            7 => options.trials * crate::figures::sampling::FIG7_OMEGAS.len() as u64,
            9 => 2 * options.trials,
            10 => options.trials,
            _ => 0,
        };
        progress.done.store(0, Ordering::Relaxed);
        // A progress bar for the sampling figures, on stderr (hidden when not a terminal).
        let bar = (total > 0).then(|| {
            let bar = indicatif::ProgressBar::new(total);
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "figure {msg} [{bar:40}] {pos}/{len} trials ({per_sec}, eta {eta})",
                )
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            bar.set_message(n.to_string());
            bar
        });
        let done = AtomicBool::new(false);
        let files = std::thread::scope(|scope| {
            if let Some(bar) = &bar {
                let (p, done) = (&progress, &done);
                scope.spawn(move || {
                    while !done.load(Ordering::Relaxed) {
                        bar.set_position(p.done.load(Ordering::Relaxed));
                        std::thread::sleep(std::time::Duration::from_millis(100));
                    }
                });
            }
            let r = crate::figures::figure_with(n, &args.out, options, &progress);
            done.store(true, Ordering::Relaxed);
            r
        })?;
        if let Some(bar) = bar {
            bar.finish_and_clear();
        }
        written.extend(files.files);
        if progress.stop.load(Ordering::Relaxed) {
            eprintln!(
                "rocking-block: interrupted: figure {n} holds the trials counted so far (see trial_ranges)"
            );
            break;
        }
    }
    print_written(out, &written, args.json)
}

/// Prints the files written, as lines or as JSON.
fn print_written(out: &mut dyn Write, files: &[PathBuf], json: bool) -> Result<()> {
    let stdout_err = |source| Error::Io {
        path: PathBuf::from("<stdout>"),
        source,
    };
    if json {
        let v = serde_json::json!({"files": files.iter().map(|f| f.display().to_string()).collect::<Vec<_>>()});
        writeln!(
            out,
            "{}",
            serde_json::to_string_pretty(&v).expect("serialises")
        )
        .map_err(stdout_err)
    } else {
        for f in files {
            writeln!(out, "wrote {}", f.display()).map_err(stdout_err)?;
        }
        Ok(())
    }
}

fn run_classify(args: &ClassifyArgs, out: &mut dyn Write) -> Result<()> {
    use crate::classes::{ClassifierSettings, classify};
    use rayon::prelude::*;
    let settings = ClassifierSettings::default();
    let stdout_err = |source| Error::Io {
        path: PathBuf::from("<stdout>"),
        source,
    };
    if let (Some(input), Some(output)) = (&args.input, &args.output) {
        let text = std::fs::read_to_string(input).map_err(io_err(input))?;
        let mut lines = text.lines();
        let header: Vec<&str> = lines
            .next()
            .unwrap_or("")
            .split(',')
            .map(str::trim)
            .collect();
        let col = |name: &'static str| {
            header
                .iter()
                .position(|h| *h == name)
                .ok_or(Error::InvalidArgument {
                    name: "input",
                    value: input.display().to_string(),
                    reason: "the header must name the columns omega, alpha, beta, phi0, psi0",
                })
        };
        let cols = [
            col("omega")?,
            col("alpha")?,
            col("beta")?,
            col("phi0")?,
            col("psi0")?,
        ];
        let mut rows = Vec::new();
        for (i, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            let mut v = [0.0; 5];
            for (k, &c) in cols.iter().enumerate() {
                v[k] = fields.get(c).and_then(|f| f.parse().ok()).ok_or_else(|| {
                    Error::InvalidArgument {
                        name: "input",
                        value: format!("line {}: {line}", i + 2),
                        reason: "expected five numbers",
                    }
                })?;
            }
            rows.push(v);
        }
        let results: Vec<String> = rows
            .par_iter()
            .map(
                |v| match classify(&Parameters::new(v[0], v[1]), v[2], v[3], v[4], &settings) {
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
        ensure_parent(output)?;
        let mut text =
            String::from("omega,alpha,beta,phi0,psi0,class,decision,periods,with_rest\n");
        for r in results {
            text.push_str(&r);
            text.push('\n');
        }
        std::fs::write(output, text).map_err(io_err(output))?;
        writeln!(
            out,
            "classified {} trials into {}",
            rows.len(),
            output.display()
        )
        .map_err(stdout_err)?;
        return Ok(());
    }
    let params = Parameters::new(args.omega, args.alpha);
    let c = classify(&params, args.beta, args.phi0, args.psi0, &settings)?;
    if args.json {
        let v = serde_json::json!({
            "omega": args.omega, "alpha": args.alpha, "beta": args.beta,
            "phi0": args.phi0, "psi0": args.psi0,
            "class": c.class.name(), "decision": c.decision, "periods": c.periods,
            "with_rest": c.with_rest,
        });
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

fn run_simulate(args: &SimulateArgs, out: &mut dyn Write) -> Result<()> {
    let params = Parameters {
        omega: args.omega,
        alpha: args.alpha,
        xi: args.xi,
        theta_b: args.theta_b,
    };
    let wants_files = args.csv.is_some() || args.svg.is_some();
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
    let (report, traj) = simulate(&req)?;
    if let Some(path) = &args.csv {
        ensure_parent(path)?;
        let mut text = String::from("t,mode,phi,psi,r,s\n");
        for (t, mode, x) in traj.samples.iter() {
            let name = crate::model::RockingBlock.mode_name(mode);
            text.push_str(&format!("{t},{name},{},{},{},{}\n", x[0], x[1], x[2], x[3]));
        }
        std::fs::write(path, text).map_err(io_err(path))?;
    }
    if let Some(path) = &args.svg {
        ensure_parent(path)?;
        let title = format!(
            "rocking block: omega = {}, alpha = {}, phi0 = {}, psi0 = {} ({:?})",
            params.omega, params.alpha, args.phi0, args.psi0, report.outcome
        );
        plot::trajectory_svg(path, &title, &traj, &params)?;
    }
    let stdout_err = |source| Error::Io {
        path: PathBuf::from("<stdout>"),
        source,
    };
    if args.json {
        let text = serde_json::to_string_pretty(&report).expect("report serialises");
        writeln!(out, "{text}").map_err(stdout_err)?;
    } else {
        writeln!(
            out,
            "outcome: {:?}\nt_end: {:.6}\nimpacts: {}\nfinal mode: {}\nfinal state: {:?}\n\
             rest times: {:?}\nsteps: {} (rejected {}), rhs evaluations: {}",
            report.outcome,
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
