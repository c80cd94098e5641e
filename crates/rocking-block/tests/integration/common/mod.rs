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

/// The JSON of a result file.
#[allow(dead_code)]
pub fn json(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// A result without its provenance (which names the command line that wrote it).
#[allow(dead_code)]
pub fn without_provenance(v: &serde_json::Value) -> serde_json::Value {
    let mut v = v.clone();
    v.as_object_mut().unwrap().remove("provenance");
    v
}

/// An empty scratch directory for test `name` of this process (not created).
#[allow(dead_code)]
pub fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("rb-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    dir
}

/// Checks that a run failed with exit `code` and one line on stderr containing `needle` (no
/// panic).
#[allow(dead_code)]
pub fn fails(out: &Output, code: i32, needle: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains(needle), "expected {needle:?} in {err}");
    assert!(!err.contains("panicked"), "{err}");
}
