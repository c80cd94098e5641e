//! The `rocking-block` command line: the arguments ([`Cli`]), the commands, and how they write
//! files ([`crate::output`]).

mod args;
mod commands;
mod continue_cmd;
mod curve_cmd;
mod sampling;
mod shard_file;

pub use shard_file::{MAX_TRIALS, SAMPLING, ShardFile};

pub use args::*;

use crate::error::{Error, Result};
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
pub fn run(cli: Cli, out: &mut dyn Write) -> Result<()> {
    match cli.command {
        Command::Simulate(args) => commands::run_simulate(&args, out),
        Command::Orbit(args) => commands::run_orbit(&args, out),
        Command::Figure(args) => sampling::run_figure(&args, out),
        Command::Continue(args) => continue_cmd::run_continue(&args, out),
        Command::Curve(args) => curve_cmd::run_curve(&args, out),
        Command::Classify(args) => commands::run_classify(&args, out),
        Command::Merge(args) => sampling::run_merge(&args, out),
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
