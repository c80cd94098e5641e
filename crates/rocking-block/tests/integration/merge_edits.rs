//! `merge` re-checks what it reads: shard files of an adaptive Fig. 9 (cells sampled to a
//! rule) and of a fixed-trial Fig. 10, edited at one value at random, are refused (one line,
//! exit 2; a merge that lacks trials writes its partial file, exit 1), or merge to the figure
//! the unedited files give, never a panic or another figure. The edits of the issue that found
//! the adaptive files trusted (a settled cell emptied, trials that are not whole batches or
//! exceed the cap) are refused by name. 100 cases per format (`PROPTEST_CASES` overrides).

use crate::common;
#[path = "../../../hycont-continuation/tests/integration/common/edits.rs"]
mod edits;

use common::{RunOk, bin, fails, json, scratch, without_provenance};
use edits::{EDITS, edit, leaf_paths};
use proptest::prelude::*;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: std::env::var("PROPTEST_CASES")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(100),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// Shards 0 and 1 of 2 of `figure` with `options`, written into `dir`.
fn shards(dir: &Path, figure: &str, options: &[&str]) -> [PathBuf; 2] {
    for i in 0..2 {
        bin()
            .args(["figure", figure])
            .args(options)
            .args(["--shard", &format!("{i}/2"), "--out"])
            .arg(dir)
            .run_ok();
    }
    [0, 1].map(|i| dir.join(format!("fig{figure}.shard-{i}-of-2.json")))
}

/// The merge of `first` (a file's text) and the file `second` into `out`: the figure's JSON
/// without provenance, or the exit code (after checking the failure is one line, no panic).
fn merged(first: &str, second: &Path, out: &Path, figure: &str) -> Result<Value, i32> {
    let input = out.with_extension("in.json");
    std::fs::write(&input, first).unwrap();
    std::fs::remove_dir_all(out).ok();
    let o = bin()
        .arg("merge")
        .arg(&input)
        .arg(second)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    match o.status.code() {
        Some(0) => Ok(without_provenance(&json(
            &out.join(format!("fig{figure}.json")),
        ))),
        Some(code @ (1 | 2)) => {
            assert!(!err.contains("panicked"), "{err}");
            assert_eq!(err.trim_end().lines().count(), 1, "{err}");
            Err(code)
        }
        other => panic!("exit {other:?}: {err}"),
    }
}

/// Random single edits of shard 0, merged with shard 1.
fn fuzz(dir: &Path, figure: &str, paths: &[PathBuf; 2]) {
    let text = std::fs::read_to_string(&paths[0]).unwrap();
    let out = dir.join("out");
    let reference = merged(&text, &paths[1], &out, figure).expect("the unedited files merge");
    let value: Value = serde_json::from_str(&text).unwrap();
    // The provenance records the command line: informational, not read.
    let leaves: Vec<_> = leaf_paths(&value)
        .into_iter()
        .filter(|p| !matches!(p.first(), Some(edits::Step::Key(k)) if k == "provenance"))
        .collect();
    proptest!(config(), |(leaf in 0..leaves.len(), op in 0..EDITS)| {
        let mut v = value.clone();
        edit(&mut v, &leaves[leaf], op);
        if let Ok(figure) = merged(&v.to_string(), &paths[1], &out, figure) {
            prop_assert!(
                figure == reference,
                "edit {op} of {:?} merged to another figure",
                leaves[leaf]
            );
        }
    });
}

#[test]
fn edited_adaptive_cell_files_are_refused() {
    let dir = scratch("merge-edits-9");
    let options = ["--halfwidth", "0.05", "--max-per-cell", "16", "--seed", "4"];
    let paths = shards(&dir, "9", &options);
    let text = std::fs::read_to_string(&paths[0]).unwrap();
    let refused = |edit: &dyn Fn(&mut Value), needle: &str| {
        let mut v: Value = serde_json::from_str(&text).unwrap();
        edit(&mut v);
        let input = dir.join("edited.json");
        std::fs::write(&input, v.to_string()).unwrap();
        let o = bin()
            .arg("merge")
            .arg(&input)
            .arg(&paths[1])
            .arg("--out")
            .arg(dir.join("edited"))
            .output()
            .unwrap();
        fails(&o, 2, needle);
    };
    // A settled cell emptied: settled with no trials where the cell has trials to run.
    refused(
        &|v| {
            let t = &mut v["tables"][0];
            t["trials"][3] = 0.into();
            t["failures"][3] = 0.into();
            for c in t["counts"][3].as_array_mut().unwrap() {
                *c = 0.into();
            }
        },
        "cell 3: it says it is settled, with 0 trials",
    );
    // 161 trials (counts adding up): not whole batches of 16.
    refused(
        &|v| {
            let t = &mut v["tables"][0];
            t["trials"][3] = 161.into();
            let c0 = t["counts"][3][0].as_u64().unwrap();
            t["counts"][3][0] = (c0 + 145).into();
        },
        "161 trials: not whole batches of 16",
    );
    // 8,352 trials against a cap of 16 (the study's 4,096 scaled down).
    refused(
        &|v| {
            let t = &mut v["tables"][0];
            t["trials"][3] = 8352.into();
            let c0 = t["counts"][3][0].as_u64().unwrap();
            t["counts"][3][0] = (c0 + 8336).into();
        },
        "8352 trials",
    );
    fuzz(&dir, "9", &paths);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn edited_fixed_trial_shard_files_are_refused() {
    let dir = scratch("merge-edits-10");
    let paths = shards(&dir, "10", &["--trials", "2000"]);
    fuzz(&dir, "10", &paths);
    std::fs::remove_dir_all(&dir).ok();
}
