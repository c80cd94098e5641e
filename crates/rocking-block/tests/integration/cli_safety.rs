//! What the command-line probe found, pinned: outputs never replace inputs or each other
//! (devices are written through), ranges outside the domain and windows that exclude the start
//! are refused, count files whose tables disagree with the trials counted are refused by
//! `merge` and `--resume`, `--resume` takes no study options, extreme values and `-inf` are
//! refused by name, and a default step follows the window given. Every refusal is one line
//! with exit code 2.

use crate::common;

use common::{RunOk, bin, fails, json};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rb-safety-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn run(args: &[&str], files: &[&Path]) -> std::process::Output {
    bin().args(args).args(files).output().unwrap()
}

/// A saved omega branch (a few points) with its labels of regular and special points.
fn saved_run(dir: &Path) -> PathBuf {
    let path = dir.join("run.json");
    bin()
        .args(["continue", "--free", "alpha", "--kind", "asymmetric-pos"])
        .args(["--max-points", "400", "--out"])
        .arg(&path)
        .run_ok();
    path
}

fn pd_label(saved: &Path) -> String {
    let v = json(saved);
    v["branch"]["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["kind"] == "PD")
        .map(|s| s["point"]["label"].to_string())
        .expect("a PD on the asymmetric branch")
}

#[test]
fn outputs_never_replace_inputs_or_each_other() {
    let dir = scratch("clobber");
    let saved = saved_run(&dir);
    let before = std::fs::read(&saved).unwrap();
    let pd = pd_label(&saved);
    let s = saved.to_str().unwrap();
    let x = dir.join("x").display().to_string();
    let y = dir.join("y").display().to_string();
    let z = dir.join("z").display().to_string();
    let alias = dir.join(".").join("run.json").display().to_string();
    let cases: [(Vec<&str>, &str); 8] = [
        (
            vec![
                "curve",
                "--restart",
                s,
                "--label",
                &pd,
                "--second",
                "omega",
                "--svg",
                s,
            ],
            "svg",
        ),
        (
            vec![
                "curve",
                "--restart",
                s,
                "--label",
                &pd,
                "--second",
                "omega",
                "--png",
                &alias,
            ],
            "png",
        ),
        (
            vec![
                "continue",
                "--free",
                "alpha",
                "--restart",
                s,
                "--label",
                "3",
                "--svg",
                s,
            ],
            "svg",
        ),
        (
            vec![
                "continue",
                "--free",
                "alpha",
                "--restart",
                s,
                "--label",
                "3",
                "--out",
                s,
            ],
            "out",
        ),
        (
            vec!["simulate", "--periods", "2", "--csv", &x, "--svg", &x],
            "svg",
        ),
        (
            vec!["simulate", "--periods", "2", "--svg", &y, "--png", &y],
            "png",
        ),
        (
            vec![
                "curve",
                "--restart",
                s,
                "--label",
                &pd,
                "--second",
                "omega",
                "--out",
                &z,
                "--png",
                &z,
            ],
            "png",
        ),
        (
            vec![
                "continue",
                "--free",
                "omega",
                "--max-points",
                "3",
                "--out",
                &z,
                "--svg",
                &z,
            ],
            "svg",
        ),
    ];
    for (args, flag) in cases {
        fails(&run(&args, &[]), 2, &format!("invalid argument {flag} ="));
    }
    assert_eq!(std::fs::read(&saved).unwrap(), before);
    for p in [&x, &y, &z] {
        assert!(!Path::new(p).exists(), "{p}");
    }
    // A device is written through, not replaced by a regular file.
    run(
        &[
            "simulate",
            "--periods",
            "2",
            "--svg",
            "/dev/null",
            "--csv",
            "/dev/null",
        ],
        &[],
    );
    let meta = std::fs::metadata("/dev/null").unwrap();
    assert!(!meta.is_file(), "/dev/null is still a device");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn starts_outside_the_domain_or_the_window_are_refused() {
    let dir = scratch("ranges");
    let out = dir.join("basin").display().to_string();
    for phi0 in ["1e308", "1.6", "1:2", "-2:-1", "-1.5708:0"] {
        fails(
            &run(
                &["basin", "--phi0", phi0, "--trials", "5", "--out", &out],
                &[],
            ),
            2,
            "invalid argument phi0",
        );
    }
    assert!(!dir.join("basin").join("basin.json").exists());
    let saved = saved_run(&dir);
    let pd = pd_label(&saved);
    let s = saved.to_str().unwrap();
    fails(
        &run(
            &[
                "curve",
                "--restart",
                s,
                "--label",
                &pd,
                "--second",
                "omega",
                "--min",
                "2",
                "--max",
                "3",
            ],
            &[],
        ),
        2,
        "outside the bounds [2, 3]",
    );
    // A label of a regular point where a special one is needed says so.
    fails(
        &run(
            &["curve", "--restart", s, "--label", "3", "--second", "omega"],
            &[],
        ),
        2,
        "is a regular point, not a special point",
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Count files whose tables disagree with the trials they counted: Fig. 10's tables bin the
/// same trials, so one short (if self-consistent) or empty table is refused by `merge` and by
/// `figure --resume` rather than drawn as if complete.
#[test]
fn count_tables_are_checked_against_the_trials_counted() {
    let dir = scratch("tables");
    let d = dir.display().to_string();
    let partial_dir = dir.join("partial");
    let p = partial_dir.display().to_string();
    for (s, out) in [("0/2", d.as_str()), ("1/2", d.as_str())] {
        bin()
            .args([
                "figure", "10", "--trials", "600", "--shard", s, "--out", out,
            ])
            .run_ok();
    }
    let out = bin()
        .args([
            "figure",
            "10",
            "--trials",
            "600",
            "--shard",
            "0/2",
            "--threads",
            "1",
        ])
        .args(["--stop-after", "200", "--out", &p])
        .output()
        .unwrap();
    fails(&out, 1, "interrupted");
    let (s0, s1) = (
        dir.join("fig10.shard-0-of-2.json"),
        dir.join("fig10.shard-1-of-2.json"),
    );
    let partial = json(&partial_dir.join("fig10.shard-0-of-2.partial.json"));
    // Shard 0 with table 1 of the partial run (256 trials, consistent in itself).
    let mut short = json(&s0);
    short["counts"][1] = partial["counts"][1].clone();
    let short_path = dir.join("short.json");
    std::fs::write(&short_path, short.to_string()).unwrap();
    let merged = dir.join("merged").display().to_string();
    fails(
        &run(&["merge", "--out", &merged], &[&short_path, &s1]),
        2,
        "table 1 counts 256 trials",
    );
    // The partial with table 2 emptied.
    let mut empty = partial.clone();
    let cells = empty["counts"][2]["counts"].as_array().unwrap().len();
    let classes = empty["counts"][2]["classes"].as_array().unwrap().len();
    empty["counts"][2]["counts"] = serde_json::json!(vec![vec![0; classes]; cells]);
    empty["counts"][2]["failures"] = serde_json::json!(vec![0; cells]);
    empty["counts"][2]["ranges"] = serde_json::json!([]);
    let empty_path = dir.join("fig10.shard-0-of-2.partial.json");
    std::fs::write(&empty_path, empty.to_string()).unwrap();
    fails(
        &run(&["figure", "--out", &d, "--resume"], &[&empty_path]),
        2,
        "table 2 counts 0 trials",
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn resume_takes_no_study_options_and_extreme_values_are_named() {
    let dir = scratch("options");
    let file = dir.join("p.json");
    std::fs::write(&file, "{}").unwrap();
    for flag in ["--trials", "--seed", "--shard"] {
        let value = if flag == "--shard" { "0/2" } else { "5" };
        let out = run(&["figure", flag, value, "--resume"], &[&file]);
        fails(&out, 2, &format!("'{flag} <"));
        assert!(String::from_utf8_lossy(&out.stderr).contains("cannot be used with"));
    }
    let cases = [
        (vec!["simulate", "--omega", "1e308"], "omega = 1e308"),
        (vec!["simulate", "--alpha", "1e308"], "alpha = 1e308"),
        (vec!["simulate", "--xi", "1e308"], "xi = 1e308"),
        (vec!["simulate", "--psi0", "1e308"], "psi0 = 1e308"),
        (vec!["simulate", "--atol", "1e308"], "atol = 1e308"),
        (vec!["simulate", "--r0", "1e308", "--s0", "0"], "r0/s0"),
        (vec!["classify", "--omega", "1e-308"], "omega = 1e-308"),
        (vec!["orbit", "--alpha", "1e308"], "alpha = 1e308"),
        (vec!["simulate", "--omega", "-inf"], "omega = -inf"),
        (
            vec!["figure", "7", "--trials", "-inf"],
            "invalid value '-inf' for '--trials",
        ),
        (
            vec!["continue", "--free", "alpha", "--max-points", "-inf"],
            "'--max-points",
        ),
    ];
    for (args, needle) in cases {
        fails(&run(&args, &[]), 2, needle);
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `--h-max 0.01` alone: the default first step (0.02) follows it down; a first step given
/// outside the window is refused.
#[test]
fn a_default_first_step_follows_the_window_given() {
    let out = bin()
        .args([
            "continue",
            "--free",
            "omega",
            "--h-max",
            "0.01",
            "--max-points",
            "5",
        ])
        .args(["--direction", "up", "--json"])
        .run_ok();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let points = v["points"].as_array().unwrap();
    assert_eq!(points.len(), 5);
    fails(
        &run(
            &[
                "continue",
                "--free",
                "omega",
                "--h0",
                "0.5",
                "--max-points",
                "3",
            ],
            &[],
        ),
        2,
        "h0 = 0.5",
    );
}

/// A build without the `mpi` feature started by an MPI launcher (as `mpirun -n 2` would: its
/// variables say rank 0 of 2) refuses to run rather than run the whole job on every rank.
#[cfg(not(feature = "mpi"))]
#[test]
fn a_build_without_mpi_refuses_to_be_one_rank_of_several() {
    let dir = scratch("no-mpi");
    for var in ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"] {
        let out = bin()
            .args(["figure", "7", "--trials", "10", "--out"])
            .arg(&dir)
            .env(var, "2")
            .output()
            .unwrap();
        common::fails(&out, 2, "built without MPI");
        assert!(!dir.join("fig7.json").exists());
    }
    // One rank of one is one process.
    bin()
        .args(["figure", "7", "--trials", "10", "--out"])
        .arg(&dir)
        .env("OMPI_COMM_WORLD_SIZE", "1")
        .run_ok();
    std::fs::remove_dir_all(&dir).ok();
}
