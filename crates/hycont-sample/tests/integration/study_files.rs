//! The study runner on a classifier with a closed form (x uniform on [0, 1), y on [0, 1):
//! class "low" where x < y / 2): interrupted runs resume to the uninterrupted result, shards
//! merge to it, partial files never lose counts, and edited files are refused.

use hycont_sample::adaptive::Adaptive;
use hycont_sample::basin::{Axis, Classifier, Distribution, Progress, Study};
use hycont_sample::study::{CountFile, Outcome, Plan, Ranks, StudyFile, merge, sample};
use std::path::PathBuf;

/// x < y / 2: "low" (a triangle of area 1/4), else "high".
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
struct Below {
    slope: f64,
}

impl Classifier for Below {
    fn classes(&self) -> Vec<String> {
        vec!["low".into(), "high".into()]
    }
    fn classify(&self, v: &[f64]) -> Result<usize, String> {
        Ok(usize::from(v[0] >= self.slope * v[1]))
    }
}

fn study() -> Study {
    Study {
        names: vec!["x".into(), "y".into()],
        variables: vec![
            Distribution::Uniform { lo: 0.0, hi: 1.0 },
            Distribution::Uniform { lo: 0.0, hi: 1.0 },
        ],
        axes: vec![Axis {
            variable: 1,
            bins: 4,
            lo: 0.0,
            hi: 1.0,
        }],
        seed: 11,
    }
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("hycont-study-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn trials(shard: (u64, u64)) -> StudyFile<Below> {
    StudyFile::trials("below", study(), Below { slope: 0.5 }, 10_000, shard).unwrap()
}

fn cells(shard: (u64, u64)) -> StudyFile<Below> {
    let rule = Adaptive {
        halfwidth: 0.05,
        ..Adaptive::default()
    };
    StudyFile::cells("below", study(), Below { slope: 0.5 }, rule, shard).unwrap()
}

fn complete(outcome: Outcome<StudyFile<Below>>) -> StudyFile<Below> {
    match outcome {
        Outcome::Complete { file, .. } => file,
        other => panic!("not complete: {other:?}"),
    }
}

/// Stopped after a budget, the partial file holds the exact trials counted; resumed from it,
/// the run ends with the counts of an uninterrupted run (equal, field by field), for trials
/// and for cells. The counted fraction of "low" agrees with 1/4 within 4 standard errors.
#[test]
fn a_resumed_run_equals_an_uninterrupted_one() {
    for (kind, make) in [("trials", trials as fn(_) -> _), ("cells", cells)] {
        let d = dir(kind);
        let whole =
            complete(sample(make((0, 1)), &d, &Progress::default(), Ranks::current()).unwrap());
        let stopped = sample(
            make((0, 1)),
            &d,
            &Progress::with_budget(500),
            Ranks::current(),
        )
        .unwrap();
        let Outcome::Partial { file, path } = stopped else {
            panic!("{kind}: not stopped")
        };
        assert!(file.progress().0 < file.progress().1);
        let read = StudyFile::<Below>::read(&path).unwrap();
        assert_eq!(read, file);
        let resumed = complete(sample(read, &d, &Progress::default(), Ranks::current()).unwrap());
        assert_eq!(resumed.plan, whole.plan, "{kind}");
        if let Plan::Trials { counts, .. } = &whole.plan {
            let low: u64 = counts.counts.iter().map(|c| c[0]).sum();
            let p = low as f64 / 10_000.0;
            assert!(
                (p - 0.25).abs() < 4.0 * (0.25f64 * 0.75 / 10_000.0).sqrt(),
                "{p}"
            );
        }
        std::fs::remove_dir_all(&d).unwrap();
    }
}

/// Three shards, each written as its complete shard file, merge into the whole run's counts.
#[test]
fn shards_merge_to_the_whole_run() {
    for (kind, make) in [
        ("shard-trials", trials as fn(_) -> _),
        ("shard-cells", cells),
    ] {
        let d = dir(kind);
        let whole =
            complete(sample(make((0, 1)), &d, &Progress::default(), Ranks::current()).unwrap());
        let mut files = Vec::new();
        for i in 0..3 {
            let outcome = sample(make((i, 3)), &d, &Progress::default(), Ranks::current()).unwrap();
            let Outcome::Complete {
                written: Some(path),
                ..
            } = outcome
            else {
                panic!("{kind}: shard {i} not written")
            };
            files.push((path.clone(), StudyFile::<Below>::read(&path).unwrap()));
        }
        let merged = merge(files.clone()).unwrap();
        assert!(merged.is_complete());
        assert_eq!(merged.plan, whole.plan, "{kind}");
        // A shard given twice counts its trials twice: refused.
        if kind == "shard-trials" {
            let twice = vec![files[0].clone(), files[0].clone()];
            assert!(merge(twice).is_err());
        }
        std::fs::remove_dir_all(&d).unwrap();
    }
}

/// An interrupted run never writes over a partial file of the same study holding trials it
/// lacks: a file holding all of its trials keeps them (nothing written); one holding others
/// is left alone and the run writes beside it, so that both merge to every trial counted.
#[test]
fn a_partial_file_holding_more_is_kept() {
    let d = dir("keep");
    let bigger = sample(
        trials((0, 1)),
        &d,
        &Progress::with_budget(3000),
        Ranks::current(),
    )
    .unwrap();
    let Outcome::Partial {
        path: first,
        file: big,
    } = bigger
    else {
        panic!("not stopped")
    };
    let smaller = sample(
        trials((0, 1)),
        &d,
        &Progress::with_budget(500),
        Ranks::current(),
    )
    .unwrap();
    let Outcome::Partial { path: second, .. } = smaller else {
        panic!("not stopped")
    };
    assert_eq!(first, second);
    assert_eq!(StudyFile::<Below>::read(&first).unwrap(), big);
    // A partial file of trials 6000..7000 only: neither holds the other's trials.
    let mut other = trials((0, 1));
    let counted = hycont_sample::basin::run(
        &other.study,
        &other.classifier,
        6000..7000,
        &Progress::default(),
    )
    .unwrap();
    if let Plan::Trials { counts, .. } = &mut other.plan {
        counts.merge(&counted).unwrap();
    }
    other.write(&first).unwrap();
    let Outcome::Partial { path: beside, file } = sample(
        trials((0, 1)),
        &d,
        &Progress::with_budget(500),
        Ranks::current(),
    )
    .unwrap() else {
        panic!("not stopped")
    };
    assert_ne!(beside, first);
    assert_eq!(StudyFile::<Below>::read(&first).unwrap(), other);
    let both = merge(vec![(first.clone(), other.clone()), (beside, file.clone())]).unwrap();
    assert_eq!(both.progress().0, other.progress().0 + file.progress().0);
    std::fs::remove_dir_all(&d).unwrap();
}

/// Files edited by hand are refused on reading, naming the file: counts that do not add up
/// to their trials, another format version, a shard out of range, trials outside the shard.
#[test]
fn edited_files_are_refused() {
    let d = dir("edit");
    let Outcome::Partial { path, .. } = sample(
        trials((0, 1)),
        &d,
        &Progress::with_budget(500),
        Ranks::current(),
    )
    .unwrap() else {
        panic!("not stopped")
    };
    let text = std::fs::read_to_string(&path).unwrap();
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    let edits: [fn(&mut serde_json::Value); 5] = [
        |v| v["plan"]["trials"]["counts"]["counts"][0][0] = 999_999.into(),
        |v| v["version"] = 2.into(),
        |v| v["shard"] = serde_json::json!([3, 3]),
        |v| v["plan"]["trials"]["counts"]["ranges"][0][1] = 20_000.into(),
        |v| v["name"] = "a/b".into(),
    ];
    for (k, edit) in edits.iter().enumerate() {
        let mut v = value.clone();
        edit(&mut v);
        let bad = d.join(format!("bad{k}.json"));
        std::fs::write(&bad, v.to_string()).unwrap();
        let e = StudyFile::<Below>::read(&bad).unwrap_err();
        assert!(e.to_string().contains(&format!("bad{k}.json")), "{k}: {e}");
    }
    std::fs::remove_dir_all(&d).unwrap();
}
