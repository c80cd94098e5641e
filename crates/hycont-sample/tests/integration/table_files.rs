//! A driver's own count file ([`TableFile`]): one study of the same trials binned two ways
//! (over x and over y), in the driver's layout on disk. The runner drives it as any count
//! file: shards merge to the whole run, an interrupted run resumes to it, the tables that bin
//! the same trials count once (progress, to-do) and must have counted the same trials, and
//! files of another run or edited counts are refused with one line naming the problem.
//!
//! Reference: with x, y uniform on [0, 1) and "low" where x < y / 2, the fraction of "low" in
//! the x-bin [a, b) is the mean over it of P(y > 2x) = 1 - 2x (for x < 1/2): the first of four
//! x-bins, [0, 1/4), has 1 - 2 * 1/8 = 3/4; the y-bin [c, d) has the mean of y / 2: the last
//! of four y-bins, [3/4, 1), has 7/16.

use hycont_sample::basin::{Axis, Classifier, Counts, Distribution, Progress, Study, run_binned};
use hycont_sample::study::{CountFile, Outcome, Ranks, TableFile, merge, sample};
use std::ops::Range;
use std::path::PathBuf;

/// x < y / 2: "low", else "high".
struct Below;

impl Classifier for Below {
    fn classes(&self) -> Vec<String> {
        vec!["low".into(), "high".into()]
    }
    fn classify(&self, v: &[f64]) -> Result<usize, String> {
        Ok(usize::from(v[0] >= 0.5 * v[1]))
    }
}

fn axis(variable: usize) -> Axis {
    Axis {
        variable,
        lo: 0.0,
        hi: 1.0,
        bins: 4,
    }
}

/// The driver's file: its own field names and order.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
struct Marginals {
    seed: u64,
    trials: u64,
    part: (u64, u64),
    /// Binned over x, then over y.
    tables: Vec<Counts>,
}

impl Marginals {
    fn new(trials: u64, part: (u64, u64)) -> Self {
        let classes = Below.classes();
        Marginals {
            seed: 5,
            trials,
            part,
            tables: vec![Counts::new(classes.clone(), 4), Counts::new(classes, 4)],
        }
    }
    fn study(&self) -> Study {
        Study {
            names: vec!["x".into(), "y".into()],
            variables: vec![Distribution::Uniform { lo: 0.0, hi: 1.0 }; 2],
            axes: Vec::new(),
            seed: self.seed,
        }
    }
}

