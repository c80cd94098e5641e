//! `figure 9` and `figure 7` sampled cell by cell (`--halfwidth`, the default without
//! `--trials`): every cell meets the rule or its cap, the figure reports trials and
//! half-widths per cell, shards merge and interrupted runs resume into exactly the whole run's
//! figure, and bad settings are refused.

use crate::common;

use common::{RunOk, bin, fails, json, scratch, without_provenance};
use std::path::{Path, PathBuf};

/// A cheap adaptive Fig. 9: one batch of 16 trials per cell (the cap), 28,800 trials.
const CAPPED: [&str; 6] = ["--halfwidth", "0.05", "--max-per-cell", "16", "--seed", "4"];

/// Figure `figure` in two shards of its cells ([`CAPPED`]) under `dir/shards`, merged into
/// `dir/merged`: the two directories.
fn two_shards_merged(figure: &str, dir: &Path) -> (PathBuf, PathBuf) {
    let shards = dir.join("shards");
    for i in 0..2 {
        bin()
            .args(["figure", figure])
            .args(CAPPED)
            .args(["--shard", &format!("{i}/2"), "--out"])
            .arg(&shards)
            .run_ok();
    }
    let merged = dir.join("merged");
    bin()
        .arg("merge")
        .args((0..2).map(|i| shards.join(format!("fig{figure}.shard-{i}-of-2.json"))))
        .arg("--out")
        .arg(&merged)
        .run_ok();
    (shards, merged)
}

