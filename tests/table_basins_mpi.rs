//! `mpirun -n 2` of the `table_basins` example (feature `mpi`; needs `mpirun` on PATH): the
//! ranks share the study's cells through hycont-sample's runner and rank 0 prints the table
//! and writes the count file one process prints and writes, byte for byte. Build the example
//! with the feature first: `cargo build --release --features mpi --example table_basins`,
//! then `cargo test --release --features mpi --test table_basins_mpi` (`scripts/test` does).
#![cfg(feature = "mpi")]

use std::path::PathBuf;
use std::process::Command;

/// The example's binary, built beside the tests (see the module docs).
fn example() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let target = exe.parent().and_then(|d| d.parent()).unwrap();
    target.join("examples").join("table_basins")
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("hycont-tb-mpi-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn two_ranks_print_and_write_what_one_process_does() {
    let (one, two) = (scratch("one"), scratch("two"));
    let single = Command::new(example())
        .args(["run", "--out"])
        .arg(&one)
        .output()
        .unwrap();
    assert!(single.status.success(), "{single:?}");
    let ranks = Command::new("mpirun")
        .args(["-n", "2", "--oversubscribe"])
        .arg(example())
        .args(["run", "--out"])
        .arg(&two)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .output()
        .unwrap();
    assert!(ranks.status.success(), "{ranks:?}");
    assert_eq!(
        String::from_utf8_lossy(&single.stdout),
        String::from_utf8_lossy(&ranks.stdout)
    );
    let name = "table_basins.json";
    assert_eq!(
        std::fs::read(one.join(name)).unwrap(),
        std::fs::read(two.join(name)).unwrap()
    );
    for d in [one, two] {
        std::fs::remove_dir_all(d).unwrap();
    }
}