impl TableFile for Marginals {
    type Table = Counts;
    type Error = hycont_sample::Error;
    const WRITER: &'static str = "marginals";
    fn what(&self) -> String {
        "marginals".into()
    }
    fn shard(&self) -> (u64, u64) {
        self.part
    }
    fn set_shard(&mut self, shard: (u64, u64)) {
        self.part = shard;
    }
    fn extent(&self) -> u64 {
        self.trials
    }
    fn tables(&self) -> &[Counts] {
        &self.tables
    }
    fn tables_mut(&mut self) -> &mut [Counts] {
        &mut self.tables
    }
    fn shares_trials(&self) -> bool {
        true
    }
    fn same_run(&self, other: &Self) -> Result<(), String> {
        if (self.seed, self.trials) == (other.seed, other.trials) {
            Ok(())
        } else {
            Err(format!(
                "seed {} or trials {} differ",
                other.seed, other.trials
            ))
        }
    }
    fn fill(&mut self, todo: &[Vec<Range<u64>>], progress: &Progress) -> hycont_sample::Result<()> {
        let binnings = [vec![axis(0)], vec![axis(1)]];
        for r in todo.iter().flatten() {
            let counts = run_binned(&self.study(), &binnings, &Below, r.clone(), progress)?;
            for (t, c) in self.tables.iter_mut().zip(&counts) {
                t.merge(c)?;
            }
        }
        Ok(())
    }
    fn check(&self) -> Result<(), String> {
        if self.tables.len() != 2 || self.tables.iter().any(|t| t.counts.len() != 4) {
            return Err("two tables of four cells".into());
        }
        Ok(())
    }
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("hycont-tables-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn complete(outcome: Outcome<Marginals>) -> Marginals {
    match outcome {
        Outcome::Complete { file, .. } => file,
        other => panic!("not complete: {other:?}"),
    }
}

fn low_fraction(c: &Counts, cell: usize) -> f64 {
    c.counts[cell][0] as f64 / (c.counts[cell][0] + c.counts[cell][1]) as f64
}

/// Three shards merge to the whole run; tables that bin the same trials count once (progress
/// and to-do); the marginal fractions agree with the closed forms (3/4 in the first x-bin,
/// 7/16 in the last y-bin) within 4 standard errors.
#[test]
fn shards_of_a_drivers_file_merge_to_the_whole_run() {
    let d = dir("shards");
    let n = 20_000;
    let fresh = Marginals::new(n, (0, 1));
    assert_eq!(fresh.progress(), (0, n));
    assert_eq!(fresh.todo((0, 1)).unwrap(), vec![vec![0..n]]);
    let whole = complete(sample(fresh, &d, &Progress::default(), Ranks::current()).unwrap());
    assert!(whole.is_complete());
    let mut shards = Vec::new();
    for i in 0..3 {
        let outcome = sample(
            Marginals::new(n, (i, 3)),
            &d,
            &Progress::default(),
            Ranks::current(),
        );
        let Outcome::Complete {
            written: Some(path),
            ..
        } = outcome.unwrap()
        else {
            panic!("shard {i} not written");
        };
        assert_eq!(path, d.join(format!("marginals.shard-{i}-of-3.json")));
        shards.push((path.clone(), Marginals::read(&path).unwrap()));
    }
    let merged = merge(shards).unwrap();
    assert_eq!(merged, whole);
    let per_bin = n as f64 / 4.0;
    for (fraction, p) in [
        (low_fraction(&whole.tables[0], 0), 0.75),
        (low_fraction(&whole.tables[1], 3), 7.0 / 16.0),
    ] {
        let se = (p * (1.0 - p) / per_bin).sqrt();
        assert!((fraction - p).abs() < 4.0 * se, "{fraction} vs {p}");
    }
    std::fs::remove_dir_all(&d).ok();
}

/// Stopped by a budget, the partial file holds the exact trials counted; resumed, the run
/// equals an uninterrupted one.
#[test]
fn an_interrupted_drivers_file_resumes_to_the_whole_run() {
    let d = dir("resume");
    let whole = complete(
        sample(
            Marginals::new(5_000, (0, 1)),
            &d,
            &Progress::default(),
            Ranks::current(),
        )
        .unwrap(),
    );
    let stopped = sample(
        Marginals::new(5_000, (0, 1)),
        &d,
        &Progress::with_budget(600),
        Ranks::current(),
    )
    .unwrap();
    let Outcome::Partial { file, path } = stopped else {
        panic!("not stopped");
    };
    let (done, total) = file.progress();
    assert!(done > 0 && done < total, "{done} of {total}");
    let read = Marginals::read(&path).unwrap();
    assert_eq!(read, file);
    let resumed = complete(sample(read, &d, &Progress::default(), Ranks::current()).unwrap());
    assert_eq!(resumed, whole);
    std::fs::remove_dir_all(&d).ok();
}

/// Edited files are refused, each with one line naming the problem: tables that bin the same
/// trials but counted different ones, an invalid shard, trials outside the shard, the
/// driver's own check; a file of another run does not merge.
#[test]
fn a_drivers_edited_files_are_refused() {
    let d = dir("refused");
    let whole = complete(
        sample(
            Marginals::new(1_000, (0, 1)),
            &d,
            &Progress::default(),
            Ranks::current(),
        )
        .unwrap(),
    );
    let text = serde_json::to_string(&whole).unwrap();
    assert_eq!(Marginals::parse(&text).unwrap(), whole);
    let edit = |f: &dyn Fn(&mut serde_json::Value)| {
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        f(&mut v);
        Marginals::parse(&v.to_string()).unwrap_err()
    };
    let mut fewer = Marginals::new(1_000, (0, 1));
    let progress = Progress::default();
    let half = fewer.todo((0, 2)).unwrap();
    TableFile::fill(&mut fewer, &half, &progress).unwrap();
    let other_table = serde_json::to_value(&fewer.tables[1]).unwrap();
    for (why, needle) in [
        (
            edit(&|v| v["tables"][1] = other_table.clone()),
            "table 1 counts 500 trials, table 0 1000",
        ),
        (
            edit(&|v| v["part"] = serde_json::json!([2, 2])),
            "shard 2/2",
        ),
        (
            edit(&|v| v["trials"] = serde_json::json!(999)),
            "outside the shard's trials 0..999",
        ),
        (
            edit(&|v| v["tables"].as_array_mut().unwrap().truncate(1)),
            "two tables",
        ),
        (
            edit(&|v| v["tables"] = serde_json::json!(7)),
            "not a file written by `marginals`",
        ),
    ] {
        assert!(why.contains(needle) && !why.contains('\n'), "{why}");
    }
    let mut other = Marginals::new(1_000, (0, 1));
    other.seed = 6;
    let mut m = whole.clone();
    assert!(
        CountFile::merge(&mut m, &other)
            .unwrap_err()
            .contains("seed 6")
    );
    assert!(!whole.subsumes(&other) && whole.subsumes(&fewer) && !fewer.subsumes(&whole));
    std::fs::remove_dir_all(&d).ok();
}