#[test]
fn cells_meet_the_rule_and_the_figure_reports_them() {
    let dir = scratch("adaptive-rule");
    bin()
        .args(["figure", "9", "--halfwidth", "0.3", "--out"])
        .arg(&dir)
        .run_ok();
    let v = json(&dir.join("fig9.json"));
    assert_eq!(v["sampling"]["adaptive"], true);
    assert_eq!(v["sampling"]["halfwidth"], 0.3);
    for basin in v["basins"].as_array().unwrap() {
        let trials = basin["trials_per_cell"].as_array().unwrap();
        let widths = basin["largest_halfwidth_per_cell"].as_array().unwrap();
        assert_eq!((trials.len(), widths.len()), (900, 900));
        for (n, w) in trials.iter().zip(widths) {
            let (n, w) = (n.as_u64().unwrap(), w.as_f64().unwrap());
            // One batch of 16 suffices at 0.3 (half-width at most 0.23 at p = 1/2).
            assert_eq!(n, 16);
            assert!(w <= 0.3, "{w}");
        }
        let total: u64 = trials.iter().map(|n| n.as_u64().unwrap()).sum();
        assert_eq!(basin["trials"].as_u64().unwrap(), total);
    }
    assert!(v["sampling"]["largest_halfwidth"].as_f64().unwrap() <= 0.3);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn shards_and_resumed_runs_give_the_whole_run() {
    let dir = scratch("adaptive-shards");
    let whole = dir.join("whole");
    bin()
        .args(["figure", "9"])
        .args(CAPPED)
        .arg("--out")
        .arg(&whole)
        .run_ok();
    // Capped at 16 per cell: every cell has 16 trials, most are not within 0.05.
    let v = json(&whole.join("fig9.json"));
    assert!(
        v["basins"][0]["trials_per_cell"]
            .as_array()
            .unwrap()
            .iter()
            .all(|n| n == 16)
    );
    // Two shards of the cells, merged.
    let (shards, merged) = two_shards_merged("9", &dir);
    let fig = |d: &std::path::Path| without_provenance(&json(&d.join("fig9.json")));
    assert_eq!(fig(&merged), fig(&whole));
    // A merge of one shard is incomplete: a partial file, exit 1.
    let out = bin()
        .arg("merge")
        .arg(shards.join("fig9.shard-0-of-2.json"))
        .arg("--out")
        .arg(dir.join("half"))
        .output()
        .unwrap();
    fails(&out, 1, "fig9.partial.json");
    // Interrupted by a budget, then resumed.
    let resumed = dir.join("resumed");
    let out = bin()
        .args(["figure", "9"])
        .args(CAPPED)
        .args(["--stop-after", "3000", "--out"])
        .arg(&resumed)
        .output()
        .unwrap();
    fails(&out, 1, "interrupted");
    let partial = resumed.join("fig9.partial.json");
    assert!(partial.exists() && !resumed.join("fig9.json").exists());
    bin()
        .args(["figure", "--resume"])
        .arg(&partial)
        .arg("--out")
        .arg(&resumed)
        .run_ok();
    assert!(!partial.exists());
    assert_eq!(fig(&resumed), fig(&whole));
    assert_eq!(
        std::fs::read(resumed.join("fig9.svg")).unwrap(),
        std::fs::read(whole.join("fig9.svg")).unwrap()
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_adaptive_settings_are_refused() {
    let dir = scratch("adaptive-bad");
    for (args, needle) in [
        (&["figure", "9", "--halfwidth", "0.6"][..], "halfwidth"),
        (&["figure", "9", "--halfwidth", "0"][..], "halfwidth"),
        (&["figure", "9", "--max-per-cell", "8"][..], "max-per-cell"),
        (&["figure", "10", "--halfwidth", "0.1"][..], "halfwidth"),
        (
            &["figure", "9", "--halfwidth", "0.1", "--trials", "50"][..],
            "--trials",
        ),
    ] {
        let out = bin().args(args).arg("--out").arg(&dir).output().unwrap();
        fails(&out, 2, needle);
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `basin --halfwidth`: every cell meets the rule; shards merge and an interrupted run resumes
/// into the whole run's files; the files report the rule, trials and half-widths per cell.
#[test]
fn basins_sampled_cell_by_cell() {
    let dir = scratch("adaptive-basin");
    let run = [
        "basin",
        "--omega",
        "1.0:2.0",
        "--bin",
        "omega:6",
        "--halfwidth",
        "0.08",
        "--seed",
        "3",
    ];
    let whole = dir.join("whole");
    bin().args(run).arg("--out").arg(&whole).run_ok();
    let v = json(&whole.join("basin.json"));
    assert_eq!(v["sampling"]["halfwidth"], 0.08);
    let trials = v["sampling"]["trials_per_cell"].as_array().unwrap();
    let widths = v["sampling"]["largest_halfwidth_per_cell"]
        .as_array()
        .unwrap();
    assert_eq!((trials.len(), widths.len()), (6, 6));
    for (n, w) in trials.iter().zip(widths) {
        assert!(w.as_f64().unwrap() <= 0.08, "{w}");
        assert_eq!(n.as_u64().unwrap() % 16, 0);
    }
    let total: u64 = trials.iter().map(|n| n.as_u64().unwrap()).sum();
    assert_eq!(v["trials"].as_u64().unwrap(), total);
    // Shards of the cells, merged.
    let shards = dir.join("shards");
    for i in 0..3 {
        bin()
            .args(run)
            .args(["--shard", &format!("{i}/3"), "--out"])
            .arg(&shards)
            .run_ok();
    }
    let merged = dir.join("merged");
    let mut merge = bin();
    merge.arg("merge");
    for i in 0..3 {
        merge.arg(shards.join(format!("basin.shard-{i}-of-3.json")));
    }
    merge.arg("--out").arg(&merged).run_ok();
    let result = |d: &std::path::Path| without_provenance(&json(&d.join("basin.json")));
    assert_eq!(result(&merged), result(&whole));
    assert_eq!(
        std::fs::read(merged.join("basin.csv")).unwrap(),
        std::fs::read(whole.join("basin.csv")).unwrap()
    );
    // Interrupted, then resumed.
    let resumed = dir.join("resumed");
    let out = bin()
        .args(run)
        .args(["--stop-after", "100", "--threads", "1", "--out"])
        .arg(&resumed)
        .output()
        .unwrap();
    fails(&out, 1, "interrupted");
    let partial = resumed.join("basin.partial.json");
    bin()
        .args(["basin", "--resume"])
        .arg(&partial)
        .arg("--out")
        .arg(&resumed)
        .run_ok();
    assert!(!partial.exists());
    assert_eq!(result(&resumed), result(&whole));
    for (args, needle) in [
        (&["basin", "--halfwidth", "0.5"][..], "halfwidth"),
        (
            &["basin", "--halfwidth", "0.1", "--max-per-cell", "4"][..],
            "max-per-cell",
        ),
        (
            &["basin", "--halfwidth", "0.1", "--trials", "50"][..],
            "--trials",
        ),
    ] {
        let out = bin().args(args).arg("--out").arg(&dir).output().unwrap();
        fails(&out, 2, needle);
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Fig. 7 by cells (its default): two shards of each omega's 1,600 cells of (phi0, psi0),
/// capped at one batch of 16 trials, merge into a figure with every cell sampled (a run of
/// 2,000 trials per omega leaves about a third of them empty), its trials and half-widths
/// reported per cell and no key entry for empty cells.
#[test]
fn figure_7_by_cells_has_no_empty_cell() {
    let dir = scratch("adaptive-fig7");
    let (_, merged) = two_shards_merged("7", &dir);
    let v = json(&merged.join("fig7.json"));
    assert_eq!(v["sampling"]["adaptive"], true);
    let basins = v["basins"].as_array().unwrap();
    assert_eq!(basins.len(), 6);
    for basin in basins {
        let trials = basin["trials_per_cell"].as_array().unwrap();
        assert_eq!(trials.len(), 1600);
        assert!(trials.iter().all(|n| n == 16));
        assert_eq!(basin["trials"], 16 * 1600);
        let dominant = basin["raster"]["dominant"].as_array().unwrap();
        assert!(
            dominant
                .iter()
                .flat_map(|r| r.as_array().unwrap())
                .all(|c| c.is_string())
        );
    }
    let svg = std::fs::read_to_string(merged.join("fig7.svg")).unwrap();
    assert!(svg.contains("trials cell by cell") && !svg.contains("no trials in the cell"));
    std::fs::remove_dir_all(&dir).ok();
}
