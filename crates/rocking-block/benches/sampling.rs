//! Sampling benchmarks (issue: sampling). Run with `cargo bench -p rocking-block --bench sampling`.
//!
//! Reference: a Python/scipy implementation of the same classifier costs 0.04-2.4 s per trial
//! and ~15-20 ms per forcing period of brute-force simulation on the project machine. Targets
//! on 2 cores: Fig. 5 at the study's settings (300 + 100 periods at each of 301 alpha values)
//! under 5 s; Fig. 7 at 20,000 trials per omega under 60 s; Fig. 9 at 1,000,000 trials per beta
//! under 10 min. Throughput is measured on 2,000-trial basins (trials per second = 2000 / time).

use criterion::{Criterion, criterion_group, criterion_main};
use hycont_sample::basin::{Progress, run};
use rocking_block::block::Block;
use rocking_block::classes::RockingClassifier;
use rocking_block::figures::sampling::{fig7_study, figure5};
use rocking_block::output::OutDir;
use rocking_block::provenance::Provenance;
use std::hint::black_box;

fn sampling(c: &mut Criterion) {
    let dir = std::env::temp_dir().join("hycont-bench-sampling");
    std::fs::create_dir_all(&dir).unwrap();
    let mut g = c.benchmark_group("sampling");
    g.sample_size(10);
    g.bench_function("figure5_study_settings_both_sweeps", |b| {
        b.iter(|| black_box(figure5(&OutDir::new(&dir), &Provenance::default()).unwrap()));
    });
    let classifier = RockingClassifier::default();
    for omega in [1.16, 4.0] {
        let study = fig7_study(omega, 1, &Block::default());
        g.bench_function(format!("fig7_basin_omega_{omega}_2000_trials"), |b| {
            b.iter(|| black_box(run(&study, &classifier, 0..2000, &Progress::default()).unwrap()));
        });
    }
    g.finish();
}

criterion_group!(benches, sampling);
criterion_main!(benches);
