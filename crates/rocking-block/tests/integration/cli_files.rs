//! Nothing lost, nothing clobbered: interrupts keep the exact trials counted in a partial file
//! that never replaces a complete result and that `--resume` completes to the same figure as an
//! uninterrupted run; `merge` checks every file; writers never replace their inputs; sizes and
//! windows are bounded. Every case exits with one line: 2 for bad input, 1 for a run that
//! could not finish.

use crate::common;

use common::{RunOk, bin, fails, json, without_provenance};
use std::path::{Path, PathBuf};
use std::process::Output;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rb-files-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Starts `args`, sends `signal` (`"INT"`, `"TERM"`, `"HUP"`) once the process has installed
/// its handler for it (read off `/proc/PID/status`, so that the signal is never delivered
/// before the run can keep its counts, however loaded the machine), and returns the output.
/// The run must be long enough not to finish first (e.g. a study of 10^9 trials).
fn interrupted(args: &[&str], signal: &str) -> Output {
    let mut child = bin()
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let bit = match signal {
        "HUP" => 1,
        "INT" => 2,
        "TERM" => 15,
        other => panic!("no signal {other}"),
    } - 1;
    let status = format!("/proc/{}/status", child.id());
    let caught = || {
        std::fs::read_to_string(&status)
            .ok()
            .and_then(|text| {
                let mask = text.lines().find_map(|l| l.strip_prefix("SigCgt:"))?;
                u64::from_str_radix(mask.trim(), 16).ok()
            })
            .is_some_and(|mask| mask & (1 << bit) != 0)
    };
    // Polls for the event (the handler in SigCgt), not for a time: the poll interval only
    // spaces the reads. A run that ends before installing it fails here instead of hanging.
    while !caught() {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended ({status}) before its {signal} handler was installed");
        }
        std::thread::yield_now();
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    let sent = std::process::Command::new("kill")
        .args([format!("-{signal}"), child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    child.wait_with_output().unwrap()
}

/// A shard stopped early (`--stop-after`, which stops as an interrupt does, after a number of
/// trials rather than a time): the partial shard holds whole chunks of trials with exact
/// ranges; `--resume` runs the rest, and the shard equals the uninterrupted one byte for byte.
#[test]
fn an_interrupted_shard_resumes_to_the_uninterrupted_shard() {
    let dir = scratch("shard");
    let (a, b) = (dir.join("a"), dir.join("b"));
    let args = |out: &Path| {
        vec![
            "figure".to_string(),
            "10".into(),
            "--trials".into(),
            "40000".into(),
            "--shard".into(),
            "0/2".into(),
            "--out".into(),
            out.display().to_string(),
        ]
    };
    // One thread (results do not depend on it): it stops after 8 chunks of 256 trials.
    let mut run: Vec<String> = args(&a);
    run.extend(["--threads", "1", "--stop-after", "2000"].map(String::from));
    let run: Vec<&str> = run.iter().map(String::as_str).collect();
    let out = bin().args(&run).output().unwrap();
    fails(&out, 1, "figure --resume");
    let partial = a.join("fig10.shard-0-of-2.partial.json");
    assert!(!a.join("fig10.shard-0-of-2.json").exists());
    let v = json(&partial);
    let ranges = v["counts"][0]["ranges"].as_array().unwrap();
    assert_eq!(
        ranges,
        &serde_json::json!([[0, 2048]]).as_array().unwrap().clone()
    );
    bin()
        .arg("figure")
        .arg("--resume")
        .arg(&partial)
        .arg("--out")
        .arg(&a)
        .run_ok();
    assert!(!partial.exists(), "the partial file is used up");
    let whole: Vec<String> = args(&b);
    bin().args(&whole).run_ok();
    let name = "fig10.shard-0-of-2.json";
    // The same counts; the provenance is the command line that started each (the resumed one's
    // ran on one thread).
    let (resumed, whole) = (json(&a.join(name)), json(&b.join(name)));
    assert_eq!(without_provenance(&resumed), without_provenance(&whole));
    let started = &resumed["provenance"]["command_line"];
    assert!(
        started.as_array().unwrap().iter().any(|a| a == "--threads"),
        "{started}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// SIGTERM during a whole run: the complete fig10.json of an earlier run stays; the partial
/// counts go to fig10.partial.json.
#[test]
fn a_terminated_run_never_replaces_a_complete_result() {
    let dir = scratch("term");
    let d = dir.display().to_string();
    bin()
        .args(["figure", "10", "--trials", "300", "--out", &d])
        .run_ok();
    let before = std::fs::read(dir.join("fig10.json")).unwrap();
    let out = interrupted(
        &["figure", "10", "--trials", "1000000000", "--out", &d],
        "TERM",
    );
    fails(&out, 1, "interrupted");
    assert_eq!(std::fs::read(dir.join("fig10.json")).unwrap(), before);
    let partial = json(&dir.join("fig10.partial.json"));
    assert_eq!(partial["trials"], 1_000_000_000u64);
    std::fs::remove_dir_all(&dir).ok();
}

/// A run into a directory that cannot be written fails at once, before sampling: a study of
/// 10^12 trials (years of work) returns.
#[test]
fn an_unwritable_output_fails_before_any_work() {
    let out = bin()
        .args([
            "figure",
            "10",
            "--trials",
            "1000000000000",
            "--shard",
            "0/2",
        ])
        .args(["--out", "/proc/rocking-block-results"])
        .output()
        .unwrap();
    fails(&out, 1, "cannot write /proc/rocking-block-results");
}

/// A partial file is never replaced by one holding less: a fresh run of the same study that
/// stops earlier leaves the partial of one that got further (it holds every trial the fresh
/// run counted); a run of another study writes beside it.
#[test]
fn a_partial_is_never_replaced_by_one_holding_less() {
    let dir = scratch("partials");
    let d = dir.display().to_string();
    let run = |stop: &str, seed: &str| {
        bin()
            .args(["figure", "7", "--trials", "3000", "--threads", "1"])
            .args(["--seed", seed, "--stop-after", stop, "--out", &d])
            .output()
            .unwrap()
    };
    let partial = dir.join("fig7.partial.json");
    fails(&run("2560", "1"), 1, "interrupted");
    let further = std::fs::read(&partial).unwrap();
    fails(&run("256", "1"), 1, "fig7.partial.json");
    assert_eq!(std::fs::read(&partial).unwrap(), further);
    let out = run("256", "2");
    fails(&out, 1, "interrupted");
    assert_eq!(std::fs::read(&partial).unwrap(), further);
    let beside: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| {
            n.starts_with("fig7.") && n.ends_with(".partial.json") && n != "fig7.partial.json"
        })
        .collect();
    assert_eq!(beside.len(), 1, "{beside:?}");
    let text = String::from_utf8_lossy(&out.stderr);
    assert!(text.contains(&beside[0]), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Shards of a 600-trial Fig. 10 and corrupted copies of the first.
fn shards(dir: &Path) -> (PathBuf, PathBuf) {
    let d = dir.display().to_string();
    for s in ["0/2", "1/2"] {
        bin()
            .args(["figure", "10", "--trials", "600", "--shard", s, "--out", &d])
            .run_ok();
    }
    (
        dir.join("fig10.shard-0-of-2.json"),
        dir.join("fig10.shard-1-of-2.json"),
    )
}

fn corrupt(from: &Path, to: &Path, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    let mut v = json(from);
    edit(&mut v);
    std::fs::write(to, v.to_string()).unwrap();
    to.to_path_buf()
}

#[test]
fn merge_checks_every_shard() {
    let dir = scratch("merge");
    let (s0, s1) = shards(&dir);
    let merge = |files: &[&Path], out: &Path| {
        bin()
            .arg("merge")
            .args(files)
            .arg("--out")
            .arg(out)
            .output()
            .unwrap()
    };
    let out = dir.join("out");
    // An inflated count: the cells count more trials than the ranges cover.
    let inflated = corrupt(&s0, &dir.join("inflated.json"), |v| {
        v["counts"][0]["counts"][0][0] = serde_json::json!(1000);
    });
    fails(&merge(&[&inflated, &s1], &out), 2, "ranges cover 300");
    // A class array cut short.
    let cut = corrupt(&s0, &dir.join("cut.json"), |v| {
        v["counts"][1]["counts"][3].as_array_mut().unwrap().pop();
    });
    fails(&merge(&[&cut, &s1], &out), 2, "cell 3 has");
    // Ranges beyond the trial count.
    let beyond = corrupt(&s0, &dir.join("beyond.json"), |v| {
        v["trials"] = serde_json::json!(100);
    });
    fails(&merge(&[&beyond], &out), 2, "outside the shard");
    // Counts that overflow when merged.
    let huge = corrupt(&s0, &dir.join("huge.json"), |v| {
        v["counts"][0]["counts"][0][0] = serde_json::json!(u64::MAX);
    });
    fails(&merge(&[&huge, &s1], &out), 2, "invalid file");
    // Missing tables, a figure without tables, the same shard twice, another seed.
    let short = corrupt(&s0, &dir.join("short.json"), |v| {
        v["counts"].as_array_mut().unwrap().pop();
    });
    fails(&merge(&[&short], &out), 2, "2 count tables");
    let fig3 = corrupt(&s0, &dir.join("fig3.json"), |v| {
        v["figure"] = serde_json::json!(3)
    });
    fails(&merge(&[&fig3], &out), 2, "no count tables");
    fails(&merge(&[&s0, &s0], &out), 2, "counted twice");
    let seed = corrupt(&s1, &dir.join("seed.json"), |v| {
        v["seed"] = serde_json::json!(9)
    });
    fails(&merge(&[&s0, &seed], &out), 2, "seed");
    let block = corrupt(&s1, &dir.join("block.json"), |v| {
        v["block"]["theta_b"] = serde_json::json!(0.85)
    });
    fails(&merge(&[&s0, &block], &out), 2, "block");
    assert!(!out.join("fig10.json").exists(), "nothing was written");
    // One shard of two: a partial file, no figure; the other completes it.
    fails(&merge(&[&s0], &out), 1, "300 of 600 trials");
    assert!(!out.join("fig10.json").exists());
    let partial = out.join("fig10.partial.json");
    let both = merge(&[&partial, &s1], &dir.join("both"));
    assert!(
        both.status.success(),
        "{}",
        String::from_utf8_lossy(&both.stderr)
    );
    let whole = dir.join("whole");
    bin()
        .args(["figure", "10", "--trials", "600", "--out"])
        .arg(&whole)
        .run_ok();
    let (merged, whole) = (
        json(&dir.join("both/fig10.json")),
        json(&whole.join("fig10.json")),
    );
    assert_eq!(without_provenance(&merged), without_provenance(&whole));
    assert_eq!(merged["provenance"]["command_line"][1], "merge");
    assert_eq!(merged["provenance"]["trials"], 600);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn an_output_that_is_the_input_is_refused() {
    let dir = scratch("classify");
    let csv = dir.join("trials.csv");
    let text = "omega,alpha,beta,phi0,psi0\n1.3,0.66,0,0.01,0\n";
    std::fs::write(&csv, text).unwrap();
    let out = bin()
        .args(["classify", "--input"])
        .arg(&csv)
        .arg("--output")
        .arg(dir.join(".").join("trials.csv"))
        .output()
        .unwrap();
    fails(&out, 2, "is an input file of this command");
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), text);
    std::fs::write(&csv, "omega,alpha,beta,phi0,psi0\n1.3,0.66,NaN,0.01,0\n").unwrap();
    let out = bin()
        .args(["classify", "--input"])
        .arg(&csv)
        .arg("--output")
        .arg(dir.join("out.csv"))
        .output()
        .unwrap();
    fails(&out, 2, "line 2: beta is not a finite number");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn sizes_are_bounded_with_a_clear_error() {
    let run = |args: &[&str]| bin().args(args).output().unwrap();
    fails(
        &run(&["figure", "10", "--trials", "18446744073709551615"]),
        2,
        "trials = 18446744073709551615",
    );
    fails(
        &run(&["simulate", "--points-per-period", "100000000"]),
        2,
        "would not fit in memory",
    );
    fails(
        &run(&["orbit", "--ntst", "100000"]),
        2,
        "collocation.ntst = 100000",
    );
}

/// An edit of a JSON file.
type Edit = fn(&mut serde_json::Value);

/// Restart files that are valid JSON with wrong contents, and labels or windows that do not
/// fit: exit 2 with the file or value named.
#[test]
fn restarts_and_windows_are_checked() {
    let dir = scratch("restart");
    let saved = dir.join("run.json");
    bin()
        .args(["continue", "--free", "omega", "--out"])
        .arg(&saved)
        .run_ok();
    let restart = |file: &Path, extra: &[&str]| {
        bin()
            .args(["continue", "--free", "omega", "--restart"])
            .arg(file)
            .args(extra)
            .output()
            .unwrap()
    };
    let cases: [(&str, Edit); 4] = [
        ("short_u", |v| {
            let u = v["branch"]["points"][2]["u"].as_array_mut().unwrap();
            u.truncate(3);
        }),
        ("empty_segments", |v| {
            v["template"]["signature"]["segments"] = serde_json::json!([]);
        }),
        ("mode_7", |v| {
            v["template"]["signature"]["segments"][0]["mode"] = serde_json::json!(7);
        }),
        ("short_params", |v| {
            v["template"]["params"].as_array_mut().unwrap().truncate(2);
        }),
    ];
    for (name, edit) in cases {
        let file = corrupt(&saved, &dir.join(format!("{name}.json")), edit);
        fails(
            &restart(&file, &["--label", "3"]),
            2,
            &format!("{name}.json"),
        );
    }
    fails(
        &restart(&saved, &["--label", "999"]),
        2,
        "no point labelled 999",
    );
    // The window: a start outside [min, max] is refused, fresh or restarted.
    let out = bin()
        .args(["continue", "--free", "omega", "--min", "2", "--max", "3"])
        .output()
        .unwrap();
    fails(&out, 2, "outside the bounds [2, 3]");
    fails(
        &restart(&saved, &["--label", "5", "--min", "2", "--max", "3"]),
        2,
        "outside the bounds [2, 3]",
    );
    std::fs::remove_dir_all(&dir).ok();
}
