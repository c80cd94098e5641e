//! `basin`: basin stability for user ranges, against Fig. 7, with shards, merges, resumes and
//! its CSV.

use crate::common;

use common::{RunOk, bin, fails, json, scratch, without_provenance};
use std::path::Path;

const CLASSES: [&str; 8] = [
    "symmetric_p1",
    "asymmetric_p1_pos",
    "asymmetric_p1_neg",
    "period2",
    "other",
    "equilibrium",
    "overturn_pos",
    "overturn_neg",
];

/// Fig. 7(c) is the basin at omega = 1.5 over the static boundary x (-1, 1), seed 1 + 2 (the
/// third panel). `basin` with those ranges and that seed draws the same trials (binning does
/// not change them): the same fractions exactly. On a coarse 2 x 2 map, minority classes
/// dominate no cell and stay out of the key. With another seed (independent trials) each class's
/// 95 % interval overlaps Fig. 7(c)'s: two samples of the same fraction fail that with
/// probability below 0.6 %.
#[test]
fn basin_reproduces_figure_7c() {
    let dir = scratch("basin-fig7");
    let fig = dir.join("fig");
    bin()
        .args(["figure", "7", "--trials", "2000", "--out"])
        .arg(&fig)
        .run_ok();
    let panel = json(&fig.join("fig7.json"))["basins"][2].clone();
    assert_eq!(panel["omega"], 1.5);
    let same = dir.join("same");
    bin()
        .args(["basin", "--omega", "1.5", "--seed", "3", "--trials", "2000"])
        .args(["--bin", "phi0:2", "--bin", "psi0:2", "--out"])
        .arg(&same)
        .run_ok();
    let v = json(&same.join("basin.json"));
    assert_eq!(v["fractions"], panel["fractions"]);
    assert_eq!(v["intervals_95"], panel["intervals_95"]);
    // The map's key names exactly the classes that dominate a cell (from the CSV's counts;
    // ties go to the later class, as the map draws them).
    let svg = std::fs::read_to_string(same.join("basin.svg")).unwrap();
    assert!(svg.contains("dominant class"));
    let csv = std::fs::read_to_string(same.join("basin.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let classes: Vec<&str> = header[6..].iter().step_by(4).copied().collect();
    let mut dominant = std::collections::BTreeSet::new();
    for line in lines {
        let row: Vec<u64> = line
            .split(',')
            .skip(6)
            .step_by(4)
            .map(|x| x.parse().unwrap())
            .collect();
        let best = row
            .iter()
            .enumerate()
            .filter(|(_, n)| **n > 0)
            .max_by_key(|(_, n)| **n);
        if let Some((k, _)) = best {
            dominant.insert(classes[k]);
        }
    }
    assert!(dominant.len() >= 2, "{dominant:?}");
    for c in CLASSES {
        let named = svg.contains(&format!("({c})"));
        assert_eq!(named, dominant.contains(c), "{c} in the key: {named}");
    }
    let other = dir.join("other");
    bin()
        .args([
            "basin", "--omega", "1.5", "--seed", "77", "--trials", "4000", "--out",
        ])
        .arg(&other)
        .run_ok();
    let w = json(&other.join("basin.json"));
    assert_eq!(w["trials"], 4000);
    for c in CLASSES {
        let a = &panel["intervals_95"][c];
        let b = &w["intervals_95"][c];
        let (a0, a1, b0, b1) = (
            a[0].as_f64().unwrap(),
            a[1].as_f64().unwrap(),
            b[0].as_f64().unwrap(),
            b[1].as_f64().unwrap(),
        );
        assert!(a0 <= b1 && b0 <= a1, "{c}: [{a0}, {a1}] vs [{b0}, {b1}]");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Two shards merge into the whole run; one shard alone merges into a partial file that
/// `--resume` completes to the same result; the CSV has one row per cell whose class counts add
/// up to its trials, and fractions inside their intervals.
#[test]
fn basin_shards_merge_resume_and_csv() {
    let dir = scratch("basin-shards");
    let args = |extra: &[&str], out: &Path| {
        let mut c = bin();
        c.args([
            "basin", "--omega", "2", "--alpha", "0.5:0.8", "--bin", "alpha:4",
        ])
        .args(["--trials", "400", "--seed", "5"])
        .args(extra)
        .arg("--out")
        .arg(out);
        c
    };
    let whole = dir.join("whole");
    args(&[], &whole).run_ok();
    for s in ["0/2", "1/2"] {
        args(&["--shard", s], &dir).run_ok();
    }
    let merged = dir.join("merged");
    bin()
        .arg("merge")
        .arg(dir.join("basin.shard-0-of-2.json"))
        .arg(dir.join("basin.shard-1-of-2.json"))
        .arg("--out")
        .arg(&merged)
        .run_ok();
    let expected = without_provenance(&json(&whole.join("basin.json")));
    assert_eq!(
        without_provenance(&json(&merged.join("basin.json"))),
        expected
    );
    // One shard: a partial file; resumed, the whole result.
    let half = dir.join("half");
    let out = bin()
        .arg("merge")
        .arg(dir.join("basin.shard-0-of-2.json"))
        .arg("--out")
        .arg(&half)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let partial = half.join("basin.partial.json");
    bin()
        .args(["basin", "--resume"])
        .arg(&partial)
        .arg("--out")
        .arg(&half)
        .run_ok();
    assert_eq!(
        without_provenance(&json(&half.join("basin.json"))),
        expected
    );
    assert!(!partial.exists());
    let csv = std::fs::read_to_string(whole.join("basin.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(&header[..4], ["cell", "alpha_lo", "alpha_hi", "trials"]);
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 4);
    let total: f64 = rows.iter().map(|r| r[3]).sum();
    assert_eq!(total, 400.0);
    for r in &rows {
        let per_class: Vec<&[f64]> = r[4..].chunks(4).collect();
        assert_eq!(per_class.len(), 8);
        assert_eq!(per_class.iter().map(|c| c[0]).sum::<f64>(), r[3]);
        for c in per_class {
            assert!(c[2] <= c[1] && c[1] <= c[3], "{c:?}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Ranges and binnings that make no study are refused as bad input, one line naming them.
#[test]
fn bad_basins_are_refused() {
    for (args, needle) in [
        (
            &["--bin", "omega:10"][..],
            "bin a variable drawn from a range",
        ),
        (&["--phi0", "1:0"], "LO must be below HI"),
        (&["--omega", "abc"], "omega"),
        (&["--omega", "0:2"], "omega"),
        (
            &["--bin", "phi0:4", "--bin", "psi0:4", "--bin", "beta:3"],
            "at most two",
        ),
        (&["--bin", "speed:4"], "NAME must be"),
        (&["--trials", "0"], "trials"),
    ] {
        fails(&bin().arg("basin").args(args).output().unwrap(), 2, needle);
    }
}
