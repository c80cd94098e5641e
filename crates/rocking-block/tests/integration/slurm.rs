//! The Slurm job-array scripts (`scripts/slurm`) run locally: `submit.sh` with a stand-in
//! `sbatch` that runs each job at once (an array's tasks in order, each with its
//! `SLURM_ARRAY_TASK_ID`), so that the steps a cluster runs (the shards, a shard requeued after
//! an interrupt, the dependent merge) run here as they would there. The merged figure must be
//! the one a single process writes.

use crate::common;

use common::{RunOk, bin, json, scratch, without_provenance};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A stand-in for `sbatch`: logs its options, runs the job script with bash (every task of
/// `--array=LO-HI` in order), writes the job's output to `job-ID[-TASK].out` as Slurm does and
/// prints the job id (`--parsable`). A failing task fails the submission.
const SBATCH: &str = r#"#!/usr/bin/env bash
set -euo pipefail
dir=$(dirname "$0")
shopt -s nullglob
logs=("$dir"/job-*.log)
id=$(( ${#logs[@]} + 100 ))
array=
while [[ $# -gt 0 && $1 == --* ]]; do
  case "$1" in --array=*) array=${1#--array=} ;; esac
  echo "$1" >> "$dir/job-$id.log"
  shift
done
touch "$dir/job-$id.log"
if [[ -n $array ]]; then
  for ((t = ${array%-*}; t <= ${array#*-}; t++)); do
    SLURM_ARRAY_TASK_ID=$t SLURM_CPUS_PER_TASK=2 bash "$@" > "$dir/job-$id-$t.out" 2>&1
  done
else
  bash "$@" > "$dir/job-$id.out" 2>&1
fi
echo "$id"
"#;

fn scripts() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/slurm")
}

/// A directory with the stand-in `sbatch`, to put first on PATH.
fn fake_slurm(dir: &Path) -> PathBuf {
    let bin_dir = dir.join("slurm-bin");
    std::fs::create_dir_all(&bin_dir).unwrap();
    let sbatch = bin_dir.join("sbatch");
    std::fs::write(&sbatch, SBATCH).unwrap();
    Command::new("chmod").arg("+x").arg(&sbatch).run_ok();
    bin_dir
}

#[test]
fn a_job_array_and_its_merge_write_what_one_process_writes() {
    let dir = scratch("slurm");
    let out = dir.join("out");
    let run = ["figure", "7", "--trials", "600", "--seed", "5"];
    // Shard 1 was interrupted before (as by the time limit's SIGTERM): its partial file is there.
    bin()
        .args(run)
        .args([
            "--shard",
            "1/3",
            "--stop-after",
            "1",
            "--threads",
            "1",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let partial = out.join("fig7.shard-1-of-3.partial.json");
    assert!(
        partial.exists(),
        "the interrupted shard left no partial file"
    );
    let slurm = fake_slurm(&dir);
    let path = format!(
        "{}:{}",
        slurm.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let submitted = Command::new("bash")
        .arg(scripts().join("submit.sh"))
        .arg("3")
        .arg(&out)
        .args(run)
        .env("PATH", &path)
        .env("ROCKING_BLOCK", env!("CARGO_BIN_EXE_rocking-block"))
        .run_ok();
    let said = String::from_utf8_lossy(&submitted.stdout);
    assert!(
        said.contains("shards: job 100 (array 0-2), merge: job 101"),
        "{said}"
    );
    // The merge job was made to wait for the array.
    let merge_log = std::fs::read_to_string(slurm.join("job-101.log")).unwrap();
    assert!(
        merge_log.contains("--dependency=afterok:100"),
        "{merge_log}"
    );
    assert!(
        std::fs::read_to_string(slurm.join("job-100.log"))
            .unwrap()
            .contains("--array=0-2")
    );
    // The requeued shard resumed (its partial file is gone) and every shard is complete.
    assert!(!partial.exists());
    for i in 0..3 {
        assert!(out.join(format!("fig7.shard-{i}-of-3.json")).exists());
    }
    let whole = dir.join("whole");
    bin().args(run).arg("--out").arg(&whole).run_ok();
    assert_eq!(
        without_provenance(&json(&out.join("fig7.json"))),
        without_provenance(&json(&whole.join("fig7.json")))
    );
    assert_eq!(
        std::fs::read(out.join("fig7.svg")).unwrap(),
        std::fs::read(whole.join("fig7.svg")).unwrap()
    );
    // Submitted again, every task finds its shard written and skips it.
    let again = Command::new("bash")
        .arg(scripts().join("shard.sbatch"))
        .args(["3"])
        .arg(&out)
        .args(run)
        .env("SLURM_ARRAY_TASK_ID", "2")
        .env("ROCKING_BLOCK", env!("CARGO_BIN_EXE_rocking-block"))
        .run_ok();
    assert!(String::from_utf8_lossy(&again.stdout).contains("already written"));
    std::fs::remove_dir_all(&dir).ok();
}

/// With one task the task runs the whole study and writes the figure itself (as `--shard
/// 0/1` does), the merge job finds it, a requeued task resumes from the whole run's partial
/// file, and a finished task is not redone.
#[test]
fn one_task_writes_the_whole_run() {
    let dir = scratch("slurm-one");
    let out = dir.join("out");
    let run = ["figure", "7", "--trials", "300", "--seed", "5"];
    // Interrupted before, as by the time limit: the whole run's partial file.
    let first = bin()
        .args(run)
        .args([
            "--shard",
            "0/1",
            "--stop-after",
            "1",
            "--threads",
            "1",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(first.status.code(), Some(1));
    let partial = out.join("fig7.partial.json");
    assert!(
        partial.exists(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let slurm = fake_slurm(&dir);
    let path = format!(
        "{}:{}",
        slurm.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let submit = || {
        Command::new("bash")
            .arg(scripts().join("submit.sh"))
            .arg("1")
            .arg(&out)
            .args(run)
            .env("PATH", &path)
            .env("ROCKING_BLOCK", env!("CARGO_BIN_EXE_rocking-block"))
            .run_ok()
    };
    submit();
    assert!(!partial.exists(), "the requeued task did not resume");
    let whole = dir.join("whole");
    bin().args(run).arg("--out").arg(&whole).run_ok();
    assert_eq!(
        without_provenance(&json(&out.join("fig7.json"))),
        without_provenance(&json(&whole.join("fig7.json")))
    );
    let merge_out = std::fs::read_to_string(slurm.join("job-101.out")).unwrap();
    assert!(merge_out.contains("written by the task"), "{merge_out}");
    // Submitted again: the task finds the figure written and skips it.
    submit();
    let task = std::fs::read_to_string(slurm.join("job-102-0.out")).unwrap();
    assert!(task.contains("already written"), "{task}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_scripts_refuse_what_they_cannot_run() {
    for (script, args, env) in [
        ("submit.sh", vec!["0", "out", "figure", "7"], None),
        ("submit.sh", vec!["3"], None),
        (
            "submit.sh",
            vec!["3", "out", "simulate", "--omega", "1.3"],
            None,
        ),
        ("submit.sh", vec!["3", "out", "figure", "5"], None),
        ("shard.sbatch", vec!["3", "out", "figure", "all"], Some("0")),
        ("shard.sbatch", vec!["3", "out", "simulate"], Some("0")),
        ("merge.sbatch", vec!["3", "out", "orbit"], None),
    ] {
        let mut cmd = Command::new("bash");
        cmd.arg(scripts().join(script)).args(&args);
        if let Some(task) = env {
            cmd.env("SLURM_ARRAY_TASK_ID", task);
        }
        // An sbatch that must not be called: a refused command submits nothing.
        let dir = scratch(&format!("slurm-refuse-{}", args.len()));
        let slurm = fake_slurm(&dir);
        let path = format!(
            "{}:{}",
            slurm.display(),
            std::env::var("PATH").unwrap_or_default()
        );
        let out = cmd.env("PATH", &path).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{script} {args:?}");
        let jobs = std::fs::read_dir(&slurm)
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .is_ok_and(|e| e.file_name().to_string_lossy().starts_with("job-"))
            })
            .count();
        assert_eq!(jobs, 0, "{script} {args:?} submitted a job");
        std::fs::remove_dir_all(&dir).ok();
    }
    // Outside an array a shard does not guess its task.
    let out = Command::new("bash")
        .arg(scripts().join("shard.sbatch"))
        .args(["3", "out", "figure", "7"])
        .env_remove("SLURM_ARRAY_TASK_ID")
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("job array"));
}

/// The scripts drive any program that keeps the runner's contract (`$STUDY_BIN`, files named
/// after `$STUDY_NAME`): a task runs `COMMAND ARGS --shard I/N --out OUT`, a task run again
/// resumes its partial file with `COMMAND --resume PARTIAL --out OUT`, and the merge job runs
/// `merge SHARDS --out OUT`; a name that is not a file stem is refused.
#[test]
fn the_scripts_drive_any_program_of_the_contract() {
    let dir = scratch("slurm-contract");
    std::fs::create_dir_all(&dir).unwrap();
    // A stand-in program that records its arguments.
    let program = dir.join("study");
    std::fs::write(
        &program,
        format!(
            "#!/usr/bin/env bash\necho \"$@\" >> {}\n",
            dir.join("calls").display()
        ),
    )
    .unwrap();
    Command::new("chmod").arg("+x").arg(&program).run_ok();
    let out = dir.join("out");
    let run = |script: &str, task: Option<&str>, name: &str| {
        let mut cmd = Command::new("bash");
        cmd.arg(scripts().join(script))
            .args(["3", out.to_str().unwrap(), "basins", "--seed", "5"])
            .env("STUDY_BIN", &program)
            .env("STUDY_NAME", name);
        if let Some(t) = task {
            cmd.env("SLURM_ARRAY_TASK_ID", t);
        }
        cmd.output().unwrap()
    };
    assert!(run("shard.sbatch", Some("1"), "table").status.success());
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("table.shard-2-of-3.partial.json"), "{}").unwrap();
    assert!(run("shard.sbatch", Some("2"), "table").status.success());
    assert!(run("merge.sbatch", None, "table").status.success());
    let calls = std::fs::read_to_string(dir.join("calls")).unwrap();
    let o = out.display();
    let expected = format!(
        "basins --seed 5 --shard 1/3 --out {o}\nbasins --resume {o}/table.shard-2-of-3.partial.json --out {o}\nmerge {o}/table.shard-0-of-3.json {o}/table.shard-1-of-3.json {o}/table.shard-2-of-3.json --out {o}\n"
    );
    assert_eq!(calls, expected);
    assert_eq!(run("shard.sbatch", Some("0"), "a/b").status.code(), Some(2));
    std::fs::remove_dir_all(&dir).ok();
}
