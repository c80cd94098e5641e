//! The `rocking-block` command line: the arguments ([`Cli`]), the commands, and how they write
//! files ([`crate::output`]).

mod args;
mod basin_cells;
mod basin_cmd;
mod basin_file;
mod block_args;
mod cell_file;
mod commands;
mod continue_cmd;
mod curve_cmd;
mod diagram_cmd;
mod driver;
mod ranks;
mod sampling;
mod shard_file;

#[cfg(feature = "mpi")]
pub use ranks::start_mpi;
pub use shard_file::{MAX_TRIALS, SAMPLING, ShardFile};

pub use args::*;
pub use basin_cells::BasinCellFile;
pub use basin_cmd::BasinArgs;
pub use basin_file::BasinFile;
pub use block_args::{describe, parameters};
pub use cell_file::CellFile;
pub use diagram_cmd::DiagramArgs;

use crate::error::{Error, Result};
use crate::provenance::Provenance;
use std::io::Write;
use std::path::{Path, PathBuf};

/// A failed write to standard output.
fn stdout_err(source: std::io::Error) -> Error {
    Error::Io {
        path: PathBuf::from("<stdout>"),
        source,
    }
}

/// A failed read of an input file.
fn read_err(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |source| Error::Read {
        path: path.to_path_buf(),
        source,
    }
}

/// Runs a parsed command line, writing results to `out`.
///
/// # Errors
/// Invalid arguments, numerical failures, or files that cannot be written.
/// Every JSON it writes records `command_line` (program first) in its provenance
/// ([`crate::provenance`]).
///
/// In an MPI job of several ranks (feature `mpi`) only `figure` and `basin` run: every rank
/// counts its share of the trials and rank 0 alone writes files and output.
pub fn run(cli: Cli, command_line: &[String], out: &mut dyn Write) -> Result<()> {
    let invocation = &Provenance::from_command_line(command_line);
    ranks::check_launcher()?;
    let ranks = ranks::Ranks::current();
    let mut sink = std::io::sink();
    let out: &mut dyn Write = if ranks.is_root() { out } else { &mut sink };
    match cli.command {
        Command::Figure(_) | Command::Basin(_) => {}
        Command::Simulate(_) => ranks::only_sampling(ranks, "simulate")?,
        Command::Orbit(_) => ranks::only_sampling(ranks, "orbit")?,
        Command::Continue(_) => ranks::only_sampling(ranks, "continue")?,
        Command::Curve(_) => ranks::only_sampling(ranks, "curve")?,
        Command::Diagram(_) => ranks::only_sampling(ranks, "diagram")?,
        Command::Classify(_) => ranks::only_sampling(ranks, "classify")?,
        Command::Merge(_) => ranks::only_sampling(ranks, "merge")?,
    }
    match cli.command {
        Command::Simulate(args) => commands::run_simulate(&args, invocation, out),
        Command::Orbit(args) => commands::run_orbit(&args, invocation, out),
        Command::Figure(args) => sampling::run_figure(&args, invocation, out),
        Command::Continue(args) => continue_cmd::run_continue(&args, invocation, out),
        Command::Curve(args) => curve_cmd::run_curve(&args, invocation, out),
        Command::Diagram(args) => diagram_cmd::run_diagram(&args, invocation, out),
        Command::Classify(args) => commands::run_classify(&args, invocation, out),
        Command::Merge(args) => sampling::run_merge(&args, invocation, out),
        Command::Basin(args) => basin_cmd::run_basin(&args, invocation, out),
    }
}

/// Prints the files written, as lines or as JSON.
fn print_written(out: &mut dyn Write, files: &[PathBuf], json: bool) -> Result<()> {
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
