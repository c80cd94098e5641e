//! `mpirun -n 2 rocking-block figure|basin ...` (feature `mpi`; needs `mpirun` on PATH): the
//! ranks split the trials, rank 0 writes byte for byte what one process writes (same command
//! line, so even the provenance agrees; Fig. 9 sampled cell by cell too), shards and resumed
//! runs split alike, an interrupt of the ranks (or of one of them: it stops them all) keeps
//! every trial counted, and the other commands refuse to run on several ranks.
//! Run with `cargo test --release -p rocking-block --features mpi --test mpi`.
#![cfg(feature = "mpi")]

#[path = "integration/common/mod.rs"]
mod common;

use common::{RunOk, bin, json, scratch, without_provenance};
use std::path::Path;
use std::process::Command;

/// `mpirun -n 2` of the binary in `cwd` (Open MPI refuses root without its two variables; a
/// 2-rank job on fewer cores needs --oversubscribe).
fn mpirun(cwd: &Path, args: &[&str]) -> Command {
    std::fs::create_dir_all(cwd).unwrap();
    let mut cmd = Command::new("mpirun");
    cmd.args(["-n", "2", "--oversubscribe"])
        .arg(env!("CARGO_BIN_EXE_rocking-block"))
        .args(args)
        .current_dir(cwd)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
    cmd
}

/// One process in `cwd`.
fn single(cwd: &Path, args: &[&str]) -> Command {
    std::fs::create_dir_all(cwd).unwrap();
    let mut cmd = bin();
    cmd.args(args).current_dir(cwd);
    cmd
}

fn same_files(a: &Path, b: &Path, names: &[&str]) {
    for name in names {
        let (x, y) = (std::fs::read(a.join(name)), std::fs::read(b.join(name)));
        assert!(x.is_ok(), "{} missing", a.join(name).display());
        assert!(x.unwrap() == y.unwrap(), "{name} differs");
    }
}

#[test]
fn two_ranks_write_what_one_process_writes() {
    let dir = scratch("mpi-same");
    let runs: [(&[&str], &[&str]); 4] = [
        (
            &[
                "figure",
                "9",
                "--halfwidth",
                "0.05",
                "--max-per-cell",
                "16",
                "--out",
                "res",
            ],
            &["fig9.json", "fig9.svg"],
        ),
        (
            &[
                "figure", "9", "--trials", "600", "--seed", "2", "--out", "res",
            ],
            &["fig9.json", "fig9.svg"],
        ),
        (
            &[
                "figure", "10", "--trials", "900", "--seed", "3", "--shard", "1/2", "--out", "res",
            ],
            &["fig10.shard-1-of-2.json"],
        ),
        (
            &[
                "basin", "--omega", "1.3", "--alpha", "0.66", "--phi0", "-0.3:0.3", "--psi0",
                "-0.5:0.5", "--bin", "phi0:5", "--trials", "500", "--out", "res",
            ],
            &["basin.json", "basin.csv", "basin.svg"],
        ),
    ];
    for (k, (args, files)) in runs.iter().enumerate() {
        let (m, s) = (dir.join(format!("mpi{k}")), dir.join(format!("one{k}")));
        let said = String::from_utf8_lossy(&mpirun(&m, args).run_ok().stdout).into_owned();
        single(&s, args).run_ok();
        same_files(&m.join("res"), &s.join("res"), files);
        // Rank 0 alone reports what it wrote; the ranks' checkpoints are gone.
        assert_eq!(said.lines().count(), files.len(), "{said}");
        let left: Vec<_> = std::fs::read_dir(m.join("res"))
            .unwrap()
            .flatten()
            .filter(|e| {
                e.file_name()
                    .to_string_lossy()
                    .ends_with(".checkpoint.json")
            })
            .map(|e| e.file_name())
            .collect();
        assert!(left.is_empty(), "{left:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn interrupted_ranks_keep_every_trial_and_resume_on_two_ranks() {
    let dir = scratch("mpi-resume");
    let run = [
        "figure", "7", "--trials", "1500", "--seed", "6", "--out", "res",
    ];
    let m = dir.join("mpi");
    // Each rank stops after a budget of its trials, as at an interrupt: rank 0 writes the
    // partial file of both ranks' counts and exits 1 naming it.
    let stopped = mpirun(
        &m,
        &[&run[..], &["--stop-after", "300", "--threads", "1"]].concat(),
    )
    .output()
    .expect("mpirun runs (install an MPI: see the README)");
    assert!(!stopped.status.success());
    let err = String::from_utf8_lossy(&stopped.stderr);
    assert!(
        err.contains("interrupted") && err.contains("fig7.partial.json"),
        "{err}"
    );
    let partial = m.join("res/fig7.partial.json");
    let counted: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&partial).unwrap()).unwrap();
    // Both ranks' trials are in it: rank 0's share of each table's trials starts at 0, rank
    // 1's at 750.
    let ranges = counted["counts"][0]["ranges"].as_array().unwrap().clone();
    assert!(
        ranges.iter().any(|r| r[0].as_u64().unwrap() < 750),
        "{ranges:?}"
    );
    assert!(
        ranges.iter().any(|r| r[0].as_u64().unwrap() >= 750),
        "{ranges:?}"
    );
    assert!(!m.join("res/fig7.json").exists());
    // Resumed on two ranks: the complete figure, as one process writes it.
    mpirun(
        &m,
        &[
            "figure",
            "--resume",
            "res/fig7.partial.json",
            "--out",
            "res",
        ],
    )
    .run_ok();
    assert!(!partial.exists());
    let s = dir.join("one");
    single(&s, &run).run_ok();
    assert_eq!(
        without_provenance(&json(&m.join("res/fig7.json"))),
        without_provenance(&json(&s.join("res/fig7.json")))
    );
    same_files(&m.join("res"), &s.join("res"), &["fig7.svg"]);
    std::fs::remove_dir_all(&dir).ok();
}

