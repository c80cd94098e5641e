//! `rocking-block`: reproduces the rocking-block study from the command line.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    // A panic is a bug; still, report it on one line rather than with a backtrace.
    std::panic::set_hook(Box::new(|info| {
        let msg = info
            .payload()
            .downcast_ref::<&str>()
            .map(ToString::to_string)
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into());
        let place = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        eprintln!("rocking-block: internal error{place}: {msg}");
    }));
    // Under an MPI launcher (feature `mpi`): MPI for the whole run, finalised at its end.
    #[cfg(feature = "mpi")]
    let _mpi = rocking_block::cli::start_mpi();
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let command_line: Vec<String> = args
        .iter()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    let cli = match rocking_block::cli::Cli::try_parse_from(&args) {
        Ok(cli) => cli,
        Err(e) => {
            if !e.use_stderr() {
                // --help, --version
                let _ = e.print();
                return ExitCode::SUCCESS;
            }
            // One line: clap's message without the usage block, whitespace collapsed.
            let text = e.to_string();
            let body = text.split("\n\nUsage").next().unwrap_or(&text);
            let line = body.split_whitespace().collect::<Vec<_>>().join(" ");
            eprintln!(
                "rocking-block: {} (see --help)",
                line.trim_start_matches("error: ")
            );
            return ExitCode::from(2);
        }
    };
    let mut stdout = std::io::stdout().lock();
    match rocking_block::cli::run(cli, &command_line, &mut stdout) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("rocking-block: {e}");
            ExitCode::from(if e.is_usage() { 2 } else { 1 })
        }
    }
}
