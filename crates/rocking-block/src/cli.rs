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
    }
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