/// The pid of rank `rank` of the job whose processes run in `cwd` (read off /proc: the
/// process's working directory and Open MPI's rank variable).
fn rank_pid(cwd: &Path, rank: u32) -> Option<u32> {
    let want = format!("OMPI_COMM_WORLD_RANK={rank}");
    std::fs::read_dir("/proc").ok()?.flatten().find_map(|e| {
        let pid: u32 = e.file_name().to_string_lossy().parse().ok()?;
        let here = std::fs::read_link(e.path().join("cwd")).ok()?;
        let env = std::fs::read(e.path().join("environ")).ok()?;
        let ours = here == cwd && env.split(|b| *b == 0).any(|v| v == want.as_bytes());
        ours.then_some(pid)
    })
}

/// A signal to one rank alone (SIGINT to rank 1; rank 0 and `mpirun` get none) stops the
/// whole job at the end of the round: the ranks agree after every round whether any of them
/// stops, rank 0 gathers both ranks' counts and keeps them in the partial file (trials of
/// rank 0's half, below 50,000, and of rank 1's) and exits 1 as interrupted; the resumed run
/// completes it.
#[test]
fn a_signal_to_one_rank_stops_the_whole_job() {
    let dir = scratch("mpi-signal");
    let m = dir.join("mpi");
    let mut job = mpirun(
        &m,
        &[
            "figure", "10", "--trials", "100000", "--seed", "4", "--out", "res",
        ],
    )
    .stdout(std::process::Stdio::null())
    .stderr(std::process::Stdio::piped())
    .spawn()
    .expect("mpirun runs (install an MPI: see the README)");
    let checkpoint = m.join("res/fig10.rank-1-of-2.checkpoint.json");
    while !checkpoint.exists() {
        assert!(job.try_wait().unwrap().is_none(), "the job ended first");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let pid = rank_pid(&m.canonicalize().unwrap(), 1).expect("rank 1's process");
    Command::new("kill")
        .args(["-INT", &pid.to_string()])
        .run_ok();
    let out = job.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("interrupted") && err.contains("fig10.partial.json"),
        "{err}"
    );
    assert!(!m.join("res/fig10.json").exists());
    let partial: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(m.join("res/fig10.partial.json")).unwrap())
            .unwrap();
    let ranges: Vec<(u64, u64)> = partial["counts"][0]["ranges"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (r[0].as_u64().unwrap(), r[1].as_u64().unwrap()))
        .collect();
    let counted: u64 = ranges.iter().map(|(a, b)| b - a).sum();
    assert!(ranges.iter().any(|r| r.0 < 50_000) && ranges.iter().any(|r| r.0 >= 50_000));
    assert!(counted < 100_000, "{counted} trials: the job did not stop");
    // Rank 0, not signalled, stopped too (at the same round): its half is incomplete.
    let rank0: u64 = ranges
        .iter()
        .map(|(a, b)| b.min(&50_000).saturating_sub(*a))
        .sum();
    assert!(rank0 < 50_000, "rank 0 counted all of its {rank0} trials");
    mpirun(
        &m,
        &[
            "figure",
            "--resume",
            "res/fig10.partial.json",
            "--out",
            "res",
        ],
    )
    .run_ok();
    assert!(m.join("res/fig10.json").exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// A rank killed outright (SIGKILL: no signal handler runs, `mpirun` ends the job, rank 0
/// never gathers) loses at most a round of the trials: every rank checkpoints its counts after
/// each twentieth of its share, `merge` gathers the checkpoints into the partial file, and the
/// resumed run is the figure one process writes.
#[test]
fn a_rank_killed_outright_loses_at_most_a_round() {
    let dir = scratch("mpi-kill");
    let run = [
        "figure", "10", "--trials", "100000", "--seed", "3", "--out", "res",
    ];
    let m = dir.join("mpi");
    let mut job = mpirun(&m, &run)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("mpirun runs (install an MPI: see the README)");
    let checkpoints = [0, 1].map(|r| m.join(format!("res/fig10.rank-{r}-of-2.checkpoint.json")));
    // Until both ranks have checkpointed (a round is 2,500 of each rank's 50,000 trials);
    // the job must not have ended first.
    while !checkpoints.iter().all(|c| c.exists()) {
        assert!(job.try_wait().unwrap().is_none(), "the job ended first");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let pid = rank_pid(&m.canonicalize().unwrap(), 1).expect("rank 1's process");
    Command::new("kill").args(["-9", &pid.to_string()]).run_ok();
    let status = job.wait().unwrap();
    assert!(!status.success());
    assert!(!m.join("res/fig10.json").exists());
    // The checkpoints merge into the run's partial file (incomplete: exit 1) ...
    let merged = single(&m, &["merge"])
        .args(checkpoints.iter().map(|c| c.strip_prefix(&m).unwrap()))
        .args(["--out", "res"])
        .output()
        .unwrap();
    assert_eq!(merged.status.code(), Some(1));
    let partial: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(m.join("res/fig10.partial.json")).unwrap())
            .unwrap();
    let counted: u64 = partial["counts"][0]["ranges"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r[1].as_u64().unwrap() - r[0].as_u64().unwrap())
        .sum();
    // Each rank had checkpointed a round at least: 2 x 2,500 of the 100,000 trials.
    assert!(counted >= 5000, "{counted} trials kept");
    // ... which the resumed run completes into what one process writes.
    single(
        &m,
        &[
            "figure",
            "--resume",
            "res/fig10.partial.json",
            "--out",
            "res",
        ],
    )
    .run_ok();
    let s = dir.join("one");
    single(&s, &run).run_ok();
    assert_eq!(
        without_provenance(&json(&m.join("res/fig10.json"))),
        without_provenance(&json(&s.join("res/fig10.json")))
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn other_commands_refuse_several_ranks() {
    let dir = scratch("mpi-refuse");
    let out = mpirun(&dir, &["simulate", "--periods", "2"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("only `figure` and `basin` split across MPI ranks"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
