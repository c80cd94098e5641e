//! Running the `rocking-block` binary from the integration tests.

use std::process::{Command, Output};

/// The `rocking-block` binary of this build.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rocking-block"))
}

/// Runs a command that must succeed (its stderr is the failure message).
pub trait RunOk {
    /// The output of a successful run.
    fn run_ok(&mut self) -> Output;
}

impl RunOk for Command {
    fn run_ok(&mut self) -> Output {
        let out = self.output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        out
    }
}
