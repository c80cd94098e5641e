//! The `table_basins` example's command line, the contract `scripts/slurm` drives
//! ([`hycont::hycont_sample::study::Invocation`]): three shards of the study's cells, each
//! run on its own, merge into the count file and the table a whole run writes and prints,
//! byte for byte; a bad shard argument is refused naming it. Needs the example built (`cargo
//! test` builds it).

use std::path::PathBuf;
use std::process::Command;

fn example() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let target = exe.parent().and_then(|d| d.parent()).unwrap();
    let path = target.join("examples").join("table_basins");
    assert!(path.exists(), "build the example first: {}", path.display());
    path
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("hycont-tb-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn run(args: &[&str], out: &PathBuf) -> std::process::Output {
    Command::new(example())
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

#[test]
fn shards_and_their_merge_equal_a_whole_run() {
    let (whole, shards, merged) = (scratch("whole"), scratch("shards"), scratch("merged"));
    let one = run(&["run"], &whole);
    assert!(one.status.success(), "{one:?}");
    for i in 0..3 {
        let shard = format!("{i}/3");
        let out = run(&["run", "--shard", &shard], &shards);
        assert!(out.status.success(), "{out:?}");
        // A shard prints no table.
        assert!(out.stdout.is_empty());
    }
    let files: Vec<String> = (0..3)
        .map(|i| {
            shards
                .join(format!("table_basins.shard-{i}-of-3.json"))
                .display()
                .to_string()
        })
        .collect();
    let mut args = vec!["merge"];
    args.extend(files.iter().map(String::as_str));
    let joined = run(&args, &merged);
    assert!(joined.status.success(), "{joined:?}");
    assert_eq!(joined.stdout, one.stdout);
    let name = "table_basins.json";
    assert_eq!(
        std::fs::read(whole.join(name)).unwrap(),
        std::fs::read(merged.join(name)).unwrap()
    );
    let bad = run(&["run", "--shard", "3/3"], &merged);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--shard 3/3"));
    for d in [whole, shards, merged] {
        std::fs::remove_dir_all(d).ok();
    }
}
